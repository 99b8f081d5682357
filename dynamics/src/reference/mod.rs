//! Reference rigid-body dynamics, written from Featherstone's recursions on spatial vectors
//! (Featherstone 2008, *Rigid Body Dynamics Algorithms*, ch. 2–7).
//!
//! # Conventions
//! - Spatial vectors are **angular first** (Featherstone): a motion is `[ω; v]`, a force is
//!   `[n; f]`; see [`crate::spatial`]. (Pinocchio is linear first.)
//! - `q`, `v`, `τ` follow the model's joint order and each joint's coordinates as documented in
//!   [`crate::model::JointKind`]. `τ` is the generalized force dual to `v`.
//! - `bias(q, v) = N(q, q̇)·q̇` holds the velocity-product terms only, **without gravity**
//!   (Wieber 2005, eq. 7); `gravity(q) = g(q)` is the generalized force needed to hold the chain
//!   still against gravity, the negative of Wieber's `𝓕_g` (Wieber 2005, eq. 8 with
//!   `f_k = m_k·g`, `τ_k = 0`). So `τ = M·a + bias + gravity`.
//!
//! # Layers
//! - Generic recursions over any [`Scalar`](crate::Scalar) on a [`Tree`] (one algorithm per
//!   file): [`rnea()`](rnea::rnea) and [`joint_forces`] (RBDA §5.3),
//!   [`crba()`](crba::crba) (RBDA §6.2), [`aba()`](aba::aba) (RBDA §7.3). They never branch on or
//!   compare a scalar, so the generator can trace them over a symbolic scalar. They do not check
//!   their inputs.
//! - The `f64` front door [`Reference`], which checks everything and returns [`Error`]s instead
//!   of panicking or returning NaN.
//! - An independent cross-check, [`jacobian`]: Wieber 2005, eqs. 6–8 from plain 3D kinematics.
//! - [`frames`]: where a named frame is, its velocity, its classical and spatial accelerations,
//!   its Jacobians and their time variation in the LOCAL, WORLD and LOCAL_WORLD_ALIGNED reference
//!   frames (DESIGN.md §9), `f64` only.

pub mod aba;
pub mod centroidal;
pub mod crba;
pub mod derivatives;
pub mod frames;
pub mod jacobian;
pub mod ltdl;
pub mod rnea;
pub mod tree;

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use nalgebra::{DMatrix, DVector, Vector3, Vector6};

pub use aba::{aba, AbaOutput};
pub use crba::{composite_inertias_with, crba, crba_columns, crba_with};
pub use frames::ReferenceFrame;
pub use ltdl::{ltdl_factor, ltdl_factor_of, ltdl_solve, Ltdl};
pub use rnea::{bottom_up, inertial_forces, joint_forces, node_forces, project, rnea, transmit};
pub use tree::{Node, NodeJoint, Tree};

use crate::model::{Coupling, JointKind, Model, ModelError};
use crate::spatial::{Force, Vec3};

/// What can go wrong in the reference dynamics. No function of [`Reference`] panics.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A state vector has the wrong length.
    Length {
        /// Which vector (`"q"`, `"v"`, `"a"`, `"tau"`).
        vector: &'static str,
        /// The length the model needs.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A state vector has a NaN or infinite entry.
    NonFinite {
        /// Which vector.
        vector: &'static str,
        /// The index of the first such entry.
        index: usize,
    },
    /// A quaternion in `q` is zero (or its squared norm is not a positive finite number), so it
    /// names no rotation.
    Quaternion {
        /// The joint it belongs to.
        joint: String,
        /// Index of its `w` entry in `q`.
        index: usize,
    },
    /// A quaternion in `q` has a norm off 1 by more than
    /// [`QUATERNION_NORM_TOLERANCE`](crate::model::QUATERNION_NORM_TOLERANCE).
    NotUnitQuaternion {
        /// The joint it belongs to.
        joint: String,
        /// Index of its `w` entry in `q`.
        index: usize,
        /// Its norm.
        norm: f64,
    },
    /// The parameter vector has the wrong length.
    ParamLength {
        /// `model.params.len()`.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A parameter value is NaN or infinite.
    ParamNonFinite {
        /// Its index.
        index: usize,
        /// Its name in the model.
        name: String,
    },
    /// The model fails [`Model::check`].
    InvalidModel(ModelError),
    /// Forward dynamics found the mass matrix singular at this state (a massless leaf, an Euler
    /// joint at gimbal lock, …).
    Singular(Singularity),
    /// Joint wrenches bottom-up need a serial chain: this model has a body with two children
    /// (or two roots), where the split of the remainder is not determined.
    NotSerial,
    /// A result overflowed to infinity or NaN although the inputs were finite (huge inputs).
    NonFiniteResult {
        /// Which output (`"mass_matrix"`, `"bias"`, …).
        output: &'static str,
    },
    /// No body or frame of the model has this name ([`frames`]).
    UnknownFrame {
        /// The name asked for.
        name: String,
        /// Every frame's name, the bodies' first ([`Model::frame_names`]).
        known: Vec<String>,
    },
}

impl core::error::Error for Error {}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Length {
                vector,
                expected,
                found,
            } => write!(
                f,
                "`{vector}` has {found} entries but the model needs {expected}"
            ),
            Error::NonFinite { vector, index } => {
                write!(f, "`{vector}[{index}]` is not a finite number")
            }
            Error::Quaternion { joint, index } => write!(
                f,
                "joint `{joint}`: the quaternion at q[{index}..{}] is zero or not finite, so it names no rotation",
                index + 4
            ),
            Error::NotUnitQuaternion { joint, index, norm } => write!(
                f,
                "joint `{joint}`: the quaternion at q[{index}..{}] has norm {norm:.4}, not 1 \
                 (within {}): it is `[w, x, y, z]`, scalar first (Pinocchio's order is \
                 `[x, y, z, w]`)",
                index + 4,
                crate::model::QUATERNION_NORM_TOLERANCE
            ),
            Error::ParamLength { expected, found } => write!(
                f,
                "{found} parameter values given but the model has {expected} parameters"
            ),
            Error::ParamNonFinite { index, name } => {
                write!(f, "parameter #{index} `{name}` is not a finite number")
            }
            Error::InvalidModel(e) => write!(f, "invalid model: {e}"),
            Error::Singular(s) => write!(f, "{s}"),
            Error::NotSerial => write!(
                f,
                "joint wrenches bottom-up need a serial chain, and this model branches"
            ),
            Error::NonFiniteResult { output } => write!(
                f,
                "`{output}` overflowed to a non-finite value (inputs too large)"
            ),
            Error::UnknownFrame { name, known } => {
                write!(f, "no body or frame is called `{name}`")?;
                const SHOWN: usize = 12;
                match known.len() {
                    0 => write!(f, ": the model has none"),
                    n => {
                        let names: Vec<String> = known
                            .iter()
                            .take(SHOWN)
                            .map(|k| alloc::format!("`{k}`"))
                            .collect();
                        write!(f, "; the frames are {}", names.join(", "))?;
                        if n > SHOWN {
                            write!(f, ", … ({n} in all)")?;
                        }
                        Ok(())
                    }
                }
            }
        }
    }
}

/// How forward dynamics found `M(q)` singular ([`Error::Singular`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Singularity {
    /// A pivot of the articulated-body factorization is not positive relative to its unreduced
    /// value (or to the largest in the tree): `M(q)` is singular to working precision.
    Pivot {
        /// The joint the pivot belongs to.
        joint: String,
        /// Its velocity coordinate.
        velocity: usize,
        /// The pivot.
        pivot: f64,
        /// The diagonal entry before elimination.
        unreduced: f64,
    },
    /// The acceleration of a coordinate is not finite.
    NonFiniteAcceleration {
        /// The joint.
        joint: String,
        /// The velocity coordinate.
        velocity: usize,
    },
    /// `M(q)` is not positive definite, or its condition number passes [`M_CONDITION_LIMIT`].
    Eigenvalues {
        /// Its smallest eigenvalue.
        min: f64,
        /// Its largest eigenvalue (in magnitude).
        max: f64,
    },
}

impl fmt::Display for Singularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Singularity::Pivot {
                joint,
                velocity,
                pivot,
                unreduced,
            } => write!(
                f,
                "the mass matrix is singular here: at joint `{joint}` (velocity {velocity}) the \
                 articulated-inertia pivot is {pivot:e}, against {unreduced:e} before elimination"
            ),
            Singularity::NonFiniteAcceleration { joint, velocity } => write!(
                f,
                "the acceleration of joint `{joint}` (velocity {velocity}) is not finite"
            ),
            Singularity::Eigenvalues { min, max } if *min <= 0.0 => write!(
                f,
                "the mass matrix is not positive definite here: its eigenvalues range from \
                 {min:e} to {max:e}"
            ),
            Singularity::Eigenvalues { min, max } => write!(
                f,
                "the mass matrix is numerically singular here: its eigenvalues range from {min:e} \
                 to {max:e}, a condition number of {:.1e}, past {M_CONDITION_LIMIT:.0e}",
                max / min
            ),
        }
    }
}

/// The wrench a joint transmits: what the parent exerts on the child across the joint, in the
/// child body frame, about the child frame origin (Hemami's joint couple and reaction force),
/// gravity included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench {
    /// The couple about the child frame origin (N·m).
    pub couple: [f64; 3],
    /// The force (N).
    pub force: [f64; 3],
}

/// The reference dynamics of one model with fixed parameter values, in `f64`.
///
/// Built once ([`Reference::new`], [`Reference::with_params`]); every query checks its inputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    model: Model,
    params: Vec<f64>,
    tree: Tree<f64>,
    coupling: Coupling,
}

/// Checks a model and a parameter vector for it.
pub(crate) fn check_model(model: &Model, params: &[f64]) -> Result<(), Error> {
    model.check().map_err(Error::InvalidModel)?;
    if params.len() != model.params.len() {
        return Err(Error::ParamLength {
            expected: model.params.len(),
            found: params.len(),
        });
    }
    if let Some(index) = params.iter().position(|x| !x.is_finite()) {
        return Err(Error::ParamNonFinite {
            index,
            name: model.params[index].name.clone(),
        });
    }
    Ok(())
}

/// Checks the length and finiteness of a state vector.
pub(crate) fn check_vector(vector: &'static str, x: &[f64], expected: usize) -> Result<(), Error> {
    if x.len() != expected {
        return Err(Error::Length {
            vector,
            expected,
            found: x.len(),
        });
    }
    match x.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(Error::NonFinite { vector, index }),
        None => Ok(()),
    }
}

/// Checks `q` for `model` as every [`Reference`] function does (length, finite entries, every
/// quaternion of unit norm within
/// [`QUATERNION_NORM_TOLERANCE`](crate::model::QUATERNION_NORM_TOLERANCE)); public so that other evaluators of a model (the CLI's symbolic engine)
/// refuse exactly the same states.
///
/// # Errors
/// [`Error::Length`], [`Error::NonFinite`], [`Error::Quaternion`] or
/// [`Error::NotUnitQuaternion`].
pub fn check_q(model: &Model, q: &[f64]) -> Result<(), Error> {
    check_vector("q", q, model.nq())?;
    let mut at = 0;
    for j in &model.joints {
        let w = match j.kind {
            JointKind::SphericalQuaternion => Some(at),
            JointKind::FreeQuaternion => Some(at + 3),
            _ => None,
        };
        if let Some(index) = w {
            let n2: f64 = q[index..index + 4].iter().map(|x| x * x).sum();
            if !(n2 > 0.0 && n2.is_finite()) {
                return Err(Error::Quaternion {
                    joint: j.name.clone(),
                    index,
                });
            }
            let norm = libm::sqrt(n2);
            if (norm - 1.0).abs() > crate::model::QUATERNION_NORM_TOLERANCE {
                return Err(Error::NotUnitQuaternion {
                    joint: j.name.clone(),
                    index,
                    norm,
                });
            }
        }
        at += j.nq();
    }
    Ok(())
}

/// Spatial forces as [`Wrench`]es, all finite.
fn wrenches(f: &[Force<f64>]) -> Result<Vec<Wrench>, Error> {
    let out: Vec<Wrench> = f
        .iter()
        .map(|f| Wrench {
            couple: f.ang.0,
            force: f.lin.0,
        })
        .collect();
    let finite = out
        .iter()
        .all(|w| w.couple.iter().chain(&w.force).all(|x| x.is_finite()));
    if finite {
        Ok(out)
    } else {
        Err(Error::NonFiniteResult {
            output: "joint_wrenches",
        })
    }
}

fn finite(output: &'static str, x: Vec<f64>) -> Result<Vec<f64>, Error> {
    if x.iter().all(|x| x.is_finite()) {
        Ok(x)
    } else {
        Err(Error::NonFiniteResult { output })
    }
}

/// A pivot of `D_i` is accepted when it is positive both relative to its own unreduced diagonal
/// entry (catches gimbal lock: the pivot cancels to rounding error) and relative to the largest
/// diagonal entry of the whole tree (catches an inertia that is zero up to rounding).
const PIVOT_LOCAL_TOL: f64 = 1e-13;
const PIVOT_GLOBAL_TOL: f64 = 1e-15;
/// `M(q)` counts as singular past this condition number: q̈ can then have fewer than three
/// correct digits in f64 (relative error up to ε·κ ≈ 2e-3).
pub const M_CONDITION_LIMIT: f64 = 1e13;

impl Reference {
    /// The reference dynamics of `model` with its parameters at their default values.
    pub fn new(model: &Model) -> Result<Self, Error> {
        Self::with_params(model, &model.param_defaults())
    }

    /// The reference dynamics of `model` with the parameter values `params` (one per
    /// `model.params`).
    pub fn with_params(model: &Model, params: &[f64]) -> Result<Self, Error> {
        check_model(model, params)?;
        Ok(Reference {
            model: model.clone(),
            params: params.to_vec(),
            tree: Tree::new(model, params),
            coupling: model.coupling(),
        })
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The parameter values in use.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The numeric tree the recursions run on (Euler joints expanded, and mimic joints with
    /// coordinates of their own: see [`Reference::coupling`]).
    pub fn tree(&self) -> &Tree<f64> {
        &self.tree
    }

    /// The map from the model's coordinates to the tree's (the identity without mimic joints).
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// Number of position coordinates.
    pub fn nq(&self) -> usize {
        self.coupling.nq
    }

    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        self.coupling.nv
    }

    /// The tree's `q`.
    fn q(&self, q: &[f64]) -> Vec<f64> {
        self.coupling.expand_q(q)
    }

    /// The tree's `v` (or `a`).
    fn v(&self, v: &[f64]) -> Vec<f64> {
        self.coupling.expand_v(v)
    }

    /// `M(q)`, `nv × nv` row-major, unchecked.
    fn m(&self, q: &[f64]) -> Vec<f64> {
        self.coupling.reduce_matrix(&crba(&self.tree, &self.q(q)))
    }

    /// RNEA, unchecked.
    fn rnea(&self, q: &[f64], v: &[f64], a: &[f64], with_gravity: bool) -> Vec<f64> {
        let (q, v, a) = (self.q(q), self.v(v), self.v(a));
        self.coupling
            .reduce(&rnea(&self.tree, &q, &v, &a, with_gravity))
    }

    /// The joint-space inertia matrix `M(q)` by CRBA (Featherstone 2008, RBDA §6.2).
    pub fn mass_matrix(&self, q: &[f64]) -> Result<DMatrix<f64>, Error> {
        check_q(&self.model, q)?;
        let m = finite("mass_matrix", self.m(q))?;
        Ok(DMatrix::from_row_slice(self.nv(), self.nv(), &m))
    }

    /// The velocity-product terms `N(q, q̇)·q̇` (Coriolis and centrifugal), **without gravity**:
    /// RNEA with `a = 0` and no gravity (Featherstone 2008, RBDA §5.3).
    pub fn bias(&self, q: &[f64], v: &[f64]) -> Result<DVector<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let zero = alloc::vec![0.0; self.nv()];
        let b = finite("bias", self.rnea(q, v, &zero, false))?;
        Ok(DVector::from_vec(b))
    }

    /// `g(q)`: the generalized force that holds the chain still against gravity (RNEA with
    /// `v = a = 0`; the negative of Wieber 2005, eq. 8 with `f_k = m_k·g`).
    pub fn gravity(&self, q: &[f64]) -> Result<DVector<f64>, Error> {
        check_q(&self.model, q)?;
        let zero = alloc::vec![0.0; self.nv()];
        let g = finite("gravity", self.rnea(q, &zero, &zero, true))?;
        Ok(DVector::from_vec(g))
    }

    /// Inverse dynamics `τ = M(q)·a + N(q, q̇)·q̇ + g(q)` by RNEA (Featherstone 2008, RBDA §5.3).
    pub fn inverse_dynamics(&self, q: &[f64], v: &[f64], a: &[f64]) -> Result<DVector<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        let tau = finite("inverse_dynamics", self.rnea(q, v, a, true))?;
        Ok(DVector::from_vec(tau))
    }

    /// Forward dynamics `q̈` (the time derivative of `v`) for the applied generalized force `tau`,
    /// by ABA (Featherstone 2008, RBDA §7.3). [`Error::Singular`] when `M(q)` is not positive
    /// definite or the result is not finite.
    pub fn forward_dynamics(
        &self,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
    ) -> Result<DVector<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("tau", tau, self.nv())?;
        if !self.coupling.is_identity() {
            return self.coupled_forward_dynamics(q, v, tau);
        }
        let out = aba(&self.tree, q, v, tau, true);
        let scale = out.diag.iter().fold(0.0f64, |s, d| s.max(d.abs()));
        // Leaves first, as ABA eliminates them: a singular joint poisons its ancestors with NaN,
        // so the first failure found this way is the culprit.
        for (k, (&p, &d)) in out.pivots.iter().zip(&out.diag).enumerate().rev() {
            if !(p > PIVOT_LOCAL_TOL * d.abs() && p > PIVOT_GLOBAL_TOL * scale) {
                return Err(Error::Singular(Singularity::Pivot {
                    joint: self.joint_of_v(k),
                    velocity: k,
                    pivot: p,
                    unreduced: d,
                }));
            }
        }
        if let Some(k) = out.qdd.iter().position(|x| !x.is_finite()) {
            return Err(Error::Singular(Singularity::NonFiniteAcceleration {
                joint: self.joint_of_v(k),
                velocity: k,
            }));
        }
        // ABA's pivots can stay positive by rounding when M is singular or indefinite (a massless
        // root under a free base, an inertia that is not positive definite), and then q̈ is
        // rounding noise times 1e16. The eigenvalues of M itself settle it: this is a reference,
        // so an O(n³) check is affordable.
        if self.nv() == 0 {
            // Nothing moves (only fixed joints); nalgebra's eigen-solver refuses an empty matrix.
            return Ok(DVector::from_vec(out.qdd));
        }
        let m = DMatrix::from_vec(self.nv(), self.nv(), self.m(q));
        self.check_eigenvalues(&m)?;
        Ok(DVector::from_vec(out.qdd))
    }

    /// Refuses an `M` that is not positive definite or is past [`M_CONDITION_LIMIT`].
    fn check_eigenvalues(&self, m: &DMatrix<f64>) -> Result<(), Error> {
        let eig = m.clone().symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x.abs()))
        });
        if lo.is_nan() || lo * M_CONDITION_LIMIT <= hi {
            return Err(Error::Singular(Singularity::Eigenvalues {
                min: lo,
                max: hi,
            }));
        }
        Ok(())
    }

    /// Forward dynamics of a model with mimic joints, which ABA cannot run (a coupled coordinate
    /// moves bodies on two branches): `M·q̈ = τ − h` with `M = Gᵀ·M_tree·G` and
    /// `h = Gᵀ·h_tree`, solved by Cholesky once the eigenvalues of `M` pass.
    fn coupled_forward_dynamics(
        &self,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
    ) -> Result<DVector<f64>, Error> {
        let n = self.nv();
        let m = DMatrix::from_row_slice(n, n, &self.m(q));
        if n == 0 {
            return Ok(DVector::zeros(0));
        }
        self.check_eigenvalues(&m)?;
        let zero = alloc::vec![0.0; n];
        let h = DVector::from_vec(self.rnea(q, v, &zero, true));
        let b = DVector::from_column_slice(tau) - h;
        let qdd =
            m.cholesky()
                .map(|c| c.solve(&b))
                .ok_or(Error::Singular(Singularity::Eigenvalues {
                    min: 0.0,
                    max: 0.0,
                }))?;
        if let Some(k) = qdd.iter().position(|x| !x.is_finite()) {
            return Err(Error::Singular(Singularity::NonFiniteAcceleration {
                joint: self.joint_of_v(k),
                velocity: k,
            }));
        }
        Ok(qdd)
    }

    /// The kinetic energy `½·Σ v_iᵀ·I_i·v_i` over the bodies (`= ½·vᵀ·M(q)·v`).
    ///
    /// # Errors
    /// As [`Reference::mass_matrix`], and for a `v` of the wrong length or not finite.
    pub fn kinetic_energy(&self, q: &[f64], v: &[f64]) -> Result<f64, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let e = centroidal::kinetic_energy(&self.tree, &self.q(q), &self.v(v));
        finite("kinetic_energy", alloc::vec![e]).map(|_| e)
    }

    /// The centre of mass `x_G(q)`, world frame.
    ///
    /// # Errors
    /// As [`Reference::mass_matrix`].
    pub fn center_of_mass(&self, q: &[f64]) -> Result<Vector3<f64>, Error> {
        check_q(&self.model, q)?;
        let c = finite(
            "center_of_mass",
            centroidal::center_of_mass(&self.tree, &self.q(q))
                .0
                .to_vec(),
        )?;
        Ok(Vector3::from_column_slice(&c))
    }

    /// The velocity of the centre of mass `ẋ_G = p / m`, world frame.
    ///
    /// # Errors
    /// As [`Reference::bias`].
    pub fn center_of_mass_velocity(&self, q: &[f64], v: &[f64]) -> Result<Vector3<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let c = finite(
            "center_of_mass_velocity",
            centroidal::center_of_mass_velocity(&self.tree, &self.q(q), &self.v(v))
                .0
                .to_vec(),
        )?;
        Ok(Vector3::from_column_slice(&c))
    }

    /// The centre of mass Jacobian `J_G(q)`, `3 × nv`: `ẋ_G = J_G·v`.
    ///
    /// # Errors
    /// As [`Reference::mass_matrix`].
    pub fn center_of_mass_jacobian(&self, q: &[f64]) -> Result<DMatrix<f64>, Error> {
        check_q(&self.model, q)?;
        let j = finite(
            "center_of_mass_jacobian",
            self.coupling.reduce_columns(
                &centroidal::center_of_mass_jacobian(&self.tree, &self.q(q)),
                3,
            ),
        )?;
        Ok(DMatrix::from_row_slice(3, self.nv(), &j))
    }

    /// The centroidal momentum `h_G = [k_G; p]`: angular momentum about the centre of mass, then
    /// linear momentum, world axes.
    ///
    /// # Errors
    /// As [`Reference::bias`].
    pub fn centroidal_momentum(&self, q: &[f64], v: &[f64]) -> Result<Vector6<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let h = centroidal::centroidal_momentum(&self.tree, &self.q(q), &self.v(v)).to_array();
        let h = finite("centroidal_momentum", h.to_vec())?;
        Ok(Vector6::from_column_slice(&h))
    }

    /// The rate of the centroidal momentum `ḣ_G = A_G·a + Ȧ_G·v`, laid out as
    /// [`Reference::centroidal_momentum`] (`[k̇_G; ṗ]`, world axes, about the centre of mass),
    /// without gravity ([`centroidal::centroidal_momentum_rate`]).
    ///
    /// # Errors
    /// As [`Reference::inverse_dynamics`].
    pub fn centroidal_momentum_rate(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<Vector6<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        let h =
            centroidal::centroidal_momentum_rate(&self.tree, &self.q(q), &self.v(v), &self.v(a))
                .to_array();
        let h = finite("centroidal_momentum_rate", h.to_vec())?;
        Ok(Vector6::from_column_slice(&h))
    }

    /// The drift of the centroidal momentum `Ȧ_G·v`: [`Reference::centroidal_momentum_rate`] at
    /// `a = 0`.
    ///
    /// # Errors
    /// As [`Reference::bias`].
    pub fn centroidal_momentum_drift(&self, q: &[f64], v: &[f64]) -> Result<Vector6<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let h =
            centroidal::centroidal_momentum_drift(&self.tree, &self.q(q), &self.v(v)).to_array();
        let h = finite("centroidal_momentum_drift", h.to_vec())?;
        Ok(Vector6::from_column_slice(&h))
    }

    /// The centroidal momentum matrix `A_G(q)`, `6 × nv`, angular rows first: `h_G = A_G·v`.
    ///
    /// # Errors
    /// As [`Reference::mass_matrix`].
    pub fn centroidal_momentum_matrix(&self, q: &[f64]) -> Result<DMatrix<f64>, Error> {
        check_q(&self.model, q)?;
        let a = finite(
            "centroidal_momentum_matrix",
            self.coupling.reduce_columns(
                &centroidal::centroidal_momentum_matrix(&self.tree, &self.q(q)),
                6,
            ),
        )?;
        Ok(DMatrix::from_row_slice(6, self.nv(), &a))
    }

    /// The Coriolis matrix `N(q, q̇)` of Wieber 2005, eq. 7 (`nv × nv`): `N·v` is
    /// [`Reference::bias`] and `Ṁ − 2N` is skew-symmetric ([`centroidal::coriolis_matrix`]).
    ///
    /// # Errors
    /// As [`Reference::bias`].
    pub fn coriolis_matrix(&self, q: &[f64], v: &[f64]) -> Result<DMatrix<f64>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        let n = finite(
            "coriolis_matrix",
            self.coupling.reduce_matrix(&centroidal::coriolis_matrix(
                &self.tree,
                &self.q(q),
                &self.v(v),
            )),
        )?;
        Ok(DMatrix::from_row_slice(self.nv(), self.nv(), &n))
    }

    /// `(∂τ/∂q, ∂τ/∂v)` of [`Reference::inverse_dynamics`], each `nv × nv`, by forward-mode
    /// differentiation of RNEA; `∂/∂q` along the tangent displacement of the configuration
    /// ([`derivatives`]: the body-frame increment for quaternions).
    ///
    /// # Errors
    /// As [`Reference::inverse_dynamics`].
    pub fn inverse_dynamics_derivatives(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<(DMatrix<f64>, DMatrix<f64>), Error> {
        self.inverse_dynamics(q, v, a)?;
        let (dq, dv) = derivatives::inverse_dynamics_derivatives(
            &self.tree,
            &self.q(q),
            &self.v(v),
            &self.v(a),
        );
        let (dq, dv) = (
            self.coupling.reduce_matrix(&dq),
            self.coupling.reduce_matrix(&dv),
        );
        let name = "inverse_dynamics_derivatives";
        let (dq, dv) = (finite(name, dq)?, finite(name, dv)?);
        let nv = self.nv();
        Ok((
            DMatrix::from_row_slice(nv, nv, &dq),
            DMatrix::from_row_slice(nv, nv, &dv),
        ))
    }

    /// `[∂q̈/∂q, ∂q̈/∂v, M⁻¹]` of [`Reference::forward_dynamics`], each `nv × nv`:
    /// `−M⁻¹·∂τ/∂(q, v)` at `a = q̈`, and `∂q̈/∂τ = M⁻¹` ([`derivatives`]).
    ///
    /// # Errors
    /// As [`Reference::forward_dynamics`] (a singular `M` is refused by the same checks).
    pub fn forward_dynamics_derivatives(
        &self,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
    ) -> Result<[DMatrix<f64>; 3], Error> {
        let qdd = self.forward_dynamics(q, v, tau)?;
        let name = "forward_dynamics_derivatives";
        let nv = self.nv();
        let matrix = |x: Vec<f64>| finite(name, x).map(|x| DMatrix::from_row_slice(nv, nv, &x));
        if !self.coupling.is_identity() {
            // `q̈ = M⁻¹·(τ − h)`: at `τ` fixed, `∂q̈ = −M⁻¹·∂τ_ID(q, v, q̈)`.
            let (dq, dv) = self.inverse_dynamics_derivatives(q, v, qdd.as_slice())?;
            let minv = self.mass_matrix_inverse(q)?;
            return Ok([-&minv * dq, -&minv * dv, minv]);
        }
        let d = derivatives::forward_dynamics_derivatives(&self.tree, q, v, tau);
        Ok([matrix(d.dqdd_dq)?, matrix(d.dqdd_dv)?, matrix(d.minv)?])
    }

    /// `M(q)⁻¹`, by the sparse `LᵀDL` of `M`.
    ///
    /// # Errors
    /// As [`Reference::forward_dynamics`] for a singular `M`, and for a bad `q`.
    pub fn mass_matrix_inverse(&self, q: &[f64]) -> Result<DMatrix<f64>, Error> {
        let zero = alloc::vec![0.0; self.nv()];
        self.forward_dynamics(q, &zero, &zero)?;
        let (inv, _) = derivatives::mass_matrix_inverse_from(self.m(q), self.nv());
        let inv = finite("mass_matrix_inverse", inv)?;
        Ok(DMatrix::from_row_slice(self.nv(), self.nv(), &inv))
    }

    /// The potential energy of gravity, `−Σ m_k·gᵀ·x_k` over the bodies' centres of mass `x_k`
    /// (world frame), zero with every centre of mass at the world origin.
    ///
    /// # Errors
    /// As [`Reference::mass_matrix`].
    pub fn potential_energy(&self, q: &[f64]) -> Result<f64, Error> {
        check_q(&self.model, q)?;
        let e = centroidal::potential_energy(&self.tree, &self.q(q));
        finite("potential_energy", alloc::vec![e]).map(|_| e)
    }

    /// The wrench each model joint transmits at `(q, v, a)`, gravity included, in joint order:
    /// what the parent exerts on the child, in the child body frame, about the child origin
    /// (RNEA's `f_i`, Featherstone 2008, RBDA Table 5.1).
    pub fn joint_wrenches(&self, q: &[f64], v: &[f64], a: &[f64]) -> Result<Vec<Wrench>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        wrenches(&joint_forces(
            &self.tree,
            &self.q(q),
            &self.v(v),
            &self.v(a),
        ))
    }

    /// The wrench each model joint transmits at `(q, v, a)`, computed bottom-up from the wrench
    /// `base` the world exerts on the root body (a measured ground reaction; in the root body's
    /// frame about its origin), as Hemami, Dariush & Barin (2005) do from the ground upwards
    /// ([`bottom_up`]). With the true base wrench it equals [`Reference::joint_wrenches`].
    ///
    /// # Errors
    /// [`Error::NotSerial`] for a model that branches; as [`Reference::joint_wrenches`].
    pub fn joint_wrenches_bottom_up(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        base: Wrench,
    ) -> Result<Vec<Wrench>, Error> {
        check_q(&self.model, q)?;
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        if !self.model.is_serial() {
            return Err(Error::NotSerial);
        }
        let (x_up, h) = inertial_forces(&self.tree, &self.q(q), &self.v(v), &self.v(a), true);
        let base = Force::new(Vec3(base.couple), Vec3(base.force));
        wrenches(&bottom_up(&self.tree, &x_up, &h, base))
    }

    fn joint_of_v(&self, k: usize) -> String {
        self.model
            .joint_of_velocity(k)
            .map_or_else(String::new, |j| j.name.clone())
    }
}
