//! MJCF export: any [`Model`] (from a `.chain` file, a URDF or MJCF) written as a MuJoCo model,
//! so that MuJoCo (and MJX) run the same bodies and joints as the generated code.
//!
//! # Mapping
//! - Each body is a `<body>` nested in its parent's, placed by its joint's placement (`pos`,
//!   `quat`); its mass, centre of mass and inertia tensor are an `<inertial>` with
//!   `fullinertia` (a massless body has none).
//! - Revolute → `hinge`, prismatic → `slide`, quaternion spherical → `ball`, quaternion free →
//!   `free` (its placement must be the identity: MuJoCo's free joint is placed in the world); an
//!   Euler spherical joint → three hinges in one body about the sequence's moving axes, and an
//!   Euler free base → three slides then those hinges: MuJoCo composes several joints of a body
//!   the same way, so `qpos` is our `q` and `qvel` our `v` (but the quaternion free joint's
//!   linear velocity, world-frame there). A fixed joint welds its body to the parent.
//! - A drive's armature, damping, friction (`frictionloss`), spring (`stiffness`, `springref`),
//!   limits (`range`) and effort (`actuatorfrcrange`) go on every joint it makes.
//! - A mimic joint keeps its coordinate in MuJoCo, tied to the joint it follows by a `<joint>`
//!   equality (`polycoef="offset multiplier 0 0 0"`), which MuJoCo enforces softly: a note says so.
//! - Frames become sites of their body (or of the world body); gravity is `<option gravity>`.
//! - Parameters are written at their defaults, with a note.
//!
//! Numbers are written with Rust's shortest round-trip form, so the file holds the model's
//! values exactly; angles are radians (`<compiler angle="radian">`).

use std::fmt::Write as _;

use articulated_dynamics::model::{Axis, Drive, JointKind, Model, Placement, Value};
use articulated_dynamics::spatial::Mat3;

use super::shapes::matrix_quat;

/// An exported model: the MJCF text, and what a MuJoCo user should know about it.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The MJCF model.
    pub text: String,
    /// What differs from the model exported (mimic joints as soft equalities, parameters at
    /// their defaults).
    pub notes: Vec<String>,
}

/// Why a model cannot be written as MJCF.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportError(pub String);

impl std::fmt::Display for ExportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ExportError {}

/// Writes `model` as MJCF (see the [module docs](self)).
///
/// # Errors
/// An [`ExportError`] for a quaternion free joint whose placement is not the identity (MuJoCo
/// places free joints in the world).
pub fn to_mjcf(model: &Model) -> Result<Exported, ExportError> {
    let mut w = Writer {
        model,
        out: String::new(),
        notes: Vec::new(),
        equalities: Vec::new(),
    };
    if !model.params.is_empty() {
        let names: Vec<String> = model
            .params
            .iter()
            .map(|p| format!("`{}` = {:?}", p.name, p.default))
            .collect();
        w.notes.push(format!(
            "parameters written at their defaults: {}",
            names.join(", ")
        ));
    }
    let g = model
        .gravity
        .as_ref()
        .map_or([0.0; 3], |g| g.map(|v| w.value(&v)));
    let _ = writeln!(w.out, "<mujoco model=\"{}\">", escape(&model.name));
    let _ = writeln!(w.out, "  <compiler angle=\"radian\" autolimits=\"true\"/>");
    let _ = writeln!(w.out, "  <option gravity=\"{}\"/>", numbers(&g));
    let _ = writeln!(w.out, "  <worldbody>");
    w.sites(None, 4);
    for (b, j) in model.joints.iter().enumerate() {
        if j.parent.is_none() {
            w.body(b, 4)?;
        }
    }
    let _ = writeln!(w.out, "  </worldbody>");
    if !w.equalities.is_empty() {
        let _ = writeln!(w.out, "  <equality>");
        for e in std::mem::take(&mut w.equalities) {
            let _ = writeln!(w.out, "    {e}");
        }
        let _ = writeln!(w.out, "  </equality>");
    }
    let _ = writeln!(w.out, "</mujoco>");
    Ok(Exported {
        text: w.out,
        notes: w.notes,
    })
}

struct Writer<'a> {
    model: &'a Model,
    out: String,
    notes: Vec<String>,
    equalities: Vec<String>,
}

impl Writer<'_> {
    /// A value, a parameter at its default.
    fn value(&self, v: &Value) -> f64 {
        match v {
            Value::Const(x) => *x,
            Value::Param(i) => self.model.params.get(*i).map_or(0.0, |p| p.default),
        }
    }

    /// The placement's `pos` and `quat` attributes (empty for the identity).
    fn pose(&self, p: &Placement) -> String {
        let xyz = p.xyz.map(|v| self.value(&v));
        let rpy = p.rpy.map(|v| self.value(&v));
        let mut s = String::new();
        if xyz != [0.0; 3] {
            let _ = write!(s, " pos=\"{}\"", numbers(&xyz));
        }
        if rpy != [0.0; 3] {
            let q = matrix_quat(&Mat3::rpy(rpy[0], rpy[1], rpy[2]));
            let _ = write!(s, " quat=\"{}\"", numbers(&q));
        }
        s
    }

    /// The frames fixed to `body` (the world for `None`), as sites.
    fn sites(&mut self, body: Option<usize>, indent: usize) {
        for f in self.model.frames.iter().filter(|f| f.parent == body) {
            let pose = self.pose(&f.placement);
            let _ = writeln!(
                self.out,
                "{:indent$}<site name=\"{}\"{pose}/>",
                "",
                escape(&f.name)
            );
        }
    }

    fn body(&mut self, b: usize, indent: usize) -> Result<(), ExportError> {
        let model = self.model;
        let j = &model.joints[b];
        let body = &model.bodies[b];
        let free = matches!(j.kind, JointKind::FreeQuaternion);
        let identity = j
            .placement
            .xyz
            .iter()
            .chain(&j.placement.rpy)
            .all(|v| self.value(v) == 0.0);
        if free && !identity {
            return Err(ExportError(format!(
                "joint `{}`: a quaternion free joint placed away from its parent's origin has no \
                 MJCF form (MuJoCo places free joints in the world)",
                j.name
            )));
        }
        let pose = self.pose(&j.placement);
        let _ = writeln!(
            self.out,
            "{:indent$}<body name=\"{}\"{pose}>",
            "",
            escape(&body.name)
        );
        let inner = indent + 2;
        self.joints(b, inner);
        let m = self.value(&body.mass);
        if m > 0.0 {
            let c = body.com.map(|v| self.value(&v));
            let i = body.inertia.map(|row| row.map(|v| self.value(&v)));
            let full = [i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2]];
            let _ = writeln!(
                self.out,
                "{:inner$}<inertial pos=\"{}\" mass=\"{m:?}\" fullinertia=\"{}\"/>",
                "",
                numbers(&c),
                numbers(&full)
            );
        }
        self.sites(Some(b), inner);
        for (k, child) in model.joints.iter().enumerate() {
            if child.parent == Some(b) {
                self.body(k, inner)?;
            }
        }
        let _ = writeln!(self.out, "{:indent$}</body>", "");
        Ok(())
    }

    /// The MJCF joints of model joint `b`.
    fn joints(&mut self, b: usize, indent: usize) {
        let j = &self.model.joints[b];
        let drive = drive_attributes(&j.drive);
        let name = escape(&j.name);
        let mut line = |ty: &str, suffix: &str, axis: Option<[f64; 3]>| {
            let axis = axis.map_or(String::new(), |a| format!(" axis=\"{}\"", numbers(&a)));
            let _ = writeln!(
                self.out,
                "{:indent$}<joint name=\"{name}{suffix}\" type=\"{ty}\"{axis}{drive}/>",
                ""
            );
        };
        let unit = |a: Axis| match a {
            Axis::X => [1.0, 0.0, 0.0],
            Axis::Y => [0.0, 1.0, 0.0],
            Axis::Z => [0.0, 0.0, 1.0],
        };
        match j.kind {
            JointKind::Revolute { axis } => line("hinge", "", Some(axis)),
            JointKind::Prismatic { axis } => line("slide", "", Some(axis)),
            JointKind::SphericalQuaternion => line("ball", "", None),
            JointKind::FreeQuaternion => line("free", "", None),
            JointKind::SphericalEuler { seq } => {
                for (k, a) in seq.0.iter().enumerate() {
                    line("hinge", &format!("_{}", k + 1), Some(unit(*a)));
                }
            }
            JointKind::FreeEuler { seq } => {
                for (a, s) in [Axis::X, Axis::Y, Axis::Z]
                    .into_iter()
                    .zip(["_x", "_y", "_z"])
                {
                    line("slide", s, Some(unit(a)));
                }
                for (k, a) in seq.0.iter().enumerate() {
                    line("hinge", &format!("_{}", k + 1), Some(unit(*a)));
                }
            }
            JointKind::Fixed => {}
        }
        if let Some(m) = &j.mimic {
            let followed = &self.model.joints[m.joint].name;
            self.equalities.push(format!(
                "<joint joint1=\"{name}\" joint2=\"{}\" polycoef=\"{:?} {:?} 0 0 0\"/>",
                escape(followed),
                m.offset,
                m.multiplier
            ));
            self.notes.push(format!(
                "joint `{}` mimics `{followed}`: in MuJoCo it keeps its coordinate, held to the \
                 other by a soft `<joint>` equality",
                j.name
            ));
        }
    }
}

/// A drive as joint attributes (each only where it is not the default).
fn drive_attributes(d: &Drive) -> String {
    let mut s = String::new();
    for (name, x) in [
        ("armature", d.armature),
        ("damping", d.damping),
        ("frictionloss", d.friction),
        ("stiffness", d.stiffness),
        ("springref", d.rest),
    ] {
        if x != 0.0 {
            let _ = write!(s, " {name}=\"{x:?}\"");
        }
    }
    if d.lower > f64::NEG_INFINITY || d.upper < f64::INFINITY {
        let lo = if d.lower.is_finite() { d.lower } else { -1e10 };
        let hi = if d.upper.is_finite() { d.upper } else { 1e10 };
        let _ = write!(s, " range=\"{lo:?} {hi:?}\"");
    }
    if d.effort.is_finite() {
        let _ = write!(s, " actuatorfrcrange=\"{:?} {:?}\"", -d.effort, d.effort);
    }
    s
}

/// Numbers separated by spaces, each in its shortest round-trip form.
fn numbers(x: &[f64]) -> String {
    x.iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `s` with XML's five special characters escaped.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}
