//! Lowering: resolve a [`ChainDef`]'s names and values, have the check stage judge them
//! ([`crate::check`]), and build the [`Model`] it describes.
//!
//! Every problem is reported, not just the first: errors are collected as `syn::Error`s, each at
//! the offending token, and combined into one (as serde_derive's `Ctxt` does), so the macro
//! shows them all and [`parse_chain_str`](crate::load::parse_chain_str) lists them all with their
//! line and column. Messages quote the user's names and say what was expected and what was found.
//!
//! What is checked here: names (settings, fields, bodies, parameters, outputs, joint kinds,
//! scalars, axes, Euler sequences, the joints mimic joints follow), duplicates, and numbers
//! (finite; parameters only standing alone and never in an axis). The check stage judges the
//! rest, at the parameters' defaults: the tree (every body the child of exactly one joint and
//! reachable from `world`), masses (positive on every body that moves, never negative),
//! inertias (symmetric, positive definite, triangle inequality), mimic joints, drives, and which
//! outputs and options go together with the model; `locate` puts each of its problems at the
//! token it is about. A `.chain` file is written for this project: every problem is an error.
//!
//! Here: [`lower`] and the assembly of the [`Description`]. By concern: `context` (the error
//! context), `numbers` (constant folding, parameters, vectors), `items` (settings, fields,
//! bodies, joints), `constraints` (`contacts` and `loops` as written), `kinds` (joint kinds, axes, Euler sequences), `locate` (the check stage's
//! problems at their tokens: the tree, masses, inertias).

pub(crate) mod constraints;
mod context;
mod ground;
mod items;
mod kinds;
mod locate;
mod numbers;

use std::collections::HashMap;

use proc_macro2::{Ident, TokenStream};
use quote::ToTokens;

use crate::check::{self, End};
use crate::model::{Body, Drive, Frame, Joint, JointKind, Mimic, Model, Param, Placement, Value};
use crate::options::{Description, Output, Visibility};
use crate::parse::{BodyDef, ChainDef, Expr, JointDef};
use context::Ctxt;

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

/// The state of one lowering: the errors so far and the parameters declared.
#[derive(Default)]
struct Lower {
    cx: Ctxt,
    params: Vec<Param>,
    /// Whether each parameter's default was valid (checks at defaults skip the others).
    param_ok: Vec<bool>,
    param_index: HashMap<String, usize>,
    /// The joints named in `lock` and the bodies named in `keep`, for errors at their tokens.
    scene_names: HashMap<String, Ident>,
    /// Each output named in `outputs`, for errors at its token.
    output_tokens: HashMap<Output, TokenStream>,
    /// The value of `accuracy`, for errors at its token.
    accuracy_token: Option<TokenStream>,
    /// The value of `lanes: …`, where a problem about it is reported.
    lanes_token: Option<TokenStream>,
    /// The frames declared with an error already reported (an unknown parent).
    broken_frames: std::collections::HashSet<String>,
    /// Each contact's frame in `contacts`, in order, for errors at its token.
    contact_tokens: Vec<Ident>,
    /// Each loop's name and frames in `loops`, in order, for errors at their tokens.
    loop_tokens: Vec<(Ident, [Ident; 2])>,
}

/// A body as declared, with its values read (`None` where an error was reported).
struct BodyDecl<'a> {
    def: &'a BodyDef,
    mass: Option<(Value, &'a Expr)>,
    com: [Value; 3],
    inertia: Option<InertiaDecl<'a>>,
}

/// An inertia as declared: its elements and the expression they were read from.
struct InertiaDecl<'a> {
    value: [[Value; 3]; 3],
    expr: &'a Expr,
    /// The diagonal elements as written for `diag(…)`; `None` for a full matrix.
    diag: Option<[&'a Expr; 3]>,
}

/// A joint as declared, its parent and child resolved to bodies (declaration indices).
struct JointDecl<'a> {
    def: &'a JointDef,
    kind: Option<JointKind>,
    /// Its parent: the world, a body (declaration index), or an error already reported.
    parent: End,
    parent_expr: Option<&'a Expr>,
    child: Option<usize>,
    placement: Placement,
    drive: Drive,
    /// `mimic: other`, with its multiplier and offset.
    mimic: Option<MimicDecl<'a>>,
    /// Another joint of the same name came first (reported once, not again as two parents).
    duplicate: bool,
}

/// A frame as declared: its parent's name (`None`: the world) and placement.
struct FrameDecl {
    name: String,
    parent: Option<String>,
    placement: Placement,
}

/// A joint's `mimic` as declared: the joint it names, its multiplier and offset.
struct MimicDecl<'a> {
    name: &'a Ident,
    multiplier: f64,
    offset: f64,
}

impl Lower {
    /// Checks every item of `def` and, if none has an error, builds its [`Description`].
    fn chain(&mut self, def: &ChainDef) -> Option<Description> {
        let doc = self.docs(&def.attrs, "before `chain`");
        self.params(def);
        let (gravity, options) = self.settings(def, doc);
        let (bodies, body_index) = self.bodies(def);
        let joints = self.joints(def, &body_index, &bodies);
        let frames = self.frames(def, &body_index, &bodies);
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

        let tree = self.tree(&bodies, &joints);
        for (b, &moving) in bodies.iter().zip(&tree.moving) {
            self.mass_properties(b, moving);
        }
        let followed = self.resolve_mimics(&joints);
        // The model, where the tree is one; the options are judged on it (its scene), or on the
        // joints as declared where it is not.
        let built = if tree.problems.is_empty() {
            renumber(&bodies, &joints, &tree.order, &followed)
        } else {
            None
        };
        let model = built.map(|(bodies, joints)| {
            let frames = frames
                .iter()
                .map(|f| Frame {
                    name: f.name.clone(),
                    parent: f
                        .parent
                        .as_ref()
                        .and_then(|p| bodies.iter().position(|b| &b.name == p)),
                    placement: f.placement,
                })
                .collect();
            Model {
                name: def.name.to_string(),
                gravity,
                params: std::mem::take(&mut self.params),
                bodies,
                joints,
                frames,
            }
        });
        let option_problems = match &model {
            Some(model) => check::options(model, &options),
            None => {
                let names: Vec<String> = joints.iter().map(|j| j.def.name.to_string()).collect();
                check::declared(&def.name.to_string(), &shape(&joints, &names), &options)
            }
        };
        // A frame whose parent is unknown is reported there, not again where it is named.
        let broken = |name: &str| self.broken_frames.contains(name);
        let option_problems: Vec<check::Problem> = option_problems
            .into_iter()
            .filter(|p| match &p.about {
                check::About::Scene(n) => !broken(n),
                check::About::Contact(k) => {
                    !options.contacts.get(*k).is_some_and(|c| broken(&c.frame))
                }
                check::About::LoopFrame(k, side) => !options
                    .loops
                    .get(*k)
                    .is_some_and(|l| broken(if *side == 0 { &l.a } else { &l.b })),
                _ => true,
            })
            .collect();
        let problems = tree.problems.into_iter().chain(option_problems);
        self.report(problems, def, &bodies, &joints);
        if self.cx.has_errors() {
            return None;
        }
        Some(Description {
            model: model?,
            options,
            warnings: Vec::new(),
            notes: Vec::new(),
            continuous: Vec::new(),
            pinocchio_order: Vec::new(),
        })
    }
}

/// The joints as declared, named `names`, for the options' rules where the tree is broken.
fn shape<'a>(joints: &[JointDecl], names: &'a [String]) -> Vec<check::JointShape<'a>> {
    joints
        .iter()
        .zip(names)
        .map(|(j, name)| check::JointShape {
            name,
            parent: match j.parent {
                End::World => Some(None),
                End::Body(p) => Some(Some(p)),
                End::Unknown => None,
            },
            nv: match (&j.mimic, j.kind) {
                (None, Some(kind)) => kind.nv(),
                _ => 0,
            },
            mimic: j.mimic.is_some(),
        })
        .collect()
}

/// The model's bodies and joints, checked: the depth-first `order` of the joints is the order of
/// their children, and parents and the joints mimic joints follow (`followed`, declaration
/// indices) are renumbered to match.
fn renumber(
    bodies: &[BodyDecl],
    joints: &[JointDecl],
    order: &[usize],
    followed: &[Option<usize>],
) -> Option<(Vec<Body>, Vec<Joint>)> {
    let mut new_index = vec![usize::MAX; bodies.len()];
    let mut new_joint = vec![usize::MAX; joints.len()];
    for (k, &j) in order.iter().enumerate() {
        new_index[joints[j].child?] = k;
        new_joint[j] = k;
    }
    let mut model_bodies = Vec::with_capacity(order.len());
    let mut model_joints = Vec::with_capacity(order.len());
    for &j in order {
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
                End::World => None,
                End::Body(p) => Some(new_index[p]),
                End::Unknown => return None,
            },
            placement: decl.placement,
            drive: decl.drive,
            mimic: match (&decl.mimic, followed[j]) {
                (Some(m), Some(f)) => Some(Mimic {
                    joint: new_joint[f],
                    multiplier: m.multiplier,
                    offset: m.offset,
                }),
                _ => None,
            },
        });
    }
    Some((model_bodies, model_joints))
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
