//! The inverse plant (Hemami, Dariush & Barin 2005, §5): the joint couples behind a sampled
//! motion.
//!
//! From positions `q(t_i)` sampled at increasing (not necessarily uniform) times:
//! 1. [`SavitzkyGolay`] gives the smoothed `q`, `q̇` and `q̈` at every sample with a full
//!    window; the first and last `k` samples (`k` the half window) get no estimate and are
//!    dropped;
//! 2. [`velocities`] turns them into the chain's `v` and `v̇` (quaternions normalized, body
//!    angular velocities; see [`crate::differentiate`]);
//! 3. an inverse-dynamics closure `(q, v, a) ↦ τ` gives the couples: a generated chain's
//!    `C::inverse_dynamics`, or the reference's `inverse_dynamics` through [`couples_dyn`].
//!
//! The result is `t_i, τ_i` for the samples kept, in order. Every input is checked before the
//! first couple is computed (lengths, one window at least, finite and increasing times, finite
//! positions), so a fault is reported before any output is produced. [`invert`] allocates
//! nothing (it hands each couple to a sink); [`couples`] and [`couples_dyn`] collect them.
//!
//! Accuracy: with noise-free samples the couple error is the differentiation error, `O(Δ^(p−1))`
//! in `q̈` for a degree-`p` fit with a fixed window in samples; noise of deviation `σ` on `q`
//! adds about `σ·‖w₂‖₂` to `q̈`, with `‖w₂‖₂ ∝ 1/(K^(5/2)·Δ²)` for a window of `K` samples
//! spaced `Δ`. The table measured on Hemami's two-link system is printed by `cargo test -p
//! articulated --test samples -- --nocapture noise_table`.

use core::convert::Infallible;
use core::fmt;

use nalgebra::allocator::Allocator;
#[cfg(feature = "alloc")]
use nalgebra::Dyn;
use nalgebra::{Const, DefaultAllocator, Dim, OVector, SVector, U1};

use crate::differentiate::{
    check_dimensions, velocities, CoordinatesError, DifferentiateError, SavitzkyGolay,
};
use crate::Coordinates;

/// Why an inversion failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InvertError<E = Infallible> {
    /// The samples cannot be differentiated (too few, bad times or values; see the variant).
    Differentiate(DifferentiateError),
    /// The coordinates do not match the sizes, or a sampled quaternion is degenerate.
    Coordinates(CoordinatesError),
    /// The inverse-dynamics closure failed at this sample.
    Dynamics {
        /// The sample (index into the input).
        index: usize,
        /// The closure's error.
        error: E,
    },
    /// The inverse dynamics returned a non-finite couple at this sample.
    NotFinite {
        /// The sample (index into the input).
        index: usize,
    },
}

impl<E> From<DifferentiateError> for InvertError<E> {
    fn from(e: DifferentiateError) -> Self {
        InvertError::Differentiate(e)
    }
}

impl<E> From<CoordinatesError> for InvertError<E> {
    fn from(e: CoordinatesError) -> Self {
        InvertError::Coordinates(e)
    }
}

impl<E: fmt::Display> fmt::Display for InvertError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InvertError::Differentiate(e) => write!(f, "{e}"),
            InvertError::Coordinates(e) => write!(f, "{e}"),
            InvertError::Dynamics { index, error } => {
                write!(f, "inverse dynamics at sample {index}: {error}")
            }
            InvertError::NotFinite { index } => {
                write!(f, "the couples at sample {index} are not finite")
            }
        }
    }
}

impl<E: fmt::Debug + fmt::Display> core::error::Error for InvertError<E> {}

/// Checks the sizes and the whole signal (so that a fault comes before any couple), then hands
/// `(i, t_i, q̂_i, v_i, v̇_i)` to `each` for every sample `i` with a full window, in order. The
/// sizes `(nq, nv)` are `Const` (nothing allocated) or `Dyn`.
fn each_state<Q: Dim, V: Dim, E, F>(
    coordinates: &[Coordinates],
    (nq, nv): (Q, V),
    t: &[f64],
    q: &[f64],
    sg: &SavitzkyGolay,
    mut each: F,
) -> Result<(), InvertError<E>>
where
    F: FnMut(
        usize,
        f64,
        &OVector<f64, Q>,
        &OVector<f64, V>,
        &OVector<f64, V>,
    ) -> Result<(), InvertError<E>>,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    check_dimensions(coordinates, nq.value(), nv.value())?;
    sg.check(t, q, nq.value())?;
    let zeros_q = || OVector::<f64, Q>::zeros_generic(nq, U1);
    let zeros_v = || OVector::<f64, V>::zeros_generic(nv, U1);
    let (mut value, mut first, mut second, mut q_hat) =
        (zeros_q(), zeros_q(), zeros_q(), zeros_q());
    let (mut v, mut a) = (zeros_v(), zeros_v());
    let centres = sg.centres(t.len());
    for (i, &time) in t.iter().enumerate().skip(centres.start).take(centres.len()) {
        sg.derivatives_at(
            t,
            q,
            nq.value(),
            i,
            value.as_mut_slice(),
            first.as_mut_slice(),
            second.as_mut_slice(),
        )?;
        velocities(
            coordinates,
            value.as_slice(),
            first.as_slice(),
            second.as_slice(),
            q_hat.as_mut_slice(),
            v.as_mut_slice(),
            a.as_mut_slice(),
        )?;
        each(i, time, &q_hat, &v, &a)?;
    }
    Ok(())
}

/// [`InvertError::NotFinite`] at sample `i` unless every couple in `tau` is finite.
fn finite<E>(i: usize, tau: &[f64]) -> Result<(), InvertError<E>> {
    if tau.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(InvertError::NotFinite { index: i })
    }
}

/// The couples `τ_i = ID(q_i, v_i, v̇_i)` at every sample with a full window, handed in order to
/// `sink(i, t_i, τ_i)` (`i` the sample's index in the input). `q` holds the positions
/// row-major, `NQ` per sample; `coordinates` are the chain's ([`Chain::COORDINATES`]). For a
/// generated chain `C`, `inverse_dynamics` is `|q, v, a| C::inverse_dynamics(q, v, a)`.
/// Allocates nothing.
///
/// [`Chain::COORDINATES`]: crate::Chain::COORDINATES
///
/// # Errors
/// [`InvertError::Coordinates`] when the coordinates do not add up to `NQ`, `NV` or a
/// quaternion sample is degenerate; [`InvertError::Differentiate`] for samples that cannot be
/// differentiated (all checked before the first couple); [`InvertError::NotFinite`].
pub fn invert<const NQ: usize, const NV: usize, F, S>(
    coordinates: &[Coordinates],
    t: &[f64],
    q: &[f64],
    sg: &SavitzkyGolay,
    mut inverse_dynamics: F,
    mut sink: S,
) -> Result<(), InvertError>
where
    F: FnMut(&SVector<f64, NQ>, &SVector<f64, NV>, &SVector<f64, NV>) -> SVector<f64, NV>,
    S: FnMut(usize, f64, &SVector<f64, NV>),
{
    each_state(
        coordinates,
        (Const::<NQ>, Const::<NV>),
        t,
        q,
        sg,
        |i, time, q, v, a| {
            let tau = inverse_dynamics(q, v, a);
            finite(i, tau.as_slice())?;
            sink(i, time, &tau);
            Ok(())
        },
    )
}

/// Couples recovered from a sampled motion: one row per sample kept, row-major.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, PartialEq)]
pub struct Couples {
    /// Index, in the input, of the first row's sample (the half window `k`).
    pub first_sample: usize,
    /// Couples per row (`NV`).
    pub nv: usize,
    /// The rows' times.
    pub t: alloc::vec::Vec<f64>,
    /// The couples, `t.len()·nv` values.
    pub tau: alloc::vec::Vec<f64>,
}

#[cfg(feature = "alloc")]
impl Couples {
    /// The couples of row `row`, or `None` past the end.
    pub fn row(&self, row: usize) -> Option<&[f64]> {
        self.tau.get(row * self.nv..(row + 1) * self.nv)
    }
}

/// [`invert`], collecting the couples.
///
/// # Errors
/// As [`invert`].
#[cfg(feature = "alloc")]
pub fn couples<const NQ: usize, const NV: usize, F>(
    coordinates: &[Coordinates],
    t: &[f64],
    q: &[f64],
    sg: &SavitzkyGolay,
    inverse_dynamics: F,
) -> Result<Couples, InvertError>
where
    F: FnMut(&SVector<f64, NQ>, &SVector<f64, NV>, &SVector<f64, NV>) -> SVector<f64, NV>,
{
    let rows = sg.centres(t.len()).len();
    let mut out = Couples {
        first_sample: sg.half_window(),
        nv: NV,
        t: alloc::vec::Vec::with_capacity(rows),
        tau: alloc::vec::Vec::with_capacity(rows * NV),
    };
    invert(coordinates, t, q, sg, inverse_dynamics, |_, time, tau| {
        out.t.push(time);
        out.tau.extend_from_slice(tau.as_slice());
    })?;
    Ok(out)
}

/// [`couples`] for sizes known at run time (a model read from a file): `inverse_dynamics(q, v,
/// a, τ)` writes `τ` (`nv` long) or fails with its own error. With the reference, the closure
/// is `|q, v, a, tau| { tau.copy_from_slice(reference.inverse_dynamics(q, v, a)?.as_slice());
/// Ok(()) }`; here a pendulum's closed form stands in for it:
///
/// ```
/// use articulated::differentiate::SavitzkyGolay;
/// use articulated::invert::couples_dyn;
/// use articulated::Coordinates;
///
/// // A point mass of 1 kg on a 1 m rod: τ = q̈ + 9.81·sin q; here q = 0.1·t², so q̈ = 0.2.
/// let t: Vec<f64> = (0..20).map(|i| 0.01 * i as f64).collect();
/// let q: Vec<f64> = t.iter().map(|t| 0.1 * t * t).collect();
/// let sg = SavitzkyGolay::new(3, 2)?;
/// let c = couples_dyn(&[Coordinates::Vector(1)], 1, 1, &t, &q, &sg, |q, _v, a, tau| {
///     tau[0] = a[0] + 9.81 * q[0].sin();
///     Ok::<(), std::convert::Infallible>(())
/// })?;
/// assert_eq!((c.first_sample, c.t.len()), (3, 20 - 2 * 3));
/// assert!((c.tau[0] - (0.2 + 9.81 * q[3].sin())).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`invert`], and [`InvertError::Dynamics`] with the closure's error and the sample.
#[cfg(feature = "alloc")]
#[allow(clippy::too_many_arguments)]
pub fn couples_dyn<F, E>(
    coordinates: &[Coordinates],
    nq: usize,
    nv: usize,
    t: &[f64],
    q: &[f64],
    sg: &SavitzkyGolay,
    mut inverse_dynamics: F,
) -> Result<Couples, InvertError<E>>
where
    F: FnMut(&[f64], &[f64], &[f64], &mut [f64]) -> Result<(), E>,
{
    let centres = sg.centres(t.len());
    let mut out = Couples {
        first_sample: centres.start,
        nv,
        t: alloc::vec::Vec::with_capacity(centres.len()),
        // Sized row by row: `nv` is checked first.
        tau: alloc::vec::Vec::new(),
    };
    each_state(
        coordinates,
        (Dyn(nq), Dyn(nv)),
        t,
        q,
        sg,
        |i, time, q, v, a| {
            let row = out.tau.len();
            out.tau.resize(row + nv, 0.0);
            let tau = out.tau.get_mut(row..).unwrap_or_default();
            inverse_dynamics(q.as_slice(), v.as_slice(), a.as_slice(), tau)
                .map_err(|error| InvertError::Dynamics { index: i, error })?;
            finite(i, tau)?;
            out.t.push(time);
            Ok(())
        },
    )?;
    Ok(out)
}
