//! Ground truth: the reference recursions evaluated in double-double arithmetic (about 32
//! significant digits), so that the error of `f64` and `f32` code, generated or not, is measured
//! rather than assumed.
//!
//! [`Dd`] is a [`Scalar`]: the sum of two non-overlapping `f64`s, with the error-free
//! transformations of Dekker (1971) and the double-double algorithms of Joldes, Muller & Popescu
//! (2017): within a few units of 2⁻¹⁰⁶ per operation. It is written here rather than taken from
//! the `twofloat` crate, whose division and functions are only about as exact as `f64`'s
//! (measured: `1/3` with a zero low word, `sin`, `cos` and `sqrt` 1e-17 relative, the cosine
//! of `π/2` rounded to `f64` wrong in its first digit), which would make the ground truth no
//! truer than what it measures. The sine and cosine reduce the angle by `π/2` held in three
//! `f64`s and sum their Taylor series; the square root takes one Newton step from `f64`'s, the
//! residual computed exactly. The tests (`dynamics/tests/extended.rs`) hold them to `mpmath`
//! values and every recursion on `Dd` to closed forms, to 1e-28.
//!
//! [`GroundTruth`] is [`crate::reference::Reference`] on `Dd`: the model's numbers (each an
//! `f64`, taken as exact) are lifted before anything is computed, so the tree's rotations, its
//! inertias about the joint frames and every recursion keep 32 digits.

use alloc::vec::Vec;
use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::model::Model;
use crate::reference::{aba, check_model, check_q, check_vector, crba, ltdl_solve, rnea};
use crate::reference::{Error, Tree};
use crate::Scalar;

/// A double-double number: `hi + lo` with `|lo| ≤ ulp(hi)/2`, about 32 significant digits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    hi: f64,
    lo: f64,
}

/// `a + b` exactly, as `(sum, error)` (Knuth's two-sum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b` exactly for `|a| ≥ |b|` (Dekker's fast two-sum).
fn fast_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

/// `x` split into two halves of 26 bits each (Veltkamp), so that their products are exact.
fn split(x: f64) -> (f64, f64) {
    const FACTOR: f64 = 134_217_729.0; // 2²⁷ + 1
    let t = FACTOR * x;
    let hi = t - (t - x);
    (hi, x - hi)
}

/// `a·b` exactly, as `(product, error)` (Dekker's two-product, no fused multiply–add needed).
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

impl Dd {
    /// The nearest `f64`.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// The leading part.
    pub fn hi(self) -> f64 {
        self.hi
    }

    /// The trailing part.
    pub fn lo(self) -> f64 {
        self.lo
    }

    /// `|self|`.
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 {
            -self
        } else {
            self
        }
    }

    /// Whether both parts are finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// `x − self`, exact as far as double-double goes: the error of an approximation `x` (an
    /// `f64`, or an `f32` widened exactly) of this value.
    pub fn error_of(self, x: f64) -> f64 {
        (Dd::from_f64(x) - self).to_f64()
    }

    /// `a·b` of two `f64`s, exactly.
    fn product(a: f64, b: f64) -> Dd {
        let (p, e) = two_prod(a, b);
        Dd { hi: p, lo: e }
    }

    /// `self·b` for an `f64` `b` (Joldes et al. 2017, algorithm 9).
    fn times(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        fast_two_sum(p, self.lo * b + e)
    }
}

impl Add for Dd {
    type Output = Dd;
    /// Joldes et al. 2017, algorithm 6 (the accurate sum).
    fn add(self, rhs: Dd) -> Dd {
        let (sh, sl) = two_sum(self.hi, rhs.hi);
        let (th, tl) = two_sum(self.lo, rhs.lo);
        let v = fast_two_sum(sh, sl + th);
        fast_two_sum(v.hi, tl + v.lo)
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, rhs: Dd) -> Dd {
        self + -rhs
    }
}

impl Mul for Dd {
    type Output = Dd;
    /// Joldes et al. 2017, algorithm 12 without fused multiply–adds.
    fn mul(self, rhs: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, rhs.hi);
        fast_two_sum(p, e + (self.hi * rhs.lo + self.lo * rhs.hi))
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three `f64` quotient digits, each remainder exact to double-double.
    fn div(self, rhs: Dd) -> Dd {
        let q1 = self.hi / rhs.hi;
        let r = self - rhs.times(q1);
        let q2 = r.hi / rhs.hi;
        let r = r - rhs.times(q2);
        let q3 = r.hi / rhs.hi;
        fast_two_sum(q1, q2) + Dd::from_f64(q3)
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

/// `π/2` as the sum of three `f64`s (to about 160 bits), for the reduction of an angle.
const HALF_PI: [f64; 3] = [
    core::f64::consts::FRAC_PI_2,
    6.123233995736766e-17,
    -1.4973849048591698e-33,
];

/// Terms of the Taylor series summed: the reduced angle is at most `π/4` (0.79), and
/// `0.79³¹/31!` is below 1e-36.
const TAYLOR_TERMS: usize = 15;

/// `(sin r, cos r)` for `|r| ≤ π/4` by their Taylor series, in double-double.
fn sin_cos_reduced(r: Dd) -> (Dd, Dd) {
    let r2 = r * r;
    // Horner from the highest term: sin r = r·(1 − r²/(2·3)·(1 − r²/(4·5)·(…))).
    let (mut s, mut c) = (Dd::one(), Dd::one());
    for k in (1..=TAYLOR_TERMS).rev() {
        let n = (2 * k) as f64;
        s = Dd::one() - r2 * s / Dd::from_f64(n * (n + 1.0));
        c = Dd::one() - r2 * c / Dd::from_f64((n - 1.0) * n);
    }
    (r * s, c)
}

impl Scalar for Dd {
    fn from_f64(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }

    /// Reduces `x` to `r = x − k·π/2`, `|r| ≤ π/4` (the product `k·π/2` exact to about 150
    /// bits for `|k| < 2²⁰`, angles up to a million radians), then the series and the quadrant.
    fn sin_cos(self) -> (Self, Self) {
        let k = libm::round(self.to_f64() / HALF_PI[0]);
        let r = self
            - Dd::product(k, HALF_PI[0])
            - Dd::product(k, HALF_PI[1])
            - Dd::product(k, HALF_PI[2]);
        let (s, c) = sin_cos_reduced(r);
        // k mod 4, for negative k too.
        match (k as i64).rem_euclid(4) {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }

    /// One Newton step from `f64`'s root `y`: `y + (x − y²)/(2y)`, with `x − y²` exact to
    /// double-double, which doubles the digits.
    fn sqrt(self) -> Self {
        let x = self.to_f64();
        if x <= 0.0 {
            // Zero (or a negative rounding of it) stays zero; a real negative argument has no
            // real root, and NaN says so as f64's does.
            return if x == 0.0 {
                Dd::zero()
            } else {
                Dd::from_f64(f64::NAN)
            };
        }
        let y = libm::sqrt(x);
        let residual = self - Dd::product(y, y);
        Dd::from_f64(y) + residual / Dd::from_f64(2.0 * y)
    }
}

/// The reference dynamics of one model in double-double ([`Dd`]); the same checks and
/// algorithms as [`crate::reference::Reference`], which the generated code is held to.
#[derive(Debug, Clone)]
pub struct GroundTruth {
    model: Model,
    tree: Tree<Dd>,
}

impl GroundTruth {
    /// The ground truth of `model` with its parameters at their default values.
    ///
    /// # Errors
    /// As [`crate::reference::Reference::new`].
    pub fn new(model: &Model) -> Result<Self, Error> {
        Self::with_params(model, &model.param_defaults())
    }

    /// The ground truth of `model` with the parameter values `params`.
    ///
    /// # Errors
    /// As [`crate::reference::Reference::with_params`].
    pub fn with_params(model: &Model, params: &[f64]) -> Result<Self, Error> {
        check_model(model, params)?;
        let params: Vec<Dd> = params.iter().map(|&p| Dd::from_f64(p)).collect();
        Ok(GroundTruth {
            model: model.clone(),
            tree: Tree::new(model, &params),
        })
    }

    /// The tree the recursions run on.
    pub fn tree(&self) -> &Tree<Dd> {
        &self.tree
    }

    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        self.tree.nv
    }

    fn lift(x: &[f64]) -> Vec<Dd> {
        x.iter().map(|&x| Dd::from_f64(x)).collect()
    }

    /// `M(q)`, row-major, by CRBA.
    ///
    /// # Errors
    /// For a `q` the reference refuses.
    pub fn mass_matrix(&self, q: &[f64]) -> Result<Vec<Dd>, Error> {
        check_q(&self.model, q)?;
        Ok(crba(&self.tree, &Self::lift(q)))
    }

    /// `τ = M·a + N·q̇ + g` by RNEA (`with_gravity: false` leaves `g` out; `a = 0` gives the
    /// bias or, with `v = 0` too, gravity).
    ///
    /// # Errors
    /// For inputs the reference refuses.
    pub fn inverse_dynamics(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        with_gravity: bool,
    ) -> Result<Vec<Dd>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        let (q, v, a) = (Self::lift(q), Self::lift(v), Self::lift(a));
        Ok(rnea(&self.tree, &q, &v, &a, with_gravity))
    }

    /// `q̈` by ABA, with its pivots (`D_i`, one per velocity coordinate).
    ///
    /// # Errors
    /// For inputs the reference refuses. A singular `M` is not an error here: its pivots say so.
    pub fn forward_dynamics(
        &self,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
    ) -> Result<(Vec<Dd>, Vec<Dd>), Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("tau", tau, self.nv())?;
        let out = aba(
            &self.tree,
            &Self::lift(q),
            &Self::lift(v),
            &Self::lift(tau),
            true,
        );
        Ok((out.qdd, out.pivots))
    }

    /// `q̈` by ABA at a state already in double-double (no checks: a step of an integration
    /// whose start [`GroundTruth::forward_dynamics`] checked). The lengths must be the model's.
    pub fn acceleration(&self, q: &[Dd], v: &[Dd], tau: &[Dd]) -> Vec<Dd> {
        aba(&self.tree, q, v, tau, true).qdd
    }

    /// `q̈` by CRBA, RNEA and `LᵀDL`: the second way to the same value, to check the first.
    ///
    /// # Errors
    /// As [`GroundTruth::forward_dynamics`].
    pub fn forward_dynamics_ltdl(
        &self,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
    ) -> Result<Vec<Dd>, Error> {
        let zero = alloc::vec![0.0; self.nv()];
        let h = self.inverse_dynamics(q, v, &zero, true)?;
        check_vector("tau", tau, self.nv())?;
        let b: Vec<Dd> = tau
            .iter()
            .zip(&h)
            .map(|(&t, &h)| Dd::from_f64(t) - h)
            .collect();
        let m = self.mass_matrix(q)?;
        Ok(ltdl_solve(m, b, self.nv()).0)
    }
}

/// `max_i |approx_i − truth_i| / max_i |truth_i|`: the normwise relative error of `approx`
/// (`f64`, or `f32` widened exactly) against ground truth; the absolute error where the truth
/// is zero. Infinite when `approx` has a non-finite entry.
pub fn relative_error(approx: &[f64], truth: &[Dd]) -> f64 {
    let scale = truth.iter().fold(0.0f64, |m, t| m.max(t.to_f64().abs()));
    let err = approx
        .iter()
        .zip(truth)
        .fold(0.0f64, |m, (&x, t)| match x.is_finite() {
            true => m.max(t.error_of(x).abs()),
            false => f64::INFINITY,
        });
    if scale > 0.0 {
        err / scale
    } else {
        err
    }
}
