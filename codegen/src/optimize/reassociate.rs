//! Sums regrouped so that the late terms are added last: a shorter critical path for the same
//! operations.
//!
//! The recursions build their sums in the order the equations are written, and a Newton–Euler
//! sum often adds a body's own, early term to a late one carried along the chain: in
//! `n_p = N_p + E·n_i + r × (E·f_i)` the parent's `N_p` is known long before the child's `n_i`,
//! yet it was added to the terms built from `n_i`. Every such addition lies on the chain from the
//! tip to the root, and the emitted code waits for it. Here each sum of terms (a tree of `+`,
//! `−` and `−x` whose inner nodes feed nothing else) is rebuilt by Huffman's rule on arrival
//! times: the two terms that are ready first are added first, so the latest term is added last,
//! once. The number of additions is unchanged (a sum of `k` terms takes `k − 1` of them whatever
//! the order), and negations are never added (see `rebuild_sum`); hash-consing may find some
//! of the new partial sums already in the graph.
//!
//! Arrival times follow a rough latency model of a current out-of-order core (`Latency`):
//! three cycles for an addition or a product, more for a quotient, a square root or a sine.
//! It only has to rank terms: the real schedule is the CPU's.
//!
//! Floating-point addition is not associative, so the results change by roundings (a few units
//! in the last place of the sum's largest term); the tests hold the generated code to the
//! reference at 1e-12, as before.
//!
//! `reassociate::tests` checks on random trees that the depth of the graphs never grows and
//! mostly shrinks.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, HashSet};

use crate::sym::{Graph, Node, Sym};

/// Assumed latencies, in cycles, of the operations (Zen 4 and recent Intel cores: 3 for
/// `addsd`/`mulsd`, 13 for `divsd`, 15–20 for `sqrtsd`; a sine with its argument reduction is
/// some twenty dependent operations).
struct Latency;

impl Latency {
    const ADD: u32 = 3;
    const MUL: u32 = 3;
    const NEG: u32 = 1;
    const DIV: u32 = 13;
    const SQRT: u32 = 18;
    const TRIG: u32 = 60;
}

/// Rebuilds the part of `graph` that `outputs` need with every sum regrouped by arrival time
/// (see the [module docs](self)), names carried over; returns the new graph and the outputs in
/// it.
///
/// # Panics
/// If an output belongs to another graph.
pub fn reassociate(graph: &Graph, outputs: &[Sym]) -> (Graph, Vec<Sym>) {
    let live = graph.live(outputs);
    let uses = graph.use_counts(outputs);
    // A sum node whose one use is by another sum node is part of that sum, not a term.
    let is_sum = |s: Sym| matches!(graph.node(s), Node::Add(..) | Node::Sub(..) | Node::Neg(_));
    let mut inner: HashSet<Sym> = HashSet::new();
    for &s in &live {
        if is_sum(s) {
            inner.extend(
                graph
                    .node(s)
                    .operands()
                    .filter(|&o| is_sum(o) && uses[&o] == 1),
            );
        }
    }

    // Arrival time of each new node.
    let mut time: HashMap<Sym, u32> = HashMap::with_capacity(live.len());
    let (new_graph, new_outputs, _) = graph.rebuild(outputs, |s, map| {
        if inner.contains(&s) {
            return None;
        }
        let node = graph.node(s);
        let m = |a: Sym| map[&a];
        let t = |a: Sym| time.get(&map[&a]).copied().unwrap_or(0);
        let (n, arrival) = match node {
            Node::Const(_) | Node::Input(_) => (node.remade(m), 0),
            Node::Add(..) | Node::Sub(..) | Node::Neg(_) => {
                let mut terms = Vec::new();
                collect_terms(graph, &inner, s, false, &mut terms);
                let terms: Vec<(Sym, bool, u32)> = terms
                    .into_iter()
                    .map(|(term, negative)| (m(term), negative, t(term)))
                    .collect();
                rebuild_sum(terms, &mut time)
            }
            Node::Mul(a, b) => (node.remade(m), t(a).max(t(b)) + Latency::MUL),
            Node::Div(a, b) => (node.remade(m), t(a).max(t(b)) + Latency::DIV),
            Node::Sin(a) | Node::Cos(a) => (node.remade(m), t(a) + Latency::TRIG),
            Node::Sqrt(a) => (node.remade(m), t(a) + Latency::SQRT),
        };
        time.entry(n).or_insert(arrival);
        Some(n)
    });
    (new_graph, new_outputs)
}

/// The terms of the sum rooted at `s`, each with whether it is subtracted (`negative` flips
/// the sign of the whole of `s`), through the inner sum nodes.
fn collect_terms(
    graph: &Graph,
    inner: &HashSet<Sym>,
    s: Sym,
    negative: bool,
    terms: &mut Vec<(Sym, bool)>,
) {
    let part = |x: Sym, negative: bool, terms: &mut Vec<(Sym, bool)>| {
        if inner.contains(&x) {
            collect_terms(graph, inner, x, negative, terms);
        } else {
            terms.push((x, negative));
        }
    };
    match graph.node(s) {
        Node::Add(a, b) => {
            part(a, negative, terms);
            part(b, negative, terms);
        }
        Node::Sub(a, b) => {
            part(a, negative, terms);
            part(b, !negative, terms);
        }
        Node::Neg(a) => part(a, !negative, terms),
        _ => terms.push((s, negative)),
    }
}

/// `Σ ±terms` built by adding the two earliest partial results first, with the arrival time
/// of each new node recorded in `time`; returns the sum and its arrival time.
///
/// Signs are kept on the partial sums: `a − b` for one of each, `a + b` carrying a minus for
/// two subtracted ones, so a sum with at least one added term needs no negation; a sum of
/// subtracted terms only (whose original had a negation too: without one, the leftmost term of
/// a tree of `+` and `−` is added) gets one at the end.
fn rebuild_sum(terms: Vec<(Sym, bool, u32)>, time: &mut HashMap<Sym, u32>) -> (Sym, u32) {
    // Min-heap on (arrival, order of appearance), so equal times keep the written order.
    let mut heap: BinaryHeap<Reverse<(u32, usize, usize)>> = BinaryHeap::new();
    let mut items: Vec<(Sym, bool)> = Vec::with_capacity(2 * terms.len());
    for (sym, negative, arrival) in terms {
        heap.push(Reverse((arrival, items.len(), items.len())));
        items.push((sym, negative));
    }
    loop {
        // `rebuild_sum` is only called on a sum (two terms or more), and each round takes two
        // and gives back one.
        #[allow(clippy::expect_used)]
        let Reverse((t1, _, i)) = heap.pop().expect("a sum has at least one term");
        let Some(Reverse((t2, _, j))) = heap.pop() else {
            let (sym, negative) = items[i];
            return if negative {
                let n = -sym;
                let t = t1 + Latency::NEG;
                time.entry(n).or_insert(t);
                (n, t)
            } else {
                (sym, t1)
            };
        };
        let ((a, na), (b, nb)) = (items[i], items[j]);
        let combined = match (na, nb) {
            (false, false) => (a + b, false),
            (false, true) => (a - b, false),
            (true, false) => (b - a, false),
            (true, true) => (a + b, true),
        };
        let t = t1.max(t2) + Latency::ADD;
        time.entry(combined.0).or_insert(t);
        heap.push(Reverse((t, items.len(), items.len())));
        items.push(combined);
    }
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::{Reference, Tree};

    use super::*;
    use crate::sym::{trace, Var};
    use crate::trace::crba::crba;
    use crate::trace::newton_euler::classical_rnea;
    use crate::trace::regroup::{coordinate_axis, regroup};

    /// The longest chain of operations from an input to an output, in operations.
    fn depth(graph: &Graph, outputs: &[Sym]) -> usize {
        let mut d: HashMap<Sym, usize> = HashMap::new();
        for s in graph.live(outputs) {
            let node = graph.node(s);
            let own = usize::from(!matches!(node, Node::Const(_) | Node::Input(_)));
            let deepest = node.operands().map(|o| d[&o]).max().unwrap_or(0);
            d.insert(s, deepest + own);
        }
        outputs.iter().map(|s| d[s]).max().unwrap_or(0)
    }

    /// On random trees of every joint kind, for `M` (by the generator's CRBA) and inverse
    /// dynamics (by classical Newton–Euler), regrouped inertias: the rebuilt graph computes the
    /// reference's values to rounding, with no more operations of any kind than the graph it
    /// came from, and a critical path no longer.
    #[test]
    fn same_values_no_more_operations_and_no_deeper() {
        let mut shorter = 0;
        for seed in 0..80u64 {
            let model = random_model(seed, 1 + (seed as usize % 10));
            let reference = Reference::new(&model).unwrap();
            let (q, v, a) = random_state(&model, seed);
            let (nq, nv) = (model.nq(), model.nv());
            for mass_matrix in [false, true] {
                let (graph, values) = trace(|| {
                    let mut tree = Tree::new(&model, &[]);
                    regroup(&mut tree);
                    let qs: Vec<Sym> = (0..nq).map(|i| Sym::input(Var::Q(i))).collect();
                    let vs: Vec<Sym> = (0..nv).map(|i| Sym::input(Var::V(i))).collect();
                    let as_: Vec<Sym> = (0..nv).map(|i| Sym::input(Var::A(i))).collect();
                    if mass_matrix {
                        crba(&tree, &qs, coordinate_axis)
                    } else {
                        classical_rnea(&tree, &qs, &vs, &as_, true)
                    }
                });
                let (new_graph, outputs) = reassociate(&graph, &values);
                let (before, after) = (graph.op_counts(&values), new_graph.op_counts(&outputs));
                let what = if mass_matrix { "M" } else { "tau" };
                assert!(after.adds <= before.adds, "seed {seed} {what}: adds");
                assert!(after.muls <= before.muls, "seed {seed} {what}: muls");
                assert!(after.negs <= before.negs, "seed {seed} {what}: negs");
                let (d0, d1) = (depth(&graph, &values), depth(&new_graph, &outputs));
                assert!(d1 <= d0, "seed {seed} {what}: depth {d0} -> {d1}");
                shorter += usize::from(d1 < d0);

                let input = |var: Var| match var {
                    Var::Q(i) => q[i],
                    Var::V(i) => v[i],
                    Var::A(i) => a[i],
                    other => panic!("unexpected input {other:?}"),
                };
                let got = new_graph.eval(&outputs, input);
                let want: Vec<f64> = if mass_matrix {
                    reference.mass_matrix(&q).unwrap().iter().copied().collect()
                } else {
                    reference
                        .inverse_dynamics(&q, &v, &a)
                        .unwrap()
                        .iter()
                        .copied()
                        .collect()
                };
                let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() <= 1e-12 * scale,
                        "seed {seed} {what}: {g} vs {w}"
                    );
                }
            }
        }
        // Not a tautology: most graphs get shorter.
        assert!(shorter > 80, "only {shorter} of 160 graphs got shorter");
    }
}
