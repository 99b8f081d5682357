//! Operational-space quantities of a task Jacobian `J` (`R × NV`: a frame's `6 × NV`, or its
//! `3 × NV` position rows) at a configuration with mass matrix `M` (Khatib 1987, "A unified
//! approach for motion and force control of robot manipulators: the operational space
//! formulation", IEEE J. Robotics and Automation 3(1), 43–53, eqs. 9 and 51–53):
//!
//! ```text
//! Λ = (J·M⁻¹·Jᵀ)⁻¹          the task-space inertia, R × R
//! J̄ = M⁻¹·Jᵀ·Λ               the dynamically consistent generalized inverse of J, NV × R
//! N = I − Jᵀ·J̄ᵀ              the null-space projector of joint torques, NV × NV
//! ```
//!
//! so that `J·J̄ = I`, and a torque `N·τ₀` leaves the task's acceleration unchanged
//! (`J·M⁻¹·N = 0`). The operational-space law of the example `operational_space` is
//! `τ = Jᵀ·Λ·(ẍ_d + K_d·ė + K_p·e − J̇·v) + nle + N·τ_posture`.
//!
//! **Rank.** `J·M⁻¹·Jᵀ` (symmetric, positive semi-definite) is decomposed by cyclic Jacobi
//! rotations (Golub & Van Loan 2013, *Matrix Computations*, 4th ed., §8.5.2); it has lost rank,
//! and the functions return [`OperationalSpaceError::RankLoss`], when its smallest eigenvalue
//! is at most `tolerance` times its largest (a condition number of at least `1/tolerance`):
//! at a singular configuration of the arm, or with rows of `J` that depend on each other.
//! [`RANK_TOLERANCE`] = `1e-10` leaves `Λ` about six good digits of sixteen; a controller that
//! should keep away from singularities asks for a larger one. `Λ` is then
//! `Σ_i v_i·v_iᵀ/μ_i` over the eigenpairs, symmetric by construction. Allocation-free.
//!
//! ```
//! use articulated::control::operational_space::{OperationalSpace, RANK_TOLERANCE};
//! use articulated::nalgebra::{SMatrix, SVector};
//!
//! // Two unit masses moved by two coordinates, a task on their sum: Λ = (1 + 1)⁻¹ = ½.
//! let m = SMatrix::<f64, 2, 2>::identity();
//! let j = SMatrix::<f64, 1, 2>::new(1.0, 1.0);
//! let os = OperationalSpace::from_mass_matrix(&m, &j, RANK_TOLERANCE)?;
//! assert!((os.inertia[(0, 0)] - 0.5).abs() < 1e-15);
//! assert!(((j * os.jbar)[(0, 0)] - 1.0).abs() < 1e-15); // J·J̄ = I
//! // Pushing the two apart is invisible to the task.
//! let apart = os.project_torque(&j, &SVector::from([1.0, -1.0]));
//! assert!((apart - SVector::from([1.0, -1.0])).amax() < 1e-15);
//! // The same row twice: J·M⁻¹·Jᵀ is singular.
//! let twice = SMatrix::<f64, 2, 2>::new(1.0, 1.0, 1.0, 1.0);
//! assert!(OperationalSpace::from_mass_matrix(&m, &twice, RANK_TOLERANCE).is_err());
//! # Ok::<(), articulated::control::operational_space::OperationalSpaceError>(())
//! ```

use core::fmt;

use nalgebra::{SMatrix, SVector};

/// The suggested rank tolerance: `J·M⁻¹·Jᵀ` has lost rank when its smallest eigenvalue is at
/// most `1e-10` times its largest.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// Why the operational-space quantities could not be formed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OperationalSpaceError {
    /// `J·M⁻¹·Jᵀ` has lost rank: its smallest eigenvalue is at most `tolerance` times its
    /// largest.
    RankLoss {
        /// Its smallest eigenvalue.
        smallest: f64,
        /// Its largest eigenvalue.
        largest: f64,
        /// The relative threshold asked for.
        tolerance: f64,
    },
    /// `M` is not positive definite (its Cholesky factorization failed).
    MassMatrix,
    /// `M`, `M⁻¹` or `J` holds a value that is not finite.
    NonFinite,
}

impl fmt::Display for OperationalSpaceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            OperationalSpaceError::RankLoss {
                smallest,
                largest,
                tolerance,
            } => write!(
                f,
                "J·M⁻¹·Jᵀ has lost rank: its smallest eigenvalue {smallest:.3e} is at most \
                 {tolerance:e} times its largest {largest:.3e} (a singular configuration, or \
                 dependent rows of J)"
            ),
            OperationalSpaceError::MassMatrix => {
                write!(f, "the mass matrix is not positive definite")
            }
            OperationalSpaceError::NonFinite => {
                write!(f, "the mass matrix or the Jacobian is not finite")
            }
        }
    }
}

impl core::error::Error for OperationalSpaceError {}

/// `Λ` and `J̄` of an `R × NV` task Jacobian (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OperationalSpace<const R: usize, const NV: usize> {
    /// `Λ = (J·M⁻¹·Jᵀ)⁻¹`, the task-space inertia, `R × R`, symmetric positive definite.
    pub inertia: SMatrix<f64, R, R>,
    /// `J̄ = M⁻¹·Jᵀ·Λ`, the dynamically consistent inverse of `J`, `NV × R`: `J·J̄ = I`.
    pub jbar: SMatrix<f64, NV, R>,
}

impl<const R: usize, const NV: usize> OperationalSpace<R, NV> {
    /// From the mass matrix `M` (solved by its Cholesky factorization) and the task Jacobian
    /// `j`; `tolerance` is the relative eigenvalue threshold of the rank test (module docs).
    ///
    /// # Errors
    /// [`OperationalSpaceError::MassMatrix`] when `M` is not positive definite,
    /// [`OperationalSpaceError::RankLoss`] when `J·M⁻¹·Jᵀ` has lost rank,
    /// [`OperationalSpaceError::NonFinite`] for a value that is not finite.
    pub fn from_mass_matrix(
        m: &SMatrix<f64, NV, NV>,
        j: &SMatrix<f64, R, NV>,
        tolerance: f64,
    ) -> Result<Self, OperationalSpaceError> {
        finite(m.iter())?;
        finite(j.iter())?;
        let cholesky = m.cholesky().ok_or(OperationalSpaceError::MassMatrix)?;
        Self::from_m_inv_jt(cholesky.solve(&j.transpose()), j, tolerance)
    }

    /// From the inverse mass matrix `M⁻¹` (as `mass_matrix_inverse` gives it) and the task
    /// Jacobian `j`; `tolerance` as in [`from_mass_matrix`](Self::from_mass_matrix).
    ///
    /// # Errors
    /// [`OperationalSpaceError::RankLoss`] when `J·M⁻¹·Jᵀ` has lost rank,
    /// [`OperationalSpaceError::NonFinite`] for a value that is not finite.
    pub fn from_mass_matrix_inverse(
        m_inv: &SMatrix<f64, NV, NV>,
        j: &SMatrix<f64, R, NV>,
        tolerance: f64,
    ) -> Result<Self, OperationalSpaceError> {
        finite(m_inv.iter())?;
        finite(j.iter())?;
        Self::from_m_inv_jt(m_inv * j.transpose(), j, tolerance)
    }

    /// From `M⁻¹·Jᵀ`.
    fn from_m_inv_jt(
        m_inv_jt: SMatrix<f64, NV, R>,
        j: &SMatrix<f64, R, NV>,
        tolerance: f64,
    ) -> Result<Self, OperationalSpaceError> {
        let phi = j * m_inv_jt;
        let phi = (phi + phi.transpose()) * 0.5;
        finite(phi.iter())?;
        let (values, vectors) = symmetric_eigen(phi);
        let largest = values.max();
        let smallest = values.min();
        if smallest.is_nan() || largest <= 0.0 || smallest <= tolerance * largest {
            return Err(OperationalSpaceError::RankLoss {
                smallest,
                largest,
                tolerance,
            });
        }
        let mut inertia = SMatrix::<f64, R, R>::zeros();
        for (k, value) in values.iter().enumerate() {
            let v = vectors.column(k);
            inertia += v * v.transpose() / *value;
        }
        Ok(OperationalSpace {
            inertia,
            jbar: m_inv_jt * inertia,
        })
    }

    /// `N = I − Jᵀ·J̄ᵀ` for the Jacobian `j` these were formed with.
    pub fn null_space_projector(&self, j: &SMatrix<f64, R, NV>) -> SMatrix<f64, NV, NV> {
        SMatrix::<f64, NV, NV>::identity() - j.transpose() * self.jbar.transpose()
    }

    /// `N·τ = τ − Jᵀ·(J̄ᵀ·τ)`: the part of `tau` that leaves the task's acceleration alone, for
    /// the Jacobian `j` these were formed with (without forming `N`).
    pub fn project_torque(
        &self,
        j: &SMatrix<f64, R, NV>,
        tau: &SVector<f64, NV>,
    ) -> SVector<f64, NV> {
        tau - j.transpose() * (self.jbar.transpose() * tau)
    }
}

/// `Ok` when every value is finite.
fn finite<'a>(mut values: impl Iterator<Item = &'a f64>) -> Result<(), OperationalSpaceError> {
    if values.all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(OperationalSpaceError::NonFinite)
    }
}

/// The eigenvalues and eigenvectors (as columns) of the symmetric `a`, by cyclic Jacobi
/// rotations (Golub & Van Loan 2013, Algorithm 8.5.3): sweeps over the off-diagonal entries
/// until their sum of squares is below `(ε·|a|_F)²`, at most 50 (quadratic convergence takes
/// fewer than ten for `R ≤ 6`).
fn symmetric_eigen<const R: usize>(
    mut a: SMatrix<f64, R, R>,
) -> (SVector<f64, R>, SMatrix<f64, R, R>) {
    let mut v = SMatrix::<f64, R, R>::identity();
    let total = a.norm_squared();
    for _ in 0..50 {
        let mut off = 0.0;
        for p in 0..R {
            for q in p + 1..R {
                off += a[(p, q)] * a[(p, q)];
            }
        }
        if off <= f64::EPSILON * f64::EPSILON * total {
            break;
        }
        for p in 0..R {
            for q in p + 1..R {
                let apq = a[(p, q)];
                if apq == 0.0 {
                    continue;
                }
                // The rotation that zeroes a[p, q]: t = tan of its angle, the smaller root of
                // t² + 2θt − 1 = 0.
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + libm::hypot(theta, 1.0));
                let c = 1.0 / libm::hypot(t, 1.0);
                let s = t * c;
                for k in 0..R {
                    let (akp, akq) = (a[(k, p)], a[(k, q)]);
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..R {
                    let (apk, aqk) = (a[(p, k)], a[(q, k)]);
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
                for k in 0..R {
                    let (vkp, vkq) = (v[(k, p)], v[(k, q)]);
                    v[(k, p)] = c * vkp - s * vkq;
                    v[(k, q)] = s * vkp + c * vkq;
                }
            }
        }
    }
    (a.diagonal(), v)
}
