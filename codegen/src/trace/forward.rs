//! Forward dynamics, traced three ways:
//! - **ABA** (Featherstone 2008, RBDA §7.3), O(n);
//! - **CRBA + `LᵀDL`**: `M` from CRBA, `h = N·q̇ + g` from Newton–Euler, then `M = LᵀDL` factored
//!   from the last coordinate to the first (RBDA §6.5), which keeps the tree's sparsity: the
//!   structural zeros of `M` are exact zeros in the graph, so every product with them folds
//!   away;
//! - **CRBA + `LᵀDL` with the limbs condensed** ([`super::condensed`]) where a body other than
//!   the root branches: each subtree off it eliminated against its own coordinates only, its
//!   effect on the rest one 6 × 6 matrix at that body.
//!
//! Each on the tree as described and regrouped, and CRBA + `LᵀDL` with all formulations of
//! `M` and `h`. Regrouping changes neither `M` nor ABA's pivots: every moved part `I_s` has
//! `I_s·S = 0`, so each `D_i = Sᵢᵀ·I^A_i·S_i` and `U_i = I^A_i·S_i` is the same.

use articulated_dynamics::model::Model;
use articulated_dynamics::reference::{aba, ltdl_solve};
use articulated_dynamics::Scalar;

use super::{condensed, crba, regroup};
use super::{label_outputs, mass_matrix, model_inputs, rnea, symbolic_tree};
use super::{Formulation, Pivots, Traced, Variant};
use crate::options::Output;
use crate::sym::{self, Sym, Var};

/// How forward dynamics is computed in generated code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FdMethod {
    /// The articulated-body algorithm.
    Aba,
    /// CRBA, Newton–Euler, then a sparse `LᵀDL` of `M` and two triangular solves.
    CrbaLtdl,
    /// As [`FdMethod::CrbaLtdl`], with the subtrees that branch off a body other than the root
    /// condensed into a 6 × 6 matrix at that body ([`super::condensed`]).
    CrbaCondensed,
}

impl FdMethod {
    /// A short name for docs and reports.
    pub fn name(self) -> &'static str {
        match self {
            FdMethod::Aba => "ABA (RBDA §7.3)",
            FdMethod::CrbaLtdl => "CRBA + sparse LᵀDL (RBDA §6.2, §6.5)",
            FdMethod::CrbaCondensed => {
                "CRBA + LᵀDL with the limbs condensed at their branching body"
            }
        }
    }
}

/// The variants of forward dynamics: ABA on the tree as described and regrouped, CRBA + `LᵀDL`
/// with every formulation, each on both trees, and the condensed form on both trees where a
/// body other than the root branches. ABA and the condensed form only without mimic joints: a
/// coordinate that moves joints on two branches has no articulated inertia of its own, nor
/// belongs to one subtree.
pub(crate) fn variants(model: &Model) -> impl Iterator<Item = Variant> {
    let aba_runs = !model.has_mimic();
    let aba = [false, true].map(|regrouped| Variant {
        regrouped,
        formulation: Formulation::Reference,
        method: Some(FdMethod::Aba),
        analytic: false,
        coriolis: false,
        quasi_static: false,
    });
    let ltdl = [false, true].into_iter().flat_map(|regrouped| {
        [
            Formulation::Reference,
            Formulation::Specialized,
            Formulation::SpecializedRootFrame,
        ]
        .map(|formulation| Variant {
            regrouped,
            formulation,
            method: Some(FdMethod::CrbaLtdl),
            analytic: false,
            coriolis: false,
            quasi_static: false,
        })
    });
    let condensed = [false, true].map(|regrouped| Variant {
        regrouped,
        formulation: Formulation::Specialized,
        method: Some(FdMethod::CrbaCondensed),
        analytic: false,
        coriolis: false,
        quasi_static: false,
    });
    let condensed_runs = aba_runs && condensed::applies(model);
    aba.into_iter()
        .filter(move |_| aba_runs)
        .chain(ltdl)
        .chain(condensed.into_iter().filter(move |_| condensed_runs))
}

/// Forward dynamics traced one way.
pub(crate) fn trace_variant(model: &Model, variant: Variant) -> Traced {
    let (graph, (values, pivots)) = sym::trace(|| {
        let (tree, turns) = symbolic_tree(model, variant.regrouped);
        let (c, nv) = (model.coupling(), model.nv());
        let (q, v, tau) = model_inputs(model, &c, &turns, variant, Var::Tau);
        let (values, pivots) = match variant.method {
            Some(FdMethod::CrbaLtdl) => {
                let m = c.reduce_matrix(&mass_matrix(variant.formulation, &tree, &q));
                let zero = vec![Sym::zero(); tree.nv];
                let h = c.reduce(&rnea(variant.formulation, &tree, &q, &v, &zero, true));
                let b: Vec<Sym> = tau.iter().zip(&h).map(|(&t, &h)| t - h).collect();
                let (values, pairs) = ltdl_solve(m, b, nv);
                // Inside the trace: the sum is recorded in this graph.
                (values, Pivots::with_scale(pairs))
            }
            Some(FdMethod::CrbaCondensed) => {
                let (m, ic, x_up) = crba::crba_with_composites(&tree, &q, regroup::coordinate_axis);
                let zero = vec![Sym::zero(); tree.nv];
                let h = rnea(variant.formulation, &tree, &q, &v, &zero, true);
                let b: Vec<Sym> = tau.iter().zip(&h).map(|(&t, &h)| t - h).collect();
                let cuts = condensed::cut_points(&tree);
                let (values, pairs) = condensed::solve(&tree, &ic, &x_up, m, b, &cuts);
                (values, Pivots::with_scale(pairs))
            }
            _ => {
                let out = aba(&tree, &q, &v, &tau, true);
                // ABA's unreduced values are articulated already; a leaf body's are its own.
                let mut exact = vec![false; tree.nv];
                for (i, node) in tree.nodes.iter().enumerate() {
                    if !tree.nodes.iter().any(|c| c.parent == Some(i)) {
                        exact[node.v_at..node.v_at + node.nv()].fill(true);
                    }
                }
                let pairs = out.pivots.into_iter().zip(out.diag).collect();
                (out.qdd, Pivots::with_exact(pairs, exact, true))
            }
        };
        let values = label_outputs(Output::ForwardDynamics, values, nv);
        (values, pivots)
    });
    Traced {
        output: Output::ForwardDynamics,
        graph,
        values,
        pivots: Some(pivots),
        variant,
        candidates: Vec::new(),
    }
}
