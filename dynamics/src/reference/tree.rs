//! The numeric tree the recursions run on: a [`Model`] with its values read for one parameter
//! vector, and every multi-axis Euler joint expanded into single-axis joints through massless
//! frames.
//!
//! A [`JointKind::SphericalEuler`] joint with sequence `[a1, a2, a3]` becomes three revolute nodes
//! about `a1`, `a2`, `a3` (`R = R1(θ1)·R2(θ2)·R3(θ3)`, ARCHITECTURE.md, "Conventions"); a [`JointKind::FreeEuler`]
//! becomes three prismatic nodes along the joint frame's x, y, z, then the three revolutes. The
//! intermediate nodes carry no inertia. Every node's motion subspace `S` is then constant in its
//! own (child) frame, so the velocity-product term of the joint is `c_J = 0` and the bias
//! acceleration is `v_i ×m (S·q̇_i)` (Featherstone 2008, RBDA §4.4 and eq. 5.7).

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use crate::model::{Axis, JointKind, Model};
use crate::scalar::Scalar;
use crate::spatial::{Force, Inertia, Mat3, Motion, Transform, Vec3};

/// What a node's joint does (a [`JointKind`] after Euler expansion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodeJoint<T> {
    /// Rotation about a unit axis (joint frame = child frame axes along it).
    Revolute(Vec3<T>),
    /// Translation along a unit axis.
    Prismatic(Vec3<T>),
    /// Rotation by the quaternion `q[0..4] = [w, x, y, z]`; velocity = body angular velocity.
    Quaternion,
    /// Position `q[0..3]` in the joint frame and quaternion `q[3..7]`; velocity
    /// `[v_origin; ω]`, both in the child frame.
    FreeQuaternion,
    /// No motion.
    Fixed,
}

/// One node of the numeric tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Node<T> {
    /// What the labels of its quantities start with ([`Scalar::label`]): the body's name for
    /// the node that is a model body, `{joint}_r{axis}` and `{joint}_t{axis}` for the massless
    /// frames an Euler or free joint expands into (a rotation about, a translation along the
    /// axis).
    pub name: String,
    /// Parent node, or `None` for the world.
    pub parent: Option<usize>,
    /// The joint frame in the parent node's frame: `X_T`, parent → joint frame.
    pub x_tree: Transform<T>,
    /// The joint.
    pub joint: NodeJoint<T>,
    /// Index of the joint's first position coordinate in `q`.
    pub q_at: usize,
    /// Index of the joint's first velocity coordinate in `v`.
    pub v_at: usize,
    /// Spatial inertia about the node's origin, in its frame (zero for massless frames).
    pub inertia: Inertia<T>,
    /// The rotor inertia on each of the joint's velocities (the model joint's
    /// [`Drive::armature`](crate::model::Drive::armature), on every node it expands into): it
    /// adds to `M`'s diagonal and `armature·q̈` to `τ`, and is a constant so that a chain
    /// without it traces no extra operation.
    pub armature: f64,
}

impl<T: Scalar> Node<T> {
    /// Number of velocity coordinates of this node's joint.
    pub fn nv(&self) -> usize {
        match self.joint {
            NodeJoint::Revolute(_) | NodeJoint::Prismatic(_) => 1,
            NodeJoint::Quaternion => 3,
            NodeJoint::FreeQuaternion => 6,
            NodeJoint::Fixed => 0,
        }
    }

    /// The joint transform `X_J(q)`, joint frame → child frame (Featherstone 2008, RBDA §4.2).
    pub fn joint_transform(&self, q: &[T]) -> Transform<T> {
        let k = self.q_at;
        match self.joint {
            NodeJoint::Revolute(axis) => {
                Transform::from_pose(Mat3::rot_axis(axis, q[k]), Vec3::zero())
            }
            NodeJoint::Prismatic(axis) => Transform::from_pose(Mat3::identity(), axis.scale(q[k])),
            NodeJoint::Quaternion => Transform::from_pose(
                Mat3::quaternion([q[k], q[k + 1], q[k + 2], q[k + 3]]),
                Vec3::zero(),
            ),
            NodeJoint::FreeQuaternion => Transform::from_pose(
                Mat3::quaternion([q[k + 3], q[k + 4], q[k + 5], q[k + 6]]),
                Vec3([q[k], q[k + 1], q[k + 2]]),
            ),
            NodeJoint::Fixed => Transform::identity(),
        }
    }

    /// Column `j` of the motion subspace `S` in the child frame (Featherstone 2008, RBDA
    /// Table 4.1); `j < self.nv()`.
    pub fn s_col(&self, j: usize) -> Motion<T> {
        let unit = |k: usize| {
            let mut e = Vec3::zero();
            e.0[k] = T::one();
            e
        };
        match self.joint {
            NodeJoint::Revolute(axis) => Motion::new(axis, Vec3::zero()),
            NodeJoint::Prismatic(axis) => Motion::new(Vec3::zero(), axis),
            NodeJoint::Quaternion => Motion::new(unit(j), Vec3::zero()),
            NodeJoint::FreeQuaternion if j < 3 => Motion::new(Vec3::zero(), unit(j)),
            NodeJoint::FreeQuaternion => Motion::new(unit(j - 3), Vec3::zero()),
            NodeJoint::Fixed => Motion::zero(),
        }
    }

    /// `S·x` for this joint's slice of a velocity-sized vector `x` (`x[v_at..][..nv]`).
    pub fn s_mul(&self, x: &[T]) -> Motion<T> {
        let mut m = Motion::zero();
        for j in 0..self.nv() {
            m = m + self.s_col(j).scale(x[self.v_at + j]);
        }
        m
    }

    /// Adds `armature·x` to this joint's slice of `out` (`out[v_at..][..nv]`): the rotor's part
    /// of `τ = (M + diag(armature))·a + …` for `x = a`. Nothing without a rotor.
    pub fn add_armature(&self, x: &[T], out: &mut [T]) {
        if self.armature != 0.0 {
            let armature = T::from_f64(self.armature);
            for k in self.v_at..self.v_at + self.nv() {
                out[k] = out[k] + armature * x[k];
            }
        }
    }

    /// Adds the armature to this joint's diagonal entries of the row-major `nv × nv` `m`.
    pub fn add_armature_to_diagonal(&self, m: &mut [T], nv: usize) {
        if self.armature != 0.0 {
            let armature = T::from_f64(self.armature);
            for k in self.v_at..self.v_at + self.nv() {
                m[k * nv + k] = m[k * nv + k] + armature;
            }
        }
    }

    /// `Sᵀ·f`, written into `out[v_at..][..nv]`.
    pub fn s_tr_mul(&self, f: Force<T>, out: &mut [T]) {
        for j in 0..self.nv() {
            out[self.v_at + j] = self.s_col(j).dot(f);
        }
    }
}

/// The numeric tree of a model for one parameter vector.
#[derive(Clone, Debug, PartialEq)]
pub struct Tree<T> {
    /// Nodes in depth-first order (`nodes[i].parent < Some(i)`).
    pub nodes: Vec<Node<T>>,
    /// `body_node[b]`: the node that is model body `b` (the last node of joint `b`'s expansion).
    pub body_node: Vec<usize>,
    /// Gravity acceleration in the world frame (zero when the model has none).
    pub gravity: Vec3<T>,
    /// Number of position coordinates.
    pub nq: usize,
    /// Number of velocity coordinates.
    pub nv: usize,
}

fn unit_axis<T: Scalar>(a: Axis) -> Vec3<T> {
    Vec3::from_f64(a.unit())
}

impl<T: Scalar> Tree<T> {
    /// Reads `model` for the parameter values `params` (`params.len() >= model.params.len()`;
    /// the f64 front door [`super::Reference`] checks this and [`Model::check`] first).
    pub fn new(model: &Model, params: &[T]) -> Self {
        let mut nodes: Vec<Node<T>> = Vec::new();
        let mut body_node = Vec::with_capacity(model.nb());
        let mut q_at = 0;
        let mut v_at = 0;
        for (joint, body) in model.joints.iter().zip(&model.bodies) {
            let p = &joint.placement;
            let xyz = Vec3(p.xyz.map(|x| x.get(params)));
            let [roll, pitch, yaw] = p.rpy.map(|x| x.get(params));
            let x_tree = Transform::from_pose(Mat3::rpy(roll, pitch, yaw), xyz);
            let mut parent = joint.parent.map(|b| body_node[b]);
            let mut x_tree = Some(x_tree);
            let armature = joint.drive.armature;
            // Pushes one node; only the first of an expansion gets the placement.
            let mut push = |name: String,
                            joint: NodeJoint<T>,
                            nq: usize,
                            nv: usize,
                            nodes: &mut Vec<Node<T>>| {
                nodes.push(Node {
                    name,
                    parent,
                    x_tree: x_tree.take().unwrap_or_else(Transform::identity),
                    joint,
                    q_at,
                    v_at,
                    inertia: Inertia::zero(),
                    armature,
                });
                parent = Some(nodes.len() - 1);
                q_at += nq;
                v_at += nv;
            };
            // The massless frames of an expansion, named after the joint and their axis; the
            // last node is the body.
            let frame = |kind: &str, a: Axis| format!("{}_{kind}{}", joint.name, a.letter());
            let body_name = || body.name.clone();
            match joint.kind {
                JointKind::Revolute { axis } => push(
                    body_name(),
                    NodeJoint::Revolute(Vec3::from_f64(axis)),
                    1,
                    1,
                    &mut nodes,
                ),
                JointKind::Prismatic { axis } => push(
                    body_name(),
                    NodeJoint::Prismatic(Vec3::from_f64(axis)),
                    1,
                    1,
                    &mut nodes,
                ),
                JointKind::SphericalEuler { seq } => {
                    for (k, a) in seq.0.into_iter().enumerate() {
                        let name = if k == 2 { body_name() } else { frame("r", a) };
                        push(name, NodeJoint::Revolute(unit_axis(a)), 1, 1, &mut nodes);
                    }
                }
                JointKind::SphericalQuaternion => {
                    push(body_name(), NodeJoint::Quaternion, 4, 3, &mut nodes)
                }
                JointKind::FreeEuler { seq } => {
                    for a in [Axis::X, Axis::Y, Axis::Z] {
                        push(
                            frame("t", a),
                            NodeJoint::Prismatic(unit_axis(a)),
                            1,
                            1,
                            &mut nodes,
                        );
                    }
                    for (k, a) in seq.0.into_iter().enumerate() {
                        let name = if k == 2 { body_name() } else { frame("r", a) };
                        push(name, NodeJoint::Revolute(unit_axis(a)), 1, 1, &mut nodes);
                    }
                }
                JointKind::FreeQuaternion => {
                    push(body_name(), NodeJoint::FreeQuaternion, 7, 6, &mut nodes)
                }
                JointKind::Fixed => push(body_name(), NodeJoint::Fixed, 0, 0, &mut nodes),
            }
            let last = nodes.len() - 1;
            let c = Vec3(body.com.map(|x| x.get(params)));
            let i_c = Mat3(body.inertia.map(|r| r.map(|x| x.get(params))));
            nodes[last].inertia = Inertia::from_com(body.mass.get(params), c, i_c);
            body_node.push(last);
        }
        let gravity = match &model.gravity {
            Some(g) => Vec3(g.map(|x| x.get(params))),
            None => Vec3::zero(),
        };
        Tree {
            nodes,
            body_node,
            gravity,
            nq: q_at,
            nv: v_at,
        }
    }

    /// The transforms `X_up[i] = X_J(q_i)·X_T[i]`, parent node → node `i` (Featherstone 2008,
    /// RBDA Table 5.1, line 5).
    ///
    /// Labels ([`Scalar::label`]): the rotation `{node}_e_xx, …` and the translation
    /// `{node}_r_x, …` (Featherstone's `E` and `r`).
    pub fn x_up(&self, q: &[T]) -> Vec<Transform<T>> {
        self.nodes
            .iter()
            .map(|n| {
                let x = n.joint_transform(q).after(&n.x_tree);
                Transform {
                    e: x.e.label(format_args!("{}_e", n.name)),
                    r: x.r.label(format_args!("{}_r", n.name)),
                }
            })
            .collect()
    }

    /// The spatial acceleration of the world that stands in for gravity, `−a_g = [0; −g]`
    /// (Featherstone 2008, RBDA §5.3: "a fictitious base acceleration").
    pub fn base_acceleration(&self, with_gravity: bool) -> Motion<T> {
        if with_gravity {
            Motion::new(Vec3::zero(), -self.gravity)
        } else {
            Motion::zero()
        }
    }
}
