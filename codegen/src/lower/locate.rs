//! The check stage's judgement of a `.chain` description ([`crate::check`]), each problem put at
//! the token it is about: the tree (a second parent at the `child:` value, a cycle at the
//! `parent:` of its first joint), masses at their value, inertias at the matrix (a `diag(…)`
//! element that is not positive at the element, an asymmetric pair at the element below the
//! diagonal), outputs and options at the name that asked for them, the size at the chain's
//! name. Every one is an error: a `.chain` file is written for this project.

use quote::ToTokens;

use super::{BodyDecl, InertiaDecl, JointDecl, Lower};
use crate::check::{self, About, Edge, Inertia, InertiaProblem, Noun, Problem, Roots, Strictness};
use crate::model::JointKind;
use crate::parse::{ChainDef, Expr};

impl Lower {
    /// The tree of the declared joints ([`check::tree`]), its problems not yet reported.
    pub(super) fn tree(&mut self, bodies: &[BodyDecl], joints: &[JointDecl]) -> check::Tree {
        let edges: Vec<Edge> = joints
            .iter()
            .map(|j| Edge {
                parent: j.parent,
                child: j.child,
                fixed: j.kind == Some(JointKind::Fixed),
                duplicate: j.duplicate,
            })
            .collect();
        let body_names: Vec<String> = bodies.iter().map(|b| b.def.name.to_string()).collect();
        let joint_names: Vec<String> = joints.iter().map(|j| j.def.name.to_string()).collect();
        check::tree(&edges, &body_names, &joint_names, Roots::World, Noun::Body)
    }

    /// Reports each of `problems` at the token it is about.
    pub(super) fn report(
        &mut self,
        problems: impl IntoIterator<Item = Problem>,
        def: &ChainDef,
        bodies: &[BodyDecl],
        joints: &[JointDecl],
    ) {
        for p in problems {
            let joint = |j: usize| joints.get(j);
            let at: Option<&dyn ToTokens> = match &p.about {
                About::Body(b) => bodies.get(*b).map(|b| &b.def.name as &dyn ToTokens),
                About::Parent(j) => joint(*j).map(|j| match j.parent_expr {
                    Some(e) => e as &dyn ToTokens,
                    None => &j.def.name,
                }),
                About::Child(j) => {
                    joint(*j).map(|j| match j.def.fields.iter().find(|f| f.key == "child") {
                        Some(f) => &f.value as &dyn ToTokens,
                        None => &j.def.name,
                    })
                }
                About::Output(o) => self.output_tokens.get(o).map(|t| t as &dyn ToTokens),
                About::Accuracy => self.accuracy_token.as_ref().map(|t| t as &dyn ToTokens),
                About::Lanes => self.lanes_token.as_ref().map(|t| t as &dyn ToTokens),
                About::Scene(name) => self.scene_names.get(name).map(|i| i as &dyn ToTokens),
                About::Contact(k) => self.contact_tokens.get(*k).map(|i| i as &dyn ToTokens),
                About::Loop(k) => self.loop_tokens.get(*k).map(|(i, _)| i as &dyn ToTokens),
                About::LoopFrame(k, side) => self
                    .loop_tokens
                    .get(*k)
                    .and_then(|(_, frames)| frames.get(*side))
                    .map(|i| i as &dyn ToTokens),
                About::Whole => None,
            };
            let at = at.map_or_else(|| def.name.to_token_stream(), ToTokens::to_token_stream);
            self.cx.error(at, p.message);
        }
    }

    /// Checks the mass and the inertia of `b` ([`check::mass`], [`check::inertia`]); `moving`
    /// says whether the body moves.
    pub(super) fn mass_properties(&mut self, b: &BodyDecl, moving: bool) {
        let name = b.def.name.to_string();
        if let Some((v, e)) = b.mass {
            let problem = self
                .at_default(v)
                .and_then(|m| check::mass("body", &name, &self.describe(v, e), m, Some(moving)));
            if let Some(message) = problem {
                self.cx.error(e, message);
            }
        }
        let Some(inertia) = &b.inertia else { return };
        let Some(m) = self.inertia_at_default(inertia) else {
            return;
        };
        let subject = format!("body `{name}`");
        let written = match inertia.diag {
            Some(_) => Inertia::Diag([m[0][0], m[1][1], m[2][2]]),
            None if self.symmetric(&subject, inertia, &m) => Inertia::Full(m),
            None => return,
        };
        let Some(problem) = check::inertia(&written, Strictness::Written { moving }) else {
            return;
        };
        let element = match (problem, inertia.diag) {
            (
                InertiaProblem::NotPositive {
                    element: Some(i), ..
                },
                Some(d),
            ) => d.get(i).copied(),
            _ => None,
        };
        self.cx
            .error(element.unwrap_or(inertia.expr), problem.message(&subject));
    }

    /// The inertia's elements at the parameters' defaults (`None` if a default was invalid).
    fn inertia_at_default(&self, inertia: &InertiaDecl) -> Option<[[f64; 3]; 3]> {
        let mut m = [[0.0; 3]; 3];
        for (row, values) in m.iter_mut().zip(&inertia.value) {
            for (x, &v) in row.iter_mut().zip(values) {
                *x = self.at_default(v)?;
            }
        }
        Some(m)
    }

    /// Whether the elements across the diagonal are equal ([`check::asymmetric`]); reports each
    /// pair that is not, at the element below the diagonal.
    fn symmetric(&mut self, subject: &str, inertia: &InertiaDecl, m: &[[f64; 3]; 3]) -> bool {
        let Expr::List(_, rows) = inertia.expr else {
            return false;
        };
        let element = |i: usize, j: usize| -> Option<&Expr> {
            match rows.iter().nth(i)? {
                Expr::List(_, elems) => elems.iter().nth(j),
                _ => None,
            }
        };
        let pairs = check::asymmetric(&inertia.value, m);
        for &(i, j) in &pairs {
            if let (Some(upper), Some(lower)) = (element(i, j), element(j, i)) {
                let message =
                    check::asymmetry(subject, (i, j), &lower.to_string(), &upper.to_string());
                self.cx.error(lower, message);
            }
        }
        pairs.is_empty()
    }
}
