//! MJCF import: builds the same [`Model`] a `.chain` file or a URDF lowers to from a MuJoCo
//! model (`<mujoco>`), with MuJoCo's compiler rules, so that our `q` is MuJoCo's `qpos`, our
//! `v` its `qvel` (but the free joint's, see below), and `M`, the bias and `τ` are MuJoCo's.
//!
//! # Mapping
//! - **Bodies.** The `<worldbody>` tree, depth first in document order (MuJoCo's order: `q` and
//!   `v` follow its `qposadr` and `dofadr`). A body with no joint is welded to its parent: its
//!   mass joins the body above (dropped when that is the world) and it stays a frame. A body's
//!   `pos` and orientation place it in its parent; `<frame>` elements compose into what they hold.
//! - **Joints.** `hinge` → revolute, `slide` → prismatic, `ball` → a quaternion spherical joint
//!   (`[w, x, y, z]`, angular velocity in the body frame, as MuJoCo), `free` and `<freejoint/>` →
//!   a quaternion free base (`[x, y, z, w, qx, qy, qz]` as MuJoCo's `qpos`; MuJoCo's free
//!   `qvel` is `[v (world); ω (body)]` where ours is `[v; ω]` both in the body frame). Several
//!   joints in one body become a chain of massless bodies, named `{body}_{joint}`, the last
//!   carrying the body's mass. A joint's `pos` is its anchor in the body frame: a hinge or ball
//!   turns the body about it (`T = P·Trans(p)·R(q)·Trans(−p)`, MuJoCo's `mj_kinematics`), so
//!   the model's body frame is put at the anchor and what the body holds is moved by `−p`. A
//!   hinge's or slide's `ref` is folded into its placement (MuJoCo moves the joint by
//!   `qpos − ref`), so `q` is `qpos` (MuJoCo's initial `qpos0` is `ref`; our neutral `q` stays
//!   0).
//! - **Drives.** `armature`, `damping` and `stiffness` (their linear terms), `springref` (the
//!   spring's rest position), `frictionloss`, a `range` that limits (`limited`, or `autolimits`
//!   and a range given), a symmetric `actuatorfrcrange` → the joint's [`Drive`]. A ball's or free
//!   joint's spring, `springdamper`, a ball's cone limit, an asymmetric force range and higher
//!   polynomial terms are not represented: skipped with a [`Warning`].
//! - **Mass.** `<inertial>` (`pos`, an orientation, `mass`, `diaginertia` or `fullinertia`
//!   ordered `xx yy zz xy xz yz`), or the geoms' by `inertiafromgeom` (`auto`: where a body has
//!   no `<inertial>`; `true`: always; `false`: never) within `inertiagrouprange`: spheres,
//!   capsules, cylinders, ellipsoids and boxes, solid or `shellinertia`, by `mass` or `density`
//!   (1000 by default), placed by `pos` and an orientation or by `fromto`. The compiler's
//!   `boundmass`, `boundinertia`, `balanceinertia` and `settotalmass` apply as MuJoCo applies
//!   them (the total counts bodies welded to the world, whose mass the model then drops). Mesh
//!   geoms from binary STL and OBJ files (or `vertex` and `face`) with the mesh's `scale` and its
//!   `inertia` (`legacy`, MuJoCo's default, which over-counts a non-convex mesh as MuJoCo
//!   does; `exact`; `shell`); a convex hull's inertia (`convex`) is not computed yet.
//! - **Compiler.** `angle` (degrees by default; quaternions are never angles), `eulerseq`
//!   (lower case: axes that move, upper case: fixed axes). `<option gravity>` and
//!   `<flag gravity="disable">` set gravity.
//! - **Defaults.** `<default>` classes, nested classes inheriting from the class around them, an
//!   element's `class`, and `childclass` on bodies and frames (`<freejoint>` takes no defaults).
//! - **Includes.** `<include file>`, relative to the model file's directory; a problem inside an
//!   included file is reported at that file's line.
//! - **Sites** become frames of their body (a site named as a body gets `_site` appended).
//! - **Not represented**, each skipped with a [`Warning`] at its line: equality constraints (the
//!   dynamics are MuJoCo's without them; on request a `<joint>` equality becomes a mimic joint or
//!   a lock, [`MjcfOptions::mimic_equalities`]), tendons, actuators (`τ` is the caller's), a body's
//!   `gravcomp`.
//!
//! # Errors
//! Malformed XML, an unknown default class, a joint or geom type that is not supported, a
//! free joint below a moving body or beside another joint, sizes and numbers that are not
//! finite or positive where MuJoCo needs them, an inertia no rigid body has: an [`MjcfError`] at
//! the element's line, every problem of the file at once.

mod equality;
pub mod export;
mod mesh;
mod shapes;
mod xml;

use std::collections::HashMap;
use std::path::Path;

use articulated_dynamics::model::{
    Drive, Frame, Joint, JointKind, Model, Placement, Value, DEFAULT_GRAVITY,
};
use articulated_dynamics::spatial::{Mat3, Vec3};

use crate::check::{self, Inertia, Strictness};
use crate::import::frames::{matrix_rpy, MassProps, Transform};
pub use crate::import::ImportError;
use crate::options::{Description, Options, Warning};
use shapes::{Shape, EPS};
use xml::{Classed, Defaults, Element, MAIN};

pub use export::{to_mjcf, ExportError, Exported};

/// An error found while importing an MJCF description (the importers' one error type).
pub type MjcfError = ImportError;

/// Whether `text` is an MJCF description: its root element is `<mujoco>` (a URDF's is
/// `<robot>`; both are `.xml` files).
pub fn is_mjcf(text: &str) -> bool {
    roxmltree::Document::parse(text).is_ok_and(|d| d.root_element().has_tag_name("mujoco"))
}

/// Builds the [`Description`] of an MJCF model given as text (see the [module docs](self)).
/// An `<include>` is refused: [`from_mjcf_file`] resolves them.
///
/// # Errors
/// A [`MjcfError`] at the line of each offending element.
pub fn from_mjcf_str(xml: &str) -> Result<Description, MjcfError> {
    import(xml, None, MjcfOptions::default())
}

/// [`from_mjcf_str`] for the text of the file `path`: its `<include>`s are read from its
/// directory, and errors name it.
///
/// # Errors
/// As [`from_mjcf_str`].
pub fn from_mjcf_file(path: &Path, xml: &str) -> Result<Description, MjcfError> {
    from_mjcf_file_with(path, xml, MjcfOptions::default())
}

/// How [`from_mjcf_file_with`] imports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MjcfOptions {
    /// Balance every body's inertia that breaks the triangle inequality, as
    /// `<compiler balanceinertia="true"/>` does (the loader's
    /// [`LoadOptions::balance_inertia`](crate::load::LoadOptions::balance_inertia)).
    pub balance_inertia: bool,
    /// Make each `<joint>` equality with a linear `polycoef` a mimic joint (`joint1` follows
    /// `joint2`), or lock `joint1` where it names no `joint2`, rather than keep every coordinate
    /// and warn ([`crate::load::LoadOptions::mimic_equalities`]).
    pub mimic_equalities: bool,
}

/// [`from_mjcf_file`] as `options` say.
///
/// # Errors
/// As [`from_mjcf_str`].
pub fn from_mjcf_file_with(
    path: &Path,
    xml: &str,
    options: MjcfOptions,
) -> Result<Description, MjcfError> {
    import(xml, Some(path), options).map_err(|e| e.in_file(path))
}

fn import(text: &str, path: Option<&Path>, options: MjcfOptions) -> Result<Description, MjcfError> {
    let dir = path.map(|p| p.parent().unwrap_or(Path::new(".")));
    let root = xml::parse(text, None, dir)?;
    if root.tag != "mujoco" {
        return Err(root.error(format!(
            "an MJCF model has a `<mujoco>` root element, found `<{}>`",
            root.tag
        )));
    }
    let defaults = Defaults::read(&root)?;
    let mut compiler = Compiler::read(&root, &defaults)?;
    compiler.balanceinertia |= options.balance_inertia;
    let importer = Importer {
        root: &root,
        defaults,
        compiler,
        bodies: Vec::new(),
        joints: Vec::new(),
        frames: Vec::new(),
        warnings: Vec::new(),
        notes: Vec::new(),
        errors: Vec::new(),
        total_mass: 0.0,
        counts: Counts::default(),
        references: HashMap::new(),
        mimic_equalities: options.mimic_equalities,
        dir: dir.map(Path::to_path_buf),
        meshes: std::cell::RefCell::new(HashMap::new()),
    };
    importer.build()
}

/// Where a body's inertia comes from (`<compiler inertiafromgeom>`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum FromGeom {
    /// From its geoms where it has no `<inertial>`.
    Auto,
    /// From its geoms always (where it has any).
    Always,
    /// From its `<inertial>` only.
    Never,
}

/// The `<compiler>` settings the dynamics depend on.
pub(super) struct Compiler {
    /// Angles in degrees (MuJoCo's default).
    pub(super) degree: bool,
    /// The Euler sequence, e.g. `xyz` (moving axes) or `XYZ` (fixed axes).
    pub(super) eulerseq: [u8; 3],
    from_geom: FromGeom,
    group_range: [f64; 2],
    boundmass: f64,
    pub(super) boundinertia: f64,
    pub(super) balanceinertia: bool,
    settotalmass: f64,
    autolimits: bool,
    /// Free bodies without children moved to their inertial frame (`alignfree`).
    alignfree: bool,
    /// Where mesh files are (`meshdir`, else `assetdir`), from the model file's directory.
    meshdir: Option<String>,
}

impl Compiler {
    fn read(root: &Element, defaults: &Defaults) -> Result<Compiler, ImportError> {
        let mut c = Compiler {
            degree: true,
            eulerseq: *b"xyz",
            from_geom: FromGeom::Auto,
            group_range: [0.0, 5.0],
            boundmass: 0.0,
            boundinertia: 0.0,
            balanceinertia: false,
            settotalmass: -1.0,
            autolimits: true,
            alignfree: false,
            meshdir: None,
        };
        let bool_of = |e: &Classed, name: &str, now: bool| -> Result<bool, ImportError> {
            Ok(match e.get(name) {
                None => now,
                Some(_) => e.keyword(name, &["false", "true"])? == "true",
            })
        };
        for el in root.each("compiler") {
            let e = Classed {
                el,
                class: MAIN,
                defaults,
            };
            if el.own("angle").is_some() {
                c.degree = e.keyword("angle", &["degree", "radian"])? == "degree";
            }
            if let Some(seq) = el.own("eulerseq") {
                let ok = seq.len() == 3 && seq.bytes().all(|b| b"xyzXYZ".contains(&b));
                match <[u8; 3]>::try_from(seq.as_bytes()) {
                    Ok(s) if ok => c.eulerseq = s,
                    _ => {
                        return Err(el.error(format!(
                            "`eulerseq=\"{seq}\"`: expected three of `x`, `y`, `z`, `X`, `Y`, `Z`"
                        )))
                    }
                }
            }
            if el.own("inertiafromgeom").is_some() {
                c.from_geom = match e.keyword("inertiafromgeom", &["auto", "true", "false"])? {
                    "true" => FromGeom::Always,
                    "false" => FromGeom::Never,
                    _ => FromGeom::Auto,
                };
            }
            if let Some([a, b]) = e.array::<2>("inertiagrouprange")? {
                c.group_range = [a, b];
            }
            c.boundmass = e.number("boundmass", c.boundmass)?;
            c.boundinertia = e.number("boundinertia", c.boundinertia)?;
            c.settotalmass = e.number("settotalmass", c.settotalmass)?;
            c.balanceinertia = bool_of(&e, "balanceinertia", c.balanceinertia)?;
            c.autolimits = bool_of(&e, "autolimits", c.autolimits)?;
            c.alignfree = bool_of(&e, "alignfree", c.alignfree)?;
            if let Some(d) = el
                .own("meshdir")
                .or(el.own("assetdir").filter(|_| c.meshdir.is_none()))
            {
                c.meshdir = Some(d.to_string());
            }
            if el.own("coordinate").is_some_and(|v| v != "local") {
                return Err(el.error(
                    "`coordinate=\"global\"` is no longer MuJoCo's: write the model in local \
                     coordinates",
                ));
            }
        }
        Ok(c)
    }
}

/// How many bodies, joints and sites MuJoCo has numbered so far (the names of unnamed ones).
#[derive(Default)]
struct Counts {
    bodies: usize,
    joints: usize,
    sites: usize,
}

/// The importer of one model.
struct Importer<'a> {
    root: &'a Element,
    defaults: Defaults,
    compiler: Compiler,
    bodies: Vec<(String, MassProps)>,
    joints: Vec<Joint>,
    frames: Vec<Frame>,
    warnings: Vec<Warning>,
    /// What is left out by design: actuators, tendons.
    notes: Vec<Warning>,
    errors: Vec<ImportError>,
    /// The mass of every MuJoCo body, those welded to the world included (`settotalmass`).
    total_mass: f64,
    counts: Counts,
    /// Each joint's `ref`, by name (a joint equality's offsets are from them).
    references: HashMap<String, f64>,
    /// `<joint>` equalities become mimic joints (or lock their joint) rather than warnings.
    mimic_equalities: bool,
    /// The model file's directory, which `<include>` files and meshes are found from.
    dir: Option<std::path::PathBuf>,
    /// Each mesh's mass properties once read, by name.
    meshes: std::cell::RefCell<HashMap<String, mesh::MeshMass>>,
}

/// An element of a body, with the class it defaults from and the `<frame>`s around it
/// composed (its placement in the body's frame before its own `pos`).
struct Item<'a> {
    el: &'a Element,
    class: String,
    frame: Transform,
}

/// A joint of a body, read.
struct Read {
    name: String,
    kind: JointKind,
    /// Its anchor in the body frame (zero for slides and free joints).
    anchor: [f64; 3],
    /// The placement that takes `ref` out (`Rot(a, −ref)` or `Trans(−a·ref)`).
    fold: Transform,
    /// Its `ref` (radians for a hinge; 0 for ball and free joints).
    reference: f64,
    drive: Drive,
    free: bool,
}

impl<'a> Importer<'a> {
    /// `el`'s own attributes and the main class's (bodies, frames, inertials, options).
    fn plain<'b>(&'b self, el: &'b Element) -> Classed<'b> {
        Classed {
            el,
            class: MAIN,
            defaults: &self.defaults,
        }
    }

    fn classed<'b>(&'b self, item: &'b Item) -> Classed<'b> {
        Classed {
            el: item.el,
            class: &item.class,
            defaults: &self.defaults,
        }
    }

    fn warn(&mut self, el: &Element, message: String) {
        let w = located(el, message);
        self.warnings.push(w);
    }

    fn note(&mut self, el: &Element, message: String) {
        let n = located(el, message);
        self.notes.push(n);
    }

    /// The class an element defaults from: its own `class`, else `inherited`.
    fn class_of(&mut self, el: &Element, inherited: &str) -> String {
        let class = el.own("class").unwrap_or(inherited);
        self.class_of_name(el, class)
    }

    /// The items of `el` (a body, a frame or the world body), through `<frame>`s.
    fn items(
        &mut self,
        el: &'a Element,
        childclass: &str,
        frame: Transform,
        out: &mut Vec<Item<'a>>,
    ) {
        for child in &el.children {
            if matches!(
                child.tag.as_str(),
                "replicate" | "composite" | "flexcomp" | "attach"
            ) {
                // They make bodies and joints of their own: skipping them would load another
                // model.
                self.errors.push(child.error(format!(
                    "`<{}>` is not supported yet: save the model as MuJoCo compiles it \
                     (`mujoco.mj_saveLastXML`), which writes out what it makes, and load that",
                    child.tag
                )));
                continue;
            }
            if child.tag == "frame" {
                let inner = match child.own("childclass") {
                    Some(c) => self.class_of_name(child, c),
                    None => childclass.to_string(),
                };
                let c = self.plain(child);
                let pose = shapes::pose(&c, &self.compiler).unwrap_or_else(|e| {
                    self.errors.push(e);
                    Transform::IDENTITY
                });
                self.items(child, &inner, frame.then(&pose), out);
                continue;
            }
            let class = if child.tag == "body" {
                childclass.to_string()
            } else {
                self.class_of(child, childclass)
            };
            out.push(Item {
                el: child,
                class,
                frame,
            });
        }
    }

    /// `class` where it is defined, else `main` with an error at `el`.
    fn class_of_name(&mut self, el: &Element, class: &str) -> String {
        if self.defaults.has(class) {
            class.to_string()
        } else {
            self.errors
                .push(el.error(format!("the default class `{class}` is not defined")));
            MAIN.to_string()
        }
    }

    fn build(mut self) -> Result<Description, ImportError> {
        let gravity = self.gravity()?;
        self.skipped();
        let root = self.root;
        for world in root.each("worldbody") {
            let mut items = Vec::new();
            self.items(world, MAIN, Transform::IDENTITY, &mut items);
            for item in &items {
                match item.el.tag.as_str() {
                    "body" => self.body(item, None, Transform::IDENTITY),
                    "site" => self.site(item, None, Transform::IDENTITY),
                    "joint" | "freejoint" | "inertial" => self.errors.push(
                        item.el
                            .error("the world body cannot have joints or an inertial"),
                    ),
                    _ => {}
                }
            }
        }
        if self.mimic_equalities {
            self.joint_equalities();
        }
        self.errors.sort_by_key(ImportError::sort_key);
        if let Some(e) = ImportError::all(std::mem::take(&mut self.errors)) {
            return Err(e);
        }
        if self.compiler.settotalmass > 0.0 {
            // MuJoCo's `mj_setTotalmass`: every body's mass and inertia scaled alike.
            let scale = (self.compiler.settotalmass / self.total_mass.max(1e-15)).max(1e-15);
            for (_, mp) in &mut self.bodies {
                mp.m *= scale;
                for row in &mut mp.i.0 {
                    for x in row {
                        *x *= scale;
                    }
                }
            }
        }
        self.unique_frame_names();
        let name = self.root.own("model").unwrap_or("MuJoCo Model");
        let model = Model {
            name: crate::urdf::camel_case(name),
            gravity: Some(gravity),
            params: Vec::new(),
            bodies: self
                .bodies
                .into_iter()
                .map(|(name, mp)| mp.into_body(name))
                .collect(),
            joints: self.joints,
            frames: self.frames,
        };
        model.check().map_err(|e| {
            ImportError::new(format!("the imported model is invalid: {e}")).called("<mjcf>")
        })?;
        let mut warnings = self.warnings;
        warnings.sort_by_key(|w| w.line);
        let mut notes = self.notes;
        notes.sort_by_key(|w| w.line);
        Ok(Description {
            model,
            options: Options {
                doc: vec![format!(" Imported from the MJCF model `{name}`.")],
                ..Options::default()
            },
            warnings,
            notes,
            continuous: Vec::new(),
            pinocchio_order: Vec::new(),
        })
    }

    /// `<option gravity>`, zero under `<flag gravity="disable">`.
    fn gravity(&self) -> Result<[Value; 3], ImportError> {
        let mut g = DEFAULT_GRAVITY;
        for option in self.root.each("option") {
            let c = self.plain(option);
            if let Some(v) = c.array::<3>("gravity")? {
                g = v.map(Value::Const);
            }
            for flag in option.each("flag") {
                if flag.own("gravity") == Some("disable") {
                    return Ok([0.0; 3].map(Value::Const));
                }
            }
        }
        Ok(g)
    }

    /// Warnings for what the model holds but the dynamics do not represent.
    fn skipped(&mut self) {
        let root = self.root;
        for section in root.each("equality") {
            for eq in &section.children {
                if self.mimic_equalities && eq.tag == "joint" {
                    continue;
                }
                let name = eq
                    .own("name")
                    .map(|n| format!(" `{n}`"))
                    .unwrap_or_default();
                self.warn(
                    eq,
                    format!(
                        "the {} equality{name} is not applied: the dynamics are MuJoCo's without \
                         it (its coordinates are all kept)",
                        eq.tag
                    ),
                );
            }
        }
        for section in root.each("tendon") {
            for t in &section.children {
                let name = t.own("name").map(|n| format!(" `{n}`")).unwrap_or_default();
                self.note(
                    t,
                    format!(
                        "the {} tendon{name} is skipped: tendons are not represented",
                        t.tag
                    ),
                );
            }
        }
        for section in root.each("actuator") {
            if let Some(first) = section.children.first() {
                let n = section.children.len();
                self.note(
                    first,
                    format!(
                        "{n} actuator{} skipped: the joint forces τ are the caller's",
                        if n == 1 { "" } else { "s" }
                    ),
                );
            }
        }
    }

    /// Renames each frame whose name a body or an earlier frame has (a site named as its body),
    /// appending `_site`.
    fn unique_frame_names(&mut self) {
        let mut taken: std::collections::HashSet<String> =
            self.bodies.iter().map(|(n, _)| n.clone()).collect();
        for f in &mut self.frames {
            while taken.contains(&f.name) {
                f.name.push_str("_site");
            }
            taken.insert(f.name.clone());
        }
    }

    /// A geom's or a site's pose from `fromto` (`None` where it has none), and half the
    /// distance between its points; `what` names it in errors.
    fn fromto_pose(
        &self,
        c: &Classed,
        what: &str,
    ) -> Result<Option<(Transform, f64)>, ImportError> {
        let Some(ft) = c.array::<6>("fromto")? else {
            return Ok(None);
        };
        if c.array::<3>("pos")?.is_some_and(|p| p != [0.0; 3]) {
            return Err(c
                .el
                .error(format!("{what}: both `pos` and `fromto` are given")));
        }
        shapes::from_to(ft).map(Some).ok_or_else(|| {
            c.el.error(format!("{what}: the `fromto` points are too close"))
        })
    }

    /// A site: a frame of `body` placed at `offset ∘ frame ∘ pose`.
    fn site(&mut self, item: &Item, body: Option<usize>, offset: Transform) {
        let c = self.classed(item);
        let what = format!("site `{}`", item.el.own("name").unwrap_or("(unnamed)"));
        let pose = match self.fromto_pose(&c, &what) {
            Ok(Some((p, _))) => Ok(p),
            Ok(None) => shapes::pose(&c, &self.compiler),
            Err(e) => Err(e),
        };
        let pose = match pose {
            Ok(p) => p,
            Err(e) => return self.errors.push(e),
        };
        let name = match item.el.own("name") {
            Some(n) => n.to_string(),
            None => format!("site{}", self.counts.sites),
        };
        self.counts.sites += 1;
        let t = offset.then(&item.frame.then(&pose));
        self.frames.push(Frame {
            name,
            parent: body,
            placement: placement(&t),
        });
    }

    /// A body and what it holds: `parent` is the model body its MuJoCo parent is (or is welded
    /// to), `offset` its MuJoCo parent's frame in that body's frame.
    fn body(&mut self, item: &Item<'a>, parent: Option<usize>, offset: Transform) {
        let el = item.el;
        self.counts.bodies += 1;
        let name = match el.own("name") {
            Some(n) => n.to_string(),
            None => format!("body{}", self.counts.bodies),
        };
        let childclass = match el.own("childclass") {
            Some(c) => self.class_of_name(el, c),
            None => item.class.clone(),
        };
        let c = self.plain(el);
        let pose = shapes::pose(&c, &self.compiler).unwrap_or_else(|e| {
            self.errors.push(e);
            Transform::IDENTITY
        });
        if el.own("gravcomp").is_some_and(|g| g.trim() != "0") {
            self.warn(
                el,
                format!("body `{name}`: its `gravcomp` is not represented"),
            );
        }
        let mut items = Vec::new();
        self.items(el, &childclass, Transform::IDENTITY, &mut items);
        let mass = self.body_mass(el, &name, &items).unwrap_or_else(|e| {
            self.errors.push(e);
            MassProps::ZERO
        });
        self.total_mass += mass.m;
        let here = offset.then(&item.frame.then(&pose));
        let mut joints = Vec::new();
        for i in items
            .iter()
            .filter(|i| matches!(i.el.tag.as_str(), "joint" | "freejoint"))
        {
            self.counts.joints += 1;
            let mut notes = Vec::new();
            match self.joint(i, &name, &mut notes) {
                Ok(j) => joints.push(j),
                Err(e) => self.errors.push(e),
            }
            for note in notes {
                self.warn(i.el, note);
            }
        }
        let childless = !items.iter().any(|i| i.el.tag == "body");
        if let [j] = joints.as_slice() {
            let align = items
                .iter()
                .find(|i| matches!(i.el.tag.as_str(), "joint" | "freejoint"))
                .and_then(|i| i.el.own("align"));
            let aligned =
                align == Some("true") || (align != Some("false") && self.compiler.alignfree);
            if j.free && childless && aligned {
                // MuJoCo moves such a body's frame to its principal axes of inertia, which
                // changes what `qpos` means.
                self.errors.push(el.error(format!(
                    "body `{name}`: a free joint aligned with the inertial frame (`align`, \
                     `alignfree`) is not supported: set `align=\"false\"`"
                )));
            }
        }
        let (body, contents) = if joints.is_empty() {
            // Welded: a frame of the body above, its mass merged there.
            if let Some(b) = parent {
                let merged = self.bodies[b].1.merged(&mass.transformed(&here));
                self.bodies[b].1 = merged;
            }
            self.frames.push(Frame {
                name,
                parent,
                placement: placement(&here),
            });
            (parent, here)
        } else {
            self.moving(el, &name, joints, parent, here, mass)
        };
        for item in &items {
            match item.el.tag.as_str() {
                "body" => self.body(item, body, contents),
                "site" => self.site(item, body, contents),
                _ => {}
            }
        }
    }

    /// The model bodies and joints of a body with joints: one body per joint (all but the last
    /// massless), each joint at its anchor. Returns the last body and the frame in which the
    /// MuJoCo body's contents sit in it.
    fn moving(
        &mut self,
        el: &Element,
        name: &str,
        joints: Vec<Read>,
        mut parent: Option<usize>,
        here: Transform,
        mass: MassProps,
    ) -> (Option<usize>, Transform) {
        let n = joints.len();
        let mut cur = here;
        for (k, j) in joints.into_iter().enumerate() {
            let placement_t = if j.free {
                if parent.is_some() || n > 1 {
                    self.errors.push(el.error(format!(
                        "body `{name}`: a free joint is supported only as the one joint of a \
                         body whose parents are welded to the world"
                    )));
                }
                // MuJoCo's free `qpos` is the body's pose in the world: its `pos` and `quat` are
                // only the initial configuration.
                parent = None;
                Transform::IDENTITY
            } else {
                cur.then(&translation(j.anchor)).then(&j.fold)
            };
            let last = k + 1 == n;
            let body_name = if last {
                name.to_string()
            } else {
                format!("{name}_{}", j.name)
            };
            let back = translation(j.anchor.map(|x| -x));
            let props = if last {
                mass.transformed(&back)
            } else {
                MassProps::ZERO
            };
            self.bodies.push((body_name, props));
            self.references.insert(j.name.clone(), j.reference);
            self.joints.push(Joint {
                name: j.name,
                kind: j.kind,
                parent,
                placement: placement(&placement_t),
                drive: j.drive,
                mimic: None,
            });
            parent = Some(self.bodies.len() - 1);
            cur = back;
        }
        (parent, cur)
    }

    /// A `<joint>` or `<freejoint/>`, read.
    fn joint(&self, item: &Item, body: &str, notes: &mut Vec<String>) -> Result<Read, ImportError> {
        let c = self.classed(item);
        let name = match item.el.own("name") {
            Some(n) => n.to_string(),
            None => format!("joint{}", self.counts.joints - 1),
        };
        let ty = if item.el.tag == "freejoint" {
            "free"
        } else {
            c.keyword("type", &["hinge", "slide", "ball", "free"])?
        };
        let pos = item
            .frame
            .then(&shapes::transform(
                c.array::<3>("pos")?.unwrap_or([0.0; 3]),
                None,
            ))
            .p
            .0;
        let axis_in = c.array::<3>("axis")?.unwrap_or([0.0, 0.0, 1.0]);
        let axis = item.frame.r.mul_vec(Vec3(axis_in)).0;
        let norm = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        let unit_axis = axis.map(|x| x / norm);
        if norm < EPS && matches!(ty, "hinge" | "slide") {
            return Err(item.el.error(format!(
                "joint `{name}` of body `{body}`: the axis is too small"
            )));
        }
        let degree = self.compiler.degree && ty == "hinge";
        let reference = c.number("ref", 0.0)?;
        let reference = if degree {
            reference.to_radians()
        } else {
            reference
        };
        let (kind, anchor, fold) = match ty {
            "hinge" => (
                JointKind::Revolute { axis: unit_axis },
                pos,
                rotation(
                    Mat3::rot_axis(Vec3(unit_axis), -reference),
                    reference != 0.0,
                ),
            ),
            "slide" => (
                JointKind::Prismatic { axis: unit_axis },
                [0.0; 3],
                translation(unit_axis.map(|a| -a * reference)),
            ),
            "ball" => (JointKind::SphericalQuaternion, pos, Transform::IDENTITY),
            _ => (JointKind::FreeQuaternion, [0.0; 3], Transform::IDENTITY),
        };
        let drive = drive(&c, &self.compiler, &name, ty, notes)?;
        Ok(Read {
            name,
            kind,
            anchor,
            fold,
            reference,
            drive,
            free: ty == "free",
        })
    }

    /// A body's mass properties in its own frame, as MuJoCo's compiler sets them.
    fn body_mass(
        &mut self,
        el: &Element,
        name: &str,
        items: &[Item],
    ) -> Result<MassProps, ImportError> {
        let inertial = el.each("inertial").next();
        let mut mp = match inertial {
            Some(i) => self.inertial(i, name)?,
            None => MassProps::ZERO,
        };
        let from_geom = match self.compiler.from_geom {
            FromGeom::Always => true,
            FromGeom::Auto => inertial.is_none(),
            FromGeom::Never => false,
        };
        if from_geom {
            let mut geoms: Option<MassProps> = None;
            for item in items.iter().filter(|i| i.el.tag == "geom") {
                if let Some(g) = self.geom_mass(item, name)? {
                    geoms = Some(match geoms {
                        None => g,
                        Some(acc) => acc.merged(&g),
                    });
                }
            }
            if let Some(g) = geoms {
                mp = g;
            }
        }
        mp.m = mp.m.max(self.compiler.boundmass);
        if let Some(i) = shapes::bound_inertia(&mp.i, &self.compiler) {
            mp.i = i;
        }
        if mp.m < 0.0 {
            return Err(el.error(format!("body `{name}`: its mass {} is negative", mp.m)));
        }
        let largest = check::principal_moments(&mp.i.0).map_or(0.0, |m| m[2].abs());
        if let Some(p) = check::inertia(&Inertia::Full(mp.i.0), Strictness::Model { largest }) {
            return Err(el.error(format!(
                "{} (MuJoCo refuses it too; `<compiler balanceinertia=\"true\"/>` fixes it)",
                p.message(&format!("body `{name}`"))
            )));
        }
        Ok(mp)
    }

    /// An `<inertial>`: its mass, centre and tensor in the body frame.
    fn inertial(&self, el: &Element, name: &str) -> Result<MassProps, ImportError> {
        let c = self.plain(el);
        let pos = c
            .array::<3>("pos")?
            .ok_or_else(|| el.error(format!("body `{name}`: `<inertial>` needs `pos`")))?;
        let m = c
            .array::<1>("mass")?
            .ok_or_else(|| el.error(format!("body `{name}`: `<inertial>` needs `mass`")))?[0];
        let quat = shapes::orientation(&c, &self.compiler)?;
        match (c.array::<3>("diaginertia")?, c.array::<6>("fullinertia")?) {
            (Some(d), None) => Ok(shapes::principal(
                m,
                pos,
                &quat.map_or(Mat3::identity(), Mat3::quaternion),
                d,
            )),
            (None, Some(f)) if quat.is_none() => Ok(MassProps {
                m,
                c: Vec3(pos),
                i: Mat3([[f[0], f[3], f[4]], [f[3], f[1], f[5]], [f[4], f[5], f[2]]]),
            }),
            (None, Some(_)) => Err(el.error(format!(
                "body `{name}`: `fullinertia` and an inertial orientation cannot both be given"
            ))),
            (Some(_), Some(_)) => Err(el.error(format!(
                "body `{name}`: `diaginertia` and `fullinertia` cannot both be given"
            ))),
            (None, None) => Err(el.error(format!(
                "body `{name}`: `<inertial>` needs `diaginertia` or `fullinertia`"
            ))),
        }
    }

    /// A mesh geom's mass properties in the body frame (`None`: massless): the mesh's, for the
    /// geom's density or mass, placed by the geom's pose. `what` names the geom in errors.
    fn mesh_geom(&self, item: &Item, what: &str) -> Result<Option<MassProps>, ImportError> {
        let c = self.classed(item);
        let el = item.el;
        if c.get("fromto").is_some() {
            return Err(el.error(format!("{what}: `fromto` cannot place a mesh geom")));
        }
        if c.get("shellinertia") == Some("true") {
            return Err(el.error(format!(
                "{what}: a mesh geom's inertia is set on the mesh (`<mesh inertia=\"shell\">`)"
            )));
        }
        let Some(name) = c.get("mesh") else {
            return Err(el.error(format!("{what}: a mesh geom needs `mesh`")));
        };
        let mesh = self
            .mesh(name)
            .map_err(|m| el.error(format!("{what}: mesh `{name}`: {m}")))?;
        let m = match c.array::<1>("mass")? {
            Some([m]) if mesh.volume > EPS => m,
            Some(_) => 0.0,
            None => c.number("density", 1000.0)? * mesh.volume,
        };
        if m <= EPS {
            return Ok(None);
        }
        let pose = item.frame.then(&shapes::pose(&c, &self.compiler)?);
        let scale = m / mesh.volume;
        let i = Mat3(mesh.inertia.map(|row| row.map(|x| x * scale)));
        Ok(Some(MassProps {
            m,
            c: pose.p + pose.r.mul_vec(Vec3(mesh.com)),
            i: crate::import::frames::rotate_inertia(&pose.r, &i),
        }))
    }

    /// The mass properties of the mesh asset `name` for a unit density, read once.
    fn mesh(&self, name: &str) -> Result<mesh::MeshMass, String> {
        if let Some(m) = self.meshes.borrow().get(name) {
            return Ok(*m);
        }
        let stem = |f: &str| {
            Path::new(f)
                .file_stem()
                .and_then(|s| s.to_str())
                .map(str::to_string)
        };
        let asset = self
            .root
            .each("asset")
            .flat_map(|a| a.each("mesh"))
            .find(|m| match m.own("name") {
                Some(n) => n == name,
                None => m.own("file").and_then(stem).as_deref() == Some(name),
            })
            .ok_or("no `<mesh>` asset has this name")?;
        let c = Classed {
            el: asset,
            class: asset.own("class").unwrap_or(MAIN),
            defaults: &self.defaults,
        };
        let message = |e: ImportError| e.message().to_string();
        let mode = match c
            .keyword("inertia", &["legacy", "exact", "shell", "convex"])
            .map_err(message)?
        {
            "exact" => mesh::MeshInertia::Exact,
            "shell" => mesh::MeshInertia::Shell,
            "convex" => {
                return Err(
                    "the inertia of its convex hull (`inertia=\"convex\"`) is not \
                            computed yet: `legacy` (MuJoCo's default) and `exact` are"
                        .into(),
                )
            }
            _ => mesh::MeshInertia::Legacy,
        };
        for moved in ["refpos", "refquat"] {
            if c.get(moved).is_some() {
                return Err(format!(
                    "`{moved}` is not supported (MuJoCo has dropped it)"
                ));
            }
        }
        let scale = c.array::<3>("scale").map_err(message)?.unwrap_or([1.0; 3]);
        // Mesh files are found from the model file's directory, under `meshdir`.
        let path = |file: &str| {
            let dir = self.dir.clone().unwrap_or_default();
            dir.join(self.compiler.meshdir.as_deref().unwrap_or(""))
                .join(file)
        };
        let mut tris = match (asset.own("file"), asset.own("vertex")) {
            (Some(file), _) if file.to_ascii_lowercase().ends_with(".stl") => {
                mesh::read_stl(&path(file))?
            }
            (Some(file), _) if file.to_ascii_lowercase().ends_with(".obj") => {
                mesh::read_obj(&path(file))?
            }
            (Some(file), _) => {
                return Err(format!(
                    "`{file}`: only binary STL and OBJ mesh files are read yet (not MSH)"
                ))
            }
            (None, Some(_)) => self.inline_mesh(&c)?,
            (None, None) => return Err("it has neither `file` nor `vertex`".into()),
        };
        for t in &mut tris {
            for v in t.iter_mut() {
                for k in 0..3 {
                    v[k] *= scale[k];
                }
            }
        }
        let m = mesh::mass_properties(&tris, mode)?;
        self.meshes.borrow_mut().insert(name.to_string(), m);
        Ok(m)
    }

    /// The triangles of a mesh given by its `vertex` and `face` attributes (single precision,
    /// as MuJoCo stores them).
    fn inline_mesh(&self, c: &Classed) -> Result<Vec<[[f64; 3]; 3]>, String> {
        let vertex = c
            .numbers("vertex")
            .map_err(|e| e.message().to_string())?
            .unwrap_or_default();
        let Some(face) = c.get("face") else {
            return Err("a mesh without `face` is its convex hull, not computed yet".into());
        };
        let verts: Vec<[f64; 3]> = vertex
            .chunks_exact(3)
            .map(|v| [0, 1, 2].map(|k| f64::from(v[k] as f32)))
            .collect();
        let index: Vec<usize> = face
            .split_whitespace()
            .map(|t| t.parse::<usize>().ok().filter(|&i| i < verts.len()))
            .collect::<Option<_>>()
            .ok_or("its `face` holds an index that is not a vertex")?;
        if !vertex.len().is_multiple_of(3) || !index.len().is_multiple_of(3) {
            return Err("its `vertex` and `face` need multiples of 3 numbers".into());
        }
        Ok(index
            .chunks_exact(3)
            .map(|f| [verts[f[0]], verts[f[1]], verts[f[2]]])
            .collect())
    }

    /// A geom's mass properties in the body frame, `None` where it adds none (outside
    /// `inertiagrouprange`, massless).
    fn geom_mass(&self, item: &Item, body: &str) -> Result<Option<MassProps>, ImportError> {
        let c = self.classed(item);
        let el = item.el;
        let group = c.number("group", 0.0)?;
        if group < self.compiler.group_range[0] || group > self.compiler.group_range[1] {
            return Ok(None);
        }
        let which = || match el.own("name") {
            Some(n) => format!("geom `{n}` of body `{body}`"),
            None => format!("a geom of body `{body}`"),
        };
        let shape = match c.keyword(
            "type",
            &[
                "sphere",
                "capsule",
                "ellipsoid",
                "cylinder",
                "box",
                "plane",
                "mesh",
                "hfield",
                "sdf",
            ],
        )? {
            "sphere" => Shape::Sphere,
            "capsule" => Shape::Capsule,
            "ellipsoid" => Shape::Ellipsoid,
            "cylinder" => Shape::Cylinder,
            "box" => Shape::Box,
            "plane" => Shape::Massless,
            "mesh" => return self.mesh_geom(item, &which()),
            other => {
                return Err(el.error(format!(
                    "{}: the inertia of `{other}` geoms is not computed yet: give the body an \
                     `<inertial>`, or put the geom outside `inertiagrouprange`",
                    which()
                )))
            }
        };
        let mut size = [0.0; 3];
        for (s, v) in size
            .iter_mut()
            .zip(c.some("size", 0, 3)?.unwrap_or_default())
        {
            *s = v;
        }
        let pose = match self.fromto_pose(&c, &which())? {
            Some((pose, half)) => {
                if !matches!(
                    shape,
                    Shape::Capsule | Shape::Cylinder | Shape::Ellipsoid | Shape::Box
                ) {
                    return Err(el.error(format!(
                        "{}: `fromto` needs a capsule, cylinder, ellipsoid or box",
                        which()
                    )));
                }
                size[1] = half;
                if matches!(shape, Shape::Ellipsoid | Shape::Box) {
                    size[2] = size[1];
                    size[1] = size[0];
                }
                pose
            }
            None => shapes::pose(&c, &self.compiler)?,
        };
        let needed = shapes::sizes_needed(shape);
        if let Some(k) = size.iter().take(needed).position(|s| *s <= 0.0) {
            return Err(el.error(format!("{}: size {k} must be positive", which())));
        }
        let shell = c.keyword("shellinertia", &["false", "true"])? == "true";
        let volume = shapes::volume(shape, size, shell);
        let m = match c.array::<1>("mass")? {
            Some([0.0]) => 0.0,
            Some([m]) if volume > EPS => m,
            Some(_) => 0.0,
            None => c.number("density", 1000.0)? * volume,
        };
        if m <= EPS {
            return Ok(None);
        }
        let pose = item.frame.then(&pose);
        Ok(Some(shapes::principal(
            m,
            pose.p.0,
            &pose.r,
            shapes::moments(shape, size, m, shell),
        )))
    }
}

/// The joint's drive, with a note in `notes` for each term that is not represented.
fn drive(
    c: &Classed,
    compiler: &Compiler,
    name: &str,
    ty: &str,
    notes: &mut Vec<String>,
) -> Result<Drive, ImportError> {
    let mut drive = Drive::FREE;
    drive.armature = c.number("armature", 0.0)?;
    if ty == "free" && drive.armature != 0.0 {
        // MuJoCo's acts on its free coordinates, whose linear velocity is in the world frame:
        // ours is in the body frame, and `d/dt` of the two differ by `ω × v`.
        notes.push(format!(
            "joint `{name}`: armature on a free joint acts on our body-frame velocity, where \
             MuJoCo's acts on the world-frame one: the dynamics differ by armature·(ω × v) on \
             the linear rows"
        ));
    }
    drive.friction = c.number("frictionloss", 0.0)?;
    if let Some(d) = c.some("damping", 1, 11)? {
        drive.damping = d.first().copied().unwrap_or(0.0);
        if d.iter().skip(1).any(|x| *x != 0.0) {
            notes.push(format!(
                "joint `{name}`: its damping beyond the linear term is not represented"
            ));
        }
    }
    if let Some(k) = c.some("stiffness", 1, 11)? {
        let linear = k.first().copied().unwrap_or(0.0);
        if matches!(ty, "hinge" | "slide") {
            drive.stiffness = linear;
            let rest = c.number("springref", 0.0)?;
            drive.rest = if compiler.degree && ty == "hinge" {
                rest.to_radians()
            } else {
                rest
            };
            if k.iter().skip(1).any(|x| *x != 0.0) {
                notes.push(format!(
                    "joint `{name}`: its stiffness beyond the linear term is not represented"
                ));
            }
        } else if k.iter().any(|x| *x != 0.0) {
            notes.push(format!(
                "joint `{name}`: the spring of a {ty} joint is not represented"
            ));
        }
    }
    if c.numbers("springdamper")?
        .is_some_and(|v| v.iter().any(|x| *x != 0.0))
    {
        notes.push(format!(
            "joint `{name}`: its `springdamper` (a spring set by its time constant) is not \
             represented"
        ));
    }
    let limited = |flag: &str, range: &str| -> Result<Option<[f64; 2]>, ImportError> {
        let r = c.array::<2>(range)?;
        let on = match c.keyword(flag, &["auto", "true", "false"])? {
            "true" => true,
            "false" => false,
            _ => compiler.autolimits && r.is_some_and(|r| r != [0.0, 0.0]),
        };
        Ok(if on {
            Some(r.unwrap_or([0.0, 0.0]))
        } else {
            None
        })
    };
    if ty != "free" {
        if let Some([lo, hi]) = limited("limited", "range")? {
            match ty {
                "ball" => notes.push(format!(
                    "joint `{name}`: the cone limit of a ball joint is not represented"
                )),
                _ => {
                    let deg = compiler.degree && ty == "hinge";
                    let f = |x: f64| if deg { x.to_radians() } else { x };
                    if lo >= hi {
                        return Err(c
                            .el
                            .error(format!("joint `{name}`: its range [{lo}, {hi}] is empty")));
                    }
                    drive.lower = f(lo);
                    drive.upper = f(hi);
                }
            }
        }
    }
    if matches!(ty, "hinge" | "slide") {
        if let Some([lo, hi]) = limited("actuatorfrclimited", "actuatorfrcrange")? {
            if lo == -hi && hi > 0.0 {
                drive.effort = hi;
            } else {
                notes.push(format!("joint `{name}`: the force range [{lo}, {hi}] is not symmetric: not represented"));
            }
        }
    }
    Ok(drive)
}

/// `message` at `el`'s line (at its file, named in the message, for an included one).
fn located(el: &Element, message: String) -> Warning {
    let message = match &el.file {
        Some(f) => format!("{message} (in `{}`)", f.display()),
        None => message,
    };
    Warning {
        line: el.file.is_none().then_some(el.line),
        message,
    }
}

/// A translation.
fn translation(p: [f64; 3]) -> Transform {
    shapes::transform(p, None)
}

/// A rotation (the identity unless `nonzero`).
fn rotation(r: Mat3<f64>, nonzero: bool) -> Transform {
    if !nonzero {
        return Transform::IDENTITY;
    }
    Transform {
        r,
        p: Vec3([0.0; 3]),
        identity: false,
    }
}

/// A model placement of a transform.
fn placement(t: &Transform) -> Placement {
    let rpy = if t.identity {
        [0.0; 3]
    } else {
        matrix_rpy(&t.r)
    };
    Placement {
        xyz: t.p.0.map(Value::Const),
        rpy: rpy.map(Value::Const),
    }
}
