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
use crate::spatial::{Force, Inertia, Mat3, Motion, Transform, Vec3};

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
                armature: n.armature,
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
    (inverse(&ltdl), pivots)
}

/// The identity, `n × n` row-major.
fn identity<S: Scalar>(n: usize) -> Vec<S> {
    (0..n * n)
        .map(|k| S::from_f64(if k / n == k % n { 1.0 } else { 0.0 }))
        .collect()
}

/// `M⁻¹`, row-major: each column solved, its upper triangle kept and mirrored (`M⁻¹` is
/// symmetric; on a symbolic scalar the entries below the diagonal are then never computed,
/// nearly halving the operations).
fn inverse<S: Scalar>(ltdl: &Ltdl<S>) -> Vec<S> {
    let n = ltdl.n;
    let mut inv = solve_columns(ltdl, &identity(n), false);
    for i in 0..n {
        for j in 0..i {
            inv[i * n + j] = inv[j * n + i];
        }
    }
    inv
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
/// `M(q)` and `h` is `N·q̇ + g` (computed by the caller's formulation), and `dtau(a)` gives
/// `(∂τ/∂q, ∂τ/∂v)` of inverse dynamics at `(q, v, a)`. `q̈` is solved with `M`'s
/// factorization, the derivatives are `−M⁻¹·∂τ/∂(q, v)` at `a = q̈`, each column solved with the
/// same factorization.
pub fn forward_dynamics_derivatives_with<S: Scalar>(
    tau: &[S],
    m: Vec<S>,
    h: &[S],
    dtau: impl FnOnce(&[S]) -> (Vec<S>, Vec<S>),
) -> FdDerivatives<S> {
    let nv = tau.len();
    let (ltdl, pivots) = Ltdl::new(m, nv);
    let b: Vec<S> = tau.iter().zip(h).map(|(&t, &h)| t - h).collect();
    let qdd = ltdl.solve(b);
    let (dtau_dq, dtau_dv) = dtau(&qdd);
    FdDerivatives {
        dqdd_dq: solve_columns(&ltdl, &dtau_dq, true),
        dqdd_dv: solve_columns(&ltdl, &dtau_dv, true),
        minv: inverse(&ltdl),
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
    forward_dynamics_derivatives_with(tau, m, &h, |qdd| {
        inverse_dynamics_derivatives(tree, q, v, qdd)
    })
}

/// The forward pass of [`inverse_dynamics_derivatives_analytic`], in the world frame.
struct WorldMotions<T> {
    /// World → node transforms.
    x0: Vec<Transform<T>>,
    /// Each node's velocity and acceleration (gravity as the base's).
    ov: Vec<Motion<T>>,
    oa: Vec<Motion<T>>,
    /// Per velocity column: the joint's axis `s` and the partial derivatives of its motion.
    s: Vec<Motion<T>>,
    dv_dq: Vec<Motion<T>>,
    da_dq: Vec<Motion<T>>,
    da_dv: Vec<Motion<T>>,
}

fn world_motions<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T], a: &[T]) -> WorldMotions<T> {
    let nv = tree.nv;
    let nodes = &tree.nodes;
    let x_up = tree.x_up(q);
    let x0 = super::centroidal::world_transforms(tree, &x_up);
    let base = tree.base_acceleration(true);
    // World-frame velocity and acceleration (gravity as the base's) of every node.
    let (mut ov, mut oa): (Vec<Motion<T>>, Vec<Motion<T>>) = (Vec::new(), Vec::new());
    let (mut vel, mut acc): (Vec<Motion<T>>, Vec<Motion<T>>) = (Vec::new(), Vec::new());
    for (i, node) in nodes.iter().enumerate() {
        let v_j = node.s_mul(v);
        let (v_i, a_i) = match node.parent {
            None => (v_j, x_up[i].apply_motion(base) + node.s_mul(a)),
            Some(p) => {
                let v_i = x_up[i].apply_motion(vel[p]) + v_j;
                let a_i = x_up[i].apply_motion(acc[p]) + node.s_mul(a) + v_i.cross_motion(v_j);
                (v_i, a_i)
            }
        };
        let n = &node.name;
        vel.push(v_i.label(format_args!("{n}_w"), format_args!("{n}_v")));
        acc.push(a_i.label(format_args!("{n}_dw"), format_args!("{n}_dv")));
        ov.push(
            x0[i]
                .inv_apply_motion(v_i)
                .label(format_args!("{n}_w0"), format_args!("{n}_v0")),
        );
        oa.push(
            x0[i]
                .inv_apply_motion(a_i)
                .label(format_args!("{n}_dw0"), format_args!("{n}_dv0")),
        );
    }
    // Per column: s, ∂v/∂q, ∂a/∂q, ∂a/∂v (world frame).
    let mut s = alloc::vec![Motion::zero(); nv];
    let mut dv_dq = alloc::vec![Motion::zero(); nv];
    let mut da_dq = alloc::vec![Motion::zero(); nv];
    let mut da_dv = alloc::vec![Motion::zero(); nv];
    for (i, node) in nodes.iter().enumerate() {
        let (v_p, a_p) = match node.parent {
            None => (Motion::zero(), base),
            Some(p) => (ov[p], oa[p]),
        };
        for c in 0..node.nv() {
            let k = node.v_at + c;
            let n = alloc::format!("{}_s{c}", node.name);
            s[k] = x0[i].inv_apply_motion(node.s_col(c));
            dv_dq[k] = v_p.cross_motion(s[k]);
            da_dq[k] = (a_p.cross_motion(s[k]) + v_p.cross_motion(dv_dq[k]))
                .label(format_args!("{n}_da_dq_w"), format_args!("{n}_da_dq_v"));
            da_dv[k] = (ov[i].cross_motion(s[k]) + dv_dq[k])
                .label(format_args!("{n}_da_dv_w"), format_args!("{n}_da_dv_v"));
        }
    }
    WorldMotions {
        x0,
        ov,
        oa,
        s,
        dv_dq,
        da_dq,
        da_dv,
    }
}

/// `(∂τ/∂q, ∂τ/∂v)` as [`inverse_dynamics_derivatives`], by the analytical recursion of
/// Carpentier & Mansard (RSS 2018, Algorithm 1) instead of duals: every quantity in the world
/// frame, where moving joint `j` changes a quantity of a body below it by a cross product with
/// the joint's world axis `s_j`. A forward pass gives, per column, `s` and the partial
/// derivatives of the joint's own motion (`∂v/∂q = v_λ × s`, `∂a/∂q = a_λ × s + v_λ × ∂v/∂q`,
/// `∂a/∂v = v × s + ∂v/∂q`, gravity entering as the base acceleration); a backward pass carries
/// three composites per node (inertia `I_c`, its rate `İ_c = Σ v ×* I − I·v×`, momentum `h_c`,
/// and the net force `f_c`) and fills each entry with one or two dot products:
/// - below the diagonal (row `k` of a joint below column `j`'s):
///   `s_kᵀ·(I_c,k·∂a_j + B_k·∂v_j)`, `B·x = İ_c·x + x ×* h_c`;
/// - on and above it (row `j`, column `k` at or below): `s_jᵀ·∂f_k`, with
///   `∂f_k/∂q = B_k·∂v_k/∂q + I_c,k·∂a_k/∂q (+ s_k ×* f_c,k` for the rows of the joints above `k`),
///   `∂f_k/∂v = B_k·s_k + I_c,k·∂a_k/∂v`.
///
/// A second formulation, from other equations than the forward-mode one: each checks the other
/// (`dynamics/tests/derivatives.rs`), and the generator traces both and keeps the cheaper.
pub fn inverse_dynamics_derivatives_analytic<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
) -> (Vec<T>, Vec<T>) {
    let nv = tree.nv;
    let nodes = &tree.nodes;
    let WorldMotions {
        x0,
        ov,
        oa,
        s,
        dv_dq,
        da_dq,
        da_dv,
    } = world_motions(tree, q, v, a);
    // Composites, from the leaves in.
    let mut ic: Vec<Inertia<T>> = Vec::new();
    let mut idc: Vec<Inertia<T>> = Vec::new();
    let mut hc: Vec<Force<T>> = Vec::new();
    let mut fc: Vec<Force<T>> = Vec::new();
    for (i, node) in nodes.iter().enumerate() {
        let oi = node.inertia.to_parent(&x0[i]);
        let h = oi.mul_motion(ov[i]);
        ic.push(oi);
        idc.push(super::centroidal::inertia_rate(&oi, ov[i]));
        hc.push(h);
        fc.push(oi.mul_motion(oa[i]) + ov[i].cross_force(h));
    }
    // The last node of each subtree (depth-first order: a subtree is contiguous).
    let mut last: Vec<usize> = (0..nodes.len()).collect();
    for i in (0..nodes.len()).rev() {
        if let Some(p) = nodes[i].parent {
            last[p] = last[p].max(last[i]);
        }
    }
    let mut df_da = alloc::vec![Force::zero(); nv];
    let mut y = alloc::vec![Force::zero(); nv];
    let mut df_dq = alloc::vec![Force::zero(); nv];
    let mut df_dv = alloc::vec![Force::zero(); nv];
    let mut dq = alloc::vec![T::zero(); nv * nv];
    let mut dvm = alloc::vec![T::zero(); nv * nv];
    for (i, node) in nodes.iter().enumerate().rev() {
        let n = &node.name;
        ic[i] = ic[i].label(format_args!("{n}_ic0"));
        idc[i] = idc[i].label(format_args!("{n}_idc0"));
        hc[i] = hc[i].label(format_args!("{n}_hc0_n"), format_args!("{n}_hc0_f"));
        fc[i] = fc[i].label(format_args!("{n}_fc0_n"), format_args!("{n}_fc0_f"));
        let (own, end) = (
            node.v_at..node.v_at + node.nv(),
            nodes[last[i]].v_at + nodes[last[i]].nv(),
        );
        let b = |x: Motion<T>| idc[i].mul_motion(x) + x.cross_force(hc[i]);
        for k in own.clone() {
            df_da[k] = ic[i].mul_motion(s[k]);
            y[k] = idc[i].mul_motion(s[k]) - s[k].cross_force(hc[i]);
            df_dq[k] = b(dv_dq[k]) + ic[i].mul_motion(da_dq[k]);
            df_dv[k] = b(s[k]) + ic[i].mul_motion(da_dv[k]);
        }
        for j in own.clone() {
            // Rows below: the joints in this subtree under this node.
            for k in own.end..end {
                dq[k * nv + j] = da_dq[j].dot(df_da[k]) + dv_dq[j].dot(y[k]);
                dvm[k * nv + j] = da_dv[j].dot(df_da[k]) + s[j].dot(y[k]);
            }
            // This joint's rows, from its own columns down.
            for k in own.start..end {
                dq[j * nv + k] = s[j].dot(df_dq[k]);
                dvm[j * nv + k] = s[j].dot(df_dv[k]);
            }
        }
        for k in own {
            df_dq[k] = df_dq[k] + s[k].cross_force(fc[i]);
        }
        if let Some(p) = node.parent {
            ic[p] = ic[p].add(&ic[i]);
            idc[p] = idc[p].add(&idc[i]);
            hc[p] = hc[p] + hc[i];
            fc[p] = fc[p] + fc[i];
        }
    }
    (dq, dvm)
}
