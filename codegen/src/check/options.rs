//! Which outputs and options go together with the model, and sizes: the scene (`lock`, `keep`)
//! fits the model; on the model the scene leaves, `joint_wrenches_bottom_up` needs a serial
//! chain, `accuracy: robust` with forward dynamics needs no mimic joint, and the velocity
//! coordinates are at most [`MAX_NV`].

use std::collections::HashMap;

use articulated_dynamics::prune::PruneError;

use super::{About, Problem};
use crate::model::Model;
use crate::options::{Accuracy, Options, Output};

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
    problems
}

/// The frames of `frames: [...]`: each a frame of the model the scene leaves (a body, a
/// declared frame, a URDF link), named once; frames named only where a frame output is
/// generated, and a frame output only with frames named.
fn frames(model: &Model, options: &Options) -> Vec<Problem> {
    let mut problems = Vec::new();
    for (k, name) in options.frames.iter().enumerate() {
        if options.frames[..k].contains(name) {
            problems.push(Problem::new(
                About::Scene(name.clone()),
                format!("frame `{name}` is named twice in `frames`"),
            ));
        } else if model.frame(name).is_none() {
            let mut known: Vec<&str> = model.frame_names().collect();
            known.sort_unstable();
            let shown: Vec<String> = known.iter().take(12).map(|n| format!("`{n}`")).collect();
            let more = if known.len() > 12 {
                format!(" and {} more", known.len() - 12)
            } else {
                String::new()
            };
            problems.push(Problem::new(
                About::Scene(name.clone()),
                format!(
                    "unknown frame `{name}`: expected a body or a frame of `{}` ({}{more})",
                    model.name,
                    shown.join(", ")
                ),
            ));
        }
    }
    let frame_outputs: Vec<Output> = options
        .outputs
        .iter()
        .copied()
        .filter(|o| o.spec().uses_nf())
        .collect();
    match (options.frames.first(), frame_outputs.first()) {
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
