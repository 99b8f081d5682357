//! URDF import: builds the same [`Model`] a `.chain` file lowers to from a URDF robot description.
//!
//! # Mapping
//! - `revolute` and `continuous` joints become [`JointKind::Revolute`] (one angle; a `continuous`
//!   joint is not stored as cos/sin as Pinocchio does), `prismatic` becomes
//!   [`JointKind::Prismatic`]. The axis is normalized; URDF's default axis is `[1, 0, 0]`; a zero
//!   axis is an error. Limits, dynamics, mimic and safety tags are ignored.
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
//!   below it get `parent: None`. With `floating = true` the root is kept as the first body (with
//!   its inertial) under a [`JointKind::FreeEuler`] `zyx` joint named `root_joint` with the
//!   identity placement, so its 6 coordinates come first.
//! - Joints and bodies are in depth-first order, the children of a link in document order.
//! - The model's name is the robot's name in UpperCamelCase (`arm6_mixed` → `Arm6Mixed`),
//!   gravity `[0, 0, −9.81]`; the [`Options`] are the defaults (a `pub` type in `f64`, the
//!   default outputs) with a doc line naming the robot.
//!
//! # Errors
//! Malformed XML, a missing required element, an unknown link, a link with two parents, two roots,
//! a cycle, a non-finite number, a negative mass, a zero axis and unsupported joint types are
//! reported as a [`UrdfError`] that names the file and, where the offending `<link>` or `<joint>`
//! can be found in the text, its line. The importer does not panic on any input.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use articulated_dynamics::model::{
    Body, EulerSeq, Joint, JointKind, Model, Placement, Value, DEFAULT_GRAVITY,
};

use crate::options::{Description, Options};

/// An error found while importing a URDF description.
///
/// Displays as `file:line: message` (or `file: message` when no line is known); a description
/// given as a string is called `<urdf>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UrdfError {
    file: Option<PathBuf>,
    line: Option<usize>,
    message: String,
}

impl UrdfError {
    fn new(message: impl Into<String>) -> Self {
        UrdfError {
            file: None,
            line: None,
            message: message.into(),
        }
    }
    fn at(mut self, line: Option<usize>) -> Self {
        self.line = line;
        self
    }
    /// The same error, in the file `path` (for messages).
    pub fn in_file(mut self, path: &Path) -> Self {
        self.file = Some(path.to_path_buf());
        self
    }
    /// The file the description was read from (`None` for [`from_urdf_str`] alone).
    pub fn file(&self) -> Option<&Path> {
        self.file.as_deref()
    }
    /// The 1-based line of the offending element, when it could be found.
    pub fn line(&self) -> Option<usize> {
        self.line
    }
    /// What is wrong, without the file and line.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for UrdfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.file {
            Some(p) => write!(f, "{}", p.display())?,
            None => write!(f, "<urdf>")?,
        }
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for UrdfError {}

/// Builds the [`Description`] of a URDF robot given as text (see the [module docs](self)). With
/// `floating`, a free `zyx` Euler base is put under the root link.
///
/// # Errors
/// A [`UrdfError`] with the line of the offending element where it can be found.
pub fn from_urdf_str(xml: &str, floating: bool) -> Result<Description, UrdfError> {
    let robot = read_robot(xml)
        .map_err(|e| UrdfError::new(format!("malformed URDF: {e}")).at(locate_parse_error(xml)))?;
    Importer { text: xml, robot }.build(floating)
}

/// urdf-rs's reader, with a panic deep in an XML library turned into an error.
fn read_robot(xml: &str) -> Result<urdf_rs::Robot, String> {
    match std::panic::catch_unwind(|| urdf_rs::read_from_string(xml)) {
        Ok(Ok(robot)) => Ok(robot),
        Ok(Err(e)) => Err(e.to_string()),
        Err(_) => Err("the XML reader failed on this text".into()),
    }
}

// ---------------------------------------------------------------------------------------------
// Finding the line of a parse error (urdf-rs gives none).

/// The line urdf-rs's error most likely comes from: the first badly nested tag, else the first
/// `<link>` or `<joint>` element that fails to read on its own.
fn locate_parse_error(text: &str) -> Option<usize> {
    if let Err(pos) = check_nesting(text) {
        return Some(line_at(text, pos));
    }
    for element in ["link", "joint"] {
        for (start, end) in element_blocks(text, element) {
            let alone = format!("<robot name=\"x\">{}</robot>", &text[start..end]);
            if read_robot(&alone).is_err() {
                return Some(line_at(text, start));
            }
        }
    }
    None
}

fn line_at(text: &str, pos: usize) -> usize {
    text[..pos.min(text.len())].matches('\n').count() + 1
}

/// Checks that tags nest; on failure the byte offset of the offending tag (a closing tag that
/// does not match, or an opening tag never closed).
fn check_nesting(text: &str) -> Result<(), usize> {
    let mut open: Vec<(&str, usize)> = Vec::new();
    let mut i = 0;
    while let Some(k) = text[i..].find('<') {
        let start = i + k;
        let rest = &text[start..];
        let (skip_to, tag) = if rest.starts_with("<!--") {
            (rest.find("-->").map(|e| e + 3), None)
        } else if rest.starts_with("<![CDATA[") {
            (rest.find("]]>").map(|e| e + 3), None)
        } else if rest.starts_with("<?") || rest.starts_with("<!") {
            (rest.find('>').map(|e| e + 1), None)
        } else {
            (
                rest.find('>').map(|e| e + 1),
                rest.find('>').map(|e| &rest[1..e]),
            )
        };
        let Some(len) = skip_to else {
            return Err(start);
        };
        i = start + len;
        let Some(tag) = tag else { continue };
        let name_of = |t: &str| -> String {
            t.chars()
                .take_while(|c| !c.is_whitespace() && *c != '/')
                .collect()
        };
        if let Some(closing) = tag.strip_prefix('/') {
            let name = name_of(closing.trim_start());
            match open.pop() {
                Some((o, _)) if name_of(o) == name => {}
                // `<a><b></a>`: `<b>` is the one left open.
                Some((_, o_start)) if open.iter().any(|(t, _)| name_of(t) == name) => {
                    return Err(o_start)
                }
                _ => return Err(start),
            }
        } else if !tag.ends_with('/') {
            open.push((tag, start));
        }
    }
    match open.first() {
        Some((_, start)) => Err(*start),
        None => Ok(()),
    }
}

/// Byte ranges of the `<element …/>` and `<element …>…</element>` elements in `text`.
fn element_blocks(text: &str, element: &str) -> Vec<(usize, usize)> {
    let open = format!("<{element}");
    let close = format!("</{element}>");
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(k) = text[from..].find(&open) {
        let start = from + k;
        from = start + open.len();
        if !text[from..].starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
            continue;
        }
        let Some(gt) = text[from..].find('>') else {
            break;
        };
        let tag_end = from + gt + 1;
        let end = if text[..tag_end].ends_with("/>") {
            tag_end
        } else {
            match text[tag_end..].find(&close) {
                Some(c) => tag_end + c + close.len(),
                None => break,
            }
        };
        out.push((start, end));
        from = end;
    }
    out
}

// ---------------------------------------------------------------------------------------------
// 3×3 helpers.

type Mat3 = [[f64; 3]; 3];
type Vec3 = [f64; 3];

const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `Rz(rpy[2])·Ry(rpy[1])·Rx(rpy[0])`.
fn rpy_matrix(rpy: Vec3) -> Mat3 {
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let (sy, cy) = rpy[2].sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// Roll, pitch, yaw of a rotation matrix, accurate to rounding everywhere (also near pitch =
/// ±π/2): yaw is taken from the first column, then `Rz(−yaw)·R = Ry(pitch)·Rx(roll)` gives the
/// other two from well-conditioned entries.
fn matrix_rpy(r: &Mat3) -> Vec3 {
    let yaw = r[1][0].atan2(r[0][0]);
    let rt = mul(&transpose(&rpy_matrix([0.0, 0.0, yaw])), r);
    let pitch = (-rt[2][0]).atan2(rt[0][0]);
    let roll = (-rt[1][2]).atan2(rt[1][1]);
    [roll, pitch, yaw]
}

fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

fn transpose(a: &Mat3) -> Mat3 {
    let mut t = [[0.0; 3]; 3];
    for (i, row) in a.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            t[j][i] = *x;
        }
    }
    t
}

fn mul_vec(a: &Mat3, v: &Vec3) -> Vec3 {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}

/// `R·I·Rᵀ`, symmetrized.
fn rotate_inertia(r: &Mat3, i: &Mat3) -> Mat3 {
    let mut out = mul(&mul(r, i), &transpose(r));
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let s = 0.5 * (out[a][b] + out[b][a]);
        out[a][b] = s;
        out[b][a] = s;
    }
    out
}

/// A rigid transform: a frame's origin `p` and axes `r` in another frame.
#[derive(Clone, Copy)]
struct Transform {
    r: Mat3,
    p: Vec3,
    identity: bool,
}

impl Transform {
    const IDENTITY: Transform = Transform {
        r: IDENTITY,
        p: [0.0; 3],
        identity: true,
    };
    fn from_pose(pose: &urdf_rs::Pose) -> Self {
        Transform {
            r: rpy_matrix(*pose.rpy),
            p: *pose.xyz,
            identity: false,
        }
    }
    /// `self ∘ other`: `other` given in the frame `self` describes.
    fn then(&self, other: &Transform) -> Transform {
        if self.identity {
            return *other;
        }
        if other.identity {
            return *self;
        }
        let q = mul_vec(&self.r, &other.p);
        Transform {
            r: mul(&self.r, &other.r),
            p: [self.p[0] + q[0], self.p[1] + q[1], self.p[2] + q[2]],
            identity: false,
        }
    }
}

/// Mass properties in some frame: mass, centre of mass, inertia about the centre of mass.
#[derive(Clone, Copy)]
struct MassProps {
    m: f64,
    c: Vec3,
    i: Mat3,
}

impl MassProps {
    /// The same properties seen from the frame in which `t` describes their frame.
    fn transformed(&self, t: &Transform) -> MassProps {
        if t.identity {
            return *self;
        }
        let c = mul_vec(&t.r, &self.c);
        MassProps {
            m: self.m,
            c: [t.p[0] + c[0], t.p[1] + c[1], t.p[2] + c[2]],
            i: rotate_inertia(&t.r, &self.i),
        }
    }

    /// Both bodies as one rigid body (both given in the same frame): the parallel-axis theorem
    /// moves each inertia to the common centre of mass.
    fn merged(&self, o: &MassProps) -> MassProps {
        let m = self.m + o.m;
        let c = if m > 0.0 {
            [0, 1, 2].map(|k| (self.m * self.c[k] + o.m * o.c[k]) / m)
        } else {
            [0.0; 3]
        };
        let mut i = [[0.0; 3]; 3];
        for (a, row) in i.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x = self.i[a][b] + o.i[a][b];
            }
        }
        for part in [self, o] {
            let d = [0, 1, 2].map(|k| part.c[k] - c[k]);
            let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            for (a, row) in i.iter_mut().enumerate() {
                for (b, x) in row.iter_mut().enumerate() {
                    let delta = if a == b { d2 } else { 0.0 };
                    *x += part.m * (delta - d[a] * d[b]);
                }
            }
        }
        MassProps { m, c, i }
    }
}

// ---------------------------------------------------------------------------------------------
// Finding an element's line in the text.

/// The 1-based line of the `n`-th (0-based) `<element … name="name" …>` tag in `text`.
fn find_line(text: &str, element: &str, name: &str, n: usize) -> Option<usize> {
    let open = format!("<{element}");
    let mut seen = 0;
    let mut from = 0;
    while let Some(k) = text[from..].find(&open) {
        let start = from + k;
        from = start + open.len();
        let rest = &text[from..];
        if !rest.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
            continue;
        }
        let end = rest.find('>').unwrap_or(rest.len());
        if tag_attribute(&rest[..end], "name") == Some(name) {
            if seen == n {
                return Some(line_at(text, start));
            }
            seen += 1;
        }
    }
    None
}

/// The value of attribute `attr` in the inside of a tag (`a="x" b='y'`).
fn tag_attribute<'t>(mut tag: &'t str, attr: &str) -> Option<&'t str> {
    loop {
        tag = tag.trim_start();
        let eq = tag.find('=')?;
        let key = tag[..eq].trim();
        let rest = tag[eq + 1..].trim_start();
        let quote = rest.chars().next().filter(|c| *c == '"' || *c == '\'')?;
        let body = &rest[1..];
        let close = body.find(quote)?;
        if key == attr {
            return Some(&body[..close]);
        }
        tag = &body[close + 1..];
    }
}

// ---------------------------------------------------------------------------------------------
// The importer.

struct Importer<'t> {
    text: &'t str,
    robot: urdf_rs::Robot,
}

impl Importer<'_> {
    fn link_line(&self, link: usize) -> Option<usize> {
        let name = &self.robot.links[link].name;
        let n = self.robot.links[..link]
            .iter()
            .filter(|l| l.name == *name)
            .count();
        find_line(self.text, "link", name, n)
    }
    fn joint_line(&self, joint: usize) -> Option<usize> {
        let name = &self.robot.joints[joint].name;
        let n = self.robot.joints[..joint]
            .iter()
            .filter(|j| j.name == *name)
            .count();
        find_line(self.text, "joint", name, n)
    }
    fn link_error(&self, link: usize, msg: String) -> UrdfError {
        UrdfError::new(msg).at(self.link_line(link))
    }
    fn joint_error(&self, joint: usize, msg: String) -> UrdfError {
        UrdfError::new(msg).at(self.joint_line(joint))
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
        if inertial.mass.value < 0.0 {
            return Err(self.link_error(
                link,
                format!("link `{}`: negative mass {}", l.name, inertial.mass.value),
            ));
        }
        let i_frame = [
            [t.ixx, t.ixy, t.ixz],
            [t.ixy, t.iyy, t.iyz],
            [t.ixz, t.iyz, t.izz],
        ];
        let rpy = *inertial.origin.rpy;
        let i = if rpy == [0.0; 3] {
            i_frame
        } else {
            rotate_inertia(&rpy_matrix(rpy), &i_frame)
        };
        Ok(MassProps {
            m: inertial.mass.value,
            c: *inertial.origin.xyz,
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

    fn build(&self, floating: bool) -> Result<Description, UrdfError> {
        let links = &self.robot.links;
        let joints = &self.robot.joints;
        if links.is_empty() {
            return Err(UrdfError::new(format!(
                "robot `{}` has no links",
                self.robot.name
            )));
        }
        // Names.
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
        // Tree structure.
        let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
        let mut joint_child = Vec::with_capacity(joints.len());
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
            if let Some(other) = parent_joint[c] {
                return Err(self.joint_error(
                    k,
                    format!(
                        "link `{}` has two parents: joints `{}` and `{}` both name it as child",
                        links[c].name, joints[other].name, j.name
                    ),
                ));
            }
            parent_joint[c] = Some(k);
            children[p].push(k);
            joint_child.push(c);
        }
        let roots: Vec<usize> = (0..links.len())
            .filter(|&k| parent_joint[k].is_none())
            .collect();
        let cycle_error = |start: usize| {
            // Follow parents until a link repeats: that link is on the cycle.
            let mut seen = vec![false; links.len()];
            let mut l = start;
            while !seen[l] {
                seen[l] = true;
                match parent_joint[l] {
                    Some(j) => l = link_index[joints[j].parent.link.as_str()],
                    None => break,
                }
            }
            let j = parent_joint[l].unwrap_or(0);
            self.joint_error(
                j,
                format!(
                    "the joints form a cycle through link `{}` (joint `{}`)",
                    links[l].name,
                    joints.get(j).map_or("", |j| j.name.as_str())
                ),
            )
        };
        let root = match roots.as_slice() {
            [] => return Err(cycle_error(0)),
            [r] => *r,
            [a, b, ..] => {
                return Err(self.link_error(
                    *b,
                    format!(
                        "two root links (links that are no joint's child): `{}` and `{}`; a \
                         URDF robot is one tree",
                        links[*a].name, links[*b].name
                    ),
                ))
            }
        };

        // Depth-first walk, children in document order, fixed joints merged.
        let mut bodies: Vec<(String, MassProps)> = Vec::new();
        let mut out_joints: Vec<Joint> = Vec::new();
        let mut reached = vec![false; links.len()];
        reached[root] = true;
        // (joint, body the joint's parent link is welded to, that link's frame in the body's).
        let mut stack: Vec<(usize, Option<usize>, Transform)> = Vec::new();
        let push_children = |stack: &mut Vec<_>, link: usize, body: Option<usize>, t: Transform| {
            for &j in children[link].iter().rev() {
                stack.push((j, body, t));
            }
        };
        let root_body = if floating {
            bodies.push((links[root].name.clone(), self.link_mass(root)?));
            out_joints.push(Joint {
                name: "root_joint".into(),
                kind: JointKind::FreeEuler { seq: EulerSeq::ZYX },
                parent: None,
                placement: Placement::IDENTITY,
            });
            Some(0)
        } else {
            self.link_mass(root)?; // checked, then dropped with the world
            None
        };
        push_children(&mut stack, root, root_body, Transform::IDENTITY);
        while let Some((j, body, t)) = stack.pop() {
            let child = joint_child[j];
            if reached[child] {
                return Err(cycle_error(child));
            }
            reached[child] = true;
            let kind = self.joint_kind(j)?;
            let mass = self.link_mass(child)?;
            let origin = Transform::from_pose(&joints[j].origin);
            let frame = t.then(&origin);
            match kind {
                None => {
                    if let Some(b) = body {
                        let here = mass.transformed(&frame);
                        bodies[b].1 = bodies[b].1.merged(&here);
                    }
                    push_children(&mut stack, child, body, frame);
                }
                Some(kind) => {
                    let placement = if t.identity {
                        placement(*joints[j].origin.xyz, *joints[j].origin.rpy)
                    } else {
                        placement(frame.p, matrix_rpy(&frame.r))
                    };
                    let b = bodies.len();
                    bodies.push((links[child].name.clone(), mass));
                    out_joints.push(Joint {
                        name: joints[j].name.clone(),
                        kind,
                        parent: body,
                        placement,
                    });
                    push_children(&mut stack, child, Some(b), Transform::IDENTITY);
                }
            }
        }
        if let Some(k) = reached.iter().position(|r| !r) {
            return Err(cycle_error(k));
        }

        let model = Model {
            name: camel_case(&self.robot.name),
            gravity: Some(DEFAULT_GRAVITY),
            params: Vec::new(),
            bodies: bodies
                .into_iter()
                .map(|(name, mp)| Body {
                    name,
                    mass: Value::Const(mp.m),
                    com: mp.c.map(Value::Const),
                    inertia: mp.i.map(|row| row.map(Value::Const)),
                })
                .collect(),
            joints: out_joints,
        };
        model
            .check()
            .map_err(|e| UrdfError::new(format!("the imported model is invalid: {e}")))?;
        let options = Options {
            doc: vec![format!(
                " Imported from the URDF robot `{}`.",
                self.robot.name
            )],
            ..Options::default()
        };
        Ok(Description { model, options })
    }
}

fn placement(xyz: Vec3, rpy: Vec3) -> Placement {
    Placement {
        xyz: xyz.map(Value::Const),
        rpy: rpy.map(Value::Const),
    }
}

/// `arm6_mixed` → `Arm6Mixed`; non-alphanumeric characters separate words. A name that would not
/// start with a letter is prefixed with `Robot`.
fn camel_case(name: &str) -> String {
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
