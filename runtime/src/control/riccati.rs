//! The continuous-time algebraic Riccati equation and the LQR gain.
//!
//! [`care`] solves `AᵀP + PA − PBR⁻¹BᵀP + Q = 0` for the **stabilizing** solution `P` (the one
//! for which `A − BK`, `K = R⁻¹BᵀP`, has all its eigenvalues in the open left half-plane);
//! [`lqr`] returns `P` and `K`, the gain of `u = −K·x` that minimizes
//! `∫ (xᵀQx + uᵀRu) dt` for `ẋ = Ax + Bu` (Kalman 1960; Anderson & Moore, *Optimal Control:
//! Linear Quadratic Methods*, 1990, §3.3).
//!
//! # Method
//! 1. **Matrix sign function of the Hamiltonian** (Roberts 1971, "Linear model reduction and
//!    solution of the algebraic Riccati equation by use of the sign function", reprinted in Int.
//!    J. Control 32(4), 1980; Byers 1987, "Solving the algebraic Riccati equation with the
//!    matrix sign function", Linear Algebra Appl. 85). With `G = BR⁻¹Bᵀ`,
//!    `H = [[A, −G], [−Q, −Aᵀ]]` satisfies `H·[I; P] = [I; P]·(A − GP)` exactly when `P` solves
//!    the equation, so the stabilizing `P` spans `H`'s stable invariant subspace, on which
//!    `W = sign(H)` is `−I`: `(W + I)·[I; P] = 0`, i.e. `[W₁₂; W₂₂ + I]·P = −[W₁₁ + I; W₂₁]`,
//!    solved by least squares (SVD). `sign(H)` is the limit of Newton's iteration
//!    `Z ← ½(cZ + (cZ)⁻¹)`, `Z₀ = H`, with Byers' determinant scaling `c = |det Z|^(−1/2n)`
//!    while far from convergence (it shortens the first, linear phase), then `c = 1`
//!    (quadratic convergence).
//! 2. **Newton–Kleinman refinement** (Kleinman 1968, "On an iterative technique for Riccati
//!    equation computations", IEEE TAC 13(1)): with `A_k = A − GP_k`, the correction `Δ` solves
//!    the Lyapunov equation `A_kᵀΔ + ΔA_k = −Res(P_k)` (Newton's method on the residual
//!    `Res(P) = AᵀP + PA − PGP + Q`); steps are taken while the residual falls. They restore
//!    the accuracy the sign iteration loses to rounding in `(cZ)⁻¹`. The Lyapunov equations
//!    are solved as linear systems on the `n(n+1)/2` entries of the symmetric unknown
//!    (Kronecker form, LU): `O(n⁶)` work, instant for the sizes of joint-space LQR (state
//!    `n = 2·NV`, 300 unknowns at `n = 24`), and not meant for `n` in the hundreds, where
//!    Bartels–Stewart (1972) would be the choice.
//!
//! # Assumptions
//! `R` symmetric positive definite, `Q` symmetric (positive semidefinite in the LQR setting),
//! `(A, B)` stabilizable and `(Q, A)` detectable: then the stabilizing solution exists, is
//! unique, symmetric and positive semidefinite (Anderson & Moore 1990, §3.4). When an
//! assumption fails the solver says so: an unstable mode that `B` cannot reach, or a mode on
//! the imaginary axis that `Q` does not see, puts eigenvalues of `H` on or next to the
//! imaginary axis or leaves the closed loop unstable, reported as
//! [`RiccatiError::NoStabilizingSolution`].

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use core::fmt;

use nalgebra::{DMatrix, Schur, SVD};

/// Why [`care`] or [`lqr`] found no solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RiccatiError {
    /// The matrices' sizes do not fit (`A` n×n, `B` n×m, `Q` n×n, `R` m×m, `n, m ≥ 1`).
    Dimensions,
    /// An entry of this matrix (`"A"`, `"B"`, `"Q"` or `"R"`) is NaN or infinite.
    NonFinite(&'static str),
    /// This matrix (`"Q"` or `"R"`) is not symmetric (to `1e-12` relative).
    NotSymmetric(&'static str),
    /// `R` is singular or not positive definite.
    SingularR,
    /// No stabilizing solution: `(A, B)` is not stabilizable or `(Q, A)` not detectable (the
    /// Hamiltonian has eigenvalues on the imaginary axis, or the solution found leaves
    /// `A − BK` unstable).
    NoStabilizingSolution,
    /// The sign iteration did not converge, or the refined solution's residual stayed above
    /// `1e-8` of the equation's scale (given).
    NoConvergence {
        /// `‖Res(P)‖_F / (‖Q‖_F + 2‖A‖_F‖P‖_F + ‖G‖_F‖P‖_F²)`, or infinity if the sign
        /// iteration failed.
        relative_residual: f64,
    },
}

impl fmt::Display for RiccatiError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RiccatiError::Dimensions => write!(f, "the sizes of A, B, Q and R do not fit"),
            RiccatiError::NonFinite(m) => write!(f, "{m} has a NaN or infinite entry"),
            RiccatiError::NotSymmetric(m) => write!(f, "{m} is not symmetric"),
            RiccatiError::SingularR => write!(f, "R is singular or not positive definite"),
            RiccatiError::NoStabilizingSolution => write!(
                f,
                "no stabilizing solution: (A, B) is not stabilizable or (Q, A) not detectable"
            ),
            RiccatiError::NoConvergence { relative_residual } => write!(
                f,
                "the Riccati solver did not converge (relative residual {relative_residual:e})"
            ),
        }
    }
}

impl core::error::Error for RiccatiError {}

/// An LQR design: the Riccati solution and the gain.
#[derive(Clone, Debug, PartialEq)]
pub struct Lqr {
    /// `P`, the stabilizing solution of `AᵀP + PA − PBR⁻¹BᵀP + Q = 0` (symmetric).
    pub p: DMatrix<f64>,
    /// `K = R⁻¹BᵀP`: the control is `u = −K·x`.
    pub k: DMatrix<f64>,
}

/// The LQR design for `ẋ = Ax + Bu` with the cost `∫ (xᵀQx + uᵀRu) dt`: [`care`], then
/// `K = R⁻¹BᵀP`.
///
/// ```
/// use articulated::control::riccati::lqr;
/// use articulated::nalgebra::DMatrix;
///
/// // The double integrator with Q = I, R = 1: K = [1, √3].
/// let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
/// let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
/// let design = lqr(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1))?;
/// assert!((design.k[(0, 0)] - 1.0).abs() < 1e-12);
/// assert!((design.k[(0, 1)] - 3f64.sqrt()).abs() < 1e-12);
/// # Ok::<(), articulated::control::riccati::RiccatiError>(())
/// ```
///
/// # Errors
/// As [`care`].
pub fn lqr(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<Lqr, RiccatiError> {
    let p = care(a, b, q, r)?;
    let chol = r.clone().cholesky().ok_or(RiccatiError::SingularR)?;
    let k = chol.solve(&(b.transpose() * &p));
    Ok(Lqr { p, k })
}

/// The stabilizing solution `P` of `AᵀP + PA − PBR⁻¹BᵀP + Q = 0` (method and assumptions in
/// the [module docs](self)).
///
/// # Errors
/// [`RiccatiError::Dimensions`], [`RiccatiError::NonFinite`], [`RiccatiError::NotSymmetric`],
/// [`RiccatiError::SingularR`] on bad input; [`RiccatiError::NoStabilizingSolution`] when the
/// system is not stabilizable or not detectable; [`RiccatiError::NoConvergence`].
pub fn care(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>, RiccatiError> {
    let n = a.nrows();
    let m = b.ncols();
    if n == 0
        || m == 0
        || a.ncols() != n
        || b.nrows() != n
        || q.shape() != (n, n)
        || r.shape() != (m, m)
    {
        return Err(RiccatiError::Dimensions);
    }
    for (name, x) in [("A", a), ("B", b), ("Q", q), ("R", r)] {
        if !x.iter().all(|v| v.is_finite()) {
            return Err(RiccatiError::NonFinite(name));
        }
    }
    for (name, x) in [("Q", q), ("R", r)] {
        if (x - x.transpose()).norm() > 1e-12 * x.norm() {
            return Err(RiccatiError::NotSymmetric(name));
        }
    }
    let chol = r.clone().cholesky().ok_or(RiccatiError::SingularR)?;
    let g = b * chol.solve(&b.transpose());
    let g = (&g + g.transpose()) * 0.5;

    let mut p = sign_solution(a, &g, q)?;
    let scale =
        |p: &DMatrix<f64>| q.norm() + 2.0 * a.norm() * p.norm() + g.norm() * p.norm() * p.norm();
    let mut res = residual(a, &g, q, &p);
    // Newton's method on the residual (Kleinman 1968), while it falls.
    for _ in 0..50 {
        if res.norm() == 0.0 {
            break;
        }
        let closed = a - &g * &p;
        let Some(delta) = lyapunov(&closed, &(-&res)) else {
            break;
        };
        let next = &p + delta;
        let next = (&next + next.transpose()) * 0.5;
        let next_res = residual(a, &g, q, &next);
        // Also stops on NaN.
        if next_res.norm().partial_cmp(&res.norm()) != Some(core::cmp::Ordering::Less) {
            break;
        }
        let small = next_res.norm() > 0.5 * res.norm();
        p = next;
        res = next_res;
        if small {
            // Rounding level: the last step gained less than a halving.
            break;
        }
    }
    if !hurwitz(&(a - &g * &p)) {
        return Err(RiccatiError::NoStabilizingSolution);
    }
    // Written without dividing, so that the zero equation (Q = 0, A stable: P = 0) passes.
    let converged = res.norm() <= 1e-8 * scale(&p);
    if !converged {
        return Err(RiccatiError::NoConvergence {
            relative_residual: res.norm() / scale(&p),
        });
    }
    Ok(p)
}

/// `AᵀP + PA − PGP + Q`.
fn residual(
    a: &DMatrix<f64>,
    g: &DMatrix<f64>,
    q: &DMatrix<f64>,
    p: &DMatrix<f64>,
) -> DMatrix<f64> {
    let ap = a.transpose() * p;
    let r = &ap + ap.transpose() - p * g * p + q;
    (&r + r.transpose()) * 0.5
}

/// `P` from the sign function of the Hamiltonian (step 1 of the module docs).
fn sign_solution(
    a: &DMatrix<f64>,
    g: &DMatrix<f64>,
    q: &DMatrix<f64>,
) -> Result<DMatrix<f64>, RiccatiError> {
    let n = a.nrows();
    let mut z = DMatrix::zeros(2 * n, 2 * n);
    z.view_mut((0, 0), (n, n)).copy_from(a);
    z.view_mut((0, n), (n, n)).copy_from(&(-g));
    z.view_mut((n, 0), (n, n)).copy_from(&(-q));
    z.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    let mut scaled = true;
    let mut converged = false;
    for _ in 0..100 {
        let lu = z.clone().lu();
        // |det Z|^(1/2n) from the LU pivots, in logarithms (no overflow at 2n = 48).
        let log_det: f64 = lu.u().diagonal().iter().map(|u| libm::log(u.abs())).sum();
        let inv = match lu.try_inverse() {
            Some(inv) if log_det.is_finite() && inv.iter().all(|x| x.is_finite()) => inv,
            // Z singular: H has an eigenvalue on the imaginary axis.
            _ => return Err(RiccatiError::NoStabilizingSolution),
        };
        let c = if scaled {
            libm::exp(-log_det / (2 * n) as f64)
        } else {
            1.0
        };
        let next = (&z * c + inv / c) * 0.5;
        let change = (&next - &z).norm();
        let size = next.norm();
        z = next;
        if !size.is_finite() {
            return Err(RiccatiError::NoStabilizingSolution);
        }
        if change <= 1e-2 * size {
            scaled = false;
        }
        if change <= 1e-12 * size {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(RiccatiError::NoConvergence {
            relative_residual: f64::INFINITY,
        });
    }
    // [W₁₂; W₂₂ + I]·P = −[W₁₁ + I; W₂₁].
    let mut lhs = DMatrix::zeros(2 * n, n);
    let mut rhs = DMatrix::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n))
        .copy_from(&z.view((0, n), (n, n)));
    lhs.view_mut((n, 0), (n, n))
        .copy_from(&(z.view((n, n), (n, n)) + DMatrix::identity(n, n)));
    rhs.view_mut((0, 0), (n, n))
        .copy_from(&(-(z.view((0, 0), (n, n)) + DMatrix::identity(n, n))));
    rhs.view_mut((n, 0), (n, n))
        .copy_from(&(-z.view((n, 0), (n, n))));
    let svd =
        SVD::try_new(lhs, true, true, f64::EPSILON, 0).ok_or(RiccatiError::NoConvergence {
            relative_residual: f64::INFINITY,
        })?;
    // A rank-deficient [W₁₂; W₂₂ + I] means the stable subspace is not a graph [I; P]: no
    // stabilizing solution.
    let sv = &svd.singular_values;
    let (max, min) = sv.iter().fold((0.0f64, f64::INFINITY), |(hi, lo), &s| {
        (hi.max(s), lo.min(s))
    });
    if min.is_nan() || min <= 1e-10 * max {
        return Err(RiccatiError::NoStabilizingSolution);
    }
    let p = svd
        .solve(&rhs, 0.0)
        .map_err(|_| RiccatiError::NoStabilizingSolution)?;
    if !p.iter().all(|x| x.is_finite()) {
        return Err(RiccatiError::NoStabilizingSolution);
    }
    Ok((&p + p.transpose()) * 0.5)
}

/// The symmetric `X` with `FᵀX + XF = C` (`C` symmetric), by LU on the `n(n+1)/2` entries
/// `X_ij`, `i ≤ j`; `None` when singular (`F` has eigenvalues `λ_i + λ_j = 0`).
pub(crate) fn lyapunov(f: &DMatrix<f64>, c: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = f.nrows();
    let idx = |i: usize, j: usize| {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        // Row-major upper triangle: rows 0..i hold n + (n−1) + … entries.
        i * n - i * (i + 1) / 2 + j
    };
    let m = n * (n + 1) / 2;
    let mut l = DMatrix::zeros(m, m);
    let mut rhs = nalgebra::DVector::zeros(m);
    for i in 0..n {
        for j in i..n {
            let row = idx(i, j);
            rhs[row] = c[(i, j)];
            for k in 0..n {
                // (FᵀX)_ij = Σ_k F_ki X_kj;  (XF)_ij = Σ_k X_ik F_kj.
                l[(row, idx(k, j))] += f[(k, i)];
                l[(row, idx(i, k))] += f[(k, j)];
            }
        }
    }
    let x = l.lu().solve(&rhs)?;
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    Some(DMatrix::from_fn(n, n, |i, j| x[idx(i, j)]))
}

/// The largest real part of the eigenvalues of a square matrix (its spectral abscissa), from a
/// real Schur decomposition; `None` if the matrix is not square or not finite or the
/// decomposition does not converge. `A` is Hurwitz (`ẋ = Ax` asymptotically stable) when it is
/// negative.
pub fn spectral_abscissa(a: &DMatrix<f64>) -> Option<f64> {
    if a.nrows() != a.ncols() || a.nrows() == 0 || !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let schur = Schur::try_new(a.clone(), f64::EPSILON, 10_000)?;
    schur
        .complex_eigenvalues()
        .iter()
        .map(|l| l.re)
        .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))))
}

/// All eigenvalues of `a` in the open left half-plane.
fn hurwitz(a: &DMatrix<f64>) -> bool {
    spectral_abscissa(a).is_some_and(|s| s < 0.0)
}
