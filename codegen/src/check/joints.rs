//! Joints: what a mimic joint may follow ([`Mimic`]), and drives ([`Drive::problem`], the one
//! implementation of their rules, shared with `Model::check`).
//!
//! [`Mimic`]: crate::model::Mimic

use crate::model::{Drive, JointKind, Mimic};

/// A mimic joint and the joint it follows, as a front end resolved them by name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Follow<'a> {
    /// The mimic joint's name.
    pub joint: &'a str,
    /// Its kind.
    pub kind: JointKind,
    /// The name of the joint it follows.
    pub followed: &'a str,
    /// That joint's kind.
    pub followed_kind: JointKind,
    /// Whether that joint is the mimic joint itself.
    pub itself: bool,
    /// Whether that joint mimics another itself.
    pub followed_mimics: bool,
    /// The factor on the followed joint's coordinate.
    pub multiplier: f64,
    /// The constant added.
    pub offset: f64,
    /// The mimic joint's drive.
    pub drive: Drive,
}

/// What is wrong with a mimic joint: it follows itself or a mimic joint, one of the two is not
/// revolute or prismatic, its multiplier or offset is not finite, or it has damping, friction
/// or limits of its own.
pub fn mimic(f: &Follow) -> Option<String> {
    let why = if f.itself {
        "itself: a joint cannot mimic itself".to_string()
    } else if f.followed_mimics {
        "which is a mimic joint itself: mimic the joint that one follows, with the multipliers \
         and offsets composed"
            .to_string()
    } else if !f.kind.has_one_axis() {
        format!(
            "but `{}` is not revolute or prismatic: only revolute and prismatic joints mimic \
             and are mimicked",
            f.joint
        )
    } else if f.followed_kind == JointKind::Fixed {
        "which is fixed: only revolute and prismatic joints mimic and are mimicked".to_string()
    } else if !f.followed_kind.has_one_axis() {
        "which is not revolute or prismatic: only revolute and prismatic joints mimic and are \
         mimicked"
            .to_string()
    } else if !(f.multiplier.is_finite() && f.offset.is_finite()) {
        format!(
            "but its multiplier {} and offset {} must be finite",
            f.multiplier, f.offset
        )
    } else if f.drive.acts_beyond_inertia() {
        format!("but {}", Mimic::DRIVE_PROBLEM)
    } else {
        return None;
    };
    Some(format!(
        "joint `{}` mimics `{}`, {why}",
        f.joint, f.followed
    ))
}

/// What is wrong with the drive of joint `joint` of `kind` ([`Drive::problem`]), with the field
/// it is about (`"lower"` for the limits together).
pub fn drive(joint: &str, kind: &JointKind, drive: &Drive) -> Option<(&'static str, String)> {
    drive
        .problem(kind)
        .map(|(field, problem)| (field, format!("joint `{joint}`: {problem}")))
}
