//! The tree: every body the child of exactly one joint, a root (`world` for a `.chain` file, the
//! one link that is no joint's child for a URDF), every body reachable from it (the joints of a
//! cycle named, parent to child), and the depth-first pre-order from the root, children in
//! declaration order, that numbers the model's bodies and joints. Also which bodies move (those
//! below a joint that is not fixed), for the mass rules.

use std::collections::HashSet;

use super::{About, Problem};

/// What a joint hangs from, as the front end resolved it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// The world.
    World,
    /// A body, by the front end's index.
    Body(usize),
    /// A name the front end could not resolve (reported there).
    Unknown,
}

/// A joint as a front end declared it: what it hangs from, what it moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Its parent.
    pub parent: End,
    /// The body it moves; `None` where the front end could not resolve it (reported there).
    pub child: Option<usize>,
    /// Whether it is fixed (its child moves only if its parent does).
    pub fixed: bool,
    /// Another joint of the same name came first (reported by the front end, and not again as a
    /// second parent).
    pub duplicate: bool,
}

/// Where a description's tree hangs from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Roots {
    /// From `world`, which joints name as their parent (`.chain`): a body no joint names as
    /// child is an error.
    World,
    /// From the one body that is no joint's child, fixed to the world (URDF's root link).
    OneBody,
}

/// What the bodies are called in messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Noun {
    /// A `.chain` body.
    Body,
    /// A URDF link.
    Link,
}

impl Noun {
    /// `body` or `link`.
    fn one(self) -> &'static str {
        match self {
            Noun::Body => "body",
            Noun::Link => "link",
        }
    }
    fn many(self) -> &'static str {
        match self {
            Noun::Body => "bodies",
            Noun::Link => "links",
        }
    }
}

/// The tree as the joints describe it, with what is wrong with it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tree {
    /// Per body, the joint whose child it is (the first, where two name it).
    pub parent_joint: Vec<Option<usize>>,
    /// Per body, the joints whose parent it is (whose child has it as first parent), in
    /// declaration order.
    pub children: Vec<Vec<usize>>,
    /// The bodies that are no joint's child, in order: with [`Roots::OneBody`] the root (one,
    /// in a tree), with [`Roots::World`] none in a tree.
    pub roots: Vec<usize>,
    /// The joints in depth-first pre-order from the root, children in declaration order.
    pub order: Vec<usize>,
    /// Per body, whether it moves (bodies not reached count as moving).
    pub moving: Vec<bool>,
    /// What is wrong: bodies with two parents or none, two roots, cycles.
    pub problems: Vec<Problem>,
}

/// Checks the tree of `edges` over the bodies named `bodies`, the joints named `joints`,
/// hanging as `roots` says.
pub fn tree(
    edges: &[Edge],
    bodies: &[String],
    joints: &[String],
    roots: Roots,
    noun: Noun,
) -> Tree {
    let nb = bodies.len();
    let name = |names: &[String], i: usize| names.get(i).cloned().unwrap_or_default();
    let mut t = Tree {
        parent_joint: vec![None; nb],
        children: vec![Vec::new(); nb],
        moving: vec![true; nb],
        ..Tree::default()
    };
    // Parents: the first joint naming a body as child; a second is an error at its child.
    for (j, e) in edges.iter().enumerate() {
        let Some(slot) = e.child.and_then(|c| t.parent_joint.get_mut(c)) else {
            continue;
        };
        match *slot {
            None => *slot = Some(j),
            Some(_) if e.duplicate => {}
            Some(first) => {
                let b = e.child.map_or_else(String::new, |c| name(bodies, c));
                let noun = noun.one();
                t.problems.push(Problem::new(
                    About::Child(j),
                    format!(
                        "{noun} `{b}` has two parents: it is already the child of joint `{}`; \
                         expected each {noun} to be the child of exactly one joint",
                        name(joints, first)
                    ),
                ));
            }
        }
    }
    for (c, pj) in t.parent_joint.iter().enumerate() {
        let parent = pj.and_then(|j| edges.get(j)).map(|e| e.parent);
        if let (Some(End::Body(p)), Some(j)) = (parent, *pj) {
            if let Some(list) = t.children.get_mut(p) {
                list.push(j);
            }
        }
        if pj.is_none() {
            t.roots.push(c);
        }
    }
    for list in &mut t.children {
        list.sort_unstable();
    }
    match roots {
        Roots::World => {
            // A joint whose child is wrong was probably meant for this body: say it once.
            let child_unresolved = edges.iter().any(|e| e.child.is_none());
            for &b in t.roots.iter().filter(|_| !child_unresolved) {
                let n = name(bodies, b);
                t.problems.push(Problem::new(
                    About::Body(b),
                    format!("body `{n}` has no parent: expected a joint with `child: {n}`"),
                ));
            }
        }
        Roots::OneBody => {
            if let [a, b, ..] = t.roots[..] {
                let many = noun.many();
                t.problems.push(Problem::new(
                    About::Body(b),
                    format!(
                        "two root {many} ({many} that are no joint's child): `{}` and `{}`; \
                         expected one tree",
                        name(bodies, a),
                        name(bodies, b)
                    ),
                ));
            }
        }
    }
    let reached = depth_first(&mut t, edges, roots);
    cycles(&mut t, edges, &reached, bodies, roots, noun);
    t
}

/// Fills `t.order` and `t.moving` by a depth-first walk from the root, children in declaration
/// order; returns, per body, whether the walk reached it.
fn depth_first(t: &mut Tree, edges: &[Edge], roots: Roots) -> Vec<bool> {
    let nb = t.parent_joint.len();
    let mut reached = vec![false; nb];
    // The joints to visit, last first; for a root body, its children.
    let mut stack: Vec<usize> = match roots {
        Roots::World => {
            let mut from_world: Vec<usize> = t
                .parent_joint
                .iter()
                .flatten()
                .copied()
                .filter(|&j| edges.get(j).is_some_and(|e| e.parent == End::World))
                .collect();
            from_world.sort_unstable();
            from_world.into_iter().rev().collect()
        }
        Roots::OneBody => {
            for &r in &t.roots {
                if let Some(x) = reached.get_mut(r) {
                    *x = true;
                }
                if let Some(m) = t.moving.get_mut(r) {
                    *m = false;
                }
            }
            t.roots
                .iter()
                .rev()
                .flat_map(|&r| t.children.get(r).into_iter().flatten().rev())
                .copied()
                .collect()
        }
    };
    while let Some(j) = stack.pop() {
        let Some(e) = edges.get(j) else { continue };
        let Some(c) = e.child else { continue };
        match reached.get_mut(c) {
            Some(r) if !*r => *r = true,
            _ => continue,
        }
        t.order.push(j);
        let parent_moves = match e.parent {
            End::Body(p) => t.moving.get(p).copied().unwrap_or(false),
            _ => false,
        };
        if let Some(m) = t.moving.get_mut(c) {
            *m = parent_moves || !e.fixed;
        }
        stack.extend(t.children.get(c).into_iter().flatten().rev());
    }
    reached
}

/// Reports the cycles the bodies not reached hang from, each once (bodies under a body without
/// a valid parent, or under a second root, are reported as such).
fn cycles(
    t: &mut Tree,
    edges: &[Edge],
    reached: &[bool],
    bodies: &[String],
    roots: Roots,
    noun: Noun,
) {
    let root = match roots {
        Roots::World => "`world`",
        Roots::OneBody => "a root link",
    };
    let mut reported: HashSet<usize> = HashSet::new();
    for (b, _) in reached.iter().enumerate().filter(|(_, r)| !**r) {
        let Some(cycle) = cycle_above(b, &t.parent_joint, edges, reached) else {
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
            .map(|&i| format!("`{}`", bodies.get(i).map_or("", String::as_str)))
            .collect();
        names.extend(names.first().cloned());
        let first_joint = cycle
            .iter()
            .filter_map(|&i| t.parent_joint.get(i).copied().flatten())
            .min();
        let Some(j) = first_joint else { continue };
        t.problems.push(Problem::new(
            About::Parent(j),
            format!(
                "joints form a cycle {}: none of these {} is reachable from {root}; expected a \
                 tree hanging from {root}",
                names.join(" → "),
                noun.many()
            ),
        ));
    }
}

/// The bodies of the cycle that body `b` hangs from, child → parent, found by walking up its
/// parents; `None` if the walk ends at a body without a valid parent or at a reached one.
fn cycle_above(
    b: usize,
    parent_joint: &[Option<usize>],
    edges: &[Edge],
    reached: &[bool],
) -> Option<Vec<usize>> {
    let mut path = vec![b];
    let mut cur = b;
    let cycle_start = loop {
        let j = parent_joint.get(cur).copied().flatten()?;
        let End::Body(p) = edges.get(j)?.parent else {
            return None;
        };
        if let Some(k) = path.iter().position(|&x| x == p) {
            break k;
        }
        if reached.get(p).copied().unwrap_or(true) {
            return None;
        }
        path.push(p);
        cur = p;
    };
    Some(path.split_off(cycle_start))
}
