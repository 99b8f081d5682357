//! Smoothed differentiation of sampled signals, and the conversion of `(q, q̇, q̈)` to `(v, v̇)`.
//!
//! # Savitzky–Golay on the actual sample times
//!
//! [`SavitzkyGolay`] fits, around each sample `i`, a polynomial of degree `p` by least squares
//! to the `2k + 1` samples `i − k ..= i + k` and returns its value, first and second derivative
//! at `t_i` (Savitzky & Golay, "Smoothing and differentiation of data by simplified least
//! squares procedures", Analytical Chemistry 36(8), 1964). Savitzky and Golay tabulate the
//! weights for uniform sampling; here the fit is done on the **actual times** of each window,
//! so non-uniform sampling needs no resampling (the local polynomial regression of Cleveland
//! 1979 with a flat kernel). On a uniform grid the result is the classic filter.
//!
//! The fit is written in the scaled time `s = (t − t_i)/h`, `h = max(t_{i+k} − t_i,
//! t_i − t_{i−k})`, so `s ∈ [−1, 1]`, on the Legendre polynomials `P_0 … P_p` in `s` rather than
//! the monomials: their Gram matrix `G_mn = Σ_j P_m(s_j)·P_n(s_j)` over a window is close to
//! diagonal (it is exactly the quadrature of their orthogonality relation on a uniform grid),
//! so the normal equations stay well conditioned up to the largest degree offered
//! ([`SavitzkyGolay::MAX_DEGREE`]). `G` is factored by Cholesky once per window and gives the
//! weights `w_d,j = P(s_j)ᵀ·G⁻¹·P⁽ᵈ⁾(0) / h^d` of the value (`d = 0`) and the two derivatives,
//! applied to every column of the window: the cost is `O((2k + 1)·(p + 1)·(p + columns))` per
//! sample, and no storage grows with the window, so it runs without an allocator.
//!
//! What to expect (Savitzky & Golay 1964; proved again by the tests): the fit reproduces every
//! polynomial of degree ≤ `p` exactly, so on a smooth signal sampled every `Δ` with a fixed
//! number of samples per window the error of derivative `d` is `O(Δ^(p+1−d))` (one order more
//! for `p + 1 − d` odd on a uniform grid, where the symmetric window cancels it); white noise
//! of deviation `σ` leaves `σ·‖w_d‖₂` in derivative `d`, which falls as the window widens.
//! Derivatives of order `d > p` are zero.
//!
//! The first and last `k` samples have no full window and get no estimate
//! ([`SavitzkyGolay::centres`]).
//!
//! # Crates looked at
//! `savgol-rs` 0.1 (one release, 2023) follows SciPy's `savgol_filter`: uniform spacing only,
//! one column, a smoothing mode for the edges, nalgebra 0.32; `scirs2-interpolate`'s
//! `SavitzkyGolayFilter` is also uniform-only and brings ndarray and the SciRS2 stack. Neither
//! takes sample times, so this module writes the fit itself.
//!
//! # From `(q, q̇, q̈)` to `(v, v̇)`
//! [`velocities`] turns the derivatives of the positions into the chain's velocities and their
//! rates, joint by joint after [`Chain::COORDINATES`](crate::Chain::COORDINATES):
//! - [`Coordinates::Vector`]: `v = q̇`, `v̇ = q̈`.
//! - [`Coordinates::Quaternion`] `q = [w, x, y, z]`, the child's orientation in the joint frame
//!   (Hamilton product, `R(q)` maps child to joint coordinates): the body angular velocity
//!   satisfies `q̇ = ½·q ⊗ (0, ω)`, so for a unit `q`, `ω = 2·Im(q̄ ⊗ q̇)`. Differentiating once
//!   more, `q̄ ⊗ q̈ = ½·(q̄ ⊗ q̇) ⊗ (0, ω) + ½·(0, ω̇) = −¼|ω|² + ½·(0, ω̇)` (a pure quaternion
//!   times itself is `−|ω|²`, real), so `ω̇ = 2·Im(q̄ ⊗ q̈)`. A sampled, smoothed quaternion is
//!   not exactly unit: with `q = n·q̂`, `n = |q|`, the same algebra gives `ω = 2·Im(q̂̄ ⊗ q̇)/n`
//!   and `ω̇ = (2·Im(q̂̄ ⊗ q̈) − 2ṅ·ω)/n` with `ṅ = q̂·q̇`, exact for any scaling of a unit
//!   trajectory. The position returned is `q̂`.
//! - [`Coordinates::FreeQuaternion`] `q = [p; quaternion]`, `p` the child origin in the joint
//!   frame, velocities `[v; ω]` in the child frame: the quaternion part as above, and
//!   `v = Rᵀ·ṗ`, `v̇ = Rᵀ·p̈ + Ṙᵀ·ṗ = Rᵀ·p̈ − ω × v` (`Ṙ = R·[ω]×`).

// Index loops mirror the sums they implement.
#![allow(clippy::needless_range_loop)]

use core::fmt;
use core::ops::Range;

use articulated_dynamics::spatial::{Mat3, Vec3};

use crate::configuration::{conjugate, cross, joints, quat_mul};
use crate::Coordinates;

/// `(Σ nq, Σ nv)` of a chain's coordinates (the one in [`crate::configuration`]).
pub use crate::configuration::dimensions;

/// Why a differentiation could not be done. Indices are sample indices (0 based) into the
/// arrays given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DifferentiateError {
    /// Fewer samples than one window.
    TooFewSamples {
        /// Samples given.
        samples: usize,
        /// Samples in one window, `2k + 1`.
        window: usize,
    },
    /// `p + 1 > 2k + 1`: more polynomial coefficients than samples in a window.
    DegreeTooHigh {
        /// The degree `p`.
        degree: usize,
        /// Samples in one window, `2k + 1`.
        window: usize,
    },
    /// The degree is above [`SavitzkyGolay::MAX_DEGREE`].
    DegreeAboveMax {
        /// The degree asked for.
        degree: usize,
    },
    /// A time is NaN or infinite.
    TimeNotFinite {
        /// The sample.
        index: usize,
    },
    /// `t[index] ≤ t[index − 1]`.
    TimesNotIncreasing {
        /// The first sample whose time is not above its predecessor's.
        index: usize,
    },
    /// A sample value is NaN or infinite.
    SampleNotFinite {
        /// The sample.
        index: usize,
        /// Its column.
        column: usize,
    },
    /// The values are not `times × columns` long.
    LengthMismatch {
        /// Number of times.
        times: usize,
        /// Number of values.
        values: usize,
        /// Columns per sample.
        columns: usize,
    },
    /// An output slice does not have `columns` entries.
    OutputLength {
        /// Its length.
        found: usize,
        /// Columns per sample.
        columns: usize,
    },
    /// The sample has no full window around it: it is not in [`SavitzkyGolay::centres`].
    NoWindow {
        /// The sample.
        index: usize,
    },
    /// The window's times are so unevenly spread that the least-squares fit is numerically
    /// singular (a Cholesky pivot fell below `1e-12` of its diagonal).
    IllConditioned {
        /// The centre sample of the window.
        index: usize,
    },
}

impl fmt::Display for DifferentiateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            DifferentiateError::TooFewSamples { samples, window } => write!(
                f,
                "{samples} samples, fewer than one differentiation window of {window}"
            ),
            DifferentiateError::DegreeTooHigh { degree, window } => write!(
                f,
                "a polynomial of degree {degree} has more coefficients than the {window} samples \
                 of a window"
            ),
            DifferentiateError::DegreeAboveMax { degree } => write!(
                f,
                "polynomial degree {degree} is above the largest supported, {}",
                SavitzkyGolay::MAX_DEGREE
            ),
            DifferentiateError::TimeNotFinite { index } => {
                write!(f, "the time of sample {index} is not finite")
            }
            DifferentiateError::TimesNotIncreasing { index } => write!(
                f,
                "the time of sample {index} is not after the time of sample {}",
                index.saturating_sub(1)
            ),
            DifferentiateError::SampleNotFinite { index, column } => {
                write!(f, "sample {index}, column {column} is not finite")
            }
            DifferentiateError::LengthMismatch {
                times,
                values,
                columns,
            } => write!(
                f,
                "{values} values for {times} times of {columns} columns (expected {})",
                times.saturating_mul(columns)
            ),
            DifferentiateError::OutputLength { found, columns } => {
                write!(f, "an output slice has {found} entries, expected {columns}")
            }
            DifferentiateError::NoWindow { index } => {
                write!(
                    f,
                    "sample {index} has no full differentiation window around it"
                )
            }
            DifferentiateError::IllConditioned { index } => write!(
                f,
                "the sample times around sample {index} are too uneven for the polynomial fit"
            ),
        }
    }
}

impl core::error::Error for DifferentiateError {}

/// Coefficients per fit at most: [`SavitzkyGolay::MAX_DEGREE`] + 1.
const MAX_COEFFS: usize = SavitzkyGolay::MAX_DEGREE + 1;

/// A Savitzky–Golay differentiator: degree-`p` least-squares polynomials over windows of
/// `2k + 1` samples, fitted on the actual sample times (see the [module docs](self)).
///
/// ```
/// use articulated::differentiate::SavitzkyGolay;
///
/// // y = t² sampled at uneven times: value, slope and curvature at t[2] = 0.25.
/// let t = [0.0, 0.1, 0.25, 0.3, 0.5];
/// let y: Vec<f64> = t.iter().map(|t| t * t).collect();
/// let sg = SavitzkyGolay::new(2, 2)?;
/// let (mut d0, mut d1, mut d2) = ([0.0], [0.0], [0.0]);
/// sg.derivatives_at(&t, &y, 1, 2, &mut d0, &mut d1, &mut d2)?;
/// assert!((d0[0] - 0.0625).abs() < 1e-14 && (d1[0] - 0.5).abs() < 1e-13);
/// assert!((d2[0] - 2.0).abs() < 1e-12);
/// # Ok::<(), articulated::differentiate::DifferentiateError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SavitzkyGolay {
    half_window: usize,
    degree: usize,
}

impl SavitzkyGolay {
    /// The largest polynomial degree offered.
    pub const MAX_DEGREE: usize = 10;

    /// A differentiator with windows of `2·half_window + 1` samples and polynomials of degree
    /// `degree`.
    ///
    /// # Errors
    /// [`DifferentiateError::DegreeTooHigh`] when `degree + 1 > 2·half_window + 1`,
    /// [`DifferentiateError::DegreeAboveMax`] above [`Self::MAX_DEGREE`].
    pub fn new(half_window: usize, degree: usize) -> Result<Self, DifferentiateError> {
        if degree > Self::MAX_DEGREE {
            return Err(DifferentiateError::DegreeAboveMax { degree });
        }
        let window = half_window.saturating_mul(2).saturating_add(1);
        if degree + 1 > window {
            return Err(DifferentiateError::DegreeTooHigh { degree, window });
        }
        Ok(SavitzkyGolay {
            half_window,
            degree,
        })
    }

    /// `k`: samples on each side of the centre.
    pub fn half_window(&self) -> usize {
        self.half_window
    }

    /// `p`: the polynomial degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// `2k + 1`: samples in one window.
    pub fn window(&self) -> usize {
        self.half_window.saturating_mul(2).saturating_add(1)
    }

    /// The samples, out of `samples`, that have a full window and so get an estimate: `k ..
    /// samples − k` (empty when there are fewer samples than a window).
    pub fn centres(&self, samples: usize) -> Range<usize> {
        let k = self.half_window;
        if samples < self.window() {
            k..k
        } else {
            k..samples - k
        }
    }

    /// Checks a whole signal: `t.len()·columns == y.len()`, at least one window of samples,
    /// finite and strictly increasing times, finite values. The first fault found, in sample
    /// order, is returned.
    ///
    /// # Errors
    /// [`DifferentiateError::LengthMismatch`], [`DifferentiateError::TooFewSamples`],
    /// [`DifferentiateError::TimeNotFinite`], [`DifferentiateError::TimesNotIncreasing`],
    /// [`DifferentiateError::SampleNotFinite`].
    pub fn check(&self, t: &[f64], y: &[f64], columns: usize) -> Result<(), DifferentiateError> {
        check_lengths(t, y, columns)?;
        if t.len() < self.window() {
            return Err(DifferentiateError::TooFewSamples {
                samples: t.len(),
                window: self.window(),
            });
        }
        check_range(t, y, columns, 0..t.len())
    }

    /// Value, first and second derivative at sample `index` of the signal `y` (row-major,
    /// `columns` values per sample) sampled at the times `t`, written into `value`, `first`
    /// and `second` (each `columns` long). Checks the window it reads (times finite and
    /// increasing, values finite); allocates nothing.
    ///
    /// # Errors
    /// [`DifferentiateError::LengthMismatch`], [`DifferentiateError::OutputLength`],
    /// [`DifferentiateError::TooFewSamples`], [`DifferentiateError::NoWindow`] when `index` is
    /// not in [`Self::centres`], the faults [`Self::check`] names within the window, and
    /// [`DifferentiateError::IllConditioned`].
    #[allow(clippy::too_many_arguments)]
    pub fn derivatives_at(
        &self,
        t: &[f64],
        y: &[f64],
        columns: usize,
        index: usize,
        value: &mut [f64],
        first: &mut [f64],
        second: &mut [f64],
    ) -> Result<(), DifferentiateError> {
        check_lengths(t, y, columns)?;
        for out in [&*value, &*first, &*second] {
            if out.len() != columns {
                return Err(DifferentiateError::OutputLength {
                    found: out.len(),
                    columns,
                });
            }
        }
        if t.len() < self.window() {
            return Err(DifferentiateError::TooFewSamples {
                samples: t.len(),
                window: self.window(),
            });
        }
        if !self.centres(t.len()).contains(&index) {
            return Err(DifferentiateError::NoWindow { index });
        }
        let k = self.half_window;
        let range = index - k..index + k + 1;
        check_range(t, y, columns, range.clone())?;
        let g = self.weights(t, index)?;
        value.fill(0.0);
        first.fill(0.0);
        second.fill(0.0);
        let n = self.degree + 1;
        let h = scale(t, index, k);
        for j in range {
            let [p, _, _] = legendre(n, (t[j] - t[index]) / h);
            let w = |gd: &[f64; MAX_COEFFS]| (0..n).map(|m| gd[m] * p[m]).sum::<f64>();
            let (w0, w1, w2) = (w(&g[0]), w(&g[1]), w(&g[2]));
            let row = &y[j * columns..(j + 1) * columns];
            for c in 0..columns {
                value[c] += w0 * row[c];
                first[c] += w1 * row[c];
                second[c] += w2 * row[c];
            }
        }
        Ok(())
    }

    /// The three coefficient vectors `g_d = G⁻¹·P⁽ᵈ⁾(0)/h^d` of the window around `index` (its
    /// times already checked).
    fn weights(
        &self,
        t: &[f64],
        index: usize,
    ) -> Result<[[f64; MAX_COEFFS]; 3], DifferentiateError> {
        let k = self.half_window;
        let n = self.degree + 1;
        let h = scale(t, index, k);
        // Gram matrix of the Legendre basis over the window's scaled times.
        let mut g = [[0.0; MAX_COEFFS]; MAX_COEFFS];
        for j in index - k..=index + k {
            let [p, _, _] = legendre(n, (t[j] - t[index]) / h);
            for a in 0..n {
                for b in 0..=a {
                    g[a][b] += p[a] * p[b];
                }
            }
        }
        // Cholesky G = L·Lᵀ in the lower triangle.
        for a in 0..n {
            for b in 0..=a {
                let mut s = g[a][b];
                for c in 0..b {
                    s -= g[a][c] * g[b][c];
                }
                if a == b {
                    // A relative pivot test; NaN fails it too.
                    if s.is_nan() || s <= 1e-12 * g[a][a] {
                        return Err(DifferentiateError::IllConditioned { index });
                    }
                    g[a][a] = libm::sqrt(s);
                } else {
                    g[a][b] = s / g[b][b];
                }
            }
        }
        let rhs = legendre(n, 0.0);
        let mut out = [[0.0; MAX_COEFFS]; 3];
        for (d, (r, o)) in rhs.iter().zip(out.iter_mut()).enumerate() {
            // L·z = r, then Lᵀ·x = z.
            let mut z = [0.0; MAX_COEFFS];
            for a in 0..n {
                let mut s = r[a];
                for c in 0..a {
                    s -= g[a][c] * z[c];
                }
                z[a] = s / g[a][a];
            }
            for a in (0..n).rev() {
                let mut s = z[a];
                for c in a + 1..n {
                    s -= g[c][a] * o[c];
                }
                o[a] = s / g[a][a];
            }
            let hd = match d {
                0 => 1.0,
                1 => h,
                _ => h * h,
            };
            for a in 0..n {
                o[a] /= hd;
            }
        }
        Ok(out)
    }

    /// Value, first and second derivative at every sample with a full window (see
    /// [`Self::centres`]; the first and last `k` samples are dropped).
    ///
    /// # Errors
    /// As [`Self::check`], and [`DifferentiateError::IllConditioned`].
    #[cfg(feature = "alloc")]
    pub fn differentiate(
        &self,
        t: &[f64],
        y: &[f64],
        columns: usize,
    ) -> Result<Derivatives, DifferentiateError> {
        use alloc::vec;
        self.check(t, y, columns)?;
        let centres = self.centres(t.len());
        let len = centres.len() * columns;
        let mut d = Derivatives {
            first_sample: centres.start,
            columns,
            t: t[centres.clone()].to_vec(),
            value: vec![0.0; len],
            first: vec![0.0; len],
            second: vec![0.0; len],
        };
        for (row, i) in centres.enumerate() {
            let r = row * columns..(row + 1) * columns;
            self.derivatives_at(
                t,
                y,
                columns,
                i,
                &mut d.value[r.clone()],
                &mut d.first[r.clone()],
                &mut d.second[r],
            )?;
        }
        Ok(d)
    }
}

/// The result of [`SavitzkyGolay::differentiate`]: one row per sample with a full window,
/// row-major.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, PartialEq)]
pub struct Derivatives {
    /// Index, in the input, of the first row's sample (`k`).
    pub first_sample: usize,
    /// Values per row.
    pub columns: usize,
    /// The rows' times.
    pub t: alloc::vec::Vec<f64>,
    /// The smoothed values.
    pub value: alloc::vec::Vec<f64>,
    /// First derivatives.
    pub first: alloc::vec::Vec<f64>,
    /// Second derivatives.
    pub second: alloc::vec::Vec<f64>,
}

fn check_lengths(t: &[f64], y: &[f64], columns: usize) -> Result<(), DifferentiateError> {
    if t.len().checked_mul(columns) != Some(y.len()) {
        return Err(DifferentiateError::LengthMismatch {
            times: t.len(),
            values: y.len(),
            columns,
        });
    }
    Ok(())
}

fn check_range(
    t: &[f64],
    y: &[f64],
    columns: usize,
    range: Range<usize>,
) -> Result<(), DifferentiateError> {
    let start = range.start;
    for i in range {
        if !t[i].is_finite() {
            return Err(DifferentiateError::TimeNotFinite { index: i });
        }
        if i > start && t[i] <= t[i - 1] {
            return Err(DifferentiateError::TimesNotIncreasing { index: i });
        }
        if let Some(column) = y[i * columns..(i + 1) * columns]
            .iter()
            .position(|x| !x.is_finite())
        {
            return Err(DifferentiateError::SampleNotFinite { index: i, column });
        }
    }
    Ok(())
}

/// `h = max(t_{i+k} − t_i, t_i − t_{i−k})`, so the window's scaled times lie in `[−1, 1]`.
fn scale(t: &[f64], i: usize, k: usize) -> f64 {
    let h = f64::max(t[i + k] - t[i], t[i] - t[i - k]);
    if h > 0.0 {
        h
    } else {
        1.0
    }
}

/// The Legendre polynomials `P_0 … P_{n−1}` at `s` (Bonnet's recurrence `(m + 1)·P_{m+1} =
/// (2m + 1)·s·P_m − m·P_{m−1}`) and their first and second derivatives
/// (`P'_{m+1} = P'_{m−1} + (2m + 1)·P_m`, and the same one order up): `[P, P', P'']`.
fn legendre(n: usize, s: f64) -> [[f64; MAX_COEFFS]; 3] {
    let mut p = [0.0; MAX_COEFFS];
    let mut d1 = [0.0; MAX_COEFFS];
    let mut d2 = [0.0; MAX_COEFFS];
    p[0] = 1.0;
    if n > 1 {
        p[1] = s;
        d1[1] = 1.0;
    }
    for m in 1..n.saturating_sub(1) {
        let mf = m as f64;
        p[m + 1] = ((2.0 * mf + 1.0) * s * p[m] - mf * p[m - 1]) / (mf + 1.0);
        d1[m + 1] = d1[m - 1] + (2.0 * mf + 1.0) * p[m];
        d2[m + 1] = d2[m - 1] + (2.0 * mf + 1.0) * d1[m];
    }
    [p, d1, d2]
}

/// Why [`velocities`] could not convert a configuration's derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinatesError {
    /// A slice's length does not match the coordinates (`Σ nq` for positions, `Σ nv` for
    /// velocities).
    Length {
        /// `"q"`, `"q_dot"`, `"q_ddot"`, `"q_out"`, `"v"` or `"v_dot"`.
        slice: &'static str,
        /// Its length.
        found: usize,
        /// The length the coordinates need.
        expected: usize,
    },
    /// A quaternion is zero or not finite, so it names no rotation.
    DegenerateQuaternion {
        /// The joint, as an index into the coordinates.
        joint: usize,
    },
}

impl fmt::Display for CoordinatesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            CoordinatesError::Length {
                slice,
                found,
                expected,
            } => write!(
                f,
                "`{slice}` has {found} entries, the chain needs {expected}"
            ),
            CoordinatesError::DegenerateQuaternion { joint } => {
                write!(f, "the quaternion of joint {joint} is zero or not finite")
            }
        }
    }
}

impl core::error::Error for CoordinatesError {}

impl CoordinatesError {
    /// The first of `(slice, found, expected)` whose length is off.
    fn lengths<const N: usize>(slices: [(&'static str, usize, usize); N]) -> Result<(), Self> {
        match slices
            .into_iter()
            .find(|(_, found, expected)| found != expected)
        {
            Some((slice, found, expected)) => Err(CoordinatesError::Length {
                slice,
                found,
                expected,
            }),
            None => Ok(()),
        }
    }
}

/// Checks that the coordinates add up to `nq` positions and `nv` velocities.
///
/// # Errors
/// [`CoordinatesError::Length`] for `"q"`, then `"v"`.
pub(crate) fn check_dimensions(
    coordinates: &[Coordinates],
    nq: usize,
    nv: usize,
) -> Result<(), CoordinatesError> {
    let (cq, cv) = dimensions(coordinates);
    CoordinatesError::lengths([("q", nq, cq), ("v", nv, cv)])
}

/// The velocities `v` and their rates `v̇` of a chain from its positions `q` and their first and
/// second time derivatives, joint by joint (formulas in the [module docs](self)). `q_out`
/// receives `q` with each quaternion normalized. Allocates nothing.
///
/// # Errors
/// [`CoordinatesError::Length`] when a slice does not fit the coordinates,
/// [`CoordinatesError::DegenerateQuaternion`] for a zero or non-finite quaternion.
#[allow(clippy::too_many_arguments)]
pub fn velocities(
    coordinates: &[Coordinates],
    q: &[f64],
    q_dot: &[f64],
    q_ddot: &[f64],
    q_out: &mut [f64],
    v: &mut [f64],
    v_dot: &mut [f64],
) -> Result<(), CoordinatesError> {
    let (nq, nv) = dimensions(coordinates);
    CoordinatesError::lengths([
        ("q", q.len(), nq),
        ("q_dot", q_dot.len(), nq),
        ("q_ddot", q_ddot.len(), nq),
        ("q_out", q_out.len(), nq),
        ("v", v.len(), nv),
        ("v_dot", v_dot.len(), nv),
    ])?;
    for (joint, (c, iq, iv)) in joints(coordinates).enumerate() {
        match c {
            Coordinates::Vector(n) => {
                q_out[iq..iq + n].copy_from_slice(&q[iq..iq + n]);
                v[iv..iv + n].copy_from_slice(&q_dot[iq..iq + n]);
                v_dot[iv..iv + n].copy_from_slice(&q_ddot[iq..iq + n]);
            }
            Coordinates::Quaternion => {
                let Angular { unit, w, w_dot } = angular(
                    joint,
                    quat(&q[iq..]),
                    quat(&q_dot[iq..]),
                    quat(&q_ddot[iq..]),
                )?;
                q_out[iq..iq + 4].copy_from_slice(&unit);
                v[iv..iv + 3].copy_from_slice(&w);
                v_dot[iv..iv + 3].copy_from_slice(&w_dot);
            }
            Coordinates::FreeQuaternion => {
                let Angular { unit, w, w_dot } = angular(
                    joint,
                    quat(&q[iq + 3..]),
                    quat(&q_dot[iq + 3..]),
                    quat(&q_ddot[iq + 3..]),
                )?;
                let r = Mat3::quaternion(unit);
                let lin = r.tr_mul_vec(Vec3(vec3(&q_dot[iq..]))).0;
                let acc = r.tr_mul_vec(Vec3(vec3(&q_ddot[iq..]))).0;
                let wxv = cross(w, lin);
                q_out[iq..iq + 3].copy_from_slice(&q[iq..iq + 3]);
                q_out[iq + 3..iq + 7].copy_from_slice(&unit);
                v[iv..iv + 3].copy_from_slice(&lin);
                v[iv + 3..iv + 6].copy_from_slice(&w);
                for a in 0..3 {
                    v_dot[iv + a] = acc[a] - wxv[a];
                }
                v_dot[iv + 3..iv + 6].copy_from_slice(&w_dot);
            }
        }
    }
    Ok(())
}

/// A quaternion joint's normalized orientation, angular velocity and its rate.
struct Angular {
    unit: [f64; 4],
    w: [f64; 3],
    w_dot: [f64; 3],
}

/// `(q̂, ω, ω̇)` from a quaternion and its two derivatives, `q = n·q̂`.
fn angular(
    joint: usize,
    q: [f64; 4],
    q_dot: [f64; 4],
    q_ddot: [f64; 4],
) -> Result<Angular, CoordinatesError> {
    let n = libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
    if !(n.is_finite() && n > 0.0) {
        return Err(CoordinatesError::DegenerateQuaternion { joint });
    }
    let unit = q.map(|x| x / n);
    let conj = conjugate(unit);
    let n_dot: f64 = (0..4).map(|a| unit[a] * q_dot[a]).sum();
    let a = quat_mul(conj, q_dot);
    let b = quat_mul(conj, q_ddot);
    let w = [2.0 * a[1] / n, 2.0 * a[2] / n, 2.0 * a[3] / n];
    let w_dot = [
        (2.0 * b[1] - 2.0 * n_dot * w[0]) / n,
        (2.0 * b[2] - 2.0 * n_dot * w[1]) / n,
        (2.0 * b[3] - 2.0 * n_dot * w[2]) / n,
    ];
    Ok(Angular { unit, w, w_dot })
}

fn quat(s: &[f64]) -> [f64; 4] {
    [s[0], s[1], s[2], s[3]]
}

fn vec3(s: &[f64]) -> [f64; 3] {
    [s[0], s[1], s[2]]
}
