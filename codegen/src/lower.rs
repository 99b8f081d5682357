//! Lowering: check a [`ChainDef`] and build the [`Model`] it describes.
//!
//! Every problem is reported, not just the first: errors are collected as `syn::Error`s, each at
//! the offending token, and combined into one (as serde_derive's `Ctxt` does), so the macro
//! shows them all and [`parse_chain_str`](crate::load::parse_chain_str) lists them all with their line and column. Messages
//! quote the user's names and say what was expected and what was found.
//!
//! What is checked: names (settings, fields, bodies, parameters, outputs, joint kinds, scalars,
//! axes, Euler sequences), duplicates, the tree (every body the child of exactly one joint and
//! reachable from `world`), numbers (finite; parameters only standing alone and never in an
//! axis), masses (positive on every body that moves, never negative), and inertias (symmetric,
//! positive definite, triangle inequality). Parameters are checked at their default values.

mod eigen;

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};
use std::fmt;

use proc_macro2::Ident;
use quote::ToTokens;
use syn::punctuated::Punctuated;
use syn::{Lit, Token};

use crate::model::{
    Body, EulerSeq, Joint, JointKind, Model, Param, Placement, Value, DEFAULT_GRAVITY,
};
use crate::options::{
    one_of, unknown_output, unknown_scalar, Description, Options, Output, ScalarKind, Visibility,
};
use crate::parse::{BodyDef, ChainDef, Expr, Field, Item, JointDef, KindDef, Setting};

/// Checks `def` and builds its [`Model`]: bodies and joints in depth-first pre-order from the
/// world (children in joint declaration order), outputs sorted and deduplicated.
///
/// On failure the returned `syn::Error` combines every problem found, each spanned at the
/// offending token (iterate it to see them one by one).
pub fn lower(def: &ChainDef) -> syn::Result<Description> {
    let mut lw = Lower::default();
    let description = lw.chain(def);
    lw.cx.check()?;
    description.ok_or_else(|| syn::Error::new_spanned(&def.name, "internal error: no model built"))
}

/// Collects errors; [`Ctxt::check`] combines them (serde_derive's `internals::Ctxt`).
#[derive(Default)]
struct Ctxt {
    errors: Vec<syn::Error>,
}

impl Ctxt {
    fn error(&mut self, at: impl ToTokens, msg: impl fmt::Display) {
        self.errors.push(syn::Error::new_spanned(at, msg));
    }
    fn has_errors(&self) -> bool {
        !self.errors.is_empty()
    }
    /// All errors combined in one, in source order where spans know their position.
    fn check(mut self) -> syn::Result<()> {
        self.errors.sort_by_key(|e| {
            let start = e.span().start();
            (start.line, start.column)
        });
        let mut errors = self.errors.into_iter();
        let Some(mut first) = errors.next() else {
            return Ok(());
        };
        for e in errors {
            first.combine(e);
        }
        Err(first)
    }
}

/// Where a number stands, for the messages about parameters.
#[derive(Clone, Copy)]
enum NumCtx<'a> {
    /// Anywhere a parameter may stand alone.
    Value,
    /// A joint axis: constants only.
    Axis,
    /// The default of the named parameter: constants only.
    Default(&'a Ident),
}

/// The twelve valid Euler sequences, for messages.
const EULER_SEQS: &str =
    "`xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx`, `xyx`, `xzx`, `yxy`, `yzy`, `zxz`, `zyz`";

#[derive(Default)]
struct Lower {
    cx: Ctxt,
    params: Vec<Param>,
    /// Whether each parameter's default was valid (checks at defaults skip the others).
    param_ok: Vec<bool>,
    param_index: HashMap<String, usize>,
}

/// A parent as resolved: the world, a body (declaration index), or an error already reported.
#[derive(Clone, Copy, PartialEq)]
enum Parent {
    World,
    Body(usize),
    Bad,
}

struct BodyDecl<'a> {
    def: &'a BodyDef,
    mass: Option<(Value, &'a Expr)>,
    com: [Value; 3],
    inertia: Option<InertiaDecl<'a>>,
}

struct InertiaDecl<'a> {
    value: [[Value; 3]; 3],
    expr: &'a Expr,
    /// The diagonal elements as written for `diag(…)`; `None` for a full matrix.
    diag: Option<[&'a Expr; 3]>,
}

struct JointDecl<'a> {
    def: &'a JointDef,
    kind: Option<JointKind>,
    parent: Parent,
    parent_expr: Option<&'a Expr>,
    child: Option<usize>,
    placement: Placement,
    /// Another joint of the same name came first (reported once, not again as two parents).
    duplicate: bool,
}

impl Lower {
    fn chain(&mut self, def: &ChainDef) -> Option<Description> {
        let doc = self.docs(&def.attrs, "before `chain`");

        // Parameters first: any item may use one, wherever it is declared.
        for item in &def.items {
            if let Item::Param(p) = item {
                self.docs(&p.attrs, "on a parameter");
                self.param(&p.name, &p.default);
            }
        }

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

        // Bodies, by name; a second body of the same name is reported and left out.
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
                let mut decl = self.joint(j, &body_index, &bodies);
                decl.duplicate = duplicate;
                joints.push(decl);
            }
        }

        if bodies.is_empty() && !self.cx.has_errors() {
            self.cx.error(
                &def.name,
                format!(
                    "chain `{}` has no bodies: expected at least one `body` and a `joint` \
                     attaching it to `world`",
                    def.name
                ),
            );
        }

        let (order, moving) = self.tree(&bodies, &joints);

        for (i, b) in bodies.iter().enumerate() {
            self.mass_properties(b, moving[i]);
        }

        if self.cx.has_errors() {
            return None;
        }

        // Renumber: the depth-first order of the joints is the order of their children.
        let mut new_index = vec![usize::MAX; bodies.len()];
        for (k, &j) in order.iter().enumerate() {
            new_index[joints[j].child?] = k;
        }
        let mut model_bodies = Vec::with_capacity(order.len());
        let mut model_joints = Vec::with_capacity(order.len());
        for &j in &order {
            let decl = &joints[j];
            let child = decl.child?;
            let b = &bodies[child];
            let inertia = b.inertia.as_ref()?;
            model_bodies.push(Body {
                name: b.def.name.to_string(),
                mass: b.mass?.0,
                com: b.com,
                inertia: inertia.value,
            });
            model_joints.push(Joint {
                name: decl.def.name.to_string(),
                kind: decl.kind?,
                parent: match decl.parent {
                    Parent::World => None,
                    Parent::Body(p) => Some(new_index[p]),
                    Parent::Bad => return None,
                },
                placement: decl.placement,
            });
        }

        let model = Model {
            name: def.name.to_string(),
            gravity,
            params: std::mem::take(&mut self.params),
            bodies: model_bodies,
            joints: model_joints,
        };
        Some(Description { model, options })
    }

    /// The doc strings among `attrs`; any other attribute is an error.
    fn docs(&mut self, attrs: &[syn::Attribute], place: &str) -> Vec<String> {
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

    fn param(&mut self, name: &Ident, default: &Expr) {
        let key = name.to_string();
        let value = self.constant(default, NumCtx::Default(name));
        if key == "pi" {
            self.cx.error(
                name,
                "`pi` is the constant π and cannot name a parameter: expected another name",
            );
        } else if self.param_index.contains_key(&key) {
            self.cx
                .error(name, format!("parameter `{key}` is declared twice"));
        } else {
            self.param_index.insert(key.clone(), self.params.len());
            self.params.push(Param {
                name: key,
                default: value.unwrap_or(0.0),
            });
            self.param_ok.push(value.is_some());
        }
    }

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
                    let output = match e {
                        Expr::Name(n) => Output::from_name(&n.to_string()),
                        _ => None,
                    };
                    match output {
                        Some(output) => outputs.push(output),
                        None => self.cx.error(e, unknown_output(&e.to_string())),
                    }
                }
                options.set_outputs(outputs);
            }
            other => self.cx.error(
                &s.key,
                format!(
                    "unknown setting `{other}`: expected `gravity`, `scalar` or `outputs` \
                     (or `param`, `body`, `joint` items)"
                ),
            ),
        }
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

    fn missing(&mut self, name: &Ident, owner: &str, field: &str) {
        self.cx.error(
            name,
            format!("{owner} is missing the required field `{field}`"),
        );
    }

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

    fn joint<'a>(
        &mut self,
        j: &'a JointDef,
        body_index: &HashMap<String, usize>,
        bodies: &[BodyDecl],
    ) -> JointDecl<'a> {
        let owner = format!("joint `{}`", j.name);
        let kind = self.kind(&j.kind, &owner);
        let f = self.fields(&j.fields, &["parent", "child", "xyz", "rpy"], &owner);
        let body_list = || {
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
        };
        let (parent, parent_expr) = match f[0] {
            None => {
                self.missing(&j.name, &owner, "parent");
                (Parent::Bad, None)
            }
            Some(f) => {
                let p = match &f.value {
                    Expr::Name(n) if n == "world" => Parent::World,
                    Expr::Name(n) => match body_index.get(&n.to_string()) {
                        Some(&i) => Parent::Body(i),
                        None => {
                            self.cx.error(
                                n,
                                format!(
                                    "unknown body `{n}` as parent of {owner}: expected `world` \
                                     or {}",
                                    body_list()
                                ),
                            );
                            Parent::Bad
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
                        Parent::Bad
                    }
                };
                (p, Some(&f.value))
            }
        };
        let child = match f[1] {
            None => {
                self.missing(&j.name, &owner, "child");
                None
            }
            Some(f) => match &f.value {
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
                                body_list()
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
            },
        };
        let zero = [Value::Const(0.0); 3];
        let xyz = f[2]
            .and_then(|f| self.vec3(&f.value, "`xyz`", ""))
            .unwrap_or(zero);
        let rpy = f[3]
            .and_then(|f| self.vec3(&f.value, "`rpy`", ""))
            .unwrap_or(zero);
        JointDecl {
            def: j,
            kind,
            parent,
            parent_expr,
            child,
            placement: Placement { xyz, rpy },
            duplicate: false,
        }
    }

    fn kind(&mut self, k: &KindDef, owner: &str) -> Option<JointKind> {
        let name = k.name.to_string();
        let args: Vec<&Expr> = k.args.iter().flat_map(|(_, a)| a.iter()).collect();
        match name.as_str() {
            "revolute" | "prismatic" => {
                let [arg] = args[..] else {
                    self.cx.error(
                        k,
                        format!(
                            "`{name}` takes one axis: expected `{name}(x)`, `{name}(y)`, \
                             `{name}(z)` or `{name}([ax, ay, az])`, found `{k}`"
                        ),
                    );
                    return None;
                };
                let axis = self.axis(arg, owner)?;
                Some(if name == "revolute" {
                    JointKind::Revolute { axis }
                } else {
                    JointKind::Prismatic { axis }
                })
            }
            "spherical" => {
                let [arg] = args[..] else {
                    self.cx.error(
                        k,
                        format!(
                            "`spherical` takes one rotation: expected `spherical(quaternion)` \
                             or `spherical(SEQ)` with an Euler sequence SEQ ({EULER_SEQS}), \
                             found `{k}`"
                        ),
                    );
                    return None;
                };
                match self.rotation(arg)? {
                    None => Some(JointKind::SphericalQuaternion),
                    Some(seq) => Some(JointKind::SphericalEuler { seq }),
                }
            }
            "free" => match args[..] {
                [] => Some(JointKind::FreeEuler { seq: EulerSeq::ZYX }),
                [arg] => match self.rotation(arg)? {
                    None => Some(JointKind::FreeQuaternion),
                    Some(seq) => Some(JointKind::FreeEuler { seq }),
                },
                _ => {
                    self.cx.error(
                        k,
                        format!(
                            "`free` takes at most one rotation: expected `free`, \
                             `free(quaternion)` or `free(SEQ)` with an Euler sequence SEQ \
                             ({EULER_SEQS}), found `{k}`"
                        ),
                    );
                    None
                }
            },
            "fixed" => {
                if k.args.is_some() {
                    self.cx.error(
                        k,
                        format!("`fixed` takes no arguments: expected `fixed`, found `{k}`"),
                    );
                    return None;
                }
                Some(JointKind::Fixed)
            }
            _ => {
                self.cx.error(
                    &k.name,
                    format!(
                        "unknown joint kind `{name}`: expected `revolute`, `prismatic`, \
                         `spherical`, `free` or `fixed`"
                    ),
                );
                None
            }
        }
    }

    /// `quaternion` (→ `Some(None)`) or an Euler sequence (→ `Some(Some(seq))`).
    fn rotation(&mut self, arg: &Expr) -> Option<Option<EulerSeq>> {
        if let Expr::Name(n) = arg {
            let s = n.to_string();
            if s == "quaternion" {
                return Some(None);
            }
            if let Some(seq) = EulerSeq::parse(&s) {
                return Some(Some(seq));
            }
        }
        self.cx.error(
            arg,
            format!(
                "invalid Euler sequence `{arg}`: expected `quaternion` or one of the 12 valid \
                 sequences {EULER_SEQS}"
            ),
        );
        None
    }

    fn axis(&mut self, arg: &Expr, owner: &str) -> Option<[f64; 3]> {
        match arg {
            Expr::Name(n) if n == "x" => Some([1.0, 0.0, 0.0]),
            Expr::Name(n) if n == "y" => Some([0.0, 1.0, 0.0]),
            Expr::Name(n) if n == "z" => Some([0.0, 0.0, 1.0]),
            Expr::Neg(_, inner) if matches!(&**inner, Expr::Name(n) if n == "x" || n == "y" || n == "z") => {
                self.axis(inner, owner).map(|a| a.map(|x| -x))
            }
            Expr::List(_, elems) if elems.len() == 3 => {
                let v: Vec<Option<f64>> = elems
                    .iter()
                    .map(|e| self.constant(e, NumCtx::Axis))
                    .collect();
                let (Some(x), Some(y), Some(z)) = (v[0], v[1], v[2]) else {
                    return None;
                };
                let n = (x * x + y * y + z * z).sqrt();
                if n == 0.0 || !n.is_finite() {
                    self.cx.error(
                        arg,
                        format!(
                            "the axis of {owner} is zero: expected a nonzero vector, found \
                             `{arg}`"
                        ),
                    );
                    return None;
                }
                Some([x / n, y / n, z / n])
            }
            _ => {
                self.cx.error(
                    arg,
                    format!(
                        "unknown axis `{arg}`: expected `x`, `y`, `z` (or `-x`, `-y`, `-z`) or a vector \
                         `[ax, ay, az]`"
                    ),
                );
                None
            }
        }
    }

    /// `[x, y, z]` of numbers (parameters allowed). `what` names the field; `alt` lists other
    /// accepted forms for the message.
    fn vec3(&mut self, e: &Expr, what: &str, alt: &str) -> Option<[Value; 3]> {
        match e {
            Expr::List(_, elems) if elems.len() == 3 => {
                let v: Vec<Option<Value>> = elems.iter().map(|x| self.value(x)).collect();
                Some([v[0]?, v[1]?, v[2]?])
            }
            _ => {
                self.cx.error(
                    e,
                    format!(
                        "expected {alt}a list of 3 numbers `[x, y, z]` for {what}, found `{e}`"
                    ),
                );
                None
            }
        }
    }

    /// A number where a parameter may stand alone.
    fn value(&mut self, e: &Expr) -> Option<Value> {
        if let Expr::Name(n) = e {
            if let Some(&i) = self.param_index.get(&n.to_string()) {
                return Some(Value::Param(i));
            }
        }
        self.constant(e, NumCtx::Value).map(Value::Const)
    }

    /// A constant number expression, folded; must be finite.
    fn constant(&mut self, e: &Expr, ctx: NumCtx) -> Option<f64> {
        let x = self.fold(e, ctx)?;
        if x.is_finite() {
            Some(x)
        } else {
            self.cx.error(
                e,
                format!(
                    "`{e}` is not a finite number: it evaluates to {x}; expected a finite value"
                ),
            );
            None
        }
    }

    /// Folds a number expression. Reports every bad operand, not just the first.
    fn fold(&mut self, e: &Expr, ctx: NumCtx) -> Option<f64> {
        match e {
            Expr::Number(lit) => {
                let (x, suffix) = match lit {
                    Lit::Float(f) => (f.base10_digits().parse::<f64>().ok(), f.suffix()),
                    Lit::Int(i) => (i.base10_digits().parse::<f64>().ok(), i.suffix()),
                    _ => (None, ""),
                };
                if !suffix.is_empty() {
                    self.cx.error(
                        lit,
                        format!(
                            "unexpected suffix `{suffix}` on `{e}`: expected a plain number \
                             (the scalar is chosen by the `scalar` setting)"
                        ),
                    );
                    return None;
                }
                match x {
                    Some(x) if x.is_finite() => Some(x),
                    _ => {
                        self.cx.error(
                            lit,
                            format!("`{e}` is not a finite number: it overflows f64; expected a finite value"),
                        );
                        None
                    }
                }
            }
            Expr::Name(n) if n == "pi" => Some(std::f64::consts::PI),
            Expr::Name(n) => {
                let is_param = self.param_index.contains_key(&n.to_string());
                let msg = match (is_param, ctx) {
                    (true, NumCtx::Value) => format!(
                        "parameter `{n}` cannot be used inside an expression: expected a \
                         parameter standing alone (such as `mass: {n}`) or a constant expression"
                    ),
                    (true, NumCtx::Axis) => format!(
                        "parameter `{n}` cannot be used in a joint axis: expected a constant"
                    ),
                    (true, NumCtx::Default(p)) => format!(
                        "parameter `{n}` cannot be used in the default of parameter `{p}`: \
                         expected a constant"
                    ),
                    (false, _) => {
                        let names: Vec<&str> =
                            self.params.iter().map(|p| p.name.as_str()).collect();
                        if names.is_empty() {
                            format!(
                                "unknown parameter `{n}`: expected a number or `pi` (no \
                                 parameters are declared)"
                            )
                        } else {
                            format!(
                                "unknown parameter `{n}`: expected a number, `pi` or a \
                                 parameter: {}",
                                one_of(&names)
                            )
                        }
                    }
                };
                self.cx.error(n, msg);
                None
            }
            Expr::Neg(_, inner) => self.fold(inner, ctx).map(|x| -x),
            Expr::Binary(l, op, r) => {
                let (l, r) = (self.fold(l, ctx), self.fold(r, ctx));
                let (l, r) = (l?, r?);
                Some(match op {
                    crate::parse::BinOp::Add(_) => l + r,
                    crate::parse::BinOp::Sub(_) => l - r,
                    crate::parse::BinOp::Mul(_) => l * r,
                    crate::parse::BinOp::Div(_) => l / r,
                })
            }
            Expr::Paren(_, inner) => self.fold(inner, ctx),
            Expr::List(..) | Expr::Call(..) => {
                self.cx.error(e, format!("expected a number, found `{e}`"));
                None
            }
        }
    }

    /// Checks that every body is the child of exactly one joint and reachable from the world.
    /// Returns the joints (declaration indices) in depth-first pre-order and, per body, whether it
    /// moves (bodies not reached count as moving).
    fn tree(&mut self, bodies: &[BodyDecl], joints: &[JointDecl]) -> (Vec<usize>, Vec<bool>) {
        let nb = bodies.len();
        // The joint naming each body as child (the first; a second is an error).
        let mut parent_joint: Vec<Option<usize>> = vec![None; nb];
        for (j, decl) in joints.iter().enumerate() {
            let Some(c) = decl.child else { continue };
            match parent_joint[c] {
                None => parent_joint[c] = Some(j),
                Some(_) if decl.duplicate => {}
                Some(first) => {
                    let child_field = decl.def.fields.iter().find(|f| f.key == "child");
                    let at: &dyn ToTokens = match child_field {
                        Some(f) => &f.value,
                        None => &decl.def.name,
                    };
                    self.cx.error(
                        at,
                        format!(
                            "body `{}` has two parents: it is already the child of joint `{}`; \
                             expected each body to be the child of exactly one joint",
                            bodies[c].def.name, joints[first].def.name
                        ),
                    );
                }
            }
        }
        let child_unresolved = joints.iter().any(|j| j.child.is_none());
        for (b, pj) in parent_joint.iter().enumerate() {
            // A joint whose child is wrong was probably meant for this body: say it once.
            if pj.is_none() && !child_unresolved {
                let name = &bodies[b].def.name;
                self.cx.error(
                    name,
                    format!("body `{name}` has no parent: expected a joint with `child: {name}`"),
                );
            }
        }

        // Depth-first pre-order from the world, children in declaration order.
        let mut roots = Vec::new();
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for pj in &parent_joint {
            let Some(j) = *pj else { continue };
            match joints[j].parent {
                Parent::World => roots.push(j),
                Parent::Body(p) => children[p].push(j),
                Parent::Bad => {}
            }
        }
        roots.sort_unstable();
        for c in &mut children {
            c.sort_unstable();
        }
        let mut order = Vec::new();
        let mut moving = vec![true; nb];
        let mut reached = vec![false; nb];
        let mut stack: Vec<usize> = roots.into_iter().rev().collect();
        while let Some(j) = stack.pop() {
            let Some(c) = joints[j].child else { continue };
            if reached[c] {
                continue;
            }
            reached[c] = true;
            order.push(j);
            let parent_moves = match joints[j].parent {
                Parent::Body(p) => moving[p],
                _ => false,
            };
            moving[c] = parent_moves || joints[j].kind != Some(JointKind::Fixed);
            stack.extend(children[c].iter().rev());
        }

        // Bodies not reached: walk up their parents to find the cycle they hang from (those
        // under a body without a valid parent are already reported).
        let mut reported: HashSet<usize> = HashSet::new();
        for b in 0..nb {
            if reached[b] {
                continue;
            }
            let mut path = vec![b];
            let cycle_start = loop {
                let cur = path[path.len() - 1];
                let Some(j) = parent_joint[cur] else {
                    break None;
                };
                let Parent::Body(p) = joints[j].parent else {
                    break None;
                };
                if let Some(k) = path.iter().position(|&x| x == p) {
                    break Some(k);
                }
                if reached[p] {
                    break None;
                }
                path.push(p);
            };
            let Some(k) = cycle_start else { continue };
            let cycle = &path[k..];
            let Some(&min) = cycle.iter().min() else {
                continue;
            };
            if !reported.insert(min) {
                continue;
            }
            // path goes child → parent; show parent → child, closing the loop.
            let mut names: Vec<String> = cycle
                .iter()
                .rev()
                .map(|&i| format!("`{}`", bodies[i].def.name))
                .collect();
            names.push(names[0].clone());
            let first_joint = cycle.iter().filter_map(|&i| parent_joint[i]).min();
            let Some(j) = first_joint else { continue };
            let at: &dyn ToTokens = match joints[j].parent_expr {
                Some(e) => e,
                None => &joints[j].def.name,
            };
            self.cx.error(
                at,
                format!(
                    "joints form a cycle {}: none of these bodies is reachable from `world`; \
                     expected a tree hanging from `world`",
                    names.join(" → ")
                ),
            );
        }
        (order, moving)
    }

    /// The value of `v` at the parameters' defaults (`None` if a default was invalid).
    fn at_default(&self, v: Value) -> Option<f64> {
        match v {
            Value::Const(x) => Some(x),
            Value::Param(i) => self.param_ok[i].then(|| self.params[i].default),
        }
    }

    fn describe(&self, v: Value, e: &Expr) -> String {
        match v {
            Value::Param(i) => format!("`{e}` = {} (its default)", num(self.params[i].default)),
            Value::Const(x) => num(x),
        }
    }

    fn mass_properties(&mut self, b: &BodyDecl, moving: bool) {
        let name = &b.def.name;
        if let Some((v, e)) = b.mass {
            if let Some(m) = self.at_default(v) {
                if m < 0.0 {
                    let expected = if moving {
                        "a positive number"
                    } else {
                        "zero or a positive number"
                    };
                    let msg = format!(
                        "mass of body `{name}` is {}: expected {expected}",
                        self.describe(v, e)
                    );
                    self.cx.error(e, msg);
                } else if m == 0.0 && moving {
                    let msg = format!(
                        "mass of body `{name}` is {}: expected a positive number, since \
                         `{name}` moves (only bodies fixed to the world may be massless)",
                        self.describe(v, e)
                    );
                    self.cx.error(e, msg);
                }
            }
        }
        let Some(inertia) = &b.inertia else { return };
        let mut m = [[0.0; 3]; 3];
        for (row, values) in m.iter_mut().zip(&inertia.value) {
            for (x, &v) in row.iter_mut().zip(values) {
                match self.at_default(v) {
                    Some(value) => *x = value,
                    None => return,
                }
            }
        }
        const NAMES: [[&str; 3]; 3] = [
            ["ixx", "ixy", "ixz"],
            ["iyx", "iyy", "iyz"],
            ["izx", "izy", "izz"],
        ];
        let scale = m.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
        let eig = if let Some(d) = inertia.diag {
            // Principal moments as written: point at the first that is not positive.
            let bad = (0..3).find(|&i| {
                if moving {
                    m[i][i] <= 0.0
                } else {
                    m[i][i] < 0.0
                }
            });
            if let Some(i) = bad {
                self.cx.error(
                    d[i],
                    format!(
                        "inertia of body `{name}` is not positive definite: principal moment \
                         {} must be positive",
                        self.describe(inertia.value[i][i], d[i])
                    ),
                );
                return;
            }
            let mut e = [m[0][0], m[1][1], m[2][2]];
            e.sort_by(f64::total_cmp);
            e
        } else {
            let Expr::List(_, rows) = inertia.expr else {
                return;
            };
            let element = |i: usize, j: usize| -> Option<&Expr> {
                match rows.iter().nth(i)? {
                    Expr::List(_, elems) => elems.iter().nth(j),
                    _ => None,
                }
            };
            let mut symmetric = true;
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                let (upper, lower) = (inertia.value[i][j], inertia.value[j][i]);
                let same = match (upper, lower) {
                    (Value::Const(a), Value::Const(b)) => (a - b).abs() <= 1e-12 * scale,
                    _ => upper == lower,
                };
                if !same {
                    symmetric = false;
                    if let (Some(eu), Some(el)) = (element(i, j), element(j, i)) {
                        self.cx.error(
                            el,
                            format!(
                                "inertia of body `{name}` is not symmetric: `{}` is `{el}` but \
                                 `{}` is `{eu}`; expected equal elements across the diagonal",
                                NAMES[j][i], NAMES[i][j]
                            ),
                        );
                    }
                }
            }
            if !symmetric {
                return;
            }
            let e = eigen::symmetric_eigenvalues(m);
            let tol = 1e-12 * scale;
            let bad = if moving { e[0] <= tol } else { e[0] < -tol };
            if bad {
                self.cx.error(
                    inertia.expr,
                    format!(
                        "inertia of body `{name}` is not positive definite: its principal \
                         moments are {}, {}, {}; expected all positive",
                        num(e[0]),
                        num(e[1]),
                        num(e[2])
                    ),
                );
                return;
            }
            e
        };
        // Triangle inequality on the sorted principal moments: e0 + e1 ≥ e2.
        if eig[0] + eig[1] < eig[2] - 1e-9 * eig[2].abs() {
            self.cx.error(
                inertia.expr,
                format!(
                    "inertia of body `{name}` breaks the triangle inequality: principal moments \
                     {} + {} < {}; expected each moment to be at most the sum of the other two",
                    num(eig[0]),
                    num(eig[1]),
                    num(eig[2])
                ),
            );
        }
    }
}

/// A number for a message: shortest form, rounded to 9 significant decimals to hide round-off.
fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let digits = 9 - x.abs().log10().floor() as i32;
    let rounded = if (0..=300).contains(&digits) {
        let p = 10f64.powi(digits);
        (x * p).round() / p
    } else {
        x
    };
    format!("{rounded}")
}

/// The visibility as written: none, `pub`, `pub(crate)`, `pub(in a::b)`.
pub(crate) fn visibility(vis: &syn::Visibility) -> Visibility {
    match vis {
        syn::Visibility::Public(_) => Visibility::Public,
        syn::Visibility::Inherited => Visibility::Private,
        syn::Visibility::Restricted(r) => {
            let path = r.path.to_token_stream().to_string().replace(' ', "");
            if r.in_token.is_some() {
                Visibility::Restricted(format!("in {path}"))
            } else {
                Visibility::Restricted(path)
            }
        }
    }
}
