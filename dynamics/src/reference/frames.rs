//! Frames: where a frame is, how it moves, and its Jacobians and their time variation
//! (DESIGN.md §9, "Frames"), from Featherstone's kinematics on the tree.
//!
//! # Frames
//! A frame is fixed to a body, or to the world, at a constant placement: every body's own frame
//! (under the body's name), and the frames of [`Model::frames`](crate::model::Model::frames)
//! ([`Model::frame`](crate::model::Model::frame) resolves both). Its placement in its parent is a
//! translation `xyz` then the rotation `Rz(yaw)·Ry(pitch)·Rx(roll)`, as a joint's. Its pose in the
//! world is `⁰M_f = (R, p)`: `R` = world_R_frame (its columns are the frame's axes in world
//! coordinates), `p` its origin in world coordinates.
//!
//! # Reference frames
//! Spatial vectors are angular first, `[ω; v]` (Pinocchio is linear first). A motion of the
//! frame's body (a velocity, a Jacobian column) is written in one of three [`ReferenceFrame`]s:
//! - **LOCAL**: frame axes; `v` is the velocity of the body point at the frame origin.
//! - **WORLD**: world axes; `v` is the velocity of the body point (extended rigidly) at the world
//!   origin. Featherstone's spatial velocity in world coordinates, Pinocchio's `WORLD`.
//! - **LOCAL_WORLD_ALIGNED**: world axes; `v` is the velocity of the frame origin.
//!
//! With `m_l = [ω_l; v_l]` in LOCAL: `m_world = Ad(⁰M_f)·m_l = [R·ω_l; R·v_l + p × R·ω_l]` and
//! `m_lwa = [R·ω_l; R·v_l]`; from WORLD, `m_lwa = [ω_w; v_w + ω_w × p]` (a shift of the reference
//! point only).
//!
//! # Kinematics
//! On the tree ([`super::tree`]: Euler joints expanded into single-axis nodes, so every node's
//! motion subspace `S_i` is constant in its own frame and `c_J = 0`), the forward pass of RNEA
//! without gravity (Featherstone 2008, RBDA Table 5.1, lines 5–9), per node `i` with parent `λ`:
//! - `ⁱX_0 = X_up[i]·X_0[λ]` (world → node `i`; `X_0[λ]` is the parent's, the identity for the
//!   world), with `X_up[i] = X_J(q_i)·X_T[i]`;
//! - `v_i = X_up[i]·v_λ + S_i·q̇_i`;
//! - `a_i = X_up[i]·a_λ + S_i·q̈_i + v_i ×m S_i·q̇_i` (RBDA eq. 5.7).
//!
//! `v_i` and `a_i` are in node `i`'s coordinates. A frame `f` on node `b` at the placement
//! `ᶠX_b` then has:
//! - the pose `ᶠX_0 = ᶠX_b·ᵇX_0`, so `R = ᶠE_0ᵀ` and `p = ᶠr_0`;
//! - the velocity `v_f = ᶠX_b·v_b` (LOCAL): `[ω; ṗ]` in frame axes, since the frame origin is a
//!   body point;
//! - the spatial acceleration `a_f = ᶠX_b·a_b` (LOCAL), which is `d/dt` of the components of
//!   `v_f` (Featherstone's `a = v̇`, RBDA §2.11).
//!
//! # Spatial and classical accelerations
//! The linear part of the spatial acceleration is the rate of change of the velocity field at a
//! point fixed in the frame's axes, not the acceleration of a body point. The **classical**
//! acceleration of the frame origin is `p̈ = a_f.lin + ω × v_f.lin` (frame axes;
//! Featherstone 2008, RBDA §2.11). This module's frame acceleration
//! ([`Reference::frame_acceleration`]) is the classical one in LOCAL_WORLD_ALIGNED:
//!
//! `[ω̇; p̈]_lwa = R·[a_f.ang; a_f.lin + ω × v_f.lin] = J_lwa·a + J̇_lwa·v`.
//!
//! [`Reference::frame_spatial_acceleration`] is `a_f` itself, and `J̇_local·v` is `a_f` at
//! `a = 0`, the **spatial drift** a six-dimensional contact needs. It differs from the classical
//! drift written in LOCAL axes, `Rᵀ·J̇_lwa·v`, by exactly `[0; ω × v]` (`ω`, `v` the two halves of
//! the LOCAL velocity): `Rᵀ·J̇_lwa·v = J̇_local·v + [0; ω × v]`.
//!
//! # Jacobians
//! `J` is `6 × nv`, with respect to `v` (the tangent for quaternion joints and the free base:
//! body angular velocity, and a free base's linear velocity in its body frame), so that the
//! frame's velocity in a reference frame is `J·v`. The column of the tree's velocity coordinate
//! `k`, column `j` of `S_n` for a node `n` that supports the frame (its body's node or an
//! ancestor), is, in WORLD, `J_w = ⁰X_n·S_n,j` (`⁰X_n = (ⁿX_0)⁻¹`: node `n` → world); other
//! columns are zero. Then
//! - LOCAL: `J_l = ᶠX_0·J_w`;
//! - LOCAL_WORLD_ALIGNED: `J_a = [J_w.ang; J_w.lin + J_w.ang × p]`.
//!
//! # Time variation of the Jacobians
//! `J̇ = d/dt J(q(t))` along the motion `q̇ ↔ v`, as Pinocchio's
//! `computeJointJacobiansTimeVariation` and `getFrameJacobianTimeVariation`. `S_n,j` is constant
//! in node `n`, and `d/dt ⁰X_n = (⁰v_n ×m)·⁰X_n` with `⁰v_n = ⁰X_n·v_n`, the node's velocity in
//! world coordinates, so
//! - WORLD: `J̇_w = ⁰v_n ×m J_w`;
//! - LOCAL: `d/dt ᶠX_0 = −(v_f ×m)·ᶠX_0`, so `J̇_l = ᶠX_0·J̇_w − v_f ×m J_l`;
//! - LOCAL_WORLD_ALIGNED: `J̇_a = [J̇_w.ang; J̇_w.lin + J̇_w.ang × p + J_w.ang × ṗ]`, with
//!   `ṗ = R·v_f.lin` the frame origin's velocity in world axes.
//!
//! Pinocchio's `dJ = ⁰v_n ×m J_w` holds only where `S` is constant in its joint's frame: for its
//! `SphericalZYX` joint and a composite `Translation + SphericalZYX` base, whose `S` depends on
//! `q`, Pinocchio 4.1's time variation leaves out the `⁰X_n·Ṡ` term and is not `dJ/dt`. The tree
//! here expands such joints into single-axis nodes, whose `S` is constant, so the formula is exact
//! (`tests/data/pinocchio_frames/make_pinocchio_frames.py` takes Pinocchio's values for the Euler
//! base from six single-axis joints for that reason).
//!
//! # Mimic joints
//! The tree gives a mimic joint a coordinate of its own ([`crate::model::Coupling`]): everything
//! above runs at `q_tree = G·q + o`, `v_tree = G·v`, `a_tree = G·a`, and the model's Jacobians
//! are `J·G` and `J̇·G` (`G` is constant), each column of a mimic joint added to the column of the
//! joint it follows.

use alloc::string::String;
use alloc::vec::Vec;

use nalgebra::{DMatrix, Matrix3, Vector3, Vector6};

use super::tree::Tree;
use super::{check_q, check_vector, finite, Error, Reference};
use crate::spatial::{Mat3, Motion, Transform, Vec3};

/// Where the linear part of a motion is taken and along which axes it is written (see the
/// [module docs](self)). Pinocchio's `pin.ReferenceFrame` of the same names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ReferenceFrame {
    /// Frame axes, at the frame origin.
    Local,
    /// World axes, at the world origin.
    World,
    /// World axes, at the frame origin.
    LocalWorldAligned,
}

impl ReferenceFrame {
    /// The three, in the order of the CLI's JSON (DESIGN.md §9).
    pub const ALL: [ReferenceFrame; 3] = [
        ReferenceFrame::Local,
        ReferenceFrame::World,
        ReferenceFrame::LocalWorldAligned,
    ];

    /// `local`, `world` or `local_world_aligned`: the keys of the CLI's JSON and the suffixes
    /// of the generated outputs' names.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceFrame::Local => "local",
            ReferenceFrame::World => "world",
            ReferenceFrame::LocalWorldAligned => "local_world_aligned",
        }
    }
}

/// Where a frame is fixed: the tree node of its body (`None`: the world) and the transform from
/// that node's frame to the frame, `ᶠX_b`.
#[derive(Clone, Copy, Debug)]
struct Attachment {
    node: Option<usize>,
    x: Transform<f64>,
}

/// The tree's kinematics at one state (see the [module docs](self)), per node, in the node's
/// coordinates.
struct Kinematics {
    /// `ⁱX_0`: world → node.
    x0: Vec<Transform<f64>>,
    /// `v_i`.
    v: Vec<Motion<f64>>,
    /// `a_i`, without gravity.
    a: Vec<Motion<f64>>,
}

/// The forward pass of RNEA without gravity (Featherstone 2008, RBDA Table 5.1, lines 5–9).
fn kinematics(tree: &Tree<f64>, q: &[f64], v: &[f64], a: &[f64]) -> Kinematics {
    let x_up = tree.x_up(q);
    let n = tree.nodes.len();
    let mut k = Kinematics {
        x0: Vec::with_capacity(n),
        v: Vec::with_capacity(n),
        a: Vec::with_capacity(n),
    };
    for (i, node) in tree.nodes.iter().enumerate() {
        let (x_parent, v_parent, a_parent) = match node.parent {
            Some(p) => (k.x0[p], k.v[p], k.a[p]),
            None => (Transform::identity(), Motion::zero(), Motion::zero()),
        };
        let v_joint = node.s_mul(v);
        let v_i = x_up[i].apply_motion(v_parent) + v_joint;
        let a_i = x_up[i].apply_motion(a_parent) + node.s_mul(a) + v_i.cross_motion(v_joint);
        k.x0.push(x_up[i].after(&x_parent));
        k.v.push(v_i);
        k.a.push(a_i);
    }
    k
}

/// A frame at one state.
struct FrameState {
    /// `ᶠX_0`: world → frame.
    x0: Transform<f64>,
    /// `v_f`, LOCAL.
    v: Motion<f64>,
    /// `a_f`, the spatial acceleration, LOCAL.
    a: Motion<f64>,
}

impl FrameState {
    fn of(k: &Kinematics, at: &Attachment) -> Self {
        match at.node {
            Some(b) => FrameState {
                x0: at.x.after(&k.x0[b]),
                v: at.x.apply_motion(k.v[b]),
                a: at.x.apply_motion(k.a[b]),
            },
            None => FrameState {
                x0: at.x,
                v: Motion::zero(),
                a: Motion::zero(),
            },
        }
    }

    /// `R·x`: frame axes to world axes.
    fn to_world_axes(&self, x: Vec3<f64>) -> Vec3<f64> {
        self.x0.e.tr_mul_vec(x)
    }

    /// The frame origin in world coordinates, `p`.
    fn origin(&self) -> Vec3<f64> {
        self.x0.r
    }

    /// The classical acceleration `[ω̇; p̈]` in LOCAL_WORLD_ALIGNED.
    fn classical_acceleration(&self) -> Motion<f64> {
        let p_ddot = self.a.lin + self.v.ang.cross(self.v.lin);
        Motion::new(self.to_world_axes(self.a.ang), self.to_world_axes(p_ddot))
    }
}

/// One column of a frame's Jacobian on the tree: the tree velocity coordinate, `J_w` and `J̇_w`
/// (WORLD).
struct Column {
    k: usize,
    j: Motion<f64>,
    j_dot: Motion<f64>,
}

/// The nonzero WORLD columns of the Jacobian of a frame on `node` and their time variation:
/// `J_w = ⁰X_n·S_n,j` and `J̇_w = ⁰v_n ×m J_w` for every node `n` from `node` to the root.
fn world_columns(tree: &Tree<f64>, k: &Kinematics, node: Option<usize>) -> Vec<Column> {
    let mut columns = Vec::new();
    let mut at = node;
    while let Some(n) = at {
        let node = &tree.nodes[n];
        let v_world = k.x0[n].inv_apply_motion(k.v[n]);
        for j in 0..node.nv() {
            let jw = k.x0[n].inv_apply_motion(node.s_col(j));
            columns.push(Column {
                k: node.v_at + j,
                j: jw,
                j_dot: v_world.cross_motion(jw),
            });
        }
        at = node.parent;
    }
    columns
}

/// `(J, J̇)` of one column in `rf`, from WORLD (see the [module docs](self)).
fn in_frame(c: &Column, f: &FrameState, rf: ReferenceFrame) -> (Motion<f64>, Motion<f64>) {
    match rf {
        ReferenceFrame::World => (c.j, c.j_dot),
        ReferenceFrame::Local => {
            let j = f.x0.apply_motion(c.j);
            (j, f.x0.apply_motion(c.j_dot) - f.v.cross_motion(j))
        }
        ReferenceFrame::LocalWorldAligned => {
            let p = f.origin();
            let p_dot = f.to_world_axes(f.v.lin);
            let j = Motion::new(c.j.ang, c.j.lin + c.j.ang.cross(p));
            let j_dot = Motion::new(
                c.j_dot.ang,
                c.j_dot.lin + c.j_dot.ang.cross(p) + c.j.ang.cross(p_dot),
            );
            (j, j_dot)
        }
    }
}

fn vector6(m: Motion<f64>) -> Vector6<f64> {
    Vector6::from_column_slice(&m.to_array())
}

impl Reference {
    /// Resolves a frame's name, with its placement's values.
    fn attachment(&self, frame: &str) -> Result<Attachment, Error> {
        let (parent, placement) = self.model.frame(frame).ok_or_else(|| Error::UnknownFrame {
            name: String::from(frame),
            known: self.model.frame_names().map(String::from).collect(),
        })?;
        let xyz = Vec3(placement.xyz.map(|x| x.get(&self.params)));
        let [roll, pitch, yaw] = placement.rpy.map(|x| x.get(&self.params));
        Ok(Attachment {
            node: parent.map(|b| self.tree.body_node[b]),
            x: Transform::from_pose(Mat3::rpy(roll, pitch, yaw), xyz),
        })
    }

    /// The frame and the tree's kinematics at `(q, v, a)` (the model's coordinates), checked.
    fn frame_state(
        &self,
        frame: &str,
        q: &[f64],
        v: Option<&[f64]>,
        a: Option<&[f64]>,
    ) -> Result<(Attachment, Kinematics, FrameState), Error> {
        let at = self.attachment(frame)?;
        check_q(&self.model, q)?;
        let zero = alloc::vec![0.0; self.nv()];
        let v = v.unwrap_or(&zero);
        let a = a.unwrap_or(&zero);
        check_vector("v", v, self.nv())?;
        check_vector("a", a, self.nv())?;
        let k = kinematics(&self.tree, &self.q(q), &self.v(v), &self.v(a));
        let f = FrameState::of(&k, &at);
        Ok((at, k, f))
    }

    /// The pose of `frame` at `q`: `(R, p)`, world_R_frame (its columns are the frame's axes in
    /// world coordinates) and its origin in world coordinates (see [`frames`](self)).
    ///
    /// # Errors
    /// [`Error::UnknownFrame`], and as [`Reference::mass_matrix`].
    pub fn frame_placement(
        &self,
        q: &[f64],
        frame: &str,
    ) -> Result<(Matrix3<f64>, Vector3<f64>), Error> {
        let (_, _, f) = self.frame_state(frame, q, None, None)?;
        let e = &f.x0.e.0;
        let r = Matrix3::from_fn(|i, j| e[j][i]);
        let p = Vector3::from(f.origin().0);
        finite("frame_placement", r.iter().chain(&p).copied().collect())?;
        Ok((r, p))
    }

    /// The velocity of `frame` at `(q, v)`, LOCAL: `[ω; ṗ]` in the frame's axes (its angular
    /// velocity and its origin's velocity).
    ///
    /// # Errors
    /// [`Error::UnknownFrame`], and as [`Reference::bias`].
    pub fn frame_velocity(&self, q: &[f64], v: &[f64], frame: &str) -> Result<Vector6<f64>, Error> {
        let (_, _, f) = self.frame_state(frame, q, Some(v), None)?;
        finite("frame_velocity", f.v.to_array().to_vec())?;
        Ok(vector6(f.v))
    }

    /// The classical acceleration of `frame` at `(q, v, a)`, LOCAL_WORLD_ALIGNED: `[ω̇; p̈]` of its
    /// origin in world axes, `= J_lwa·a + J̇_lwa·v`; its drift at `a = 0` is what a point contact
    /// holds to zero.
    ///
    /// # Errors
    /// [`Error::UnknownFrame`], and as [`Reference::inverse_dynamics`].
    pub fn frame_acceleration(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        frame: &str,
    ) -> Result<Vector6<f64>, Error> {
        let (_, _, f) = self.frame_state(frame, q, Some(v), Some(a))?;
        let acc = f.classical_acceleration();
        finite("frame_acceleration", acc.to_array().to_vec())?;
        Ok(vector6(acc))
    }

    /// The spatial acceleration of `frame` at `(q, v, a)`, LOCAL: the time derivative of the
    /// components of [`Reference::frame_velocity`], `= J_local·a + J̇_local·v`. It differs from
    /// the classical acceleration in LOCAL axes (`Rᵀ·`[`Reference::frame_acceleration`]) by
    /// `[0; ω × v]` (see [`frames`](self)).
    ///
    /// # Errors
    /// As [`Reference::frame_acceleration`].
    pub fn frame_spatial_acceleration(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        frame: &str,
    ) -> Result<Vector6<f64>, Error> {
        let (_, _, f) = self.frame_state(frame, q, Some(v), Some(a))?;
        finite("frame_spatial_acceleration", f.a.to_array().to_vec())?;
        Ok(vector6(f.a))
    }

    /// The Jacobian of `frame` at `q` in `rf`, `6 × nv`, with respect to `v`: the frame's
    /// velocity in `rf` is `J·v` (see [`frames`](self)).
    ///
    /// # Errors
    /// [`Error::UnknownFrame`], and as [`Reference::mass_matrix`].
    pub fn frame_jacobian(
        &self,
        q: &[f64],
        frame: &str,
        rf: ReferenceFrame,
    ) -> Result<DMatrix<f64>, Error> {
        let (at, k, f) = self.frame_state(frame, q, None, None)?;
        let j = self.jacobians(&at, &k, &f, rf).0;
        let j = finite("frame_jacobian", j)?;
        Ok(DMatrix::from_row_slice(6, self.nv(), &j))
    }

    /// The time variation `J̇ = d/dt J(q(t))` of [`Reference::frame_jacobian`] at `(q, v)` in
    /// `rf`, `6 × nv` (Pinocchio's `getFrameJacobianTimeVariation`; see [`frames`](self)).
    ///
    /// # Errors
    /// [`Error::UnknownFrame`], and as [`Reference::bias`].
    pub fn frame_jacobian_time_variation(
        &self,
        q: &[f64],
        v: &[f64],
        frame: &str,
        rf: ReferenceFrame,
    ) -> Result<DMatrix<f64>, Error> {
        let (at, k, f) = self.frame_state(frame, q, Some(v), None)?;
        let j_dot = self.jacobians(&at, &k, &f, rf).1;
        let j_dot = finite("frame_jacobian_time_variation", j_dot)?;
        Ok(DMatrix::from_row_slice(6, self.nv(), &j_dot))
    }

    /// `(J, J̇)` in `rf`, each `6 × nv` row-major in the model's coordinates.
    fn jacobians(
        &self,
        at: &Attachment,
        k: &Kinematics,
        f: &FrameState,
        rf: ReferenceFrame,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = self.tree.nv;
        let mut j = alloc::vec![0.0; 6 * n];
        let mut j_dot = alloc::vec![0.0; 6 * n];
        for c in world_columns(&self.tree, k, at.node) {
            let (col, col_dot) = in_frame(&c, f, rf);
            for (r, (x, x_dot)) in col
                .to_array()
                .into_iter()
                .zip(col_dot.to_array())
                .enumerate()
            {
                j[r * n + c.k] = x;
                j_dot[r * n + c.k] = x_dot;
            }
        }
        (
            self.coupling.reduce_columns(&j, 6),
            self.coupling.reduce_columns(&j_dot, 6),
        )
    }
}
