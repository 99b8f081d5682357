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
    fn letter(self) -> char {
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
    /// Rotation by a quaternion `q = [w, x, y, z]` (normalized before use; the zero quaternion is
    /// an error). 4 positions, 3 velocities: the child's angular velocity in the child frame.
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

/// A joint: its kind, its parent, its placement. Its child is the body with the same index.
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
}

/// Which scalar the generated code uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ScalarKind {
    /// `f64` (the default).
    #[default]
    F64,
    /// `f32`.
    F32,
    /// Generic over `T: nalgebra::RealField + Copy`.
    Generic,
}

/// An output the generator can emit for a chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Output {
    /// `M(q)`.
    MassMatrix,
    /// `N(q, q̇)·q̇` without gravity.
    Bias,
    /// `g(q)`.
    Gravity,
    /// `τ = M·a + bias + gravity`.
    InverseDynamics,
    /// `q̈` from `τ`.
    ForwardDynamics,
    /// The matrix `N(q, q̇)` with `Ṁ − 2N` skew.
    Coriolis,
    /// Centre of mass of the whole chain.
    CenterOfMass,
    /// Linear and angular momentum.
    Momentum,
    /// Kinetic and potential energy.
    Energy,
    /// The wrench each joint transmits.
    JointWrenches,
    /// Linearization about a state.
    Linearization,
}

impl Output {
    /// Every output, with its name in the description grammar.
    pub const ALL: [(Output, &'static str); 11] = [
        (Output::MassMatrix, "mass_matrix"),
        (Output::Bias, "bias"),
        (Output::Gravity, "gravity"),
        (Output::InverseDynamics, "inverse_dynamics"),
        (Output::ForwardDynamics, "forward_dynamics"),
        (Output::Coriolis, "coriolis"),
        (Output::CenterOfMass, "center_of_mass"),
        (Output::Momentum, "momentum"),
        (Output::Energy, "energy"),
        (Output::JointWrenches, "joint_wrenches"),
        (Output::Linearization, "linearization"),
    ];
    /// The outputs generated when a description names none.
    pub const DEFAULT: [Output; 5] = [
        Output::MassMatrix,
        Output::Bias,
        Output::Gravity,
        Output::InverseDynamics,
        Output::ForwardDynamics,
    ];
    /// Its name in the grammar.
    pub fn name(self) -> &'static str {
        Output::ALL
            .iter()
            .find(|(o, _)| *o == self)
            .map(|(_, n)| *n)
            .unwrap_or("")
    }
    /// The output of that name.
    pub fn from_name(s: &str) -> Option<Output> {
        Output::ALL.iter().find(|(_, n)| *n == s).map(|(o, _)| *o)
    }
}

/// A whole chain or tree of rigid bodies: what every front end produces.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// The chain's name (the generated type's name).
    pub name: String,
    /// Visibility of the generated type as Rust source (`""`, `"pub"`, `"pub(crate)"`).
    pub visibility: String,
    /// Documentation lines given with the chain.
    pub doc: Vec<String>,
    /// Gravity acceleration in the world frame (m/s²), or `None` for no gravity.
    pub gravity: Option<[Value; 3]>,
    /// Runtime parameters, referred to by [`Value::Param`].
    pub params: Vec<Param>,
    /// Bodies in depth-first pre-order; `bodies[i]` is the child of `joints[i]`.
    pub bodies: Vec<Body>,
    /// Joints; `joints[i].parent < Some(i)`.
    pub joints: Vec<Joint>,
    /// The scalar of the generated code.
    pub scalar: ScalarKind,
    /// The outputs to generate, sorted, without duplicates.
    pub outputs: Vec<Output>,
}

/// The default gravity, `[0, 0, −9.81]` m/s².
pub const DEFAULT_GRAVITY: [Value; 3] = [Value::Const(0.0), Value::Const(0.0), Value::Const(-9.81)];

impl Model {
    /// A public chain named `name` with the default gravity, no parameters, the default scalar
    /// and the default outputs ([`Output::DEFAULT`]): what a program that builds models (random
    /// trees, tests) needs before it sets anything else.
    pub fn new(name: &str, bodies: Vec<Body>, joints: Vec<Joint>) -> Model {
        Model {
            name: String::from(name),
            visibility: String::from("pub"),
            doc: Vec::new(),
            gravity: Some(DEFAULT_GRAVITY),
            params: Vec::new(),
            bodies,
            joints,
            scalar: ScalarKind::default(),
            outputs: Output::DEFAULT.to_vec(),
        }
    }

    /// Number of bodies (= number of joints).
    pub fn nb(&self) -> usize {
        self.bodies.len()
    }
    /// Number of position coordinates.
    pub fn nq(&self) -> usize {
        self.joints.iter().map(|j| j.kind.nq()).sum()
    }
    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        self.joints.iter().map(|j| j.kind.nv()).sum()
    }
    /// Index of joint `i`'s first position coordinate.
    pub fn q_offset(&self, i: usize) -> usize {
        self.joints[..i].iter().map(|j| j.kind.nq()).sum()
    }
    /// Index of joint `i`'s first velocity coordinate.
    pub fn v_offset(&self, i: usize) -> usize {
        self.joints[..i].iter().map(|j| j.kind.nv()).sum()
    }
    /// The neutral configuration (zeros, identity quaternions).
    pub fn neutral(&self) -> Vec<f64> {
        self.joints.iter().flat_map(|j| j.kind.neutral()).collect()
    }
    /// The parameters' default values.
    pub fn param_defaults(&self) -> Vec<f64> {
        self.params.iter().map(|p| p.default).collect()
    }
    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
    /// Checks the structural invariants the back ends rely on (lengths, parent order, depth-first
    /// order, parameter indices, finite constants, unit axes). Front ends report user errors
    /// themselves, at the user's token; this is the last line of defence, for models built by hand.
    pub fn check(&self) -> Result<(), String> {
        use alloc::format;
        if self.bodies.len() != self.joints.len() {
            return Err(format!(
                "{} bodies but {} joints: each body needs exactly one parent joint",
                self.bodies.len(),
                self.joints.len()
            ));
        }
        let nparams = self.params.len();
        let check_value = |v: &Value, what: &str| -> Result<(), String> {
            match *v {
                Value::Const(x) if !x.is_finite() => Err(format!("{what} is not finite ({x})")),
                Value::Param(i) if i >= nparams => {
                    Err(format!("{what} names parameter #{i}, which does not exist"))
                }
                _ => Ok(()),
            }
        };
        // Depth-first pre-order: each body's parent is either the world or an earlier body that is
        // still on the current path from the root.
        let mut path: Vec<usize> = Vec::new();
        for (i, (j, b)) in self.joints.iter().zip(&self.bodies).enumerate() {
            match j.parent {
                None => path.clear(),
                Some(p) => {
                    if p >= i {
                        return Err(format!(
                            "joint `{}`: parent {p} does not come before child {i}",
                            j.name
                        ));
                    }
                    while path.last().is_some_and(|&top| top != p) {
                        path.pop();
                    }
                    if path.is_empty() {
                        return Err(format!(
                            "joint `{}`: bodies are not in depth-first order",
                            j.name
                        ));
                    }
                }
            }
            path.push(i);
            if let JointKind::Revolute { axis } | JointKind::Prismatic { axis } = j.kind {
                let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
                if !(n - 1.0).abs().le(&1e-9) {
                    return Err(format!(
                        "joint `{}`: axis {axis:?} is not a unit vector",
                        j.name
                    ));
                }
            }
            for v in j.placement.xyz.iter().chain(&j.placement.rpy) {
                check_value(v, &format!("joint `{}` placement", j.name))?;
            }
            check_value(&b.mass, &format!("body `{}` mass", b.name))?;
            for v in b.com.iter().chain(b.inertia.iter().flatten()) {
                check_value(v, &format!("body `{}` mass properties", b.name))?;
            }
        }
        if let Some(g) = &self.gravity {
            for v in g {
                check_value(v, "gravity")?;
            }
        }
        Ok(())
    }
}
