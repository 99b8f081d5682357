//! The chain model: the intermediate representation every front end lowers to (the `chain!`
//! grammar, `.chain` files, URDF) and every back end reads (the reference dynamics, the
//! generator).
//!
//! # Frames
//! Every body has a frame. A joint connects a parent (a body, or the world) to exactly one child
//! body. The **joint frame** is the parent frame moved by the joint's [`Placement`]: first the
//! translation `xyz`, then the rotation `R = Rz(yaw)·Ry(pitch)·Rx(roll)` with `rpy = [roll, pitch,
//! yaw]` (as URDF). The child's body frame is the joint frame moved by the joint's own motion
//! ([`JointKind`]). A body's centre of mass and its inertia (about the centre of mass) are given
//! in its body frame.
//!
//! # Order
//! `bodies[i]` is the child of `joints[i]`. Bodies are stored in depth-first pre-order from the
//! world, children in declaration order (URDF: document order), so `joints[i].parent < Some(i)`.
//! Generalized coordinates follow the same order: joint `i` owns `q[q_offset(i)..][..nq]` and
//! `v[v_offset(i)..][..nv]`.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

pub use crate::drive::Drive;
use crate::scalar::Scalar;

/// A number in the model: a constant, or a runtime parameter (an index into [`Model::params`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A literal, already folded.
    Const(f64),
    /// The runtime parameter `params[i]`.
    Param(usize),
}

impl Value {
    /// The value for the given parameter values, in the scalar `T`.
    pub fn get<T: Scalar>(&self, params: &[T]) -> T {
        match *self {
            Value::Const(x) => T::from_f64(x),
            Value::Param(i) => params[i],
        }
    }
    /// The constant, if it is one.
    pub fn as_const(&self) -> Option<f64> {
        match *self {
            Value::Const(x) => Some(x),
            Value::Param(_) => None,
        }
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Const(x)
    }
}

/// A runtime parameter: a named number the user can change without regenerating code (a payload,
/// a mass being identified). `default` is the value the description gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Its name in the description.
    pub name: String,
    /// The value it takes unless the caller passes another.
    pub default: f64,
}

/// A coordinate axis of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The frame's x axis.
    X,
    /// The frame's y axis.
    Y,
    /// The frame's z axis.
    Z,
}

impl Axis {
    /// The unit vector of this axis.
    pub fn unit(self) -> [f64; 3] {
        match self {
            Axis::X => [1.0, 0.0, 0.0],
            Axis::Y => [0.0, 1.0, 0.0],
            Axis::Z => [0.0, 0.0, 1.0],
        }
    }
    /// `x`, `y` or `z`.
    pub fn letter(self) -> char {
        match self {
            Axis::X => 'x',
            Axis::Y => 'y',
            Axis::Z => 'z',
        }
    }
}

/// An intrinsic Euler-angle sequence: `"xyz"` means `R = Rx(θ1)·Ry(θ2)·Rz(θ3)` (rotations about the
/// moving frame's axes, applied left to right), the same as three revolute joints about x, then y,
/// then z through massless frames. Hemami's roll-pitch-yaw is `xyz`. Valid sequences have no two
/// equal neighbours: the six Tait–Bryan (`xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx`) and the six
/// proper Euler (`xyx`, `xzx`, `yxy`, `yzy`, `zxz`, `zyz`) sequences.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EulerSeq(pub [Axis; 3]);

impl EulerSeq {
    /// Wieber's free-base orientation and the default of a free Euler joint: `R = Rz·Ry·Rx`.
    pub const ZYX: EulerSeq = EulerSeq([Axis::Z, Axis::Y, Axis::X]);
    /// Roll, pitch, yaw about the moving axes (Hemami): `R = Rx·Ry·Rz`.
    pub const XYZ: EulerSeq = EulerSeq([Axis::X, Axis::Y, Axis::Z]);

    /// Parses a three-letter sequence such as `"zyx"`; `None` if it is not one of the twelve valid
    /// sequences.
    pub fn parse(s: &str) -> Option<Self> {
        let mut axes = [Axis::X; 3];
        let mut n = 0;
        for c in s.chars() {
            if n == 3 {
                return None;
            }
            axes[n] = match c {
                'x' | 'X' => Axis::X,
                'y' | 'Y' => Axis::Y,
                'z' | 'Z' => Axis::Z,
                _ => return None,
            };
            n += 1;
        }
        if n != 3 || axes[0] == axes[1] || axes[1] == axes[2] {
            return None;
        }
        Some(EulerSeq(axes))
    }

    /// The sequence as three lowercase letters.
    pub fn name(&self) -> String {
        self.0.iter().map(|a| a.letter()).collect()
    }
}

pub use crate::spatial::QUATERNION_NORM_TOLERANCE;

/// What a joint lets its child do relative to the joint frame, and how its coordinates read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation by `q` about `axis` (a unit vector in the joint frame). 1 position, 1 velocity
    /// (`v = q̇`). A URDF `continuous` joint is this, with one angle.
    Revolute {
        /// Unit axis in the joint frame.
        axis: [f64; 3],
    },
    /// Translation by `q·axis` (a unit vector in the joint frame). 1 position, 1 velocity.
    Prismatic {
        /// Unit axis in the joint frame.
        axis: [f64; 3],
    },
    /// Rotation by three Euler angles `[θ1, θ2, θ3]` in the sequence `seq` (see [`EulerSeq`]).
    /// 3 positions, 3 velocities, `v = q̇` (the angle rates).
    SphericalEuler {
        /// The angle sequence.
        seq: EulerSeq,
    },
    /// Rotation by a quaternion `q = [w, x, y, z]`, **scalar first** (normalized before use; one
    /// whose norm is off 1 by more than [`QUATERNION_NORM_TOLERANCE`] is an error). 4 positions,
    /// 3 velocities: the child's angular velocity in the child frame.
    SphericalQuaternion,
    /// A free-floating base in Wieber's form: `q = [x, y, z, θ1, θ2, θ3]`, a translation in the
    /// joint frame followed by Euler angles in `seq` (default [`EulerSeq::ZYX`]); `v = q̇`.
    /// Equivalent to three prismatic joints x, y, z then a [`JointKind::SphericalEuler`].
    FreeEuler {
        /// The angle sequence of the orientation.
        seq: EulerSeq,
    },
    /// A free-floating base `q = [x, y, z, w, qx, qy, qz]`: position of the child origin in the
    /// joint frame, then its orientation as a quaternion. 6 velocities `v = [vx, vy, vz, ωx, ωy,
    /// ωz]`: the linear velocity of the child origin and the angular velocity, **both in the child
    /// frame** (Pinocchio's free-flyer convention).
    FreeQuaternion,
    /// No motion: the child is rigidly attached. No coordinates.
    Fixed,
}

impl JointKind {
    /// Number of position coordinates.
    pub fn nq(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::SphericalEuler { .. } => 3,
            JointKind::SphericalQuaternion => 4,
            JointKind::FreeEuler { .. } => 6,
            JointKind::FreeQuaternion => 7,
            JointKind::Fixed => 0,
        }
    }
    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::SphericalEuler { .. } | JointKind::SphericalQuaternion => 3,
            JointKind::FreeEuler { .. } | JointKind::FreeQuaternion => 6,
            JointKind::Fixed => 0,
        }
    }
    /// Whether the joint moves along or about one axis (revolute, prismatic): the joints that
    /// can mimic and be mimicked ([`Mimic`]).
    pub fn has_one_axis(&self) -> bool {
        matches!(
            self,
            JointKind::Revolute { .. } | JointKind::Prismatic { .. }
        )
    }
    /// The neutral configuration of this joint (zeros; the identity quaternion).
    pub fn neutral(&self) -> Vec<f64> {
        let mut q = alloc::vec![0.0; self.nq()];
        match self {
            JointKind::SphericalQuaternion => q[0] = 1.0,
            JointKind::FreeQuaternion => q[3] = 1.0,
            _ => {}
        }
        q
    }
}

/// Where a joint frame sits in its parent's frame: translation `xyz`, then rotation
/// `Rz(rpy[2])·Ry(rpy[1])·Rx(rpy[0])` (URDF's `origin`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Translation of the joint frame's origin, in the parent frame (m).
    pub xyz: [Value; 3],
    /// Roll, pitch, yaw (rad), fixed-axis x-y-z, i.e. `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub rpy: [Value; 3],
}

impl Placement {
    /// The identity placement.
    pub const IDENTITY: Placement = Placement {
        xyz: [Value::Const(0.0); 3],
        rpy: [Value::Const(0.0); 3],
    };
}

/// A rigid body's mass properties, in its own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Its name in the description.
    pub name: String,
    /// Mass (kg). Zero is allowed only for massless frames (URDF links without an inertial).
    pub mass: Value,
    /// Centre of mass in the body frame (m).
    pub com: [Value; 3],
    /// Inertia tensor about the centre of mass, in body-frame axes (kg·m²), symmetric.
    pub inertia: [[Value; 3]; 3],
}

/// A named frame fixed to a body (or to the world): a tool tip, a foot sole, a sensor, or a
/// URDF link that the importer merged into the body it is welded to. Every body is a frame too,
/// under its own name, at its body frame ([`Model::frame`]); these are the others.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Its name: unique among the bodies' and the frames'.
    pub name: String,
    /// The body it is fixed to, or `None` for the world.
    pub parent: Option<usize>,
    /// Where it sits in its parent's frame.
    pub placement: Placement,
}

/// A joint: its kind, its parent, its placement, its drive. Its child is the body with the same
/// index.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Its name in the description.
    pub name: String,
    /// Kind and coordinates.
    pub kind: JointKind,
    /// Index of the parent body, or `None` for the world.
    pub parent: Option<usize>,
    /// The joint frame in the parent frame.
    pub placement: Placement,
    /// What lies between the joint and its actuator: rotor inertia, losses, limits.
    pub drive: Drive,
    /// `Some` when the joint follows another (URDF's `<mimic>`): it then has no coordinate of its
    /// own (see [`Mimic`]).
    pub mimic: Option<Mimic>,
}

impl Joint {
    /// Number of position coordinates the joint owns in `q`: its kind's, none for a mimic joint.
    pub fn nq(&self) -> usize {
        if self.mimic.is_some() {
            0
        } else {
            self.kind.nq()
        }
    }
    /// Number of velocity coordinates the joint owns in `v`: its kind's, none for a mimic joint.
    pub fn nv(&self) -> usize {
        if self.mimic.is_some() {
            0
        } else {
            self.kind.nv()
        }
    }
}

/// A joint that follows another: its coordinate is `multiplier·q_j + offset`, where `q_j` is the
/// coordinate of the joint it follows (URDF's `<mimic joint multiplier offset>`, a gripper's
/// second finger, gears, a parallelogram linkage). As in Pinocchio 3, the mimic joint leaves `q`
/// and `v`: the model has one coordinate fewer, its velocity is `multiplier·v_j`, and the
/// dynamics are those of the tree with the coupling built in, `M = Gᵀ·M_tree·G` and
/// `τ = Gᵀ·τ_tree`, where `G` maps the model's velocities to the tree's ([`Coupling`]). Both
/// joints are revolute or prismatic (of either kind), and the followed joint is not itself a
/// mimic joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mimic {
    /// Index of the joint it follows in [`Model::joints`].
    pub joint: usize,
    /// The factor on the followed joint's coordinate (URDF's default 1).
    pub multiplier: f64,
    /// The constant added (rad or m; URDF's default 0).
    pub offset: f64,
}

impl Mimic {
    /// Why a mimic joint's drive may hold nothing but its armature ([`Drive::acts_beyond_inertia`]).
    pub const DRIVE_PROBLEM: &'static str = "a mimic joint has no coordinate, so no damping, \
         friction or limits of its own (its armature is allowed: it is inertia)";
}

/// Where one coordinate of the tree (every joint with its own coordinates, mimic joints too)
/// comes from in the model's coordinates: `tree[k] = multiplier·model[index] + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Source {
    /// The model coordinate.
    pub index: usize,
    /// Its factor (1 but for a mimic joint's coordinate).
    pub multiplier: f64,
    /// The constant added (0 but for a mimic joint's position).
    pub offset: f64,
}

/// The linear map `G` from a model's coordinates to those of its tree, where every mimic joint has
/// a coordinate of its own ([`Mimic`]): `q_tree = G·q + o`, `v_tree = G·v`, and back, by the
/// principle of virtual work, `τ = Gᵀ·τ_tree`, `M = Gᵀ·M_tree·G`. The identity for a model
/// without mimic joints. Its maps never multiply by one nor add zero, so that a symbolic scalar
/// traced through them records nothing for the joints that do not mimic.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    /// Per position coordinate of the tree.
    pub q: Vec<Source>,
    /// Per velocity coordinate of the tree.
    pub v: Vec<Source>,
    /// Number of the model's position coordinates.
    pub nq: usize,
    /// Number of the model's velocity coordinates.
    pub nv: usize,
}

impl Coupling {
    /// Whether the model has no mimic joint (`G = I`).
    pub fn is_identity(&self) -> bool {
        self.q.len() == self.nq && self.v.len() == self.nv
    }

    fn apply<T: Scalar>(s: &Source, x: &[T], offset: bool) -> T {
        let mut y = x[s.index];
        if s.multiplier != 1.0 {
            y = y * T::from_f64(s.multiplier);
        }
        if offset && s.offset != 0.0 {
            y = y + T::from_f64(s.offset);
        }
        y
    }

    /// The tree's positions `G·q + o`.
    pub fn expand_q<T: Scalar>(&self, q: &[T]) -> Vec<T> {
        self.q.iter().map(|s| Self::apply(s, q, true)).collect()
    }

    /// The tree's velocities (or accelerations) `G·v`.
    pub fn expand_v<T: Scalar>(&self, v: &[T]) -> Vec<T> {
        self.v.iter().map(|s| Self::apply(s, v, false)).collect()
    }

    /// The model's generalized force `Gᵀ·f` for the tree's `f` (one per tree velocity).
    pub fn reduce<T: Scalar>(&self, f: &[T]) -> Vec<T> {
        let mut out: Vec<Option<T>> = alloc::vec![None; self.nv];
        for (s, &x) in self.v.iter().zip(f) {
            let x = if s.multiplier != 1.0 {
                x * T::from_f64(s.multiplier)
            } else {
                x
            };
            let slot = &mut out[s.index];
            *slot = Some(match *slot {
                Some(y) => y + x,
                None => x,
            });
        }
        out.into_iter().map(|x| x.unwrap_or_else(T::zero)).collect()
    }

    /// `J·G` for the tree's `J`, `rows × nv_tree` row-major: `rows × nv`, row-major.
    pub fn reduce_columns<T: Scalar>(&self, j: &[T], rows: usize) -> Vec<T> {
        let n = self.v.len();
        (0..rows)
            .flat_map(|r| self.reduce(&j[r * n..(r + 1) * n]))
            .collect()
    }

    /// `Gᵀ·M·G` for the tree's square `M` (`nv_tree × nv_tree`, row-major): `nv × nv`, row-major.
    pub fn reduce_matrix<T: Scalar>(&self, m: &[T]) -> Vec<T> {
        if self.is_identity() {
            // The reference's forward dynamics reads `M` at every call: no copies by column.
            return m.to_vec();
        }
        let n = self.v.len();
        // `M·G`, then `Gᵀ·(M·G)` by reducing its columns.
        let mg = self.reduce_columns(m, n);
        let nv = self.nv;
        let column = |c: usize| -> Vec<T> { (0..n).map(|r| mg[r * nv + c]).collect() };
        let reduced_columns: Vec<Vec<T>> = (0..nv).map(|c| self.reduce(&column(c))).collect();
        (0..nv * nv)
            .map(|k| reduced_columns[k % nv][k / nv])
            .collect()
    }
}

/// A whole chain or tree of rigid bodies: what every front end produces.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// The chain's name (the generated type's name).
    pub name: String,
    /// Gravity acceleration in the world frame (m/s²), or `None` for no gravity.
    pub gravity: Option<[Value; 3]>,
    /// Runtime parameters, referred to by [`Value::Param`].
    pub params: Vec<Param>,
    /// Bodies in depth-first pre-order; `bodies[i]` is the child of `joints[i]`.
    pub bodies: Vec<Body>,
    /// Joints; `joints[i].parent < Some(i)`.
    pub joints: Vec<Joint>,
    /// The frames besides the bodies' ([`Frame`]).
    pub frames: Vec<Frame>,
}

/// The default gravity, `[0, 0, −9.81]` m/s².
pub const DEFAULT_GRAVITY: [Value; 3] = [Value::Const(0.0), Value::Const(0.0), Value::Const(-9.81)];

impl Model {
    /// A chain named `name` with the default gravity and no parameters: what a program that
    /// builds models (random trees, tests) needs before it sets anything else.
    pub fn new(name: &str, bodies: Vec<Body>, joints: Vec<Joint>) -> Model {
        Model {
            name: String::from(name),
            gravity: Some(DEFAULT_GRAVITY),
            params: Vec::new(),
            bodies,
            joints,
            frames: Vec::new(),
        }
    }

    /// The frame called `name`: a body's (at its body frame) or one of [`Model::frames`], as
    /// its parent body (`None`: the world) and its placement there.
    pub fn frame(&self, name: &str) -> Option<(Option<usize>, Placement)> {
        match self.body_index(name) {
            Some(b) => Some((Some(b), Placement::IDENTITY)),
            None => self
                .frames
                .iter()
                .find(|f| f.name == name)
                .map(|f| (f.parent, f.placement)),
        }
    }

    /// Every frame's name: the bodies', then [`Model::frames`]'.
    pub fn frame_names(&self) -> impl Iterator<Item = &str> {
        self.bodies
            .iter()
            .map(|b| b.name.as_str())
            .chain(self.frames.iter().map(|f| f.name.as_str()))
    }

    /// Number of bodies (= number of joints).
    pub fn nb(&self) -> usize {
        self.bodies.len()
    }
    /// Number of position coordinates (mimic joints have none).
    pub fn nq(&self) -> usize {
        self.joints.iter().map(Joint::nq).sum()
    }
    /// Number of velocity coordinates (mimic joints have none).
    pub fn nv(&self) -> usize {
        self.joints.iter().map(Joint::nv).sum()
    }
    /// Index of joint `i`'s first position coordinate.
    pub fn q_offset(&self, i: usize) -> usize {
        self.joints[..i].iter().map(Joint::nq).sum()
    }
    /// Index of joint `i`'s first velocity coordinate.
    pub fn v_offset(&self, i: usize) -> usize {
        self.joints[..i].iter().map(Joint::nv).sum()
    }
    /// The name of each position and each velocity coordinate, in order: the joint's name, and
    /// for a joint of several coordinates a component after a dot. Revolute and prismatic:
    /// `elbow`. Euler angles: `hip.rz`, `hip.ry`, `hip.rx` in the joint's sequence (rates the
    /// same). A quaternion: `q` is `wrist.qw`, `.qx`, `.qy`, `.qz` and `v` is `wrist.wx`, `.wy`,
    /// `.wz` (the child frame's angular velocity). A free Euler base: `base.x`, `.y`, `.z` then its
    /// angles, for `q` and `v` alike. A free quaternion base: `q` is `base.x`, `.y`, `.z`, `.qw`,
    /// `.qx`, `.qy`, `.qz` and `v` is `base.vx`, `.vy`, `.vz`, `.wx`, `.wy`, `.wz`. Fixed and mimic
    /// joints have none.
    pub fn coordinate_names(&self) -> (Vec<String>, Vec<String>) {
        let (mut q, mut v) = (Vec::new(), Vec::new());
        for j in self.joints.iter().filter(|j| j.mimic.is_none()) {
            let named = |parts: &[&str]| -> Vec<String> {
                parts
                    .iter()
                    .map(|p| alloc::format!("{}.{p}", j.name))
                    .collect()
            };
            let angles = |seq: &EulerSeq| -> Vec<String> {
                seq.0
                    .iter()
                    .map(|a| alloc::format!("{}.r{}", j.name, a.letter()))
                    .collect()
            };
            let (jq, jv) = match &j.kind {
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
                    (alloc::vec![j.name.clone()], alloc::vec![j.name.clone()])
                }
                JointKind::SphericalEuler { seq } => (angles(seq), angles(seq)),
                JointKind::SphericalQuaternion => {
                    (named(&["qw", "qx", "qy", "qz"]), named(&["wx", "wy", "wz"]))
                }
                JointKind::FreeEuler { seq } => {
                    let mut all = named(&["x", "y", "z"]);
                    all.extend(angles(seq));
                    (all.clone(), all)
                }
                JointKind::FreeQuaternion => (
                    named(&["x", "y", "z", "qw", "qx", "qy", "qz"]),
                    named(&["vx", "vy", "vz", "wx", "wy", "wz"]),
                ),
                JointKind::Fixed => (Vec::new(), Vec::new()),
            };
            q.extend(jq);
            v.extend(jv);
        }
        (q, v)
    }
    /// The unit of each position and each velocity coordinate, in the order of
    /// [`coordinate_names`](Self::coordinate_names): angles (revolute, Euler) `rad` and their
    /// rates `rad/s`; translations (prismatic, a free base's `x`, `y`, `z`) `m` and `m/s`; a
    /// quaternion's components `1` (a unit quaternion has no dimension) and its angular velocity
    /// `rad/s`. Fixed and mimic joints have none.
    pub fn coordinate_units(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let (mut q, mut v) = (Vec::new(), Vec::new());
        for j in self.joints.iter().filter(|j| j.mimic.is_none()) {
            let (jq, jv): (&[&str], &[&str]) = match &j.kind {
                JointKind::Revolute { .. } => (&["rad"], &["rad/s"]),
                JointKind::Prismatic { .. } => (&["m"], &["m/s"]),
                JointKind::SphericalEuler { .. } => (&["rad"; 3], &["rad/s"; 3]),
                JointKind::SphericalQuaternion => (&["1"; 4], &["rad/s"; 3]),
                JointKind::FreeEuler { .. } => (
                    &["m", "m", "m", "rad", "rad", "rad"],
                    &["m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"],
                ),
                JointKind::FreeQuaternion => (
                    &["m", "m", "m", "1", "1", "1", "1"],
                    &["m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"],
                ),
                JointKind::Fixed => (&[], &[]),
            };
            q.extend_from_slice(jq);
            v.extend_from_slice(jv);
        }
        (q, v)
    }
    /// Whether a joint follows another ([`Mimic`]).
    pub fn has_mimic(&self) -> bool {
        self.joints.iter().any(|j| j.mimic.is_some())
    }
    /// The map from the model's coordinates to its tree's, where mimic joints have coordinates
    /// of their own (the order of `reference::Tree`). Call it on a checked model
    /// ([`Model::check`]): a mimic joint naming a joint out of range panics.
    pub fn coupling(&self) -> Coupling {
        let (mut q, mut v) = (Vec::new(), Vec::new());
        for (i, j) in self.joints.iter().enumerate() {
            match j.mimic {
                Some(m) => {
                    let followed = Source {
                        index: self.q_offset(m.joint),
                        multiplier: m.multiplier,
                        offset: m.offset,
                    };
                    q.push(followed);
                    v.push(Source {
                        index: self.v_offset(m.joint),
                        offset: 0.0,
                        ..followed
                    });
                }
                None => {
                    let own = |index, n: usize| {
                        (index..index + n).map(|index| Source {
                            index,
                            multiplier: 1.0,
                            offset: 0.0,
                        })
                    };
                    q.extend(own(self.q_offset(i), j.kind.nq()));
                    v.extend(own(self.v_offset(i), j.kind.nv()));
                }
            }
        }
        Coupling {
            q,
            v,
            nq: self.nq(),
            nv: self.nv(),
        }
    }
    /// The neutral configuration (zeros, identity quaternions).
    pub fn neutral(&self) -> Vec<f64> {
        self.joints
            .iter()
            .filter(|j| j.mimic.is_none())
            .flat_map(|j| j.kind.neutral())
            .collect()
    }
    /// The parameters' default values.
    pub fn param_defaults(&self) -> Vec<f64> {
        self.params.iter().map(|p| p.default).collect()
    }
    /// The joint that velocity coordinate `k` belongs to.
    pub fn joint_of_velocity(&self, k: usize) -> Option<&Joint> {
        let mut at = 0;
        self.joints.iter().find(|j| {
            at += j.nv();
            k < at
        })
    }
    /// Whether the bodies form a serial chain: one joint on the world, and no body with two
    /// children.
    pub fn is_serial(&self) -> bool {
        let mut children = alloc::vec![0usize; self.nb()];
        let mut roots = 0;
        for j in &self.joints {
            match j.parent {
                Some(p) => children[p] += 1,
                None => roots += 1,
            }
        }
        roots <= 1 && children.iter().all(|&c| c <= 1)
    }
    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
    /// What is wrong with joint `j`'s [`Mimic`], if anything.
    fn mimic_problem(&self, j: &Joint) -> Option<String> {
        use alloc::format;
        let m = j.mimic?;
        let Some(followed) = self.joints.get(m.joint) else {
            return Some(format!(
                "it mimics joint #{}, which does not exist",
                m.joint
            ));
        };
        Some(if core::ptr::eq(followed, j) {
            String::from("it mimics itself")
        } else if followed.mimic.is_some() {
            format!(
                "it mimics `{}`, which is a mimic joint itself: mimic the joint that one follows",
                followed.name
            )
        } else if !j.kind.has_one_axis() || !followed.kind.has_one_axis() {
            format!(
                "it mimics `{}`: only revolute and prismatic joints mimic and are mimicked",
                followed.name
            )
        } else if !(m.multiplier.is_finite() && m.offset.is_finite()) {
            format!(
                "its multiplier {} and offset {} must be finite",
                m.multiplier, m.offset
            )
        } else if j.drive.acts_beyond_inertia() {
            String::from(Mimic::DRIVE_PROBLEM)
        } else {
            return None;
        })
    }

    /// Checks the structural invariants the back ends rely on (lengths, parent order, depth-first
    /// order, parameter indices, finite constants, unit axes). Front ends report user errors
    /// themselves, at the user's token; this is the last line of defence, for models built by hand.
    ///
    /// # Errors
    /// The first [`ModelError`] found.
    pub fn check(&self) -> Result<(), ModelError> {
        if self.bodies.len() != self.joints.len() {
            return Err(ModelError::Counts {
                bodies: self.bodies.len(),
                joints: self.joints.len(),
            });
        }
        let check_value = |v: &Value, place: Place| -> Result<(), ModelError> {
            match *v {
                Value::Const(x) if !x.is_finite() => Err(ModelError::NonFinite { place, value: x }),
                Value::Param(index) if index >= self.params.len() => {
                    Err(ModelError::UnknownParam { place, index })
                }
                _ => Ok(()),
            }
        };
        // Depth-first pre-order: each body's parent is either the world or an earlier body that is
        // still on the current path from the root.
        let mut path: Vec<usize> = Vec::new();
        for (i, (j, b)) in self.joints.iter().zip(&self.bodies).enumerate() {
            let joint = || j.name.clone();
            match j.parent {
                None => path.clear(),
                Some(p) if p >= i => {
                    return Err(ModelError::ParentAfterChild { joint: joint() });
                }
                Some(p) => {
                    while path.last().is_some_and(|&top| top != p) {
                        path.pop();
                    }
                    if path.is_empty() {
                        return Err(ModelError::NotDepthFirst { joint: joint() });
                    }
                }
            }
            path.push(i);
            if let JointKind::Revolute { axis } | JointKind::Prismatic { axis } = j.kind {
                let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
                if !(n - 1.0).abs().le(&1e-9) {
                    return Err(ModelError::AxisNotUnit {
                        joint: joint(),
                        axis,
                    });
                }
            }
            for v in j.placement.xyz.iter().chain(&j.placement.rpy) {
                check_value(v, Place::Placement(joint()))?;
            }
            if let Some(problem) = self.mimic_problem(j) {
                return Err(ModelError::Mimic {
                    joint: joint(),
                    problem,
                });
            }
            if let Some((_, problem)) = j.drive.problem(&j.kind) {
                return Err(ModelError::Drive {
                    joint: joint(),
                    problem,
                });
            }
            for v in [&b.mass]
                .into_iter()
                .chain(&b.com)
                .chain(b.inertia.iter().flatten())
            {
                check_value(v, Place::MassProperties(b.name.clone()))?;
            }
        }
        for v in self.gravity.iter().flatten() {
            check_value(v, Place::Gravity)?;
        }
        for (k, f) in self.frames.iter().enumerate() {
            if f.parent.is_some_and(|p| p >= self.bodies.len()) {
                return Err(ModelError::Frame {
                    frame: f.name.clone(),
                    problem: String::from("its parent body does not exist"),
                });
            }
            let taken = self.bodies.iter().any(|b| b.name == f.name)
                || self.frames[..k].iter().any(|g| g.name == f.name);
            if taken {
                return Err(ModelError::Frame {
                    frame: f.name.clone(),
                    problem: String::from("another body or frame has its name"),
                });
            }
            for v in f.placement.xyz.iter().chain(&f.placement.rpy) {
                check_value(v, Place::Frame(f.name.clone()))?;
            }
        }
        Ok(())
    }
}

/// Where in a [`Model`] a number stands, for [`ModelError`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Place {
    /// The placement of the named joint.
    Placement(String),
    /// The mass, centre of mass or inertia of the named body.
    MassProperties(String),
    /// Gravity.
    Gravity,
    /// The placement of the named frame.
    Frame(String),
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::Placement(joint) => write!(f, "the placement of joint `{joint}`"),
            Place::MassProperties(body) => write!(f, "the mass properties of body `{body}`"),
            Place::Gravity => write!(f, "gravity"),
            Place::Frame(frame) => write!(f, "the placement of frame `{frame}`"),
        }
    }
}

/// A model that breaks an invariant the back ends rely on ([`Model::check`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ModelError {
    /// `bodies` and `joints` differ in length: each body needs exactly one parent joint.
    Counts {
        /// Number of bodies.
        bodies: usize,
        /// Number of joints.
        joints: usize,
    },
    /// A joint's parent does not come before its child.
    ParentAfterChild {
        /// The joint.
        joint: String,
    },
    /// The bodies are not in depth-first pre-order.
    NotDepthFirst {
        /// The first joint out of order.
        joint: String,
    },
    /// A revolute or prismatic axis is not a unit vector.
    AxisNotUnit {
        /// The joint.
        joint: String,
        /// Its axis.
        axis: [f64; 3],
    },
    /// A constant is NaN or infinite.
    NonFinite {
        /// Where it stands.
        place: Place,
        /// The value.
        value: f64,
    },
    /// A joint's [`Drive`] is not valid ([`Drive::problem`]).
    Drive {
        /// The joint.
        joint: String,
        /// What is wrong.
        problem: String,
    },
    /// A joint's [`Mimic`] is not valid.
    Mimic {
        /// The joint.
        joint: String,
        /// What is wrong.
        problem: String,
    },
    /// A [`Value::Param`] names a parameter the model does not have.
    UnknownParam {
        /// Where it stands.
        place: Place,
        /// The index it names.
        index: usize,
    },
    /// A [`Frame`] with an unknown parent or a name already taken.
    Frame {
        /// The frame.
        frame: String,
        /// What is wrong.
        problem: String,
    },
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelError::Counts { bodies, joints } => write!(
                f,
                "{bodies} bodies but {joints} joints: each body needs exactly one parent joint"
            ),
            ModelError::ParentAfterChild { joint } => {
                write!(
                    f,
                    "joint `{joint}`: its parent does not come before its child"
                )
            }
            ModelError::NotDepthFirst { joint } => {
                write!(f, "joint `{joint}`: bodies are not in depth-first order")
            }
            ModelError::AxisNotUnit { joint, axis } => {
                write!(f, "joint `{joint}`: axis {axis:?} is not a unit vector")
            }
            ModelError::NonFinite { place, value } => {
                write!(f, "a number in {place} is not finite ({value})")
            }
            ModelError::Drive { joint, problem } | ModelError::Mimic { joint, problem } => {
                write!(f, "joint `{joint}`: {problem}")
            }
            ModelError::UnknownParam { place, index } => write!(
                f,
                "a number in {place} names parameter #{index}, which does not exist"
            ),
            ModelError::Frame { frame, problem } => write!(f, "frame `{frame}`: {problem}"),
        }
    }
}

impl core::error::Error for ModelError {}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint(name: &str, kind: JointKind, mimic: Option<Mimic>) -> Joint {
        Joint {
            name: name.into(),
            kind,
            parent: None,
            placement: Placement::IDENTITY,
            drive: Drive::FREE,
            mimic,
        }
    }

    /// Every kind of joint, a fixed and a mimic one: each name has its unit, written out here
    /// from the kinds' definitions.
    #[test]
    fn every_coordinate_has_its_unit() {
        let mimic = Mimic {
            joint: 1,
            multiplier: 1.0,
            offset: 0.0,
        };
        let model = Model::new(
            "units",
            Vec::new(),
            alloc::vec![
                joint("base", JointKind::FreeQuaternion, None),
                joint(
                    "elbow",
                    JointKind::Revolute {
                        axis: [0.0, 0.0, 1.0]
                    },
                    None
                ),
                joint(
                    "slide",
                    JointKind::Prismatic {
                        axis: [1.0, 0.0, 0.0]
                    },
                    None
                ),
                joint(
                    "hip",
                    JointKind::SphericalEuler { seq: EulerSeq::XYZ },
                    None
                ),
                joint("wrist", JointKind::SphericalQuaternion, None),
                joint("float", JointKind::FreeEuler { seq: EulerSeq::ZYX }, None),
                joint("weld", JointKind::Fixed, None),
                joint(
                    "twin",
                    JointKind::Revolute {
                        axis: [0.0, 0.0, 1.0]
                    },
                    Some(mimic)
                ),
            ],
        );
        let (names_q, names_v) = model.coordinate_names();
        let (units_q, units_v) = model.coordinate_units();
        let named = |names: &[String], units: &[&str]| -> Vec<String> {
            names
                .iter()
                .zip(units)
                .map(|(n, u)| alloc::format!("{n} {u}"))
                .collect()
        };
        let q = [
            "base.x m",
            "base.y m",
            "base.z m",
            "base.qw 1",
            "base.qx 1",
            "base.qy 1",
            "base.qz 1",
            "elbow rad",
            "slide m",
            "hip.rx rad",
            "hip.ry rad",
            "hip.rz rad",
            "wrist.qw 1",
            "wrist.qx 1",
            "wrist.qy 1",
            "wrist.qz 1",
            "float.x m",
            "float.y m",
            "float.z m",
            "float.rz rad",
            "float.ry rad",
            "float.rx rad",
        ];
        let v = [
            "base.vx m/s",
            "base.vy m/s",
            "base.vz m/s",
            "base.wx rad/s",
            "base.wy rad/s",
            "base.wz rad/s",
            "elbow rad/s",
            "slide m/s",
            "hip.rx rad/s",
            "hip.ry rad/s",
            "hip.rz rad/s",
            "wrist.wx rad/s",
            "wrist.wy rad/s",
            "wrist.wz rad/s",
            "float.x m/s",
            "float.y m/s",
            "float.z m/s",
            "float.rz rad/s",
            "float.ry rad/s",
            "float.rx rad/s",
        ];
        assert_eq!((units_q.len(), units_v.len()), (model.nq(), model.nv()));
        assert_eq!(named(&names_q, &units_q), q);
        assert_eq!(named(&names_v, &units_v), v);
    }
}
