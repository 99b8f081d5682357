//! Which outputs and options go together with the model, and sizes: the scene (`lock`, `keep`)
//! fits the model; on the model the scene leaves, `joint_wrenches_bottom_up` needs a serial
//! chain, `accuracy: robust` with forward dynamics needs no mimic joint, the velocity
//! coordinates are at most [`MAX_NV`], the frames named exist, and the constraints (`contacts`,
//! `loops`) hold frames that exist and move, in `f64`, with no more rows than velocities.

use std::collections::HashMap;

use articulated_dynamics::prune::PruneError;

use super::{About, Problem};
use crate::model::{JointKind, Model};
use crate::options::{did_you_mean, Accuracy, ContactKind, Options, Output, ScalarKind};

/// The most velocity coordinates the generator emits straight-line code for.
pub const MAX_NV: usize = 160;

/// What the options' rules read of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JointShape<'a> {
    /// Its name.
    pub name: &'a str,
    /// Its parent: `Some(None)` the world, `Some(Some(b))` a body, `None` not known.
    pub parent: Option<Option<usize>>,
    /// Its velocity coordinates (none for a mimic joint).
    pub nv: usize,
    /// Whether it mimics another.
    pub mimic: bool,
}

/// What is wrong with `options` for `model`: a scene that does not fit it, then the rules of
/// [`declared`] on the model the scene leaves.
pub fn options(model: &Model, options: &Options) -> Vec<Problem> {
    let scene = match options.scene_model(model) {
        Ok(scene) => scene,
        Err(e) => return vec![Problem::new(About::Scene(scene_name(&e)), e.to_string())],
    };
    let shape: Vec<JointShape> = scene
        .joints
        .iter()
        .map(|j| JointShape {
            name: &j.name,
            parent: Some(j.parent),
            nv: j.nv(),
            mimic: j.mimic.is_some(),
        })
        .collect();
    let mut problems = rules(&model.name, &shape, options);
    problems.extend(frames(&scene, options));
    problems.extend(constraints(&scene, options));
    problems.extend(contact_scene(&scene, options));
    problems
}

/// The contact simulation's scene (`grounds`, `spheres`, `friction`): each sphere on a frame the
/// model has, named once, and spheres with a ground and a friction coefficient.
fn contact_scene(model: &Model, options: &Options) -> Vec<Problem> {
    let mut problems = Vec::new();
    for (k, s) in options.spheres.iter().enumerate() {
        if options.spheres[..k].iter().any(|t| t.name == s.name) {
            problems.push(Problem::new(
                About::Scene(s.frame.clone()),
                format!("sphere `{}` is declared twice in `spheres`", s.name),
            ));
        } else if let Some(message) = unknown_frame(model, &s.frame) {
            problems.push(Problem::new(About::Scene(s.frame.clone()), message));
        }
    }
    if let Some(first) = options.spheres.first() {
        let about = || About::Scene(first.frame.clone());
        if options.grounds.is_empty() {
            problems.push(Problem::new(
                about(),
                "`spheres` touch nothing without `grounds`: expected `grounds: [floor: [0.0, \
                 0.0, 1.0, 0.0]]` (the half-space n·x ≥ d) beside them",
            ));
        }
        if options.friction.is_none() {
            problems.push(Problem::new(
                about(),
                "`spheres` need their friction coefficient: expected `friction: 0.8` (or the \
                 value of the contact) beside them",
            ));
        }
    }
    problems
}

/// The message for a frame `name` that `model` does not have (`None` if it has it): the
/// nearest name where one is near, and the frames it has.
fn unknown_frame(model: &Model, name: &str) -> Option<String> {
    if model.frame(name).is_some() {
        return None;
    }
    let mut known: Vec<&str> = model.frame_names().collect();
    known.sort_unstable();
    let hint = did_you_mean(name, known.iter().copied());
    let shown: Vec<String> = known.iter().take(12).map(|n| format!("`{n}`")).collect();
    let more = if known.len() > 12 {
        format!(" and {} more", known.len() - 12)
    } else {
        String::new()
    };
    Some(format!(
        "unknown frame `{name}`:{hint} expected a body or a frame of `{}` ({}{more})",
        model.name,
        shown.join(", ")
    ))
}

/// The body that frame `name` moves with, past the fixed joints: `Some(None)` for a frame
/// that does not move (every joint between it and the world fixed), `None` for no such frame.
fn rigid_body(model: &Model, name: &str) -> Option<Option<usize>> {
    let (mut body, _) = model.frame(name)?;
    while let Some(b) = body {
        match model.joints.get(b) {
            Some(j) if j.kind == JointKind::Fixed => body = j.parent,
            _ => break,
        }
    }
    Some(body)
}

/// The constraints (`contacts`, `loops`) on the model the scene leaves: each frame one it has,
/// one contact per frame, one loop per name, frames that move (a contact's; a loop's two apart
/// from each other), and no more rows than velocities (rows that always depend on each other, which the exact solve of the generated
/// `constrained_forward_dynamics` refuses at every state).
fn constraints(model: &Model, options: &Options) -> Vec<Problem> {
    let mut problems = Vec::new();
    if !options.constrained() {
        return problems;
    }
    for k in 0..options.contacts.len() {
        contact(model, options, k, &mut problems);
    }
    for k in 0..options.loops.len() {
        closed_loop(model, options, k, &mut problems);
    }
    // Counted once each constraint is sound (the count may change as they are fixed).
    if problems.is_empty() {
        problems.extend(too_many_rows(model, options));
    }
    problems
}

/// Contact `k`: declared once, on a frame of the model that moves.
fn contact(model: &Model, options: &Options, k: usize, problems: &mut Vec<Problem>) {
    let Some(c) = options.contacts.get(k) else {
        return;
    };
    let about = About::Contact(k);
    if options.contacts[..k].iter().any(|d| d.frame == c.frame) {
        problems.push(Problem::new(
            about,
            format!(
                "contact `{}` is declared twice in `contacts`: a frame holds one contact (a \
                 `six_d` contact holds its origin too)",
                c.frame
            ),
        ));
    } else if let Some(message) = unknown_frame(model, &c.frame) {
        problems.push(Problem::new(about, message));
    } else if rigid_body(model, &c.frame) == Some(None) {
        problems.push(Problem::new(
            about,
            format!(
                "contact `{}` holds a frame that cannot move (every joint between it and the \
                 world is fixed or locked): its rows are zero, and `constrained_forward_dynamics` \
                 would refuse them at every state; constrain a frame that moves",
                c.frame
            ),
        ));
    }
}

/// Loop `k`: named once, between two frames of the model, different, that move apart.
fn closed_loop(model: &Model, options: &Options, k: usize, problems: &mut Vec<Problem>) {
    let Some(l) = options.loops.get(k) else {
        return;
    };
    if options.loops[..k].iter().any(|m| m.name == l.name) {
        problems.push(Problem::new(
            About::Loop(k),
            format!("loop `{}` is declared twice in `loops`", l.name),
        ));
    }
    let unknown: Vec<Problem> = [&l.a, &l.b]
        .iter()
        .enumerate()
        .filter_map(|(side, f)| {
            unknown_frame(model, f).map(|m| Problem::new(About::LoopFrame(k, side), m))
        })
        .collect();
    if !unknown.is_empty() {
        problems.extend(unknown);
    } else if l.a == l.b {
        problems.push(Problem::new(
            About::LoopFrame(k, 1),
            format!(
                "loop `{}` holds frame `{}` on itself: expected two different frames, \
                 `{}(a, b)` holding `a`{} on `b`{}",
                l.name,
                l.a,
                l.kind.name(),
                if l.kind == ContactKind::Point {
                    "'s origin"
                } else {
                    ""
                },
                if l.kind == ContactKind::Point {
                    "'s"
                } else {
                    ""
                },
            ),
        ));
    } else if let (Some(a), Some(b)) = (rigid_body(model, &l.a), rigid_body(model, &l.b)) {
        if a == b {
            let fixed_to = match a.and_then(|b| model.bodies.get(b)) {
                Some(body) => format!("fixed to the same body `{}`", body.name),
                None => "both fixed to the world".to_string(),
            };
            problems.push(Problem::new(
                About::Loop(k),
                format!(
                    "loop `{}` holds frames `{}` and `{}`, {fixed_to}: the distance between \
                     them never changes, so the loop holds nothing and its rows depend on \
                     each other at every state; close it between frames on bodies that \
                     move apart",
                    l.name, l.a, l.b
                ),
            ));
        }
    }
}

/// More rows than velocities, at the constraint whose rows pass them.
fn too_many_rows(model: &Model, options: &Options) -> Option<Problem> {
    let rows = options.constraint_rows();
    let nv = model.nv();
    if rows <= nv {
        return None;
    }
    // At the constraint whose rows pass the velocities.
    let sizes = options
        .contacts
        .iter()
        .map(|c| c.kind.rows())
        .chain(options.loops.iter().map(crate::options::Loop::rows));
    let mut total = 0;
    let past = sizes
        .enumerate()
        .find(|&(_, r)| {
            total += r;
            total > nv
        })
        .map_or(0, |(k, _)| k);
    let about = match past.checked_sub(options.contacts.len()) {
        Some(l) => About::Loop(l),
        None => About::Contact(past),
    };
    Some(Problem::new(
        about,
        format!(
            "the constraints have {rows} rows and `{}` has {nv} velocity coordinates: more \
             rows than velocities depend on each other at every state, which the exact \
             solve of `constrained_forward_dynamics` refuses; declare fewer constraints, or \
             `point` contacts (3 rows) for `six_d` ones (6)",
            model.name
        ),
    ))
}

/// The frames of `frames: [...]`: each a frame of the model the scene leaves (a body, a
/// declared frame, a URDF link), named once; frames named only where a frame output is
/// generated, and a frame output only with frames named (the constraints' frames and outputs
/// counted: [`Options::resolved`]).
fn frames(model: &Model, options: &Options) -> Vec<Problem> {
    let mut problems = Vec::new();
    for (k, name) in options.frames.iter().enumerate() {
        if options.frames[..k].contains(name) {
            problems.push(Problem::new(
                About::Scene(name.clone()),
                format!("frame `{name}` is named twice in `frames`"),
            ));
        } else if let Some(message) = unknown_frame(model, name) {
            problems.push(Problem::new(About::Scene(name.clone()), message));
        }
    }
    let resolved = options.resolved();
    let frame_outputs: Vec<Output> = resolved
        .outputs
        .iter()
        .copied()
        .filter(|o| o.spec().uses_nf())
        .collect();
    match (resolved.frames.first(), frame_outputs.first()) {
        (None, Some(&o)) => problems.push(Problem::new(
            About::Output(o),
            format!(
                "`{}` computes the frames named in `frames: [...]`, and none is named: name \
                 them, e.g. `frames: [tool]` (a body's name, a `frame` item's, a URDF link's)",
                o.name()
            ),
        )),
        (Some(first), None) => problems.push(Problem::new(
            About::Scene(first.clone()),
            "`frames` names frames, but no frame output is generated: add one to `outputs` \
             (`frame_placements`, `frame_jacobians_local_world_aligned`, …, or the group \
             `frames`)"
                .to_string(),
        )),
        _ => {}
    }
    problems
}

/// The rules of [`options`] on a model that could not be built (its tree is broken), from its
/// joints as declared (`shape`); nothing if `options` prune it (the scene cannot be judged).
pub fn declared(name: &str, shape: &[JointShape], options: &Options) -> Vec<Problem> {
    if options.prunes() {
        return Vec::new();
    }
    rules(name, shape, options)
}

/// What [`options`] finds, after the invariants of a model a program built ([`Model::check`]):
/// what `generate` refuses before it traces.
pub fn program(model: &Model, options: &Options) -> Vec<Problem> {
    if let Err(e) = model.check() {
        let message = format!("the model `{}` is invalid: {e}", model.name);
        return vec![Problem::new(About::Whole, message)];
    }
    self::options(model, options)
}

/// The joint or body a [`PruneError`] is about.
fn scene_name(e: &PruneError) -> String {
    match e {
        PruneError::UnknownJoint(n) | PruneError::UnknownBody(n) => n.clone(),
        PruneError::Coordinates { joint, .. }
        | PruneError::Value { joint }
        | PruneError::Parameter { joint }
        | PruneError::Mimic { joint } => joint.clone(),
        PruneError::NotConnected { body, .. } => body.clone(),
    }
}

/// The options' rules on the joints of the chain `name`.
fn rules(name: &str, shape: &[JointShape], options: &Options) -> Vec<Problem> {
    let mut problems = Vec::new();
    if options.outputs.contains(&Output::JointWrenchesBottomUp) && !serial(shape) {
        problems.push(Problem::new(
            About::Output(Output::JointWrenchesBottomUp),
            format!(
                "`joint_wrenches_bottom_up` needs a serial chain, and `{name}` branches: where a \
                 body has two children, how the wrench splits between them is not determined; \
                 use `joint_wrenches` (from the free ends down)"
            ),
        ));
    }
    let robust_fd =
        options.accuracy == Accuracy::Robust && options.outputs.contains(&Output::ForwardDynamics);
    if let Some(j) = shape.iter().find(|j| j.mimic).filter(|_| robust_fd) {
        problems.push(Problem::new(
            About::Accuracy,
            format!(
                "`accuracy: robust` keeps forward dynamics to ABA, which cannot run with mimic \
                 joints (`{}` follows another joint, so one coordinate moves two branches); use \
                 `accuracy: fastest` (CRBA + LᵀDL of the coupled M)",
                j.name
            ),
        ));
    }
    if let Some(n) = options.lanes {
        let (scalar, allowed) = match options.scalar {
            ScalarKind::F64 => ("f64", &[2, 4, 8][..]),
            ScalarKind::F32 => ("f32", &[4, 8, 16][..]),
            ScalarKind::Generic => ("generic", &[][..]),
        };
        if !allowed.contains(&n) {
            let message = match allowed {
                [] => "`lanes` needs `scalar: f64` or `f32`: a generic scalar has no vector type \
                       (its batch functions run state by state)"
                    .to_string(),
                _ => format!(
                    "`lanes: {n}` is not a vector of `{scalar}`: use {} (states per vector \
                     value; 4 in `f64` and 8 in `f32` fill a 256-bit register)",
                    allowed
                        .iter()
                        .map(|a| format!("`{a}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            problems.push(Problem::new(About::Lanes, message));
        }
    }
    let nv: usize = shape.iter().map(|j| j.nv).sum();
    if nv > MAX_NV {
        problems.push(Problem::new(
            About::Whole,
            format!(
                "`{name}` has {nv} velocity coordinates, past the generator's limit of {MAX_NV}: \
                 straight-line code grows as their square (200 serial joints: a mass matrix of \
                 235,000 operations, 1.8 GB to generate); generate what the scene moves \
                 (`keep: […]`, `lock: […]`) or use the interpreted reference \
                 (`articulated::interpreted`)"
            ),
        ));
    }
    problems
}

/// Whether the joints form a serial chain: one joint on the world, and no body with two
/// children ([`Model::is_serial`]; joints whose parent is not known are left out).
fn serial(shape: &[JointShape]) -> bool {
    let mut children: HashMap<usize, usize> = HashMap::new();
    let mut roots = 0;
    for j in shape {
        match j.parent {
            Some(Some(p)) => *children.entry(p).or_default() += 1,
            Some(None) => roots += 1,
            None => {}
        }
    }
    roots <= 1 && children.values().all(|&c| c <= 1)
}
