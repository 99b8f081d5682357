//! A joint's drive: the rotor inertia (armature), the losses (viscous damping, dry friction), a
//! spring (stiffness about a rest position) and the limits (position, speed, effort) a description gives beside the kinematics. Here, outside
//! the `alloc`-only [`model`](crate::model), so that a generated chain can list its joints'
//! drives as constants in a `no_std` build without an allocator.

#[cfg(feature = "alloc")]
use alloc::{
    format,
    string::{String, ToString},
};

/// What a description says about a joint's drive beyond its kinematics (URDF's `<dynamics>` and
/// `<limit>`, MuJoCo's and Pinocchio's `armature`, MuJoCo's joint `stiffness` and `springref`). Each value applies to every velocity
/// coordinate of the joint; [`Drive::FREE`] (no rotor, no losses, no limits) unless given.
///
/// Only the armature enters the dynamics (it is inertia: `M(q) + diag(armature)`, and `τ` gains
/// `armature·q̈`, as in Pinocchio and MuJoCo). Damping, friction, the spring and limits are forces the
/// simulator applies (the runtime's `drives`), so the generated `M`, `τ` and `q̈` stay those of
/// the rigid bodies and their rotors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    /// Rotor inertia reflected through the transmission (kg·m² for rotations, kg for
    /// translations), added to `M`'s diagonal; `≥ 0`.
    pub armature: f64,
    /// Viscous damping `d` (N·m·s/rad or N·s/m): the force `−d·v`; `≥ 0`.
    pub damping: f64,
    /// Dry (Coulomb) friction `f` (N·m or N): the force `−f·sign(v)`; `≥ 0`.
    pub friction: f64,
    /// A spring's stiffness `k` (N·m/rad or N/m): the force `−k·(q − rest)`; `≥ 0`. For revolute
    /// and prismatic joints only.
    pub stiffness: f64,
    /// The position where the spring holds no force (rad or m; MuJoCo's `springref`).
    pub rest: f64,
    /// Lowest position (rad or m; `−∞` for none). For revolute and prismatic joints only.
    pub lower: f64,
    /// Highest position (rad or m; `+∞` for none).
    pub upper: f64,
    /// Largest speed `|v|` (rad/s or m/s; `+∞` for none): reported, not enforced.
    pub velocity: f64,
    /// Largest force `|τ|` the actuator gives (N·m or N; `+∞` for none): the simulator saturates
    /// the commanded force to it.
    pub effort: f64,
}

impl Drive {
    /// Whether it gives anything besides a rotor inertia: damping, friction, a spring or a limit (what a
    /// joint without a coordinate of its own, a mimic joint, cannot have).
    pub fn acts_beyond_inertia(&self) -> bool {
        Drive {
            armature: 0.0,
            ..*self
        } != Drive::FREE
    }

    /// No rotor, no losses, no spring, no limits.
    pub const FREE: Drive = Drive {
        armature: 0.0,
        damping: 0.0,
        friction: 0.0,
        stiffness: 0.0,
        rest: 0.0,
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
        velocity: f64::INFINITY,
        effort: f64::INFINITY,
    };

    /// Whether it is [`Drive::FREE`].
    pub fn is_free(&self) -> bool {
        *self == Drive::FREE
    }

    /// What is wrong with it, if anything: a negative or non-finite armature, damping or
    /// friction or stiffness; a rest position that is not finite; a NaN bound, `lower > upper`, a
    /// speed or effort limit that is not positive; position limits or a spring on a joint with
    /// more than one coordinate (`kind`). With the message,
    /// the field it is about (`"lower"` for the limits together).
    #[cfg(feature = "alloc")]
    pub fn problem(&self, kind: &crate::model::JointKind) -> Option<(&'static str, String)> {
        for (name, x) in [
            ("armature", self.armature),
            ("damping", self.damping),
            ("friction", self.friction),
            ("stiffness", self.stiffness),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Some((name, format!("{name} must be finite and >= 0, found {x}")));
            }
        }
        if !self.rest.is_finite() {
            return Some((
                "rest",
                format!("the rest position must be finite, found {}", self.rest),
            ));
        }
        if self.stiffness != 0.0 && kind.nq() != 1 {
            let message = "a spring (stiffness) applies to revolute and prismatic joints only";
            return Some(("stiffness", message.to_string()));
        }
        if self.lower.is_nan() || self.upper.is_nan() || self.lower > self.upper {
            let message = format!(
                "limits must satisfy lower <= upper, found [{}, {}]",
                self.lower, self.upper
            );
            return Some(("lower", message));
        }
        for (name, x) in [("velocity", self.velocity), ("effort", self.effort)] {
            if x.is_nan() || x <= 0.0 {
                return Some((name, format!("the {name} limit must be > 0, found {x}")));
            }
        }
        let bounded = self.lower > f64::NEG_INFINITY || self.upper < f64::INFINITY;
        if bounded && kind.nq() != 1 {
            let message = "position limits apply to revolute and prismatic joints only";
            let field = if self.lower > f64::NEG_INFINITY {
                "lower"
            } else {
                "upper"
            };
            return Some((field, message.to_string()));
        }
        None
    }
}

impl Default for Drive {
    fn default() -> Self {
        Drive::FREE
    }
}
