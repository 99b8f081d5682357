//! The frames' outputs: placements, velocities, classical accelerations, Jacobians and their
//! time variations, for the frames a description names (`frames: [tool, left_sole]`), all
//! frames in one traced pass (the graph shares what they have in common).
//!
//! On the model's tree ([`Tree`], Euler joints expanded into single-axis nodes), with `X0[i]`
//! the world → node `i` transform (`E_i` the node's orientation transposed, `r_i` its origin in
//! the world) and a frame fixed to body `b` at `(R_p, p)` in the body's frame:
//! - placement: `world_R_frame = E_bᵀ·R_p`, origin `o = r_b + E_bᵀ·p`;
//! - velocity (LOCAL): the body's spatial velocity `[ω; v]` in its frame (the recursion
//!   `v_i = X_up·v_λ + S_i·q̇_i`) moved to the frame's origin and axes:
//!   `[R_pᵀ·ω; R_pᵀ·(v + ω × p)]`;
//! - classical acceleration (LOCAL_WORLD_ALIGNED): with the spatial acceleration
//!   `a_i = X_up·a_λ + S_i·q̈_i + v_i × S_i·q̇_i` (no gravity: kinematics), the origin's
//!   `p̈ = a_lin + ω̇ × p + ω × (v + ω × p)` in the body's axes, both rotated to the world's;
//! - Jacobians: each ancestor node `i`'s motion subspace column in world axes, `a = E_iᵀ·S_ω`,
//!   `l = E_iᵀ·S_v`; WORLD (the motion of the point at the world's origin) `[a; l + r_i × a]`;
//!   LOCAL_WORLD_ALIGNED `[a; l + a × d_i]` with `d_i = o − r_i` summed from the frame down
//!   (no world positions subtracted: `Kinematics::offsets`); LOCAL rotates that into the
//!   frame's axes;
//! - time variations: `S_i` is constant in node `i`'s frame, so WORLD's `ṡ = v_i⁰ × s` (the
//!   node's spatial velocity in world coordinates, Featherstone's motion cross product);
//!   LOCAL_WORLD_ALIGNED differentiates `[a; l + a × d_i]` directly,
//!   `[ω_i × a; ω_i × l + (ω_i × a) × d_i + a × (ȯ − ṙ_i)]` (a third fewer operations than
//!   moving `ṡ` to the origin); and, from `J_local = Wᵀ·J_lwa` (block by block,
//!   `W = world_R_frame`, `Ẇ = [ω]×·W`), `J̇_local = Wᵀ·(J̇_lwa − ω × J_lwa)`.
//!
//! Mimic joints: the tree's columns reduced through the coupling (`Coupling::reduce_columns`).

use articulated_dynamics::model::{Model, Placement};
use articulated_dynamics::reference::centroidal::world_transforms;
use articulated_dynamics::reference::derivatives::{configuration_tangent, map_tree, Dual, Wrt};
use articulated_dynamics::reference::Tree;
use articulated_dynamics::spatial::{Mat3, Motion, Transform, Vec3};
use articulated_dynamics::Scalar;

use super::{inputs, symbolic_tree, tree_inputs, Formulation, Traced, Variant};
use crate::options::Output;
use crate::sym::{self, Sym, Var};

/// A frame the description names: its parent body (`None`: the world) and its placement there.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameAt {
    /// Its name (for the labels of its values).
    pub name: String,
    /// The body it is fixed to.
    pub parent: Option<usize>,
    /// Its placement in the body's frame.
    pub placement: Placement,
}

/// Which of the three reference frames a Jacobian is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum In {
    Local,
    World,
    LocalWorldAligned,
}

/// The one variant frames are traced with.
fn variant(quasi_static: bool) -> Variant {
    Variant {
        regrouped: false,
        formulation: Formulation::Reference,
        method: None,
        analytic: false,
        coriolis: false,
        quasi_static,
    }
}

/// Traces a frame output for `frames` (in that order).
pub fn trace(model: &Model, output: Output, frames: &[FrameAt], quasi_static: bool) -> Traced {
    let variant = variant(quasi_static);
    let (graph, values) = sym::trace(|| {
        let (tree, turns) = symbolic_tree(model, false);
        let c = model.coupling();
        let (q, v, a) = tree_inputs(model, &c, &turns, variant);
        let params = inputs(model.params.len(), Var::Param);
        let k = Kinematics::new(&tree, &q, &v);
        let mut values = Vec::new();
        for f in frames {
            let frame = k.frame(f, &params);
            let name = &f.name;
            match output {
                Output::FramePlacements => {
                    let w = frame.rotation;
                    for (r, row) in w.0.iter().enumerate() {
                        for (col, x) in row.iter().enumerate() {
                            values.push(x.label(format_args!("{name}_rot_{r}{col}")));
                        }
                    }
                    values.extend(label3(frame.origin, name, "pos"));
                }
                Output::FrameVelocities => {
                    let (w, v) = k.local_velocity(&frame);
                    values.extend(label3(w, name, "v_w"));
                    values.extend(label3(v, name, "v_v"));
                }
                Output::FrameAccelerations => {
                    let (dw, ddp) = k.classical_acceleration(&frame, &a);
                    values.extend(label3(dw, name, "acc_w"));
                    values.extend(label3(ddp, name, "acc_p"));
                }
                Output::FrameJacobiansLocal
                | Output::FrameJacobiansWorld
                | Output::FrameJacobiansLocalWorldAligned => {
                    let j = k.jacobian(&frame, reference_frame(output));
                    values.extend(label_matrix(c.reduce_columns(&j, 6), name, "j", model.nv()));
                }
                Output::FrameJacobianTimeVariationsLocal
                | Output::FrameJacobianTimeVariationsWorld
                | Output::FrameJacobianTimeVariationsLocalWorldAligned => {
                    let j = k.jacobian_rate(&frame, reference_frame(output));
                    values.extend(label_matrix(
                        c.reduce_columns(&j, 6),
                        name,
                        "dj",
                        model.nv(),
                    ));
                }
                Output::FrameVelocityDerivatives => {
                    let nv = model.nv();
                    let (dq, dv) = derivatives(&tree, &q, &v, &a, f, &params, false);
                    values.extend(label_matrix(c.reduce_columns(&dq, 6), name, "dv_dq", nv));
                    values.extend(label_matrix(c.reduce_columns(&dv, 6), name, "dv_dv", nv));
                }
                Output::FrameAccelerationDerivatives => {
                    let nv = model.nv();
                    let (dq, dv) = derivatives(&tree, &q, &v, &a, f, &params, true);
                    values.extend(label_matrix(c.reduce_columns(&dq, 6), name, "da_dq", nv));
                    values.extend(label_matrix(c.reduce_columns(&dv, 6), name, "da_dv", nv));
                    // ∂α/∂a is the LOCAL_WORLD_ALIGNED Jacobian.
                    let j = k.jacobian(&frame, In::LocalWorldAligned);
                    values.extend(label_matrix(c.reduce_columns(&j, 6), name, "da_da", nv));
                }
                other => unreachable!("`{}` is not a frame output", other.name()),
            }
        }
        values
    });
    Traced {
        output,
        graph,
        values,
        pivots: None,
        variant,
        candidates: Vec::new(),
    }
}

/// `(∂x/∂q, ∂x/∂v)` of the frame's LOCAL velocity (`acceleration`: its classical
/// acceleration at `a`), `6 × nv` of the tree each, row-major: the kinematics run on dual
/// numbers once per tangent direction (`q` along the configuration's tangent, as the dynamics'
/// derivatives take it), the value parts hash-consing to the same nodes.
fn derivatives(
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
    f: &FrameAt,
    params: &[Sym],
    acceleration: bool,
) -> (Vec<Sym>, Vec<Sym>) {
    let nv = tree.nv;
    let dual_tree = map_tree(tree, Dual::constant);
    let constant = |x: &[Sym]| -> Vec<Dual<Sym>> { x.iter().map(|&x| Dual::constant(x)).collect() };
    let (qc, vc, ac, pc) = (constant(q), constant(v), constant(a), constant(params));
    let value = |q: &[Dual<Sym>], v: &[Dual<Sym>]| -> [Dual<Sym>; 6] {
        let k = Kinematics::new(&dual_tree, q, v);
        let frame = k.frame(f, &pc);
        let (x, y) = if acceleration {
            k.classical_acceleration(&frame, &ac)
        } else {
            k.local_velocity(&frame)
        };
        [x.0[0], x.0[1], x.0[2], y.0[0], y.0[1], y.0[2]]
    };
    let (mut dq, mut dv) = (vec![Sym::zero(); 6 * nv], vec![Sym::zero(); 6 * nv]);
    for col in 0..nv {
        let tangent = configuration_tangent(tree, q, col);
        let qk: Vec<Dual<Sym>> = q
            .iter()
            .zip(tangent)
            .map(|(&x, d)| Dual::seeded(x, d, Wrt::Q(col)))
            .collect();
        for (r, x) in value(&qk, &vc).into_iter().enumerate() {
            dq[r * nv + col] = x.du;
        }
        let vk: Vec<Dual<Sym>> = v
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                Dual::seeded(
                    x,
                    Sym::from_f64(if i == col { 1.0 } else { 0.0 }),
                    Wrt::V(col),
                )
            })
            .collect();
        for (r, x) in value(&qc, &vk).into_iter().enumerate() {
            dv[r * nv + col] = x.du;
        }
    }
    (dq, dv)
}

fn reference_frame(output: Output) -> In {
    match output {
        Output::FrameJacobiansLocal | Output::FrameJacobianTimeVariationsLocal => In::Local,
        Output::FrameJacobiansWorld | Output::FrameJacobianTimeVariationsWorld => In::World,
        _ => In::LocalWorldAligned,
    }
}

fn label3(x: Vec3<Sym>, name: &str, stem: &str) -> [Sym; 3] {
    let [a, b, c] = x.0;
    [
        a.label(format_args!("{name}_{stem}x")),
        b.label(format_args!("{name}_{stem}y")),
        c.label(format_args!("{name}_{stem}z")),
    ]
}

fn label_matrix(values: Vec<Sym>, name: &str, stem: &str, nv: usize) -> Vec<Sym> {
    values
        .into_iter()
        .enumerate()
        .map(|(k, x)| {
            x.label(format_args!(
                "{name}_{stem}_{}_{}",
                k / nv.max(1),
                k % nv.max(1)
            ))
        })
        .collect()
}

/// A frame on the traced tree: its body's node, its placement in the world.
pub(super) struct Frame<T> {
    /// The node of its body, `None` for a frame fixed to the world.
    pub(super) node: Option<usize>,
    /// Its origin in its body's frame.
    pub(super) offset: Vec3<T>,
    /// Its axes in its body's frame, `body_R_frame`.
    pub(super) in_body: Mat3<T>,
    /// `world_R_frame`.
    pub(super) rotation: Mat3<T>,
    /// Its origin in the world.
    pub(super) origin: Vec3<T>,
}

/// The tree's kinematics at `(q, v)`: each node's transforms and spatial velocity.
pub(super) struct Kinematics<'a, T> {
    tree: &'a Tree<T>,
    /// Parent → node.
    pub(super) x_up: Vec<Transform<T>>,
    /// World → node.
    pub(super) x0: Vec<Transform<T>>,
    /// Each node's spatial velocity in its own frame.
    pub(super) vel: Vec<Motion<T>>,
    /// The velocities `v` of the tree.
    v: Vec<T>,
}

impl<'a, T: Scalar> Kinematics<'a, T> {
    pub(super) fn new(tree: &'a Tree<T>, q: &[T], v: &[T]) -> Self {
        let x_up = tree.x_up(q);
        let x0 = world_transforms(tree, &x_up);
        let mut vel: Vec<Motion<T>> = Vec::with_capacity(tree.nodes.len());
        for (i, node) in tree.nodes.iter().enumerate() {
            let from_parent = match node.parent {
                Some(p) => x_up[i].apply_motion(vel[p]),
                None => Motion::zero(),
            };
            vel.push(from_parent + node.s_mul(v));
        }
        Kinematics {
            tree,
            x_up,
            x0,
            vel,
            v: v.to_vec(),
        }
    }

    /// The frame `f`, placed.
    pub(super) fn frame(&self, f: &FrameAt, params: &[T]) -> Frame<T> {
        let p = &f.placement;
        let offset = Vec3(p.xyz.map(|x| x.get(params)));
        let [roll, pitch, yaw] = p.rpy.map(|x| x.get(params));
        let r_p = Mat3::rpy(roll, pitch, yaw);
        match f.parent {
            None => Frame {
                node: None,
                offset,
                in_body: r_p,
                rotation: r_p,
                origin: offset,
            },
            Some(b) => {
                let n = self.tree.body_node[b];
                let x = &self.x0[n];
                let world_r_body = x.e.transpose();
                Frame {
                    node: Some(n),
                    offset,
                    in_body: r_p,
                    rotation: world_r_body.mul_mat(&r_p),
                    origin: x.r + world_r_body.mul_vec(offset),
                }
            }
        }
    }

    /// The frame's body's rotation `world_R_body`.
    fn body_rotation(&self, f: &Frame<T>) -> Mat3<T> {
        f.node
            .map_or_else(Mat3::identity, |n| self.x0[n].e.transpose())
    }

    /// `[ω; v]` of the frame in LOCAL.
    pub(super) fn local_velocity(&self, f: &Frame<T>) -> (Vec3<T>, Vec3<T>) {
        let Some(n) = f.node else {
            return (Vec3::zero(), Vec3::zero());
        };
        let body = self.vel[n];
        let at_origin = body.lin + body.ang.cross(f.offset);
        // R_p = world_R_bodyᵀ·world_R_frame, so R_pᵀ·x = world_R_frameᵀ·world_R_body·x.
        let world_r_body = self.body_rotation(f);
        let to_frame = |x: Vec3<T>| f.rotation.tr_mul_vec(world_r_body.mul_vec(x));
        (to_frame(body.ang), to_frame(at_origin))
    }

    /// `[ω; ṗ]` of the frame's origin in world axes (LOCAL_WORLD_ALIGNED).
    pub(super) fn aligned_velocity(&self, f: &Frame<T>) -> (Vec3<T>, Vec3<T>) {
        let Some(n) = f.node else {
            return (Vec3::zero(), Vec3::zero());
        };
        let body = self.vel[n];
        let at_origin = body.lin + body.ang.cross(f.offset);
        let world_r_body = self.body_rotation(f);
        (
            world_r_body.mul_vec(body.ang),
            world_r_body.mul_vec(at_origin),
        )
    }

    /// `[ω̇; p̈]` of the frame's origin, world axes, at the accelerations `a`.
    pub(super) fn classical_acceleration(&self, f: &Frame<T>, a: &[T]) -> (Vec3<T>, Vec3<T>) {
        let Some(n) = f.node else {
            return (Vec3::zero(), Vec3::zero());
        };
        // The spatial accelerations of the nodes from the root to the frame's body.
        let path = self.path(n);
        let mut acc = Motion::zero();
        for &i in path.iter().rev() {
            let node = &self.tree.nodes[i];
            let from_parent = match node.parent {
                Some(_) => self.x_up[i].apply_motion(acc),
                None => Motion::zero(),
            };
            acc = from_parent + node.s_mul(a) + self.vel[i].cross_motion(node.s_mul(&self.v));
        }
        let body = self.vel[n];
        let p = f.offset;
        let ddp = acc.lin + acc.ang.cross(p) + body.ang.cross(body.lin + body.ang.cross(p));
        let world_r_body = self.body_rotation(f);
        (world_r_body.mul_vec(acc.ang), world_r_body.mul_vec(ddp))
    }

    /// Node `n` and its ancestors, from `n` to the root.
    fn path(&self, n: usize) -> Vec<usize> {
        let mut path = vec![n];
        while let Some(p) = self.tree.nodes[path[path.len() - 1]].parent {
            path.push(p);
        }
        path
    }

    /// Each tree velocity's column: `(tree velocity index, s)` with `s` the node's motion
    /// subspace column in world coordinates, for the nodes from the frame's body to the root.
    fn world_columns(&self, f: &Frame<T>) -> Vec<(usize, usize, Motion<T>)> {
        let Some(n) = f.node else {
            return Vec::new();
        };
        let mut columns = Vec::new();
        for i in self.path(n) {
            let node = &self.tree.nodes[i];
            for j in 0..node.nv() {
                let s = self.x0[i].inv_apply_motion(node.s_col(j));
                columns.push((node.v_at + j, i, s));
            }
        }
        columns
    }

    /// `o − r_i` for each node `i` of [`Kinematics::path`] (the frame's body first): the
    /// frame's origin relative to the node's origin, world axes. Summed from the frame down,
    /// `d_b = E_bᵀ·p` and `d_λ = d_i + E_λᵀ·t_i` (`t_i`: node `i`'s origin in its parent, the
    /// term [`world_transforms`] adds to place it), so that no two world positions are
    /// subtracted: fewer operations than `o − r_i`, and no cancellation far from the origin.
    fn offsets(&self, f: &Frame<T>, path: &[usize]) -> Vec<Vec3<T>> {
        let mut d = Vec::with_capacity(path.len());
        if path.is_empty() {
            return d;
        }
        d.push(self.body_rotation(f).mul_vec(f.offset));
        for w in path.windows(2) {
            let (i, parent) = (w[0], w[1]);
            let step = self.x0[parent].e.tr_mul_vec(self.x_up[i].r);
            d.push(d[d.len() - 1] + step);
        }
        d
    }

    /// Each tree velocity's column in LOCAL_WORLD_ALIGNED, from the frame's body to the root
    /// ([`Aligned`]).
    fn aligned_columns(&self, f: &Frame<T>) -> Vec<Aligned<T>> {
        let Some(n) = f.node else {
            return Vec::new();
        };
        let path = self.path(n);
        let offsets = self.offsets(f, &path);
        let mut columns = Vec::new();
        for (&node_index, &d) in path.iter().zip(&offsets) {
            let node = &self.tree.nodes[node_index];
            let e = &self.x0[node_index].e;
            for j in 0..node.nv() {
                let s = node.s_col(j);
                columns.push(Aligned {
                    velocity: node.v_at + j,
                    node: node_index,
                    a: e.tr_mul_vec(s.ang),
                    l: e.tr_mul_vec(s.lin),
                    d,
                });
            }
        }
        columns
    }

    /// The frame's Jacobian in `frame`, `6 × nv` of the tree, row-major.
    pub(super) fn jacobian(&self, f: &Frame<T>, frame: In) -> Vec<T> {
        let nv = self.tree.nv;
        let mut j = vec![T::zero(); 6 * nv];
        let mut put = |k: usize, col: Motion<T>| {
            for (r, x) in col.to_array().into_iter().enumerate() {
                j[r * nv + k] = x;
            }
        };
        match frame {
            In::World => {
                for (k, _, s) in self.world_columns(f) {
                    put(k, s);
                }
            }
            In::LocalWorldAligned | In::Local => {
                for Aligned {
                    velocity, a, l, d, ..
                } in self.aligned_columns(f)
                {
                    let lwa = Motion::new(a, l + a.cross(d));
                    put(
                        velocity,
                        if frame == In::Local {
                            to_local(f, lwa)
                        } else {
                            lwa
                        },
                    );
                }
            }
        }
        j
    }

    /// `J̇` of the frame's Jacobian in `frame` at the velocities, `6 × nv`, row-major.
    ///
    /// WORLD: `ṡ = v_i⁰ × s`. LOCAL_WORLD_ALIGNED, the time derivative of `[a; l + a × d]`
    /// ([`Aligned`]): `a` and `l` turn with the node (`ȧ = ω_i × a`,
    /// `l̇ = ω_i × l`, `ω_i` its angular velocity in world axes) and `ḋ = ȯ − ṙ_i` (the
    /// origin's velocity less the node origin's), so the column is
    /// `[ω_i × a; ω_i × l + ȧ × d + a × ḋ]`. LOCAL from it, `J̇_local = Wᵀ·(J̇_lwa − ω × J_lwa)`.
    fn jacobian_rate(&self, f: &Frame<T>, frame: In) -> Vec<T> {
        let nv = self.tree.nv;
        let mut out = vec![T::zero(); 6 * nv];
        let Some(n) = f.node else {
            return out;
        };
        let mut put = |k: usize, col: Motion<T>| {
            for (r, x) in col.to_array().into_iter().enumerate() {
                out[r * nv + k] = x;
            }
        };
        if frame == In::World {
            let world_vel = |i: usize| self.x0[i].inv_apply_motion(self.vel[i]);
            for (k, i, s) in self.world_columns(f) {
                put(k, world_vel(i).cross_motion(s));
            }
            return out;
        }
        // The body's angular velocity and the origin's velocity, world axes.
        let world_r_body = self.body_rotation(f);
        let body = self.vel[n];
        let omega = world_r_body.mul_vec(body.ang);
        let o_dot = world_r_body.mul_vec(body.lin + body.ang.cross(f.offset));
        for Aligned {
            velocity: k,
            node: i,
            a,
            l,
            d,
        } in self.aligned_columns(f)
        {
            let e = &self.x0[i].e;
            let omega_i = e.tr_mul_vec(self.vel[i].ang);
            let d_dot = o_dot - e.tr_mul_vec(self.vel[i].lin);
            let a_dot = omega_i.cross(a);
            let lwa = Motion::new(a_dot, omega_i.cross(l) + a_dot.cross(d) + a.cross(d_dot));
            put(
                k,
                if frame == In::Local {
                    let j = Motion::new(a, l + a.cross(d));
                    let back = |dx: Vec3<T>, x: Vec3<T>| f.rotation.tr_mul_vec(dx - omega.cross(x));
                    Motion::new(back(lwa.ang, j.ang), back(lwa.lin, j.lin))
                } else {
                    lwa
                },
            );
        }
        out
    }
}

/// A tree velocity's LOCAL_WORLD_ALIGNED Jacobian column `[a; l + a × d]` in its parts: the
/// angular and linear parts of the node's motion subspace column in world axes (`E_iᵀ·S`) and
/// the frame's origin relative to the node's ([`Kinematics::offsets`]); the WORLD column
/// `[a; l + r_i × a]` moved to the origin `o = r_i + d` without forming it.
struct Aligned<T> {
    /// The tree velocity.
    velocity: usize,
    /// Its node.
    node: usize,
    a: Vec3<T>,
    l: Vec3<T>,
    d: Vec3<T>,
}

/// A LOCAL_WORLD_ALIGNED column in LOCAL: both halves rotated into the frame's axes.
fn to_local<T: Scalar>(f: &Frame<T>, lwa: Motion<T>) -> Motion<T> {
    Motion::new(
        f.rotation.tr_mul_vec(lwa.ang),
        f.rotation.tr_mul_vec(lwa.lin),
    )
}
