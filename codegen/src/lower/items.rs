//! Items: the doc comments (the only attribute allowed), the settings (`gravity`, `scalar`,
//! `outputs`, each once), the fields of a block (known, each once, the required ones present),
//! bodies (`mass`, `com`, `inertia` as `diag(…)` or a 3×3 matrix; names unique, never `world`)
//! and joints (unique names, a parent that is `world` or a body, a child that is a body, the
//! placement, the drive: rotor inertia, losses and limits). The joint kinds are in
//! [`kinds`](super::kinds).

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};

use proc_macro2::Ident;
use quote::ToTokens;
use syn::punctuated::Punctuated;
use syn::{Lit, Token};

use super::constraints::{contacts_of, loops_of};
use super::numbers::NumCtx;
use super::{visibility, BodyDecl, FrameDecl, InertiaDecl, JointDecl, Lower, MimicDecl};
use crate::check::{self, End};
use crate::model::{Drive, JointKind, Placement, Value, DEFAULT_GRAVITY};
use crate::options::{
    one_of, unknown_accuracy, unknown_lanes, unknown_output, unknown_scalar, Accuracy, Contact,
    Loop, Options, Output, ScalarKind, LANES,
};
use crate::parse::{BodyDef, ChainDef, Expr, Field, Item, JointDef, Setting};

impl Lower {
    /// The parameters, first: any item may use one, wherever it is declared.
    pub(super) fn params(&mut self, def: &ChainDef) {
        for item in &def.items {
            if let Item::Param(p) = item {
                self.docs(&p.attrs, "on a parameter");
                self.param(&p.name, &p.default);
            }
        }
    }

    /// The settings, each given once: the gravity (`None` for `gravity: none`) and the
    /// generator's options, with the chain's visibility and `doc`.
    pub(super) fn settings(
        &mut self,
        def: &ChainDef,
        doc: Vec<String>,
    ) -> (Option<[Value; 3]>, Options) {
        let mut gravity = Some(DEFAULT_GRAVITY);
        let mut options = Options {
            visibility: visibility(&def.vis),
            doc,
            ..Options::default()
        };
        let mut seen_settings: HashSet<String> = HashSet::new();
        for item in &def.items {
            if let Item::Setting(s) = item {
                self.docs(&s.attrs, "on a setting");
                let key = s.key.to_string();
                if !seen_settings.insert(key.clone()) {
                    self.cx
                        .error(&s.key, format!("setting `{key}` is given twice"));
                    continue;
                }
                self.setting(s, &mut gravity, &mut options);
            }
        }
        (gravity, options)
    }

    /// The bodies and their indices by name; a second body of the same name is reported and
    /// left out.
    pub(super) fn bodies<'a>(
        &mut self,
        def: &'a ChainDef,
    ) -> (Vec<BodyDecl<'a>>, HashMap<String, usize>) {
        let mut bodies: Vec<BodyDecl> = Vec::new();
        let mut body_index: HashMap<String, usize> = HashMap::new();
        for item in &def.items {
            if let Item::Body(b) = item {
                self.docs(&b.attrs, "on a body");
                let name = b.name.to_string();
                let decl = self.body(b);
                if name == "world" {
                    self.cx.error(
                        &b.name,
                        "`world` is the fixed frame every chain hangs from, not a body: \
                         expected another body name",
                    );
                } else if let Entry::Vacant(slot) = body_index.entry(name) {
                    slot.insert(bodies.len());
                    bodies.push(decl);
                } else {
                    self.cx
                        .error(&b.name, format!("body `{}` is declared twice", b.name));
                }
            }
        }
        (bodies, body_index)
    }

    /// The joints, in declaration order; a second joint of the same name is reported.
    pub(super) fn joints<'a>(
        &mut self,
        def: &'a ChainDef,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> Vec<JointDecl<'a>> {
        let mut joints: Vec<JointDecl> = Vec::new();
        let mut joint_names: HashSet<String> = HashSet::new();
        for item in &def.items {
            if let Item::Joint(j) = item {
                self.docs(&j.attrs, "on a joint");
                let name = j.name.to_string();
                let duplicate = !joint_names.insert(name.clone());
                if duplicate {
                    self.cx
                        .error(&j.name, format!("joint `{name}` is declared twice"));
                }
                let mut decl = self.joint(j, body_index, bodies);
                decl.duplicate = duplicate;
                joints.push(decl);
            }
        }
        joints
    }

    /// The frames, in declaration order: a parent that is `world` or a body, a name no body
    /// or other frame has, the placement.
    pub(super) fn frames(
        &mut self,
        def: &ChainDef,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> Vec<FrameDecl> {
        let mut frames: Vec<FrameDecl> = Vec::new();
        for item in &def.items {
            let Item::Frame(f) = item else {
                continue;
            };
            self.docs(&f.attrs, "on a frame");
            let name = f.name.to_string();
            let owner = format!("frame `{name}`");
            if name == "world" {
                self.cx.error(
                    &f.name,
                    "`world` is the fixed frame every chain hangs from: expected another frame \
                     name",
                );
            } else if body_index.contains_key(&name) {
                self.cx.error(
                    &f.name,
                    format!(
                        "frame `{name}` has the name of a body, which is a frame already: every \
                         body is a frame under its own name; name this one otherwise"
                    ),
                );
            } else if frames.iter().any(|g| g.name == name) {
                self.cx
                    .error(&f.name, format!("frame `{name}` is declared twice"));
            }
            let fields = self.fields(&f.fields, &["parent", "xyz", "rpy"], &owner);
            let parent = match fields[0] {
                None => {
                    self.missing(&f.name, &owner, "parent");
                    End::Unknown
                }
                Some(p) => self.parent(&p.value, &owner, body_index, bodies),
            };
            let zero = [Value::Const(0.0); 3];
            let xyz = fields[1]
                .and_then(|f| self.vec3(&f.value, "`xyz`", ""))
                .unwrap_or(zero);
            let rpy = fields[2]
                .and_then(|f| self.vec3(&f.value, "`rpy`", ""))
                .unwrap_or(zero);
            let parent = match parent {
                End::World => Some(None),
                End::Body(b) => bodies.get(b).map(|b| Some(b.def.name.to_string())),
                End::Unknown => None,
            };
            match parent {
                Some(parent) => frames.push(FrameDecl {
                    name,
                    parent,
                    placement: Placement { xyz, rpy },
                }),
                // Reported here: not again as an unknown frame in `frames`.
                None => {
                    self.broken_frames.insert(name);
                }
            }
        }
        frames
    }

    /// The doc strings among `attrs`; any other attribute is an error.
    pub(super) fn docs(&mut self, attrs: &[syn::Attribute], place: &str) -> Vec<String> {
        let mut doc = Vec::new();
        for attr in attrs {
            let text = match &attr.meta {
                syn::Meta::NameValue(nv) if attr.path().is_ident("doc") => match &nv.value {
                    syn::Expr::Lit(syn::ExprLit {
                        lit: Lit::Str(s), ..
                    }) => Some(s.value()),
                    _ => None,
                },
                _ => None,
            };
            match text {
                Some(text) => doc.push(text),
                None => {
                    let path = attr.path().to_token_stream().to_string().replace(' ', "");
                    self.cx.error(
                        attr,
                        format!(
                            "unsupported attribute `#[{path}]` {place}: expected only doc \
                             comments (`/// …`)"
                        ),
                    );
                }
            }
        }
        doc
    }

    /// One setting, checked, into `gravity` or `options`.
    fn setting(&mut self, s: &Setting, gravity: &mut Option<[Value; 3]>, options: &mut Options) {
        let v = &s.value;
        match s.key.to_string().as_str() {
            "gravity" => {
                if matches!(v, Expr::Name(n) if n == "none") {
                    *gravity = None;
                } else if let Some(g) = self.vec3(v, "`gravity`", "`none` or ") {
                    *gravity = Some(g);
                }
            }
            "scalar" => {
                let kind = match v {
                    Expr::Name(n) => ScalarKind::from_name(&n.to_string()),
                    _ => None,
                };
                match kind {
                    Some(kind) => options.scalar = kind,
                    None => self.cx.error(v, unknown_scalar(&v.to_string())),
                }
            }
            "accuracy" => {
                let accuracy = match v {
                    Expr::Name(n) => Accuracy::from_name(&n.to_string()),
                    _ => None,
                };
                match accuracy {
                    Some(a) => {
                        options.accuracy = a;
                        self.accuracy_token = Some(v.to_token_stream());
                    }
                    None => self.cx.error(v, unknown_accuracy(&v.to_string())),
                }
            }
            "lock" => self.locks(v, options),
            "frames" => self.frame_list(v, options),
            "contacts" => self.contact_list(v, options),
            "loops" => self.loop_list(v, options),
            "grounds" => self.ground_list(v, options),
            "spheres" => self.sphere_list(v, options),
            key @ ("friction" | "restitution") => self.coefficient(key, v, options),
            "keep" => self.keep(v, options),
            "lanes" => match v {
                Expr::Number(Lit::Int(n)) if n.base10_parse().is_ok_and(|n| LANES.contains(&n)) => {
                    options.lanes = n.base10_parse().ok();
                    self.lanes_token = Some(v.to_token_stream());
                }
                _ => self.cx.error(v, unknown_lanes(&v.to_string())),
            },
            "quasi_static" => match v {
                Expr::Name(n) if n == "true" || n == "false" => options.quasi_static = n == "true",
                _ => self
                    .cx
                    .error(v, format!("expected `true` or `false`, found `{v}`")),
            },
            "outputs" => {
                let Expr::List(_, elems) = v else {
                    self.cx.error(
                        v,
                        format!(
                            "expected a list of outputs such as `[mass_matrix, bias]`, found `{v}`"
                        ),
                    );
                    return;
                };
                let mut outputs = Vec::new();
                for e in elems {
                    let named = match e {
                        Expr::Name(n) => Output::named(&n.to_string()),
                        _ => None,
                    };
                    match named {
                        Some(named) => {
                            for output in named {
                                // A group's outputs are at the group's name.
                                self.output_tokens
                                    .entry(output)
                                    .or_insert_with(|| e.to_token_stream());
                                outputs.push(output);
                            }
                        }
                        None => self.cx.error(e, unknown_output(&e.to_string())),
                    }
                }
                options.set_outputs(outputs);
            }
            other => self.cx.error(
                &s.key,
                format!(
                    "unknown setting `{other}`: expected `gravity`, `scalar`, `outputs`, \
                     `accuracy`, `lock`, `keep`, `quasi_static`, `frames`, `contacts`, `loops`, \
                     `lanes`, `grounds`, `spheres`, `friction` or `restitution` (or `param`, \
                     `body`, `joint`, `frame` items)"
                ),
            ),
        }
    }

    /// `lock: [joint(q, …), …]`: each joint and its position coordinates, constants only.
    fn locks(&mut self, v: &Expr, options: &mut Options) {
        let Expr::List(_, elems) = v else {
            self.cx.error(
                v,
                format!(
                    "expected a list of locked joints such as `[elbow(0.3), hip(0.0, \
                     0.1, 0.0)]`, found `{v}`"
                ),
            );
            return;
        };
        for e in elems {
            let Expr::Call(name, _, args) = e else {
                self.cx.error(
                    e,
                    format!(
                        "expected a joint and its position coordinates such as \
                         `elbow(0.3)`, found `{e}`"
                    ),
                );
                continue;
            };
            let values: Vec<Option<f64>> = args
                .iter()
                .map(|a| self.constant(a, NumCtx::Axis))
                .collect();
            if values.iter().all(Option::is_some) {
                let values = values.into_iter().flatten().collect();
                self.scene_names.insert(name.to_string(), name.clone());
                options.locks.push((name.to_string(), values));
            }
        }
    }

    /// `frames: [name, …]`: the frames the frame outputs compute, in that order.
    fn frame_list(&mut self, v: &Expr, options: &mut Options) {
        let Expr::List(_, elems) = v else {
            self.cx.error(
                v,
                format!("expected a list of frames such as `[tool, left_sole]`, found `{v}`"),
            );
            return;
        };
        for e in elems {
            match e {
                Expr::Name(n) => {
                    self.scene_names.insert(n.to_string(), n.clone());
                    options.frames.push(n.to_string());
                }
                _ => self
                    .cx
                    .error(e, format!("expected a frame name, found `{e}`")),
            }
        }
    }

    /// `contacts: [frame: kind, …]` ([`contacts_of`]).
    fn contact_list(&mut self, v: &Expr, options: &mut Options) {
        let (contacts, errors) = contacts_of(v);
        self.cx.errors(errors);
        for (frame, kind) in contacts {
            options.contacts.push(Contact {
                frame: frame.to_string(),
                kind,
            });
            self.contact_tokens.push(frame);
        }
    }

    /// `loops: [name: point(a, b), name: six_d(a, b), …]` ([`loops_of`]).
    fn loop_list(&mut self, v: &Expr, options: &mut Options) {
        let (loops, errors) = loops_of(v);
        self.cx.errors(errors);
        for (name, kind, [a, b]) in loops {
            options.loops.push(Loop {
                name: name.to_string(),
                kind,
                a: a.to_string(),
                b: b.to_string(),
            });
            self.loop_tokens.push((name, [a, b]));
        }
    }

    /// `keep: [body, …]`: the bodies the scene moves.
    fn keep(&mut self, v: &Expr, options: &mut Options) {
        let Expr::List(_, elems) = v else {
            self.cx.error(
                v,
                format!(
                    "expected a list of the bodies to keep such as `[base, upper]`, \
                     found `{v}`"
                ),
            );
            return;
        };
        let mut names = Vec::new();
        for e in elems {
            match e {
                Expr::Name(n) => {
                    self.scene_names.insert(n.to_string(), n.clone());
                    names.push(n.to_string());
                }
                _ => self
                    .cx
                    .error(e, format!("expected a body name, found `{e}`")),
            }
        }
        options.keep = Some(names);
    }

    /// The fields of a block, by position in `allowed`; reports unknown and repeated fields.
    fn fields<'f>(
        &mut self,
        fields: &'f Punctuated<Field, Token![,]>,
        allowed: &[&str],
        owner: &str,
    ) -> Vec<Option<&'f Field>> {
        let mut found: Vec<Option<&Field>> = vec![None; allowed.len()];
        for f in fields {
            let key = f.key.to_string();
            match allowed.iter().position(|a| *a == key) {
                Some(i) if found[i].is_some() => self
                    .cx
                    .error(&f.key, format!("field `{key}` is given twice in {owner}")),
                Some(i) => found[i] = Some(f),
                None => self.cx.error(
                    &f.key,
                    format!(
                        "unknown field `{key}` in {owner}: expected {}",
                        one_of(allowed)
                    ),
                ),
            }
        }
        found
    }

    /// Reports the required `field` missing from `owner`, at its `name`.
    fn missing(&mut self, name: &Ident, owner: &str, field: &str) {
        self.cx.error(
            name,
            format!("{owner} is missing the required field `{field}`"),
        );
    }

    /// A body: its mass, centre of mass (the origin if not given) and inertia.
    fn body<'a>(&mut self, b: &'a BodyDef) -> BodyDecl<'a> {
        let owner = format!("body `{}`", b.name);
        let f = self.fields(&b.fields, &["mass", "com", "inertia"], &owner);
        let mass = match f[0] {
            Some(f) => self.value(&f.value).map(|v| (v, &f.value)),
            None => {
                self.missing(&b.name, &owner, "mass");
                None
            }
        };
        let com = f[1]
            .and_then(|f| self.vec3(&f.value, "`com`", ""))
            .unwrap_or([Value::Const(0.0); 3]);
        let inertia = match f[2] {
            Some(f) => self.inertia(&f.value),
            None => {
                self.missing(&b.name, &owner, "inertia");
                None
            }
        };
        BodyDecl {
            def: b,
            mass,
            com,
            inertia,
        }
    }

    /// The inertia `e`: `diag(ixx, iyy, izz)` or the full matrix, by rows.
    fn inertia<'a>(&mut self, e: &'a Expr) -> Option<InertiaDecl<'a>> {
        let expected = "expected `diag(ixx, iyy, izz)` or `[[ixx, ixy, ixz], [ixy, iyy, iyz], \
                        [ixz, iyz, izz]]` for `inertia`";
        let zero = Value::Const(0.0);
        match e {
            Expr::Call(name, _, args) if name == "diag" && args.len() == 3 => {
                let d: Vec<&Expr> = args.iter().collect();
                let v: Vec<Option<Value>> = d.iter().map(|a| self.value(a)).collect();
                let (Some(a), Some(b), Some(c)) = (v[0], v[1], v[2]) else {
                    return None;
                };
                Some(InertiaDecl {
                    value: [[a, zero, zero], [zero, b, zero], [zero, zero, c]],
                    expr: e,
                    diag: Some([d[0], d[1], d[2]]),
                })
            }
            Expr::List(_, rows) if rows.len() == 3 => {
                let mut value = [[zero; 3]; 3];
                let mut ok = true;
                for (i, row) in rows.iter().enumerate() {
                    match row {
                        Expr::List(_, elems) if elems.len() == 3 => {
                            for (j, x) in elems.iter().enumerate() {
                                match self.value(x) {
                                    Some(v) => value[i][j] = v,
                                    None => ok = false,
                                }
                            }
                        }
                        _ => {
                            self.cx.error(
                                row,
                                format!(
                                    "expected row {} of `inertia` to be a list of 3 numbers, \
                                     found `{row}`",
                                    i + 1
                                ),
                            );
                            ok = false;
                        }
                    }
                }
                ok.then_some(InertiaDecl {
                    value,
                    expr: e,
                    diag: None,
                })
            }
            _ => {
                self.cx.error(e, format!("{expected}, found `{e}`"));
                None
            }
        }
    }

    /// A joint: its kind, its parent and child among `bodies` (`body_index` by name) and its
    /// placement.
    fn joint<'a>(
        &mut self,
        j: &'a JointDef,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> JointDecl<'a> {
        let owner = format!("joint `{}`", j.name);
        let kind = self.kind(&j.kind, &owner);
        let f = self.fields(&j.fields, &JOINT_FIELDS, &owner);
        let (parent, parent_expr) = match f[0] {
            None => {
                self.missing(&j.name, &owner, "parent");
                (End::Unknown, None)
            }
            Some(f) => (
                self.parent(&f.value, &owner, body_index, bodies),
                Some(&f.value),
            ),
        };
        let child = match f[1] {
            None => {
                self.missing(&j.name, &owner, "child");
                None
            }
            Some(f) => self.child(&f.value, &owner, body_index, bodies),
        };
        let zero = [Value::Const(0.0); 3];
        let xyz = f[2]
            .and_then(|f| self.vec3(&f.value, "`xyz`", ""))
            .unwrap_or(zero);
        let rpy = f[3]
            .and_then(|f| self.vec3(&f.value, "`rpy`", ""))
            .unwrap_or(zero);
        let drive = self.drive(&f[4..11], kind.as_ref(), &j.name.to_string());
        let mimic = self.mimic(&f[11..], &owner);
        JointDecl {
            def: j,
            kind,
            parent,
            parent_expr,
            child,
            placement: Placement { xyz, rpy },
            drive,
            mimic,
            duplicate: false,
        }
    }

    /// A joint's `mimic: other` with its `multiplier` (default 1) and `offset` (default 0),
    /// constants; `multiplier` or `offset` without `mimic` is an error at the field. The joint it
    /// names is resolved once every joint is declared ([`Lower::resolve_mimics`]).
    fn mimic<'a>(&mut self, f: &[Option<&'a Field>], owner: &str) -> Option<MimicDecl<'a>> {
        let mut read = |i: usize, default: f64| match f[i] {
            Some(field) => self.constant(&field.value, NumCtx::Drive(JOINT_FIELDS[11 + i])),
            None => Some(default),
        };
        let (multiplier, offset) = (read(1, 1.0), read(2, 0.0));
        let Some(field) = f[0] else {
            for field in f.iter().flatten() {
                self.cx.error(
                    &field.key,
                    format!("{owner}: `{}` needs `mimic: <joint>`", field.key),
                );
            }
            return None;
        };
        let Expr::Name(name) = &field.value else {
            self.cx.error(
                &field.value,
                format!(
                    "expected the name of the joint {owner} mimics, found `{}`",
                    field.value
                ),
            );
            return None;
        };
        Some(MimicDecl {
            name,
            multiplier: multiplier?,
            offset: offset?,
        })
    }

    /// Resolves each joint's `mimic` among the declared joints, and checks what it follows
    /// ([`check::mimic`]). Returns, per joint, the declaration index of the joint it follows.
    pub(super) fn resolve_mimics(&mut self, joints: &[JointDecl]) -> Vec<Option<usize>> {
        let mut out = vec![None; joints.len()];
        for (i, j) in joints.iter().enumerate() {
            let Some(m) = &j.mimic else { continue };
            let Some(f) = joints.iter().position(|x| x.def.name == *m.name) else {
                let names: Vec<String> =
                    joints.iter().map(|x| format!("`{}`", x.def.name)).collect();
                self.cx.error(
                    m.name,
                    format!(
                        "joint `{}` mimics `{}`, which is not a joint: expected one of {}",
                        j.def.name,
                        m.name,
                        names.join(", ")
                    ),
                );
                continue;
            };
            // A kind in error is reported already.
            let (Some(kind), Some(followed_kind)) = (j.kind, joints[f].kind) else {
                continue;
            };
            let (joint, followed) = (j.def.name.to_string(), m.name.to_string());
            let problem = check::mimic(&check::Follow {
                joint: &joint,
                kind,
                followed: &followed,
                followed_kind,
                itself: f == i,
                followed_mimics: joints[f].mimic.is_some(),
                multiplier: m.multiplier,
                offset: m.offset,
                drive: j.drive,
            });
            match problem {
                Some(p) => self.cx.error(m.name, p),
                None => out[i] = Some(f),
            }
        }
        out
    }

    /// A joint's drive from its fields `armature`, `damping`, `friction`, `lower`, `upper`,
    /// `velocity`, `effort` (in [`JOINT_FIELDS`]' order; each optional, constants only), checked
    /// by [`Drive::problem`] at the field the problem is about (the other bound if that one is
    /// not given).
    fn drive(&mut self, f: &[Option<&Field>], kind: Option<&JointKind>, name: &str) -> Drive {
        let mut read = |i: usize| {
            let field = f[i]?;
            let name = JOINT_FIELDS[4 + i];
            self.constant(&field.value, NumCtx::Drive(name))
        };
        let free = Drive::FREE;
        let drive = Drive {
            armature: read(0).unwrap_or(free.armature),
            damping: read(1).unwrap_or(free.damping),
            friction: read(2).unwrap_or(free.friction),
            lower: read(3).unwrap_or(free.lower),
            upper: read(4).unwrap_or(free.upper),
            velocity: read(5).unwrap_or(free.velocity),
            effort: read(6).unwrap_or(free.effort),
            ..free
        };
        if let Some((about, problem)) = kind.and_then(|kind| check::drive(name, kind, &drive)) {
            let at = |name: &str| f.iter().flatten().find(|field| field.key == name);
            if let Some(field) = at(about).or_else(|| at("upper")).or_else(|| at("lower")) {
                self.cx.error(&field.key, problem);
            }
        }
        drive
    }

    /// The parent `e` of the joint `owner`: `world` or a declared body.
    fn parent(
        &mut self,
        e: &Expr,
        owner: &str,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> End {
        match e {
            Expr::Name(n) if n == "world" => End::World,
            Expr::Name(n) => match body_index.get(&n.to_string()) {
                Some(&i) => End::Body(i),
                None => {
                    self.cx.error(
                        n,
                        format!(
                            "unknown body `{n}` as parent of {owner}: expected `world` \
                             or {}",
                            body_list(bodies)
                        ),
                    );
                    End::Unknown
                }
            },
            other => {
                self.cx.error(
                    other,
                    format!(
                        "expected `world` or a body name as parent of {owner}, found \
                         `{other}`"
                    ),
                );
                End::Unknown
            }
        }
    }

    /// The child `e` of the joint `owner`: a declared body, never `world`.
    fn child(
        &mut self,
        e: &Expr,
        owner: &str,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> Option<usize> {
        match e {
            Expr::Name(n) if n == "world" => {
                self.cx.error(
                    n,
                    format!(
                        "`world` cannot be the child of {owner}: the world does not move; \
                         expected a body"
                    ),
                );
                None
            }
            Expr::Name(n) => match body_index.get(&n.to_string()) {
                Some(&i) => Some(i),
                None => {
                    self.cx.error(
                        n,
                        format!(
                            "unknown body `{n}` as child of {owner}: expected {}",
                            body_list(bodies)
                        ),
                    );
                    None
                }
            },
            other => {
                self.cx.error(
                    other,
                    format!("expected a body name as child of {owner}, found `{other}`"),
                );
                None
            }
        }
    }
}

/// The fields of a joint: where it is, then its drive ([`Drive`]).
const JOINT_FIELDS: [&str; 14] = [
    "parent",
    "child",
    "xyz",
    "rpy",
    "armature",
    "damping",
    "friction",
    "lower",
    "upper",
    "velocity",
    "effort",
    "mimic",
    "multiplier",
    "offset",
];

/// The declared bodies, for messages: "a body (`a`, `b`)" or "a body (none is declared)".
fn body_list(bodies: &[BodyDecl]) -> String {
    let names: Vec<String> = bodies.iter().map(|b| b.def.name.to_string()).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    if names.is_empty() {
        "a body (none is declared)".to_string()
    } else {
        format!(
            "a body ({})",
            names
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}
