//! Only what a scene needs: a model with joints **locked** at given coordinates (they become
//! fixed), a **sub-tree** of the bodies a scene moves (every other joint locked, at its neutral
//! configuration unless locked elsewhere), and fixed joints **merged** (the child's mass
//! properties added to its parent's, its children re-attached to the parent), so that the
//! generator sees fewer coordinates and fewer bodies. Each transformation is exact: the locked
//! model's dynamics are the full model's with the locked coordinates held at their values and
//! their velocities and accelerations zero (`tests/prune.rs` holds them to that).
//!
//! A locked joint takes the [`Mimic`] joints that follow it along, each locked at
//! `multiplier·q + offset` (`tests/mimic.rs`); a mimic joint cannot be locked on its own.
//!
//! Locking and merging need the numbers they move to be constants: a placement or mass property
//! that is a runtime parameter is refused ([`PruneError::Parameter`]) or, for merging, the fixed
//! joint is kept as it is.

use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;

use crate::model::{Body, Drive, Frame, Joint, JointKind, Mimic, Model, Placement, Value};
use crate::spatial::{Mat3, Vec3};

/// Why a model could not be pruned as asked.
#[derive(Clone, Debug, PartialEq)]
pub enum PruneError {
    /// No joint of that name.
    UnknownJoint(String),
    /// No body of that name.
    UnknownBody(String),
    /// The values given for a locked joint do not match its coordinates.
    Coordinates {
        /// The joint.
        joint: String,
        /// Its number of position coordinates.
        expected: usize,
        /// The number of values given.
        found: usize,
    },
    /// A value given for a locked joint is not finite, or a locked quaternion is zero.
    Value {
        /// The joint.
        joint: String,
    },
    /// A locked joint's placement is a runtime parameter: the fixed placement that replaces it
    /// could not be computed.
    Parameter {
        /// The joint.
        joint: String,
    },
    /// A mimic joint ([`crate::model::Mimic`]) asked to be locked on its own (lock the joint
    /// it follows, which locks it too), or dropped from a sub-tree while the joint it follows
    /// is kept.
    Mimic {
        /// The mimic joint.
        joint: String,
    },
    /// A body kept in a sub-tree whose parent is not kept.
    NotConnected {
        /// The body.
        body: String,
        /// Its parent, not in the sub-tree.
        parent: String,
    },
}

impl fmt::Display for PruneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PruneError::UnknownJoint(j) => write!(f, "cannot lock `{j}`: no joint of that name"),
            PruneError::Mimic { joint } => write!(
                f,
                "joint `{joint}` mimics another joint, which moves: a mimic joint is locked with \
                 the joint it follows (lock or drop that one) and moves with it"
            ),
            PruneError::UnknownBody(b) => write!(f, "cannot keep `{b}`: no body of that name"),
            PruneError::Coordinates {
                joint,
                expected,
                found,
            } => write!(
                f,
                "joint `{joint}` is locked with {found} value{} but has {expected} position \
                 coordinate{}",
                if *found == 1 { "" } else { "s" },
                if *expected == 1 { "" } else { "s" },
            ),
            PruneError::Value { joint } => write!(
                f,
                "joint `{joint}` is locked at a value that is not finite (or a zero quaternion)"
            ),
            PruneError::Parameter { joint } => write!(
                f,
                "joint `{joint}` cannot be locked: its placement is a runtime parameter"
            ),
            PruneError::NotConnected { body, parent } => write!(
                f,
                "body `{body}` is kept but its parent `{parent}` is not: a sub-tree keeps every \
                 body between the world and the bodies it names"
            ),
        }
    }
}

impl core::error::Error for PruneError {}

/// The rotation `R` (child axes to joint axes) and the translation `p` (the child origin in the
/// joint frame) of `kind` at the coordinates `q`.
fn joint_pose(kind: JointKind, q: &[f64]) -> (Mat3<f64>, Vec3<f64>) {
    let euler = |seq: crate::model::EulerSeq, a: &[f64]| {
        seq.0
            .iter()
            .zip(a)
            .fold(Mat3::identity(), |r, (axis, &angle)| {
                r.mul_mat(&Mat3::rot_axis(Vec3(axis.unit()), angle))
            })
    };
    match kind {
        JointKind::Revolute { axis } => (Mat3::rot_axis(Vec3(axis), q[0]), Vec3::zero()),
        JointKind::Prismatic { axis } => (Mat3::identity(), Vec3(axis).scale(q[0])),
        JointKind::SphericalEuler { seq } => (euler(seq, q), Vec3::zero()),
        JointKind::SphericalQuaternion => {
            (Mat3::quaternion([q[0], q[1], q[2], q[3]]), Vec3::zero())
        }
        JointKind::FreeEuler { seq } => (euler(seq, &q[3..6]), Vec3([q[0], q[1], q[2]])),
        JointKind::FreeQuaternion => (
            Mat3::quaternion([q[3], q[4], q[5], q[6]]),
            Vec3([q[0], q[1], q[2]]),
        ),
        JointKind::Fixed => (Mat3::identity(), Vec3::zero()),
    }
}

/// A placement's rotation and translation, if both are constants.
fn pose_of(p: &Placement) -> Option<(Mat3<f64>, Vec3<f64>)> {
    let xyz = [
        p.xyz[0].as_const()?,
        p.xyz[1].as_const()?,
        p.xyz[2].as_const()?,
    ];
    let [r, pi, y] = [
        p.rpy[0].as_const()?,
        p.rpy[1].as_const()?,
        p.rpy[2].as_const()?,
    ];
    Some((Mat3::rpy(r, pi, y), Vec3(xyz)))
}

/// The placement of the rotation `r` and translation `p`: `r` as roll, pitch, yaw
/// (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`), the roll taken as zero where the pitch is ±90°.
fn placement(r: &Mat3<f64>, p: Vec3<f64>) -> Placement {
    let m = &r.0;
    let cos_pitch = libm::hypot(m[0][0], m[1][0]);
    let pitch = libm::atan2(-m[2][0], cos_pitch);
    let (roll, yaw) = if cos_pitch > 1e-12 {
        (libm::atan2(m[2][1], m[2][2]), libm::atan2(m[1][0], m[0][0]))
    } else {
        // R = Rz(yaw)·Ry(±π/2): the roll folds into the yaw.
        (0.0, libm::atan2(-m[0][1], m[1][1]))
    };
    Placement {
        xyz: p.0.map(Value::Const),
        rpy: [roll, pitch, yaw].map(Value::Const),
    }
}

/// `joint` locked at the position coordinates `q`: a fixed joint whose placement is the joint's
/// placement followed by the joint's motion at `q`.
fn fixed_at(joint: &Joint, q: &[f64]) -> Result<Joint, PruneError> {
    let (r0, x0) = pose_of(&joint.placement).ok_or_else(|| PruneError::Parameter {
        joint: joint.name.clone(),
    })?;
    let (rj, pj) = joint_pose(joint.kind, q);
    Ok(Joint {
        name: joint.name.clone(),
        kind: JointKind::Fixed,
        parent: joint.parent,
        placement: placement(&r0.mul_mat(&rj), vadd(x0, r0.mul_vec(pj))),
        // A locked joint has no coordinate left for its rotor or limits to act on.
        drive: Drive::FREE,
        mimic: None,
    })
}

/// `model` with `joint` locked at the position coordinates `q`: a fixed joint whose placement is
/// the joint's placement followed by the joint's motion at `q`; the mimic joints that follow it
/// are locked too, each at `multiplier·q + offset`.
///
/// # Errors
/// An unknown joint, a mimic joint, the wrong number of values, a non-finite value or a zero
/// quaternion, or a placement that is a runtime parameter.
pub fn lock(model: &Model, joint: &str, q: &[f64]) -> Result<Model, PruneError> {
    let i = model
        .joints
        .iter()
        .position(|j| j.name == joint)
        .ok_or_else(|| PruneError::UnknownJoint(joint.to_string()))?;
    let j = &model.joints[i];
    if j.mimic.is_some() {
        return Err(PruneError::Mimic {
            joint: joint.to_string(),
        });
    }
    if q.len() != j.kind.nq() {
        return Err(PruneError::Coordinates {
            joint: joint.to_string(),
            expected: j.kind.nq(),
            found: q.len(),
        });
    }
    let quaternion = match j.kind {
        JointKind::SphericalQuaternion => Some(&q[0..4]),
        JointKind::FreeQuaternion => Some(&q[3..7]),
        _ => None,
    };
    let zero = quaternion.is_some_and(|w| w.iter().all(|&x| x == 0.0));
    if zero || q.iter().any(|x| !x.is_finite()) {
        return Err(PruneError::Value {
            joint: joint.to_string(),
        });
    }
    let mut out = model.clone();
    out.joints[i] = fixed_at(j, q)?;
    // The joints that follow it are locked where they follow it to.
    for (k, follower) in model.joints.iter().enumerate() {
        if let Some(m) = follower.mimic.filter(|m| m.joint == i) {
            out.joints[k] = fixed_at(follower, &[m.multiplier * q[0] + m.offset])?;
        }
    }
    Ok(out)
}

/// `model` reduced to the bodies in `keep` (which must include every body between the world and
/// each of them): every joint whose child is not kept is locked at `locks`' value for it if there
/// is one, else at its neutral configuration; the rest stays. Then [`merge_fixed`] folds the
/// dropped bodies, as a payload, into the last kept body above them.
///
/// # Errors
/// An unknown body or a kept body whose parent is not kept, or what [`lock`] refuses.
pub fn keep(model: &Model, keep: &[&str], locks: &[(&str, &[f64])]) -> Result<Model, PruneError> {
    for name in keep {
        let b = model
            .body_index(name)
            .ok_or_else(|| PruneError::UnknownBody(name.to_string()))?;
        if let Some(p) = model.joints[b].parent {
            if !keep.contains(&model.bodies[p].name.as_str()) {
                return Err(PruneError::NotConnected {
                    body: name.to_string(),
                    parent: model.bodies[p].name.clone(),
                });
            }
        }
    }
    let mut out = model.clone();
    for (b, body) in model.bodies.iter().enumerate() {
        if keep.contains(&body.name.as_str()) || model.joints[b].kind == JointKind::Fixed {
            continue;
        }
        let joint = &model.joints[b];
        if let Some(m) = joint.mimic {
            // Locked with the joint it follows, below; if that one moves, so must this body.
            if keep.contains(&model.bodies[m.joint].name.as_str()) {
                return Err(PruneError::Mimic {
                    joint: joint.name.clone(),
                });
            }
            continue;
        }
        let q = match locks.iter().find(|(name, _)| *name == joint.name) {
            Some((_, q)) => q.to_vec(),
            None => joint.kind.neutral(),
        };
        out = lock(&out, &joint.name, &q)?;
    }
    Ok(out)
}

fn vadd(a: Vec3<f64>, b: Vec3<f64>) -> Vec3<f64> {
    Vec3(core::array::from_fn(|k| a.0[k] + b.0[k]))
}

fn vsub(a: Vec3<f64>, b: Vec3<f64>) -> Vec3<f64> {
    Vec3(core::array::from_fn(|k| a.0[k] - b.0[k]))
}

/// A body's mass properties as constants: mass, centre of mass, inertia about it.
fn mass_props(b: &Body) -> Option<(f64, Vec3<f64>, Mat3<f64>)> {
    let c = [
        b.com[0].as_const()?,
        b.com[1].as_const()?,
        b.com[2].as_const()?,
    ];
    let mut i = [[0.0; 3]; 3];
    for (r, row) in b.inertia.iter().enumerate() {
        for (k, x) in row.iter().enumerate() {
            i[r][k] = x.as_const()?;
        }
    }
    Some((b.mass.as_const()?, Vec3(c), Mat3(i)))
}

/// The inertia of a point mass `m` at `d` from the point it is taken about: `m·(|d|²·1 − d·dᵀ)`.
fn parallel_axis(m: f64, d: Vec3<f64>) -> Mat3<f64> {
    let dd = d.dot(d);
    Mat3(core::array::from_fn(|r| {
        core::array::from_fn(|k| m * (if r == k { dd } else { 0.0 } - d.0[r] * d.0[k]))
    }))
}

/// `host` with `body` rigidly attached at the pose `(r, x)` (body axes to host axes, body origin
/// in the host frame): one body with the sum of their masses and the inertia of both about the
/// common centre of mass.
fn merged(host: &Body, body: &Body, r: &Mat3<f64>, x: Vec3<f64>) -> Option<Body> {
    let (m1, c1, i1) = mass_props(host)?;
    let (m2, c2, i2) = mass_props(body)?;
    let c2 = vadd(x, r.mul_vec(c2));
    let i2 = r.mul_mat(&i2).mul_mat(&r.transpose());
    let m = m1 + m2;
    let c = if m > 0.0 {
        vadd(c1.scale(m1 / m), c2.scale(m2 / m))
    } else {
        c1
    };
    let i = i1
        .add(&parallel_axis(m1, vsub(c1, c)))
        .add(&i2)
        .add(&parallel_axis(m2, vsub(c2, c)));
    Some(Body {
        name: host.name.clone(),
        mass: Value::Const(m),
        com: c.0.map(Value::Const),
        inertia: i.0.map(|row| row.map(Value::Const)),
    })
}

/// `model` with every fixed joint between two bodies folded away: the child's mass properties
/// added to the nearest ancestor that stays, its children re-attached to that ancestor with
/// their placements composed. Bodies fixed to the world stay (they carry the base's frame and
/// count in the centre of mass); a fixed joint whose numbers are runtime parameters stays too.
pub fn merge_fixed(model: &Model) -> Model {
    let n = model.bodies.len();
    // For each body: the body it merges into (itself if it stays) and its pose there.
    let mut host: Vec<usize> = (0..n).collect();
    let mut pose: Vec<(Mat3<f64>, Vec3<f64>)> = alloc::vec![(Mat3::identity(), Vec3::zero()); n];
    let mut bodies: Vec<Body> = model.bodies.clone();
    for (b, joint) in model.joints.iter().enumerate() {
        let Some(parent) = joint.parent else {
            continue;
        };
        if joint.kind != JointKind::Fixed {
            continue;
        }
        let Some((r, x)) = pose_of(&joint.placement) else {
            continue;
        };
        let h = host[parent];
        let (rh, xh) = pose[parent];
        let (r, x) = (rh.mul_mat(&r), vadd(xh, rh.mul_vec(x)));
        if let Some(m) = merged(&bodies[h], &model.bodies[b], &r, x) {
            bodies[h] = m;
            host[b] = h;
            pose[b] = (r, x);
        }
    }
    // Keep the bodies that stay, in order, their joints re-attached to the hosts (and mimic
    // joints to the joints they follow, which stay: they move).
    let mut index: Vec<Option<usize>> = alloc::vec![None; n];
    let mut kept = 0;
    for b in 0..n {
        if host[b] == b {
            index[b] = Some(kept);
            kept += 1;
        }
    }
    let mut out_bodies = Vec::new();
    let mut out_joints: Vec<Joint> = Vec::new();
    for b in 0..n {
        if host[b] != b {
            continue;
        }
        let joint = &model.joints[b];
        let (parent, placement_of) = match joint.parent {
            Some(p) if host[p] != p => {
                // The parent merged away: compose its pose in its host with this placement.
                let (rh, xh) = pose[p];
                let composed = pose_of(&joint.placement)
                    .map(|(r, x)| placement(&rh.mul_mat(&r), vadd(xh, rh.mul_vec(x))));
                (Some(host[p]), composed)
            }
            other => (other, Some(joint.placement)),
        };
        let Some(placement_of) = placement_of else {
            // A parameter placement under a merged parent cannot be composed: keep the model.
            return model.clone();
        };
        out_bodies.push(bodies[b].clone());
        out_joints.push(Joint {
            name: joint.name.clone(),
            kind: joint.kind,
            parent: parent.and_then(|p| index[p]),
            placement: placement_of,
            drive: joint.drive,
            mimic: joint.mimic.and_then(|m| {
                Some(Mimic {
                    joint: index.get(m.joint).copied().flatten()?,
                    ..m
                })
            }),
        });
    }
    // Each merged body stays a frame, at its pose in its host; each frame on a merged body
    // moves to the host, its placement composed.
    let mut frames: Vec<Frame> = Vec::new();
    for f in &model.frames {
        let frame = match f.parent {
            Some(p) if host[p] != p => {
                let (rh, xh) = pose[p];
                let Some((r, x)) = pose_of(&f.placement) else {
                    return model.clone();
                };
                Frame {
                    name: f.name.clone(),
                    parent: index[host[p]],
                    placement: placement(&rh.mul_mat(&r), vadd(xh, rh.mul_vec(x))),
                }
            }
            parent => Frame {
                parent: parent.and_then(|p| index[p]),
                ..f.clone()
            },
        };
        frames.push(frame);
    }
    for b in (0..n).filter(|&b| host[b] != b) {
        let (r, x) = pose[b];
        frames.push(Frame {
            name: model.bodies[b].name.clone(),
            parent: index[host[b]],
            placement: placement(&r, x),
        });
    }
    Model {
        bodies: out_bodies,
        joints: out_joints,
        frames,
        ..model.clone()
    }
}
