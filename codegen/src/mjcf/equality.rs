//! MJCF `<joint>` equalities as mimic joints, on request ([`MjcfOptions::mimic_equalities`]).
//!
//! MuJoCo's equality `y1 − y1ref = a0 + a1·(y2 − y2ref)` (its `polycoef`, offsets from the
//! joints' `ref`) is soft and keeps both coordinates. Here it becomes exact: `joint1` a mimic
//! joint of `joint2` with multiplier `a1` and offset `a0 + y1ref − a1·y2ref` (our `q` is MuJoCo's
//! `qpos`); without `joint2`, `joint1` is locked at `y1ref + a0` (a fixed joint). A `polycoef`
//! with higher terms, or a joint that is not a hinge or a slide, keeps the coordinates with a
//! warning; an inactive equality (`active="false"`) does nothing.
//!
//! [`MjcfOptions::mimic_equalities`]: super::MjcfOptions::mimic_equalities

use articulated_dynamics::model::{Drive, JointKind, Mimic, Placement};
use articulated_dynamics::spatial::{Mat3, Vec3};

use super::xml::{Classed, Element};
use super::{placement, rotation, translation, Importer};
use crate::check::{self, Follow};
use crate::import::frames::Transform;
use crate::import::ImportError;

/// A class no element has: an equality's own attributes only (equality defaults set solver
/// parameters, and a `joint` default is a joint's, not a `<joint>` equality's).
const OWN: &str = "\u{0}own";

impl Importer<'_> {
    /// Every `<joint>` equality of the model, as the [module docs](self) say; each problem is
    /// an error at the equality's line.
    pub(super) fn joint_equalities(&mut self) {
        let root = self.root;
        for section in root.each("equality") {
            for eq in section.each("joint") {
                if let Err(e) = self.joint_equality(eq) {
                    self.errors.push(e);
                }
            }
        }
    }

    fn joint_equality(&mut self, eq: &Element) -> Result<(), ImportError> {
        if eq.own("active") == Some("false") {
            return Ok(());
        }
        let c = Classed {
            el: eq,
            class: OWN,
            defaults: &self.defaults,
        };
        let mut poly = [0.0, 1.0, 0.0, 0.0, 0.0];
        for (p, x) in poly
            .iter_mut()
            .zip(c.some("polycoef", 1, 5)?.unwrap_or_default())
        {
            *p = x;
        }
        let Some(name1) = eq.own("joint1") else {
            return Err(eq.error("a `<joint>` equality needs `joint1`"));
        };
        let find = |name: &str| {
            self.joints
                .iter()
                .position(|j| j.name == name)
                .ok_or_else(|| {
                    eq.error(format!(
                        "the equality names `{name}`, which is not a joint of the model"
                    ))
                })
        };
        let j1 = find(name1)?;
        let one_axis =
            |k: &JointKind| matches!(k, JointKind::Revolute { .. } | JointKind::Prismatic { .. });
        if poly[2..].iter().any(|x| *x != 0.0) || !one_axis(&self.joints[j1].kind) {
            self.warn(
                eq,
                format!(
                    "the joint equality on `{name1}` is not linear between hinges or slides: \
                     not applied, its coordinates are kept"
                ),
            );
            return Ok(());
        }
        let ref1 = self.references.get(name1).copied().unwrap_or(0.0);
        let Some(name2) = eq.own("joint2") else {
            // Locked at `y1ref + a0`: the joint's motion at that position joins its placement.
            let at = ref1 + poly[0];
            let joint = &mut self.joints[j1];
            let motion = match joint.kind {
                JointKind::Revolute { axis } => rotation(Mat3::rot_axis(Vec3(axis), at), at != 0.0),
                JointKind::Prismatic { axis } => translation(axis.map(|a| a * at)),
                _ => Transform::IDENTITY,
            };
            joint.placement = placement(&transform(&joint.placement).then(&motion));
            joint.kind = JointKind::Fixed;
            joint.drive = Drive::FREE;
            return Ok(());
        };
        let j2 = find(name2)?;
        let ref2 = self.references.get(name2).copied().unwrap_or(0.0);
        let mimic = Mimic {
            joint: j2,
            multiplier: poly[1],
            offset: poly[0] + ref1 - poly[1] * ref2,
        };
        let drive = self.joints[j1].drive;
        if drive.acts_beyond_inertia() {
            self.warn(
                eq,
                format!(
                    "joint `{name1}` now mimics `{name2}`: its own damping, friction, spring and \
                     limits are dropped (those of `{name2}` apply)"
                ),
            );
        }
        let drive = Drive {
            armature: drive.armature,
            ..Drive::FREE
        };
        let problem = check::mimic(&Follow {
            joint: name1,
            kind: self.joints[j1].kind,
            followed: name2,
            followed_kind: self.joints[j2].kind,
            itself: j1 == j2,
            followed_mimics: self.joints[j2].mimic.is_some(),
            multiplier: mimic.multiplier,
            offset: mimic.offset,
            drive,
        });
        if let Some(p) = problem {
            return Err(eq.error(p));
        }
        self.joints[j1].drive = drive;
        self.joints[j1].mimic = Some(mimic);
        Ok(())
    }
}

/// The transform of a placement of constants.
fn transform(p: &Placement) -> Transform {
    let c = |v: &articulated_dynamics::model::Value| v.as_const().unwrap_or(0.0);
    let [x, y, z] = p.xyz.each_ref().map(c);
    let [roll, pitch, yaw] = p.rpy.each_ref().map(c);
    Transform {
        r: Mat3::rpy(roll, pitch, yaw),
        p: Vec3([x, y, z]),
        identity: false,
    }
}
