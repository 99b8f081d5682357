//! The derivative outputs: `∂τ/∂q` and `∂τ/∂v` of inverse dynamics, `∂q̈/∂q`, `∂q̈/∂v` and
//! `M⁻¹` of forward dynamics, and `M⁻¹` alone.
//!
//! Each is the reference's forward-mode differentiation
//! (`articulated_dynamics::reference::derivatives`) traced on `Dual<Sym>`: one run of inverse
//! dynamics per tangent direction, whose value parts hash-cons to the same nodes (computed
//! once) and whose derivative parts fold to zero wherever the tree's structure says so (a
//! body's motion does not depend on the joints below it). Forward dynamics' derivatives are
//! `−M⁻¹·∂τ/∂(q, v)` at `a = q̈`, every product with `M⁻¹` a solve with the sparse `LᵀDL` of
//! `M` that also gives `q̈` and `M⁻¹`.
//!
//! Variants, the fewest operations kept as for the values: inverse dynamics by the reference's
//! spatial RNEA or by [`super::newton_euler`], on the tree as described or regrouped; `M` (for
//! forward dynamics and `M⁻¹`) by each CRBA formulation.

use articulated_dynamics::model::{JointKind, Model};
use articulated_dynamics::reference::derivatives::{
    forward_dynamics_derivatives_with, inverse_dynamics_derivatives_analytic,
    inverse_dynamics_derivatives_with, mass_matrix_inverse_from, Dual, DualRnea,
};
use articulated_dynamics::reference::{self, centroidal, Tree};
use articulated_dynamics::spatial::Mat3;
use articulated_dynamics::Scalar;

use super::forward::FdMethod;
use super::{
    mass_matrix, model_inputs, newton_euler, rnea, symbolic_tree, tree_angles, tree_inputs,
};
use super::{Formulation, Pivots, Traced, Variant};
use crate::options::Output;
use crate::sym::{self, Sym, Var};

/// The variants of a derivative output: for `∂τ`, forward-mode duals through each Newton–Euler
/// formulation and the analytical recursion, and (for chains without quaternion joints) each of
/// those with `∂τ/∂v = 2·N`; for forward dynamics, each of those with each CRBA formulation for
/// `M`; for `M⁻¹`, each CRBA formulation. Each on the tree as described and regrouped.
pub(crate) fn variants(model: &Model, output: Output) -> Vec<Variant> {
    let quaternions = model.joints.iter().any(|j| {
        matches!(
            j.kind,
            JointKind::SphericalQuaternion | JointKind::FreeQuaternion
        )
    });
    let coriolis: &[bool] = if quaternions {
        &[false]
    } else {
        &[false, true]
    };
    let rneas: &[Formulation] = match output {
        Output::InverseDynamicsDerivatives => &[Formulation::Reference, Formulation::Specialized],
        _ => &[
            Formulation::Reference,
            Formulation::Specialized,
            Formulation::SpecializedRootFrame,
        ],
    };
    let mut methods: Vec<(Formulation, bool, bool)> = Vec::new();
    if output == Output::MassMatrixInverse {
        methods.extend(rneas.iter().map(|&f| (f, false, false)));
    } else {
        for &f in rneas {
            for analytic in [false, true] {
                for &c in coriolis {
                    methods.push((f, analytic, c));
                }
            }
        }
    }
    let method = (output != Output::InverseDynamicsDerivatives).then_some(FdMethod::CrbaLtdl);
    [false, true]
        .into_iter()
        .flat_map(|regrouped| {
            methods
                .iter()
                .map(move |&(formulation, analytic, coriolis)| Variant {
                    regrouped,
                    formulation,
                    method,
                    analytic,
                    coriolis,
                    quasi_static: false,
                })
        })
        .collect()
}

/// Inverse dynamics with gravity on duals, by a formulation.
struct Rnea(Formulation);

/// `(∂τ/∂q, ∂τ/∂v)` by the variant's method.
fn rnea_derivatives(
    variant: Variant,
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
) -> (Vec<Sym>, Vec<Sym>) {
    let (dq, dv) = if variant.analytic {
        inverse_dynamics_derivatives_analytic(tree, q, v, a)
    } else {
        inverse_dynamics_derivatives_with(tree, q, v, a, &Rnea(variant.formulation))
    };
    if !variant.coriolis {
        return (dq, dv);
    }
    // τ's velocity terms are the quadratic form Σ Γ_ijk·v_j·v_k with Γ symmetric in j, k (v = q̇),
    // so ∂τ/∂v = 2·Σ_k Γ_ijk·v_k = 2·N: N of the tree with every inertia doubled (`N` is linear
    // in the inertias), whose 2 folds into the constants. The dual runs for `v` go unused, and
    // with them their operations.
    let mut doubled = tree.clone();
    let two = Sym::from_f64(2.0);
    for node in &mut doubled.nodes {
        let i = &mut node.inertia;
        i.m = two * i.m;
        i.h = i.h.scale(two);
        i.i = Mat3(i.i.0.map(|r| r.map(|x| two * x)));
    }
    let dv = match variant.formulation {
        Formulation::Reference => centroidal::coriolis_matrix(&doubled, q, v),
        _ => super::crba::coriolis_matrix(&doubled, q, v, super::regroup::coordinate_axis),
    };
    (dq, dv)
}

impl DualRnea<Sym> for Rnea {
    fn rnea(
        &self,
        tree: &Tree<Dual<Sym>>,
        q: &[Dual<Sym>],
        v: &[Dual<Sym>],
        a: &[Dual<Sym>],
    ) -> Vec<Dual<Sym>> {
        match self.0 {
            Formulation::Reference => reference::rnea(tree, q, v, a, true),
            _ => newton_euler::classical_rnea(tree, q, v, a, true),
        }
    }
}

/// Labels a row-major `n × n` matrix `{stem}_{i}_{j}`.
fn labelled(stem: &str, x: Vec<Sym>, n: usize) -> Vec<Sym> {
    x.into_iter()
        .enumerate()
        .map(|(k, s)| s.label(format_args!("{stem}_{}_{}", k / n, k % n)))
        .collect()
}

/// A derivative output traced one way. Its values: `∂τ/∂q` then `∂τ/∂v` (row-major); `q̈`,
/// `∂q̈/∂q`, `∂q̈/∂v`, `M⁻¹` (`q̈` is not returned: the generated code checks it is finite); or
/// `M⁻¹`.
pub(crate) fn trace_variant(model: &Model, output: Output, variant: Variant) -> Traced {
    let (graph, (values, pivots)) = sym::trace(|| {
        let (tree, turns) = symbolic_tree(model, variant.regrouped);
        let (c, nv) = (model.coupling(), model.nv());
        let form = variant.formulation;
        // With mimic joints, `∂τ/∂x = Gᵀ·∂τ_tree/∂x_tree·G` (`G` constant): the tree's
        // derivatives at the tree's state, reduced like `M`.
        let derivatives = |q: &[Sym], v: &[Sym], a: &[Sym]| {
            let (dq, dv) = rnea_derivatives(variant, &tree, q, v, a);
            (c.reduce_matrix(&dq), c.reduce_matrix(&dv))
        };
        match output {
            Output::InverseDynamicsDerivatives => {
                let (q, v, a) = tree_inputs(model, &c, &turns, variant);
                let (dq, dv) = derivatives(&q, &v, &a);
                let mut values = labelled("dtau_dq", dq, nv);
                values.extend(labelled("dtau_dv", dv, nv));
                (values, None)
            }
            Output::ForwardDynamicsDerivatives => {
                let (q, v, tau) = model_inputs(model, &c, &turns, variant, Var::Tau);
                let zero = vec![Sym::zero(); tree.nv];
                let m = c.reduce_matrix(&mass_matrix(form, &tree, &q));
                let h = c.reduce(&rnea(form, &tree, &q, &v, &zero, true));
                let d = forward_dynamics_derivatives_with(&tau, m, &h, |qdd| {
                    derivatives(&q, &v, &c.expand_v(qdd))
                });
                let mut values: Vec<Sym> = d
                    .qdd
                    .into_iter()
                    .enumerate()
                    .map(|(k, x)| x.label(format_args!("qdd_{k}")))
                    .collect();
                values.extend(labelled("ddq_dq", d.dqdd_dq, nv));
                values.extend(labelled("ddq_dv", d.dqdd_dv, nv));
                values.extend(labelled("minv", d.minv, nv));
                (values, Some(Pivots::with_scale(d.pivots)))
            }
            _ => {
                let q = tree_angles(model, &c, &turns);
                let m = c.reduce_matrix(&mass_matrix(form, &tree, &q));
                let (minv, pairs) = mass_matrix_inverse_from(m, nv);
                (labelled("minv", minv, nv), Some(Pivots::with_scale(pairs)))
            }
        }
    });
    Traced {
        output,
        graph,
        values,
        pivots,
        variant,
        candidates: Vec::new(),
    }
}
