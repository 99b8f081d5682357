//! Derivatives of the dynamics: `∂τ/∂q`, `∂τ/∂v` of inverse dynamics, `∂q̈/∂q`, `∂q̈/∂v` of
//! forward dynamics, and `M⁻¹ = ∂q̈/∂τ`, by **forward-mode automatic differentiation** of the
//! recursions themselves.
//!
//! [`Dual`] is a [`Scalar`] carrying a value and its derivative along one direction. Running a
//! recursion on it (RNEA here) computes the value and its directional derivative together; one
//! run per direction gives one column of the Jacobian. On `f64` that is the reference's
//! derivative; on the generator's symbolic scalar the value part of every run is the same
//! expression graph (hash-consed, so computed once), and derivative parts that are zero by the
//! tree's structure (a body's velocity does not depend on the joints below it) fold away, which
//! is forward mode with one direction per coordinate, written once.
//!
//! # Directions: the tangent space
//! `∂/∂q` is taken along the velocity-sized tangent displacement `δ` of [`configuration_tangent`]
//! (`q ⊕ δ`, the runtime's `control::tangent::retract`), so every derivative with respect to the
//! configuration is `NV` columns wide:
//! - revolute, prismatic and Euler-angle coordinates: `q + δ`, so `∂/∂δ_k = ∂/∂q_k`;
//! - quaternion `[w, x, y, z]`: `q ⊗ exp(δ/2)`, `δ` a rotation vector in the child frame (the
//!   body-frame increment, as Pinocchio takes it), so `∂q/∂δ_k = ½·q ⊗ (0, e_k)`;
//! - free quaternion: the position moves by `R(q)·δ_lin` (the displacement in the child frame,
//!   like the linear velocity), the quaternion as above.
//!
//! # Forward dynamics
//! `M(q)·q̈ + h(q, v) = τ` holds identically, so with `q̈ = FD(q, v, τ)` and `ID` inverse
//! dynamics, `∂q̈/∂q = −M⁻¹·∂ID/∂q` and `∂q̈/∂v = −M⁻¹·∂ID/∂v`, both at `a = q̈`, and
//! `∂q̈/∂τ = M⁻¹` (Carpentier & Mansard, "Analytical derivatives of rigid body dynamics
//! algorithms", RSS 2018, §III-C). `M⁻¹` and the products with it come from the sparse `LᵀDL`
//! of `M` ([`super::ltdl`]), one solve per column.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::ltdl::Ltdl;
use super::tree::{Node, NodeJoint, Tree};
use crate::scalar::Scalar;
use crate::spatial::{Inertia, Mat3, Transform, Vec3};

/// What a [`Dual`]'s derivative is taken with respect to, for the labels of generated code
/// (`trunk_w_x_dq3`): nothing yet, tangent coordinate `k` of the configuration, or velocity `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrt {
    /// A constant of the direction (no seed reached it).
    None,
    /// `∂/∂δ_k`, the tangent of the configuration.
    Q(usize),
    /// `∂/∂v_k`.
    V(usize),
}

impl fmt::Display for Wrt {
    /// `_dq3`, `_dv0`, or nothing.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Wrt::None => Ok(()),
            Wrt::Q(k) => write!(f, "_dq{k}"),
            Wrt::V(k) => write!(f, "_dv{k}"),
        }
    }
}

/// A number with its derivative along one direction: `re + ε·du`, `ε² = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<S> {
    /// The value.
    pub re: S,
    /// Its derivative along the direction.
    pub du: S,
    /// The direction, for labels only.
    pub wrt: Wrt,
}

impl<S: Scalar> Dual<S> {
    /// A constant: derivative zero.
    pub fn constant(re: S) -> Self {
        Dual {
            re,
            du: S::zero(),
            wrt: Wrt::None,
        }
    }

    /// A value with the derivative `du` along `wrt`.
    pub fn seeded(re: S, du: S, wrt: Wrt) -> Self {
        Dual { re, du, wrt }
    }

    fn with(self, other: Self, re: S, du: S) -> Self {
        let wrt = match self.wrt {
            Wrt::None => other.wrt,
            w => w,
        };
        Dual { re, du, wrt }
    }
}

impl<S: Scalar> Add for Dual<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        self.with(o, self.re + o.re, self.du + o.du)
    }
}

impl<S: Scalar> Sub for Dual<S> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self.with(o, self.re - o.re, self.du - o.du)
    }
}

impl<S: Scalar> Mul for Dual<S> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        self.with(o, self.re * o.re, self.du * o.re + self.re * o.du)
    }
}

impl<S: Scalar> Div for Dual<S> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let re = self.re / o.re;
        self.with(o, re, (self.du - re * o.du) / o.re)
    }
}

impl<S: Scalar> Neg for Dual<S> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            re: -self.re,
            du: -self.du,
            wrt: self.wrt,
        }
    }
}

impl<S: Scalar> Scalar for Dual<S> {
    fn from_f64(x: f64) -> Self {
        Dual::constant(S::from_f64(x))
    }
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (
            Dual {
                re: s,
                du: c * self.du,
                wrt: self.wrt,
            },
            Dual {
                re: c,
                du: -(s * self.du),
                wrt: self.wrt,
            },
        )
    }
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        Dual {
            re: r,
            du: self.du / (r + r),
            wrt: self.wrt,
        }
    }
    /// Labels the value `name` and the derivative `name_dq3` (after its direction).
    fn label(self, name: fmt::Arguments<'_>) -> Self {
        let re = self.re.label(name);
        let du = self.du.label(format_args!("{}{}", name, self.wrt));
        Dual { re, du, ..self }
    }
}

fn map3<S: Copy, T>(v: Vec3<S>, f: &impl Fn(S) -> T) -> Vec3<T> {
    Vec3(v.0.map(f))
}

fn map33<S: Copy, T>(m: Mat3<S>, f: &impl Fn(S) -> T) -> Mat3<T> {
    Mat3(m.0.map(|r| r.map(f)))
}

/// The same tree with every number `x` replaced by `f(x)` (a constant [`Dual`] for a tree to
/// differentiate on).
pub fn map_tree<S: Scalar, T: Scalar>(tree: &Tree<S>, f: impl Fn(S) -> T) -> Tree<T> {
    let f = &f;
    Tree {
        nodes: tree
            .nodes
            .iter()
            .map(|n| Node {
                name: n.name.clone(),
                parent: n.parent,
                x_tree: Transform {
                    e: map33(n.x_tree.e, f),
                    r: map3(n.x_tree.r, f),
                },
                joint: match n.joint {
                    NodeJoint::Revolute(a) => NodeJoint::Revolute(map3(a, f)),
                    NodeJoint::Prismatic(a) => NodeJoint::Prismatic(map3(a, f)),
                    NodeJoint::Quaternion => NodeJoint::Quaternion,
                    NodeJoint::FreeQuaternion => NodeJoint::FreeQuaternion,
                    NodeJoint::Fixed => NodeJoint::Fixed,
                },
                q_at: n.q_at,
                v_at: n.v_at,
                inertia: Inertia {
                    m: f(n.inertia.m),
                    h: map3(n.inertia.h, f),
                    i: map33(n.inertia.i, f),
                },
            })
            .collect(),
        body_node: tree.body_node.clone(),
        gravity: map3(tree.gravity, f),
        nq: tree.nq,
        nv: tree.nv,
    }
}

/// `∂q/∂δ_k`: how the position coordinates move along tangent coordinate `k` (`k < nv`; see
/// the [module docs](self)). `nq` entries, zero outside the joint that owns `k`.
pub fn configuration_tangent<S: Scalar>(tree: &Tree<S>, q: &[S], k: usize) -> Vec<S> {
    let mut dq = vec![S::zero(); tree.nq];
    let Some(node) = tree
        .nodes
        .iter()
        .find(|n| n.v_at <= k && k < n.v_at + n.nv())
    else {
        return dq;
    };
    let j = k - node.v_at;
    let half = S::from_f64(0.5);
    // ½·q ⊗ (0, e_j) for the quaternion at `at`.
    let quaternion = |dq: &mut [S], at: usize, j: usize| {
        let [w, x, y, z] = [q[at], q[at + 1], q[at + 2], q[at + 3]];
        let d = match j {
            0 => [-x, w, z, -y],
            1 => [-y, -z, w, x],
            _ => [-z, y, -x, w],
        };
        for (i, di) in d.into_iter().enumerate() {
            dq[at + i] = half * di;
        }
    };
    match node.joint {
        NodeJoint::Revolute(_) | NodeJoint::Prismatic(_) => dq[node.q_at] = S::one(),
        NodeJoint::Quaternion => quaternion(&mut dq, node.q_at, j),
        NodeJoint::FreeQuaternion if j < 3 => {
            let at = node.q_at;
            let r = Mat3::quaternion([q[at + 3], q[at + 4], q[at + 5], q[at + 6]]);
            for i in 0..3 {
                dq[at + i] = r.0[i][j];
            }
        }
        NodeJoint::FreeQuaternion => quaternion(&mut dq, node.q_at + 3, j - 3),
        NodeJoint::Fixed => {}
    }
    dq
}

/// Inverse dynamics on the dual tree: `(tree, q, v, a) ↦ τ`, gravity included.
pub trait DualRnea<S> {
    /// `τ` on duals.
    fn rnea(
        &self,
        tree: &Tree<Dual<S>>,
        q: &[Dual<S>],
        v: &[Dual<S>],
        a: &[Dual<S>],
    ) -> Vec<Dual<S>>;
}

impl<S, F> DualRnea<S> for F
where
    F: Fn(&Tree<Dual<S>>, &[Dual<S>], &[Dual<S>], &[Dual<S>]) -> Vec<Dual<S>>,
{
    fn rnea(
        &self,
        tree: &Tree<Dual<S>>,
        q: &[Dual<S>],
        v: &[Dual<S>],
        a: &[Dual<S>],
    ) -> Vec<Dual<S>> {
        self(tree, q, v, a)
    }
}

/// The reference's RNEA with gravity, on duals.
pub fn reference_rnea<S: Scalar>(
    tree: &Tree<Dual<S>>,
    q: &[Dual<S>],
    v: &[Dual<S>],
    a: &[Dual<S>],
) -> Vec<Dual<S>> {
    super::rnea(tree, q, v, a, true)
}

/// `(∂τ/∂q, ∂τ/∂v)` of inverse dynamics with gravity at `(q, v, a)`, each `nv × nv` row-major
/// (`[i * nv + j] = ∂τ_i/∂δ_j`), by forward mode through `rnea` on `tree` (see the
/// [module docs](self)).
pub fn inverse_dynamics_derivatives_with<S: Scalar>(
    tree: &Tree<S>,
    q: &[S],
    v: &[S],
    a: &[S],
    rnea: &impl DualRnea<S>,
) -> (Vec<S>, Vec<S>) {
    let nv = tree.nv;
    let dual_tree = map_tree(tree, Dual::constant);
    let constant = |x: &[S]| -> Vec<Dual<S>> { x.iter().map(|&x| Dual::constant(x)).collect() };
    let (qc, vc, ac) = (constant(q), constant(v), constant(a));
    let mut dq = vec![S::zero(); nv * nv];
    let mut dv = vec![S::zero(); nv * nv];
    for k in 0..nv {
        let tangent = configuration_tangent(tree, q, k);
        let qk: Vec<Dual<S>> = q
            .iter()
            .zip(tangent)
            .map(|(&x, d)| Dual::seeded(x, d, Wrt::Q(k)))
            .collect();
        for (i, t) in rnea.rnea(&dual_tree, &qk, &vc, &ac).iter().enumerate() {
            dq[i * nv + k] = t.du;
        }
        let vk: Vec<Dual<S>> = v
            .iter()
            .enumerate()
            .map(|(i, &x)| Dual::seeded(x, S::from_f64(if i == k { 1.0 } else { 0.0 }), Wrt::V(k)))
            .collect();
        for (i, t) in rnea.rnea(&dual_tree, &qc, &vk, &ac).iter().enumerate() {
            dv[i * nv + k] = t.du;
        }
    }
    (dq, dv)
}

/// [`inverse_dynamics_derivatives_with`] the reference's RNEA.
pub fn inverse_dynamics_derivatives<S: Scalar>(
    tree: &Tree<S>,
    q: &[S],
    v: &[S],
    a: &[S],
) -> (Vec<S>, Vec<S>) {
    inverse_dynamics_derivatives_with(tree, q, v, a, &reference_rnea::<S>)
}

/// `M⁻¹` from `M` (row-major, symmetric), by its sparse `LᵀDL`: row-major `M⁻¹` and the pivots
/// with their unreduced values (all must be positive, as for forward dynamics).
pub fn mass_matrix_inverse_from<S: Scalar>(m: Vec<S>, nv: usize) -> (Vec<S>, Vec<(S, S)>) {
    let (ltdl, pivots) = Ltdl::new(m, nv);
    (solve_columns(&ltdl, &identity(nv), false), pivots)
}

/// The identity, `n × n` row-major.
fn identity<S: Scalar>(n: usize) -> Vec<S> {
    (0..n * n)
        .map(|k| S::from_f64(if k / n == k % n { 1.0 } else { 0.0 }))
        .collect()
}

/// `M⁻¹·x` (or `−M⁻¹·x`) for a row-major `n × n` matrix `x`, one solve per column.
fn solve_columns<S: Scalar>(ltdl: &Ltdl<S>, x: &[S], negate: bool) -> Vec<S> {
    let n = ltdl.n;
    let mut out = vec![S::zero(); n * n];
    for j in 0..n {
        let col: Vec<S> = (0..n)
            .map(|i| if negate { -x[i * n + j] } else { x[i * n + j] })
            .collect();
        for (i, y) in ltdl.solve(col).into_iter().enumerate() {
            out[i * n + j] = y;
        }
    }
    out
}

/// What [`forward_dynamics_derivatives_with`] computes.
#[derive(Clone, Debug)]
pub struct FdDerivatives<S> {
    /// `q̈`.
    pub qdd: Vec<S>,
    /// `∂q̈/∂q`, row-major `nv × nv`.
    pub dqdd_dq: Vec<S>,
    /// `∂q̈/∂v`, row-major.
    pub dqdd_dv: Vec<S>,
    /// `M⁻¹ = ∂q̈/∂τ`, row-major.
    pub minv: Vec<S>,
    /// The pivots of `M = LᵀDL` with their unreduced values.
    pub pivots: Vec<(S, S)>,
}

/// Forward dynamics and its derivatives at `(q, v, τ)` (see the [module docs](self)): `m` is
/// `M(q)` and `h` is `N·q̇ + g` (computed by the caller's formulation), `rnea` inverse dynamics
/// on duals. `q̈` is solved with `M`'s factorization, the derivatives are `−M⁻¹·∂τ/∂(q, v)` at
/// `a = q̈`, each column solved with the same factorization.
pub fn forward_dynamics_derivatives_with<S: Scalar>(
    tree: &Tree<S>,
    q: &[S],
    v: &[S],
    tau: &[S],
    m: Vec<S>,
    h: &[S],
    rnea: &impl DualRnea<S>,
) -> FdDerivatives<S> {
    let nv = tree.nv;
    let (ltdl, pivots) = Ltdl::new(m, nv);
    let b: Vec<S> = tau.iter().zip(h).map(|(&t, &h)| t - h).collect();
    let qdd = ltdl.solve(b);
    let (dtau_dq, dtau_dv) = inverse_dynamics_derivatives_with(tree, q, v, &qdd, rnea);
    FdDerivatives {
        dqdd_dq: solve_columns(&ltdl, &dtau_dq, true),
        dqdd_dv: solve_columns(&ltdl, &dtau_dv, true),
        minv: solve_columns(&ltdl, &identity(nv), false),
        qdd,
        pivots,
    }
}

/// [`forward_dynamics_derivatives_with`] the reference's CRBA and RNEA.
pub fn forward_dynamics_derivatives<S: Scalar>(
    tree: &Tree<S>,
    q: &[S],
    v: &[S],
    tau: &[S],
) -> FdDerivatives<S> {
    let zero = vec![S::zero(); tree.nv];
    let m = super::crba(tree, q);
    let h = super::rnea(tree, q, v, &zero, true);
    forward_dynamics_derivatives_with(tree, q, v, tau, m, &h, &reference_rnea::<S>)
}
