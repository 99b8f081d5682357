//! URDF import: builds the same [`Model`] a `.chain` file lowers to from a URDF robot description.
//!
//! # Mapping
//! - `revolute` and `continuous` joints become [`JointKind::Revolute`] (one angle; a `continuous`
//!   joint is not stored as cos/sin as Pinocchio does), `prismatic` becomes
//!   [`JointKind::Prismatic`]. The axis is normalized; URDF's default axis is `[1, 0, 0]`; a zero
//!   axis is an error. Safety tags are ignored.
//! - A `<mimic joint multiplier offset>` joint (revolute, continuous or prismatic, following one
//!   of those) becomes a [`Mimic`] as in Pinocchio 3: its coordinate is
//!   `multiplier·q_followed + offset` (defaults 1 and 0), it leaves `q` and `v`, and the dynamics
//!   are the coupled ones (`M = Gᵀ·M_tree·G`, see [`Mimic`]). Its `<limit>`, damping and
//!   friction are not used (those of the joint it follows apply); its armature is inertia and
//!   is kept. Mimicking a fixed joint, a mimic joint or itself is an error at its line; a
//!   `<mimic>` naming no joint of the file leaves an independent joint, and one on a fixed
//!   joint is ignored, each with a warning (as Pinocchio loads such files).
//! - A joint's `<dynamics damping friction>` and `<limit lower upper effort velocity>` become its
//!   [`Drive`], and so does `<dynamics armature>` (not URDF 1.0; MuJoCo's and Pinocchio's name
//!   for the rotor inertia, added to `M`'s diagonal). Absent limit attributes are no limits;
//!   a negative damping or `lower > upper` is an error at the joint's line.
//! - `<visual>`, `<collision>` and `<material>` (meshes, textures) are never read: an element
//!   there that urdf-rs would refuse (Romeo's empty `<texture/>`) does not stop the import.
//! - Inertias are judged on each moving body once the links welded to it are merged into it
//!   (`Importer::judge_inertias`): one that breaks the triangle inequality or is not positive
//!   semi-definite beyond rounding ([`INERTIA_ROUNDING`] of the model's largest principal
//!   moment) loads as written with a [`Warning`] at the body's link, or is balanced on request
//!   ([`UrdfOptions::balance_inertia`]); a strict load refuses every warning
//!   ([`crate::load::LoadOptions::strict`]). Real files hold placeholders and noise (a 1e-6
//!   base, a camera's odd tensor, ±1e-20), Pinocchio and ROS load them, and the `.chain` rules,
//!   errors at the token, are for descriptions written for this project. Only a non-finite
//!   number or a negative mass is an error.
//! - `floating` joints become [`JointKind::FreeEuler`] with the sequence [`EulerSeq::ZYX`].
//! - `fixed` joints are merged: the child link's mass properties are added to the nearest body
//!   above it (masses summed, centres of mass combined, inertias combined with the parallel-axis
//!   theorem in that body's frame) and the joints below the child are re-attached to that body
//!   with their placements composed. Links fixed to a fixed-base root are part of the world and
//!   their mass is dropped.
//! - `planar` and `spherical` joints are errors.
//! - Frames are URDF's: a joint's `origin` (`xyz`, then `R = Rz(yaw)·Ry(pitch)·Rx(roll)`) is its
//!   [`Placement`]; the axis is in the joint frame. A link's `inertial/origin` places the inertial
//!   frame in the link frame: the centre of mass is its `xyz`, and the tensor, given in the
//!   inertial frame, is `R·I·Rᵀ` in the link frame. A link without `<inertial>` is a massless
//!   body (mass 0, zero inertia).
//! - The root link (the one that is no joint's child) is fixed to the world and dropped: the joints
//!   below it get `parent: None`. With a [`FloatingBase`] other than `Fixed` the root is kept as
//!   the first body (with its inertial) under a joint named `root_joint` with the identity
//!   placement, [`JointKind::FreeEuler`] `zyx` (6 coordinates) or [`JointKind::FreeQuaternion`]
//!   (7 positions, 6 velocities), whose coordinates come first.
//! - Joints and bodies are in depth-first order, the children of a link in document order.
//! - The model's name is the robot's name in UpperCamelCase (`arm6_mixed` → `Arm6Mixed`),
//!   gravity `[0, 0, −9.81]`; the [`Options`] are the defaults (a `pub` type in `f64`, the
//!   default outputs) with a doc line naming the robot.
//!
//! # Errors
//! Malformed XML, a missing required element, an unknown link, a link with two parents, two roots,
//! a cycle, a non-finite number, a negative mass, a zero axis and unsupported joint types are
//! reported as a [`UrdfError`] that names the file and, where the offending `<link>` or `<joint>`
//! can be found in the text, its line; every problem of the links and joints at once. The
//! importer does not panic on any input.
//!
//! # Layout
//! Here: [`UrdfError`], [`from_urdf_str`], the links' and joints' names and numbers, the tree
//! walk that merges fixed joints, and the policy that puts the check stage's problems
//! ([`crate::check`]: the tree, masses, inertias, mimic joints, drives) at their lines, as
//! errors or, for the inertias of merged bodies, warnings. [`crate::import::frames`] holds the
//! transforms and mass properties the walk composes,
//! `lines` finds the lines of elements and of parse errors (urdf-rs gives none) with roxmltree.

use std::cell::RefCell;
use std::collections::HashMap;

use articulated_dynamics::model::{
    Drive, EulerSeq, Frame, Joint, JointKind, Mimic, Model, Placement, Value, DEFAULT_GRAVITY,
};
use articulated_dynamics::spatial::{Mat3, Vec3};

use crate::check::{self, About, Edge, End, Inertia, Noun, Problem, Roots, Strictness};
use crate::options::{Description, Options, Warning};

pub use crate::check::INERTIA_ROUNDING;

mod lines;

use crate::import::frames::{matrix_rpy, rotate_inertia, MassProps, Transform};
pub use crate::import::ImportError;
use lines::{parse_error_line, ElementLines};

/// What a URDF root is attached to the world by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FloatingBase {
    /// Nothing: the root link is the world (a fixed-base robot).
    #[default]
    Fixed,
    /// A free base in Wieber's form, translation then Euler angles `zyx`
    /// ([`JointKind::FreeEuler`]): 6 positions, singular at a pitch of ±90°.
    Euler,
    /// A free base with a quaternion ([`JointKind::FreeQuaternion`], Pinocchio's free flyer):
    /// 7 positions, 6 velocities, no singularity.
    Quaternion,
}

impl From<bool> for FloatingBase {
    /// `true`: [`FloatingBase::Euler`] (what `--floating` and `floating` alone have always
    /// meant); `false`: [`FloatingBase::Fixed`].
    fn from(floating: bool) -> Self {
        if floating {
            FloatingBase::Euler
        } else {
            FloatingBase::Fixed
        }
    }
}

impl FloatingBase {
    /// The base of that name: `euler` or `quaternion` (a free base), `fixed`.
    pub fn from_name(name: &str) -> Option<FloatingBase> {
        match name {
            "fixed" => Some(FloatingBase::Fixed),
            "euler" => Some(FloatingBase::Euler),
            "quaternion" => Some(FloatingBase::Quaternion),
            _ => None,
        }
    }

    /// Whether the root gets a free joint.
    pub fn is_floating(self) -> bool {
        self != FloatingBase::Fixed
    }
}

/// An error found while importing a URDF description (the importers' one error type).
pub type UrdfError = ImportError;

/// Builds the [`Description`] of a URDF robot given as text (see the [module docs](self)), with
/// the root attached to the world as `floating` says (`true`: a free `zyx` Euler base).
///
/// # Errors
/// A [`UrdfError`] with the line of the offending element where it can be found.
pub fn from_urdf_str(
    xml: &str,
    floating: impl Into<FloatingBase>,
) -> Result<Description, UrdfError> {
    from_urdf_str_with(
        xml,
        UrdfOptions {
            floating: floating.into(),
            balance_inertia: false,
        },
    )
}

/// How [`from_urdf_str_with`] imports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UrdfOptions {
    /// The base under the root.
    pub floating: FloatingBase,
    /// Balance the inertias no rigid body has instead of warning about them (MuJoCo's
    /// `balanceinertia`; [`crate::load::LoadOptions::balance_inertia`]).
    pub balance_inertia: bool,
}

/// [`from_urdf_str`] as `options` say.
///
/// # Errors
/// As [`from_urdf_str`].
pub fn from_urdf_str_with(xml: &str, options: UrdfOptions) -> Result<Description, UrdfError> {
    // What the dynamics never reads (`<visual>`, `<collision>`, `<material>`) is blanked
    // out first, newlines kept, so that an element urdf-rs would refuse there (a `<mesh>`
    // without `filename`, as in iCub's description) does not stop the import, and every line
    // number stays the file's.
    let kept = without_geometry(xml);
    let robot = read_robot(&kept)
        .map_err(|e| ImportError::new(format!("malformed URDF: {e}")).at(parse_error_line(xml)))?;
    let lines = ElementLines::new(xml);
    Importer {
        lines,
        robot,
        warnings: RefCell::new(Vec::new()),
        balance: options.balance_inertia,
    }
    .build(options.floating)
}

/// `xml` with every `<visual>`, `<collision>` and `<material>` element replaced by spaces
/// (newlines kept; a `<material>` may stand at the top level, with an empty `<texture/>` that
/// urdf-rs refuses, as in Romeo's description); the text unchanged if it is not well-formed XML
/// (urdf-rs then reports the error).
fn without_geometry(xml: &str) -> String {
    let Ok(doc) = roxmltree::Document::parse(xml) else {
        return xml.to_string();
    };
    let mut bytes = xml.as_bytes().to_vec();
    for node in doc.descendants() {
        if node.is_element()
            && matches!(node.tag_name().name(), "visual" | "collision" | "material")
        {
            for b in &mut bytes[node.range()] {
                if *b != b'\n' {
                    *b = b' ';
                }
            }
        }
    }
    // Only ASCII bytes of whole elements were replaced by ASCII spaces: still UTF-8.
    String::from_utf8(bytes).unwrap_or_else(|_| xml.to_string())
}

/// urdf-rs's reader, with a panic deep in an XML library turned into an error.
fn read_robot(xml: &str) -> Result<urdf_rs::Robot, String> {
    match std::panic::catch_unwind(|| urdf_rs::read_from_string(xml)) {
        Ok(Ok(robot)) => Ok(robot),
        Ok(Err(e)) => Err(e.to_string()),
        Err(_) => Err("the XML reader failed on this text".into()),
    }
}

/// The importer of one robot, with the lines of its elements (for errors).
struct Importer {
    lines: ElementLines,
    robot: urdf_rs::Robot,
    /// What loads but deserves a look, in the order found.
    warnings: RefCell<Vec<Warning>>,
    /// Balance the inertias no rigid body has rather than warn ([`UrdfOptions`]).
    balance: bool,
}

/// The links' tree as the joints describe it ([`check::tree`]), with each joint's links.
struct Tree {
    /// The links' parents, children, roots, and what is wrong with them.
    checked: check::Tree,
    /// Per joint, its parent link and its child link.
    joint_links: Vec<(usize, usize)>,
}

/// The bodies and joints of the model, as the walk builds them.
#[derive(Default)]
struct Built {
    bodies: Vec<(String, MassProps)>,
    /// Per body, the links it is made of: its own, then those welded to it by fixed joints.
    body_links: Vec<Vec<usize>>,
    joints: Vec<Joint>,
    /// `(model joint, URDF joint)` of each mimic joint, resolved once every joint is built.
    mimics: Vec<(usize, usize)>,
    /// The links welded to a body (or to the world) by fixed joints: each stays a frame.
    frames: Vec<Frame>,
}

impl Importer {
    /// The line of the `link`-th link's element.
    fn link_line(&self, link: usize) -> Option<usize> {
        let name = &self.robot.links[link].name;
        let n = self.robot.links[..link]
            .iter()
            .filter(|l| l.name == *name)
            .count();
        self.lines.line("link", name, n)
    }
    /// The line of the `joint`-th joint's element.
    fn joint_line(&self, joint: usize) -> Option<usize> {
        let name = &self.robot.joints[joint].name;
        self.lines.line("joint", name, self.same_name_before(joint))
    }
    /// How many joints before the `joint`-th share its name (which of that name's elements it is).
    fn same_name_before(&self, joint: usize) -> usize {
        let name = &self.robot.joints[joint].name;
        self.robot.joints[..joint]
            .iter()
            .filter(|j| j.name == *name)
            .count()
    }
    /// Records a warning.
    fn warn(&self, line: Option<usize>, message: String) {
        self.warnings.borrow_mut().push(Warning { line, message });
    }
    /// The error `msg` at the `link`-th link's line.
    fn link_error(&self, link: usize, msg: String) -> UrdfError {
        ImportError::new(msg).at(self.link_line(link))
    }
    /// The error `msg` at the `joint`-th joint's line.
    fn joint_error(&self, joint: usize, msg: String) -> UrdfError {
        ImportError::new(msg).at(self.joint_line(joint))
    }

    /// The link's mass properties in its own frame, checked.
    fn link_mass(&self, link: usize) -> Result<MassProps, UrdfError> {
        let l = &self.robot.links[link];
        let inertial = &l.inertial;
        let t = &inertial.inertia;
        let numbers = [
            inertial.mass.value,
            t.ixx,
            t.ixy,
            t.ixz,
            t.iyy,
            t.iyz,
            t.izz,
        ]
        .into_iter()
        .chain(inertial.origin.xyz.0)
        .chain(inertial.origin.rpy.0);
        if numbers.clone().any(|x| !x.is_finite()) {
            return Err(self.link_error(
                link,
                format!("link `{}`: its inertial has a non-finite number", l.name),
            ));
        }
        let m = inertial.mass.value;
        if let Some(problem) = check::mass("link", &l.name, &check::num(m), m, None) {
            return Err(self.link_error(link, problem));
        }
        let i_frame = Mat3([
            [t.ixx, t.ixy, t.ixz],
            [t.ixy, t.iyy, t.iyz],
            [t.ixz, t.iyz, t.izz],
        ]);
        // The inertia is judged once the links welded together are one body
        // (`Importer::judge_inertias`).
        let [roll, pitch, yaw] = *inertial.origin.rpy;
        let i = if [roll, pitch, yaw] == [0.0; 3] {
            i_frame
        } else {
            rotate_inertia(&Mat3::rpy(roll, pitch, yaw), &i_frame)
        };
        Ok(MassProps {
            m: inertial.mass.value,
            c: Vec3(*inertial.origin.xyz),
            i,
        })
    }

    /// The joint's kind (for movable joints), checked; `None` for a fixed joint.
    fn joint_kind(&self, joint: usize) -> Result<Option<JointKind>, UrdfError> {
        use urdf_rs::JointType as T;
        let j = &self.robot.joints[joint];
        let numbers = j.origin.xyz.0.into_iter().chain(j.origin.rpy.0);
        if numbers.chain(j.axis.xyz.0).any(|x| !x.is_finite()) {
            return Err(self.joint_error(
                joint,
                format!(
                    "joint `{}`: its origin or axis has a non-finite number",
                    j.name
                ),
            ));
        }
        if let (Some(m), T::Fixed) = (&j.mimic, &j.joint_type) {
            // TALOS's grippers: a fixed joint has no coordinate to follow anything with.
            self.warn(
                self.joint_line(joint),
                format!(
                    "joint `{}` is fixed and mimics `{}`: the `<mimic>` is ignored",
                    j.name, m.joint
                ),
            );
        }
        let axis = || -> Result<[f64; 3], UrdfError> {
            let a = *j.axis.xyz;
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            if n < 1e-12 {
                return Err(
                    self.joint_error(joint, format!("joint `{}`: the axis {a:?} is zero", j.name))
                );
            }
            Ok([a[0] / n, a[1] / n, a[2] / n])
        };
        Ok(match j.joint_type {
            T::Revolute | T::Continuous => Some(JointKind::Revolute { axis: axis()? }),
            T::Prismatic => Some(JointKind::Prismatic { axis: axis()? }),
            T::Floating => Some(JointKind::FreeEuler { seq: EulerSeq::ZYX }),
            T::Fixed => None,
            T::Planar => {
                return Err(self.joint_error(
                    joint,
                    format!(
                        "joint `{}`: planar joints are not supported (write two prismatic \
                         joints and a revolute joint through massless links)",
                        j.name
                    ),
                ))
            }
            T::Spherical => {
                return Err(self.joint_error(
                    joint,
                    format!(
                        "joint `{}`: spherical joints are not URDF 1.0 and not supported \
                         (write three revolute joints through massless links)",
                        j.name
                    ),
                ))
            }
        })
    }

    /// The joint's drive: `<dynamics damping friction>`, the non-standard `<dynamics armature>`,
    /// and `<limit>`. urdf-rs reads absent limit attributes as 0: a revolute or prismatic
    /// joint with `lower = upper = 0` has no position limits, and a zero `effort` or `velocity`
    /// is no limit (a motor that gives no force would stop every such joint). A continuous
    /// joint has no position limits.
    fn drive(&self, joint: usize, kind: &JointKind) -> Result<Drive, UrdfError> {
        use urdf_rs::JointType as T;
        let j = &self.robot.joints[joint];
        let mut drive = Drive::FREE;
        if let Some(d) = &j.dynamics {
            drive.damping = d.damping;
            drive.friction = d.friction;
        }
        if let Some(text) = self.lines.armature(&j.name, self.same_name_before(joint)) {
            drive.armature = text.trim().parse().map_err(|_| {
                self.joint_error(
                    joint,
                    format!(
                        "joint `{}`: `<dynamics armature=\"{text}\">` is not a number",
                        j.name
                    ),
                )
            })?;
        }
        let l = &j.limit;
        if matches!(j.joint_type, T::Revolute | T::Prismatic) && !(l.lower == 0.0 && l.upper == 0.0)
        {
            drive.lower = l.lower;
            drive.upper = l.upper;
        }
        if l.effort != 0.0 {
            drive.effort = l.effort;
        }
        if l.velocity != 0.0 {
            drive.velocity = l.velocity;
        }
        match check::drive(&j.name, kind, &drive) {
            None => Ok(drive),
            Some((_, problem)) => Err(self.joint_error(joint, problem)),
        }
    }

    /// The names of the model's joints with coordinates in the order Pinocchio's URDF parser
    /// gives them: depth first from the root as ours, but a link's child joints taken in the
    /// order of their names (urdfdom keeps them in a `std::map`), not the file's; fixed joints
    /// are walked through; the free base, named `root_joint` as Pinocchio names it, first.
    fn pinocchio_order(&self, tree: &Tree, root: usize, model: &Model) -> Vec<String> {
        let joints = &self.robot.joints;
        let with_coordinates =
            |name: &str| model.joints.iter().any(|j| j.name == name && j.nv() > 0);
        let mut order: Vec<String> = model
            .joints
            .iter()
            .filter(|j| j.parent.is_none() && j.nv() > 0 && j.name == "root_joint")
            .map(|j| j.name.clone())
            .collect();
        let sorted = |link: usize| {
            let mut children: Vec<usize> = tree.checked.children[link].clone();
            children.sort_by(|&a, &b| joints[a].name.cmp(&joints[b].name));
            children.into_iter().rev()
        };
        let mut stack: Vec<usize> = sorted(root).collect();
        while let Some(j) = stack.pop() {
            if with_coordinates(&joints[j].name) {
                order.push(joints[j].name.clone());
            }
            stack.extend(sorted(tree.joint_links[j].1));
        }
        order
    }

    /// The model: names checked, the tree checked, then walked from the root.
    fn build(&self, floating: FloatingBase) -> Result<Description, UrdfError> {
        if self.robot.links.is_empty() {
            return Err(ImportError::new(format!(
                "robot `{}` has no links",
                self.robot.name
            )));
        }
        let tree = self.tree()?;
        // Every problem of the file at once: the tree's, then those the walk finds from the
        // root (there is none where every link is in a cycle).
        let mut errors: Vec<UrdfError> = tree
            .checked
            .problems
            .iter()
            .map(|p| self.located(p))
            .collect();
        let built = tree
            .checked
            .roots
            .first()
            .map(|&root| self.walk(&tree, root, floating, &mut errors));
        errors.sort_by_key(ImportError::sort_key);
        if let Some(e) = ImportError::all(errors) {
            return Err(e);
        }
        let Some(mut built) = built else {
            return Err(ImportError::new("the robot has no root link"));
        };
        self.judge_inertias(&mut built);
        let model = Model {
            name: camel_case(&self.robot.name),
            gravity: Some(DEFAULT_GRAVITY),
            params: Vec::new(),
            bodies: built
                .bodies
                .into_iter()
                .map(|(name, mp)| mp.into_body(name))
                .collect(),
            joints: built.joints,
            frames: built.frames,
        };
        model
            .check()
            .map_err(|e| ImportError::new(format!("the imported model is invalid: {e}")))?;
        let options = Options {
            doc: vec![format!(
                " Imported from the URDF robot `{}`.",
                self.robot.name
            )],
            ..Options::default()
        };
        let mut warnings = self.warnings.take();
        warnings.sort_by_key(|w| w.line);
        let pinocchio_order = tree
            .checked
            .roots
            .first()
            .map(|&root| self.pinocchio_order(&tree, root, &model))
            .unwrap_or_default();
        let continuous = model
            .joints
            .iter()
            .filter(|j| j.mimic.is_none())
            .filter(|j| {
                self.robot.joints.iter().any(|u| {
                    u.name == j.name && matches!(u.joint_type, urdf_rs::JointType::Continuous)
                })
            })
            .map(|j| j.name.clone())
            .collect();
        Ok(Description {
            model,
            options,
            warnings,
            notes: Vec::new(),
            continuous,
            pinocchio_order,
        })
    }

    /// Judges each moving body's inertia once the links welded to it are merged into it (a
    /// camera's or an antenna's odd tensor merges into a base whose inertia is fine): one
    /// that is not positive semi-definite beyond rounding, or breaks the triangle inequality,
    /// loads with a warning at the body's link. Pinocchio and ROS load such files, M stays
    /// positive definite where the rest of the chain dominates, and MuJoCo offers
    /// `balanceinertia` for them.
    ///
    /// Rounding is judged against the largest principal moment of the whole model, not the
    /// body's own: iCub's ankle holds an otherwise zero tensor with an off-diagonal 1.4e-20,
    /// whose eigenvalues are ±1.4e-20, which is rounding next to a leg's 1e-3 whatever its
    /// sign. Negative down to `16·ε` of that passes silently ([`INERTIA_ROUNDING`]).
    fn judge_inertias(&self, built: &mut Built) {
        let moments: Vec<Option<[f64; 3]>> = built
            .bodies
            .iter()
            .map(|(_, mp)| check::principal_moments(&mp.i.0))
            .collect();
        let largest = moments
            .iter()
            .flatten()
            .fold(0.0f64, |a, e| a.max(e[2].abs()));
        for ((name, mp), links) in built.bodies.iter_mut().zip(&built.body_links) {
            let Some(problem) =
                check::inertia(&Inertia::Full(mp.i.0), Strictness::Model { largest })
            else {
                continue;
            };
            let [a, b, c] = problem.moments();
            let mean = (a + b + c) / 3.0;
            if self.balance && mean > 0.0 {
                // MuJoCo's `balanceinertia`: every principal moment set to their mean, which
                // is isotropic in any frame.
                mp.i = Mat3([[mean, 0.0, 0.0], [0.0, mean, 0.0], [0.0, 0.0, mean]]);
                continue;
            }
            let merged = match &links[1..] {
                [] => String::new(),
                rest => format!(
                    " (with {} welded to it)",
                    rest.iter()
                        .map(|&l| format!("`{}`", self.robot.links[l].name))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            let subject = format!("link `{name}`{merged}");
            self.warn(self.link_line(links[0]), problem.message(&subject));
        }
    }

    /// The tree the joints describe, with every link and joint name defined once and every link
    /// a joint names defined (the first problem of these names); then judged by the check stage
    /// ([`check::tree`]: one root link, no link the child of two joints, no cycle).
    fn tree(&self) -> Result<Tree, UrdfError> {
        let links = &self.robot.links;
        let joints = &self.robot.joints;
        let mut link_index: HashMap<&str, usize> = HashMap::new();
        for (k, l) in links.iter().enumerate() {
            if link_index.insert(l.name.as_str(), k).is_some() {
                return Err(self.link_error(k, format!("link `{}` is defined twice", l.name)));
            }
        }
        let mut joint_names: HashMap<&str, usize> = HashMap::new();
        for (k, j) in joints.iter().enumerate() {
            if joint_names.insert(j.name.as_str(), k).is_some() {
                return Err(self.joint_error(k, format!("joint `{}` is defined twice", j.name)));
            }
        }
        let mut joint_links = Vec::with_capacity(joints.len());
        let mut edges = Vec::with_capacity(joints.len());
        for (k, j) in joints.iter().enumerate() {
            let find = |name: &str, role: &str| {
                link_index.get(name).copied().ok_or_else(|| {
                    self.joint_error(
                        k,
                        format!(
                            "joint `{}`: its {role} link `{name}` is not defined",
                            j.name
                        ),
                    )
                })
            };
            let p = find(&j.parent.link, "parent")?;
            let c = find(&j.child.link, "child")?;
            joint_links.push((p, c));
            edges.push(Edge {
                parent: End::Body(p),
                child: Some(c),
                fixed: matches!(j.joint_type, urdf_rs::JointType::Fixed),
                duplicate: false,
            });
        }
        let link_names: Vec<String> = links.iter().map(|l| l.name.clone()).collect();
        let joint_names: Vec<String> = joints.iter().map(|j| j.name.clone()).collect();
        let checked = check::tree(
            &edges,
            &link_names,
            &joint_names,
            Roots::OneBody,
            Noun::Link,
        );
        Ok(Tree {
            checked,
            joint_links,
        })
    }

    /// A problem of the check stage as an error at the line of the link or joint it is about.
    fn located(&self, p: &Problem) -> UrdfError {
        let line = match p.about {
            About::Body(l) if l < self.robot.links.len() => self.link_line(l),
            About::Parent(j) | About::Child(j) if j < self.robot.joints.len() => self.joint_line(j),
            _ => None,
        };
        ImportError::new(p.message.clone()).at(line)
    }

    /// The bodies and joints in depth-first order from `root`, children in document order:
    /// a movable joint starts a body, a fixed joint welds its child link to the body above (or,
    /// above the first movable joint of a fixed base, to the world, dropping its mass).
    ///
    /// Every problem of the links and joints reached is pushed to `errors`: a link or joint in
    /// error is noted and the walk goes on (the joint as if fixed, the link as if massless).
    /// The check stage has judged the tree: each link is the child of one listed joint at
    /// most, and is reached once.
    fn walk(
        &self,
        tree: &Tree,
        root: usize,
        floating: FloatingBase,
        errors: &mut Vec<UrdfError>,
    ) -> Built {
        let joints = &self.robot.joints;
        let mut built = Built::default();
        // (joint, body the joint's parent link is welded to, that link's frame in the body's).
        let mut stack: Vec<(usize, Option<usize>, Transform)> = Vec::new();
        let push_children = |stack: &mut Vec<_>, link: usize, body: Option<usize>, t: Transform| {
            for &j in tree.checked.children[link].iter().rev() {
                stack.push((j, body, t));
            }
        };
        let mass_of = |link: usize, errors: &mut Vec<UrdfError>| {
            self.link_mass(link).unwrap_or_else(|e| {
                errors.push(e);
                MassProps::ZERO
            })
        };
        let root_body = if floating.is_floating() {
            let name = self.robot.links[root].name.clone();
            built.bodies.push((name, mass_of(root, errors)));
            built.body_links.push(vec![root]);
            built.joints.push(Joint {
                name: "root_joint".into(),
                kind: match floating {
                    FloatingBase::Quaternion => JointKind::FreeQuaternion,
                    _ => JointKind::FreeEuler { seq: EulerSeq::ZYX },
                },
                parent: None,
                placement: Placement::IDENTITY,
                drive: Drive::FREE,
                mimic: None,
            });
            Some(0)
        } else {
            mass_of(root, errors); // checked, then dropped with the world
                                   // The root link stays a frame, at the world's origin.
            built.frames.push(Frame {
                name: self.robot.links[root].name.clone(),
                parent: None,
                placement: Placement::IDENTITY,
            });
            None
        };
        push_children(&mut stack, root, root_body, Transform::IDENTITY);
        while let Some((j, body, t)) = stack.pop() {
            let child = tree.joint_links[j].1;
            let kind = self.joint_kind(j).unwrap_or_else(|e| {
                errors.push(e);
                None
            });
            let mass = mass_of(child, errors);
            let origin = Transform::from_pose(&joints[j].origin);
            let frame = t.then(&origin);
            match kind {
                None => {
                    if let Some(b) = body {
                        let here = mass.transformed(&frame);
                        built.bodies[b].1 = built.bodies[b].1.merged(&here);
                        built.body_links[b].push(child);
                    }
                    built.frames.push(Frame {
                        name: self.robot.links[child].name.clone(),
                        parent: body,
                        placement: placement(frame.p.0, matrix_rpy(&frame.r)),
                    });
                    push_children(&mut stack, child, body, frame);
                }
                Some(kind) => {
                    let placement = if t.identity {
                        placement(*joints[j].origin.xyz, *joints[j].origin.rpy)
                    } else {
                        placement(frame.p.0, matrix_rpy(&frame.r))
                    };
                    let b = built.bodies.len();
                    built
                        .bodies
                        .push((self.robot.links[child].name.clone(), mass));
                    built.body_links.push(vec![child]);
                    let mut drive = self.drive(j, &kind).unwrap_or_else(|e| {
                        errors.push(e);
                        Drive::FREE
                    });
                    if joints[j].mimic.is_some() {
                        // It has no coordinate for limits or losses to act on: those of the
                        // joint it follows apply. Its rotor is inertia and stays.
                        drive = Drive {
                            armature: drive.armature,
                            ..Drive::FREE
                        };
                        built.mimics.push((b, j));
                    }
                    built.joints.push(Joint {
                        name: joints[j].name.clone(),
                        kind,
                        parent: body,
                        placement,
                        drive,
                        mimic: None,
                    });
                    push_children(&mut stack, child, Some(b), Transform::IDENTITY);
                }
            }
        }
        self.resolve_mimics(&mut built, errors);
        built
    }

    /// Points each mimic joint at the model joint it follows, once every joint has its place.
    /// Every problem is pushed to `errors` ([`check::mimic`], at the mimic joint's line).
    fn resolve_mimics(&self, built: &mut Built, errors: &mut Vec<UrdfError>) {
        for &(b, j) in &built.mimics {
            let urdf = &self.robot.joints[j];
            let Some(m) = &urdf.mimic else { continue };
            // A joint of the file that is not one of the model's is fixed (merged away).
            let followed = built.joints.iter().position(|x| x.name == m.joint);
            let followed_kind = match followed {
                Some(f) => built.joints[f].kind,
                None if self.robot.joints.iter().any(|x| x.name == m.joint) => JointKind::Fixed,
                None => {
                    // Alex's hands name joints their file does not have. As Pinocchio loads
                    // it: the joint moves on its own, with its own limits.
                    self.warn(
                        self.joint_line(j),
                        format!(
                            "joint `{}` mimics `{}`, which is not a joint of this robot: it is \
                             loaded as an independent joint",
                            urdf.name, m.joint
                        ),
                    );
                    let kind = built.joints[b].kind;
                    match self.drive(j, &kind) {
                        Ok(drive) => built.joints[b].drive = drive,
                        Err(e) => errors.push(e),
                    }
                    continue;
                }
            };
            let mimic = Mimic {
                joint: followed.unwrap_or(b),
                multiplier: m.multiplier.unwrap_or(1.0),
                offset: m.offset.unwrap_or(0.0),
            };
            let problem = check::mimic(&check::Follow {
                joint: &urdf.name,
                kind: built.joints[b].kind,
                followed: &m.joint,
                followed_kind,
                itself: followed == Some(b),
                followed_mimics: built
                    .mimics
                    .iter()
                    .any(|&(other, _)| Some(other) == followed),
                multiplier: mimic.multiplier,
                offset: mimic.offset,
                drive: built.joints[b].drive,
            });
            match problem {
                Some(p) => errors.push(self.joint_error(j, p)),
                None => built.joints[b].mimic = Some(mimic),
            }
        }
    }
}

/// A placement of constants.
fn placement(xyz: [f64; 3], rpy: [f64; 3]) -> Placement {
    Placement {
        xyz: xyz.map(Value::Const),
        rpy: rpy.map(Value::Const),
    }
}

/// `arm6_mixed` → `Arm6Mixed`; non-alphanumeric characters separate words. A name that would not
/// start with a letter is prefixed with `Robot`.
pub(crate) fn camel_case(name: &str) -> String {
    let mut out = String::new();
    for word in name.split(|c: char| !c.is_ascii_alphanumeric()) {
        let mut chars = word.chars();
        if let Some(first) = chars.next() {
            out.push(first.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    if !out.starts_with(|c: char| c.is_ascii_alphabetic()) {
        out.insert_str(0, "Robot");
    }
    out
}
