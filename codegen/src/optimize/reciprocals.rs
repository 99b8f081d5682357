//! Divisions by one divisor turned into one reciprocal and products.
//!
//! The sparse `LᵀDL` divides a whole row of `M` by its pivot (`l_k_i = m_k_i / d_k`), and the
//! solve divides once more by the same pivot; on the 37-coordinate humanoid that was 344
//! divisions for 37 pivots. A division costs far more than a product: on Zen 4 `divsd` issues
//! once every 5 cycles against two products a cycle (one every 4–5 cycles on recent Intel
//! cores), so a function with hundreds of them waits on the divider. Here every divisor that
//! divides two or more times gets one reciprocal, `1/d`, and each `x / d` becomes `x · (1/d)`;
//! a constant divisor becomes the product by its reciprocal, folded while generating. An
//! existing `1/d` is reused, and the graph's own names are kept (`l_35_34` stays the entry it
//! was); the reciprocal is named after its divisor, `inv_<name>`.
//!
//! The operation count rises by one per divisor (the reciprocal) while all but one division of
//! each becomes a product. `x · (1/d)` rounds twice where `x / d` rounds once: at most a unit
//! in the last place more per quotient, which the tests against the reference (1e-12) and
//! against Pinocchio cover.
//!
//! `reciprocals::tests` checks on random trees that forward dynamics, the factorization with the
//! most divisions, keeps its values and is left with one division per divisor.

use std::collections::HashMap;

use articulated_dynamics::Scalar;

use crate::sym::{Graph, Node, Sym};

/// Rebuilds the part of `graph` that `outputs` need with the divisions by a shared or constant
/// divisor turned into products by its reciprocal (see the [module docs](self)), names carried
/// over; returns the new graph and the outputs in it. A graph without such divisions comes back
/// as a copy of its live part.
///
/// # Panics
/// If an output belongs to another graph.
pub fn reciprocals(graph: &Graph, outputs: &[Sym]) -> (Graph, Vec<Sym>) {
    let live = graph.live(outputs);
    let mut divisions: HashMap<Sym, usize> = HashMap::new();
    for &s in &live {
        if let Node::Div(_, b) = graph.node(s) {
            *divisions.entry(b).or_insert(0) += 1;
        }
    }
    // A constant's reciprocal is folded while generating, so even one division by it goes; a
    // reciprocal that is not a normal number (a divisor that is huge, tiny or zero) stays a
    // quotient, as the reference computes it.
    let shared = |b: Sym| match graph.node(b) {
        Node::Const(c) => (1.0 / c).is_normal(),
        _ => divisions[&b] >= 2,
    };

    // Old divisor → its reciprocal in the new graph.
    let mut inverses: HashMap<Sym, Sym> = HashMap::new();
    let (mut new_graph, new_outputs, _) = graph.rebuild(outputs, |s, map| {
        let m = |a: Sym| map[&a];
        Some(match graph.node(s) {
            Node::Div(a, b) if shared(b) => {
                let inverse = *inverses.entry(b).or_insert_with(|| match graph.node(b) {
                    Node::Const(c) => Sym::from_f64(1.0 / c),
                    _ => Sym::one() / m(b),
                });
                m(a) * inverse
            }
            node => node.remade(m),
        })
    });
    // The reciprocals that had no name of their own are named after their divisor.
    for (divisor, inverse) in &inverses {
        if let Some(name) = graph.hint_of(*divisor) {
            new_graph.hint(*inverse, &format!("inv_{name}"));
        }
    }
    (new_graph, new_outputs)
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::Reference;

    use super::*;
    use crate::options::Output;
    use crate::sym::Var;
    use crate::trace::forward::{trace_variant, variants};

    /// Divisions in the live part of `graph`, and how many distinct divisors they have.
    fn divisions(graph: &Graph, outputs: &[Sym]) -> (usize, usize) {
        let mut divisors = std::collections::HashSet::new();
        let mut count = 0;
        for s in graph.live(outputs) {
            if let Node::Div(_, b) = graph.node(s) {
                count += 1;
                divisors.insert(b);
            }
        }
        (count, divisors.len())
    }

    /// On random trees of every joint kind, every way of tracing forward dynamics (ABA and
    /// CRBA + `LᵀDL`): after the pass, no divisor divides twice, the
    /// operations grow by at most one per divisor, and the values are the reference's to
    /// `max(1e-12, 1e-13·κ(M))` of the largest. Not vacuous: most graphs lose divisions.
    #[test]
    fn one_division_per_divisor_same_values() {
        let mut fewer = 0;
        let mut graphs = 0;
        for seed in 0..40u64 {
            let model = random_model(seed, 2 + (seed as usize % 8));
            let reference = Reference::new(&model).unwrap();
            let (q, v, tau) = random_state(&model, seed);
            // As the generated code's own tests (`tests/tests/common`, `fd_tol`): two backward-
            // stable solvers differ by up to κ(M) times a few hundred ulps.
            let eig = reference.mass_matrix(&q).unwrap().symmetric_eigenvalues();
            let kappa = eig.amax() / eig.amin();
            let tol = 1e-12f64.max(1e-13 * kappa);
            let want: Vec<f64> = reference
                .forward_dynamics(&q, &v, &tau)
                .unwrap()
                .iter()
                .copied()
                .collect();
            for variant in variants(&model) {
                let traced = trace_variant(&model, variant);
                assert_eq!(traced.output, Output::ForwardDynamics);
                let (before_divs, _) = divisions(&traced.graph, &traced.values);
                let before = traced.graph.op_counts(&traced.values);
                let (graph, values) = reciprocals(&traced.graph, &traced.values);
                let (after_divs, divisors) = divisions(&graph, &values);
                let after = graph.op_counts(&values);
                assert_eq!(after_divs, divisors, "seed {seed}: a divisor divides twice");
                assert!(after_divs <= before_divs, "seed {seed}");
                assert!(
                    after.total() <= before.total() + after_divs,
                    "seed {seed}: {} -> {} operations",
                    before.total(),
                    after.total()
                );
                fewer += usize::from(after_divs < before_divs);
                graphs += 1;

                let input = |var: Var| match var {
                    Var::Q(i) => q[i],
                    Var::V(i) => v[i],
                    Var::Tau(i) => tau[i],
                    other => panic!("unexpected input {other:?}"),
                };
                let got = graph.eval(&values, input);
                let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() <= tol * scale,
                        "seed {seed} {variant:?}: {g} vs {w}"
                    );
                }
            }
        }
        assert!(
            fewer * 2 > graphs,
            "only {fewer} of {graphs} graphs lost divisions"
        );
    }
}
