//! Basic blocks for a long function: a branch that is never taken ([`boundary`]) about every
//! 80 or 200 statements, where the fewest values are live, so that LLVM schedules each block as
//! one region and keeps fewer values live than the registers hold (the mass matrix only: see
//! [`with_boundaries`]).

use std::collections::{HashMap, HashSet};

use proc_macro2::TokenStream;
use quote::quote;

use super::{Kind, Statement};
use crate::sym::Sym;

/// The call that cuts a function into basic blocks where a [`Sink`] asks for it: a branch that is
/// never taken (its documentation says why it helps).
fn boundary() -> TokenStream {
    quote!(::articulated::math::block_boundary())
}

/// `stmts` with a [`boundary`] about every 80 statements (functions of 300 to 1,000) or 200
/// (longer ones; shorter ones are left whole), each where the fewest values are live (bound
/// before it and read after it; `memory`, the values that live in memory anyway, not counted)
/// within a quarter of that spacing (a choice, not measured against evenly spaced cuts: the
/// difference is smaller than the noise from code placement below).
///
/// The spacing was measured on `mass_matrix_update` of the humanoid, chain50 and arm7
/// (`x86-64-v3`; cuts every 80, 120, 200, 500 and 1,500 statements against none, each in five
/// layouts of one binary, the linker's `--shuffle-sections` seeds 1–5, because a function of
/// about 32 KB runs at one of two speeds depending on where it lands). Every spacing was faster
/// and smaller than none; about 200 was the best on the long functions (chain50 clearly, the
/// humanoid tied with 500 within the spread of the layouts), 80 helped arm7 (311 statements),
/// and below 300 statements a cut changed nothing beyond noise. The figures are in this
/// comment's history (commit 4b955c8); `BENCHMARKS.md` has the current times.
pub(super) fn with_boundaries(stmts: Vec<Statement>, memory: &HashSet<Sym>) -> Vec<Statement> {
    let n = stmts.len();
    if n < 300 {
        return stmts;
    }
    let every = if n < 1_000 { 80 } else { 200 };
    // live[i]: values live between statement i - 1 and statement i.
    let mut last_read: HashMap<Sym, usize> = HashMap::new();
    for (i, st) in stmts.iter().enumerate() {
        for &r in &st.reads {
            last_read.insert(r, i);
        }
    }
    let mut delta = vec![0_i64; n + 1];
    for (i, st) in stmts.iter().enumerate() {
        for b in st.binds.iter().filter(|b| !memory.contains(b)) {
            if let Some(&l) = last_read.get(b) {
                if l > i {
                    delta[i + 1] += 1;
                    delta[l + 1] -= 1;
                }
            }
        }
    }
    let mut live = Vec::with_capacity(n + 1);
    let mut cur = 0;
    for d in &delta {
        cur += d;
        live.push(cur);
    }
    let cuts: HashSet<usize> = cut_positions(&live, every).into_iter().collect();
    let mut out = Vec::with_capacity(n + cuts.len());
    for (i, st) in stmts.into_iter().enumerate() {
        if cuts.contains(&i) {
            out.push(Statement {
                pattern: TokenStream::new(),
                value: boundary(),
                binds: Vec::new(),
                reads: Vec::new(),
                kind: Kind::Boundary,
            });
        }
        out.push(st);
    }
    out
}

/// Where [`with_boundaries`] cuts `live.len() - 1` statements, `live[i]` values being live before
/// statement `i`: one cut about every `every` statements, each at the fewest live values within
/// `every / 4` of where it would fall (the nearer on a tie), the next `every` after it, and none
/// within `every / 2` of the end.
fn cut_positions(live: &[i64], every: usize) -> Vec<usize> {
    let n = live.len().saturating_sub(1);
    let mut cuts = Vec::new();
    let mut at = every;
    while every > 0 && at + every / 2 < n {
        let window = at - every / 4..(at + every / 4).min(n - 1);
        let best = window
            .min_by_key(|&i| (live[i], i.abs_diff(at)))
            .unwrap_or(at);
        cuts.push(best);
        at = best + every;
    }
    cuts
}

#[cfg(test)]
mod tests {
    use super::cut_positions;

    #[test]
    fn cuts_fall_where_fewest_values_are_live_near_each_place() {
        // 1,000 statements, 30 values live everywhere but a dip to 3 at 190 and to 5 at 430
        // (and a deeper one at 260, outside every window: 200 ± 50 and then 390 ± 50).
        let mut live = vec![30_i64; 1001];
        live[190] = 3;
        live[260] = 1;
        live[430] = 5;
        let cuts = cut_positions(&live, 200);
        assert_eq!(cuts[..2], [190, 430]);
        // Flat elsewhere: the place itself, then every 200, none in the last 100.
        assert_eq!(cuts[2..], [630, 830]);
    }

    #[test]
    fn short_functions_are_not_cut() {
        assert!(cut_positions(&[4; 101], 80).is_empty());
        assert_eq!(cut_positions(&[4; 201], 80), [80]);
        assert!(cut_positions(&[], 80).is_empty());
    }
}
