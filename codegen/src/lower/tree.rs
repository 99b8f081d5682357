//! The tree: every body the child of exactly one joint (no body with two parents or none), every
//! body reachable from `world` (joints that form a cycle are named, parent to child), and the
//! depth-first pre-order from the world, children in joint declaration order, that numbers the
//! model's bodies and joints. Also which bodies move (those below a joint that is not `fixed`),
//! for the mass checks.

use std::collections::HashSet;

use quote::ToTokens;

use super::{BodyDecl, JointDecl, Lower, Parent};
use crate::model::JointKind;

/// The bodies in depth-first pre-order from the world.
struct Walk {
    /// The joints (declaration indices) in depth-first pre-order.
    order: Vec<usize>,
    /// Per body, whether it moves (bodies not reached count as moving).
    moving: Vec<bool>,
    /// Per body, whether the walk reached it.
    reached: Vec<bool>,
}

impl Lower {
    /// Checks that every body is the child of exactly one joint and reachable from the world.
    /// Returns the joints (declaration indices) in depth-first pre-order and, per body, whether it
    /// moves (bodies not reached count as moving).
    pub(super) fn tree(
        &mut self,
        bodies: &[BodyDecl],
        joints: &[JointDecl],
    ) -> (Vec<usize>, Vec<bool>) {
        let parent_joint = self.parent_joints(bodies, joints);
        let walk = depth_first(&parent_joint, joints);
        self.cycles(bodies, joints, &parent_joint, &walk.reached);
        (walk.order, walk.moving)
    }

    /// Per body, the joint naming it as child (the first; a second is an error). Reports bodies
    /// with two parents or none.
    fn parent_joints(&mut self, bodies: &[BodyDecl], joints: &[JointDecl]) -> Vec<Option<usize>> {
        let nb = bodies.len();
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
        parent_joint
    }

    /// Reports the cycles the bodies not reached hang from, each once (bodies under a body
    /// without a valid parent are already reported).
    fn cycles(
        &mut self,
        bodies: &[BodyDecl],
        joints: &[JointDecl],
        parent_joint: &[Option<usize>],
        reached: &[bool],
    ) {
        let mut reported: HashSet<usize> = HashSet::new();
        for b in 0..bodies.len() {
            if reached[b] {
                continue;
            }
            let Some(cycle) = cycle_above(b, parent_joint, joints, reached) else {
                continue;
            };
            let Some(&min) = cycle.iter().min() else {
                continue;
            };
            if !reported.insert(min) {
                continue;
            }
            // The cycle goes child → parent; show parent → child, closing the loop.
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
    }
}

/// The depth-first pre-order from the world, children in declaration order.
fn depth_first(parent_joint: &[Option<usize>], joints: &[JointDecl]) -> Walk {
    let nb = parent_joint.len();
    let mut roots = Vec::new();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); nb];
    for pj in parent_joint {
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
    Walk {
        order,
        moving,
        reached,
    }
}

/// The bodies of the cycle that body `b` hangs from, child → parent, found by walking up its
/// parents; `None` if the walk ends at a body without a valid parent or at a reached one.
fn cycle_above(
    b: usize,
    parent_joint: &[Option<usize>],
    joints: &[JointDecl],
    reached: &[bool],
) -> Option<Vec<usize>> {
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
    Some(path.split_off(cycle_start?))
}
