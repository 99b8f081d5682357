//! Batch functions (`C::x_batch`) against the scalar function of the same output, state by
//! state: [`same!`] calls both and compares every entry ([`Flat`]), relative to the largest.
//!
//! The scalar functions are held to the reference by the other tests; this holds the batch to
//! them. States differ from lane to lane, so a lane that reads or writes its neighbour's values,
//! a partial last group padded wrongly or a result left unwritten fails it.

use articulated::nalgebra::{SMatrix, SVector};
use articulated::FramePlacement;

/// Every entry of a result as `f64`, in a fixed order; an `Err` as its velocity, negated
/// (never equal to a value's entries, which are compared with their sign).
pub trait Flat {
    /// The entries.
    fn flat(&self) -> Vec<f64>;
}

impl Flat for f64 {
    fn flat(&self) -> Vec<f64> {
        vec![*self]
    }
}

impl Flat for f32 {
    fn flat(&self) -> Vec<f64> {
        vec![f64::from(*self)]
    }
}

impl<T: Flat + articulated::nalgebra::Scalar, const R: usize, const C: usize> Flat
    for SMatrix<T, R, C>
{
    fn flat(&self) -> Vec<f64> {
        self.iter().flat_map(Flat::flat).collect()
    }
}

impl<T: Flat + articulated::nalgebra::Scalar> Flat for FramePlacement<T> {
    fn flat(&self) -> Vec<f64> {
        let mut v = self.rotation.flat();
        v.extend(self.translation.flat());
        v
    }
}

impl<A: Flat, const K: usize> Flat for [A; K] {
    fn flat(&self) -> Vec<f64> {
        self.iter().flat_map(Flat::flat).collect()
    }
}

impl<A: Flat, B: Flat> Flat for (A, B) {
    fn flat(&self) -> Vec<f64> {
        let mut v = self.0.flat();
        v.extend(self.1.flat());
        v
    }
}

impl<A: Flat, B: Flat, C: Flat> Flat for (A, B, C) {
    fn flat(&self) -> Vec<f64> {
        let mut v = self.0.flat();
        v.extend(self.1.flat());
        v.extend(self.2.flat());
        v
    }
}

impl<A: Flat> Flat for Result<A, articulated::SingularMassMatrix> {
    fn flat(&self) -> Vec<f64> {
        match self {
            Ok(a) => a.flat(),
            Err(e) => vec![f64::NAN, -(e.velocity as f64)],
        }
    }
}

/// The largest difference between two results relative to the largest entry of `want` (1 where
/// that is below 1); an error against a value, or a NaN on either side where the other has
/// none, is infinite.
pub fn difference(got: &[f64], want: &[f64]) -> f64 {
    if got.len() != want.len() {
        return f64::INFINITY;
    }
    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    got.iter()
        .zip(want)
        .map(|(g, w)| match (g.is_nan(), w.is_nan()) {
            (true, true) => 0.0,
            (false, false) => (g - w).abs() / scale,
            _ => f64::INFINITY,
        })
        .fold(0.0, f64::max)
}

/// `n` states of `K` entries in `[-2, 2]` from `seed` (a linear congruential generator: the
/// same on every machine).
pub fn states<const K: usize>(n: usize, seed: u64) -> Vec<SVector<f64, K>> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            SVector::from_fn(|_, _| {
                x = x
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((x >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
            })
        })
        .collect()
}

// Each test crate that includes `common` uses part of it (see `common`).
#[allow(unused_macros)]
/// Calls `C::$batch` on the argument slices and `C::$scalar` on each state, and returns the
/// largest [`difference`] over the states, labelled. The output slice starts filled with state
/// 0's result, so a result the batch leaves unwritten differs for every other state.
macro_rules! same {
    ($c:ty, $scalar:ident, $batch:ident, $($arg:ident),+) => {{
        let first = <$c>::$scalar($(&$arg[0]),+);
        let n = [$($arg.len()),+][0];
        let mut out = vec![first; n];
        <$c>::$batch($(&$arg),+, &mut out).unwrap();
        let worst = (0..n)
            .map(|i| {
                let want = <$c>::$scalar($(&$arg[i]),+);
                common::batch::difference(
                    &common::batch::Flat::flat(&out[i]),
                    &common::batch::Flat::flat(&want),
                )
            })
            .fold(0.0, f64::max);
        (stringify!($scalar), worst)
    }};
}
#[allow(unused_imports)]
pub(crate) use same;

/// Every `(output, difference)` at most `tol`.
pub fn assert_within(label: &str, results: &[(&str, f64)], tol: f64) {
    for (output, d) in results {
        assert!(
            *d <= tol,
            "{label} {output}: batch differs from the scalar function by {d:e}"
        );
    }
}
