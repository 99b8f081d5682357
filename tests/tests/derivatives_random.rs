//! The generator's derivative graphs on random trees of every joint kind, up to 30 bodies
//! (free bases, Euler and quaternion joints included), evaluated in `f64`
//! (`articulated_codegen::trace::Traced::eval`: what the generated code computes, without
//! compiling tens of thousands of lines per tree) against the reference's forward-mode duals:
//! `∂τ/∂q`, `∂τ/∂v` to 1e-11 relative to the largest entry, forward dynamics' derivatives and
//! `M⁻¹` to the κ(M)-aware tolerance of `q̈`. The emitted code itself is checked on the
//! shipped models (`generated_derivatives.rs`); the reference against finite differences on
//! random trees in `dynamics/tests/derivatives.rs`.

mod common;

use articulated::nalgebra::DMatrix;
use articulated::reference::Reference;
use articulated_codegen::options::Output;
use articulated_codegen::sym::Var;
use articulated_codegen::trace::trace;
use articulated_dynamics::random::{random_model, random_state};
use common::{condition, fd_tol, rel_err};

/// Trees: `(seed, bodies)`.
const TREES: [(u64, usize); 8] = [
    (1, 1),
    (2, 2),
    (3, 4),
    (4, 6),
    (5, 9),
    (6, 12),
    (7, 20),
    (8, 30),
];

fn rows(m: &DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

#[test]
fn derivative_graphs_match_the_reference_on_random_trees() {
    for (seed, n) in TREES {
        let model = random_model(seed, n);
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let nv = model.nv();
        let tau: Vec<f64> = r
            .inverse_dynamics(&q, &v, &a)
            .unwrap()
            .iter()
            .map(|t| t - 0.25)
            .collect();
        let input = |var: Var| match var {
            Var::Q(i) => q[i],
            Var::V(i) => v[i],
            Var::A(i) => a[i],
            Var::Tau(i) => tau[i],
            _ => 0.0,
        };
        let label = format!("random tree {seed} ({n} bodies, nv {nv})");

        let (values, ok) = trace(&model, Output::InverseDynamicsDerivatives).eval(input);
        assert!(ok);
        let (dq, dv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
        let (e_dq, e_dv) = (
            rel_err(&values[..nv * nv], &rows(&dq)),
            rel_err(&values[nv * nv..], &rows(&dv)),
        );
        println!("{label}: dtau/dq {e_dq:.1e}, dtau/dv {e_dv:.1e}");
        assert!(e_dq < 1e-11 && e_dv < 1e-11, "{label}: {e_dq:e}, {e_dv:e}");

        let tol = fd_tol(condition(&r.mass_matrix(&q).unwrap()));
        let (minv, ok) = trace(&model, Output::MassMatrixInverse).eval(input);
        assert!(ok, "{label}: M⁻¹ refused");
        let reference_minv = r.mass_matrix_inverse(&q).unwrap();
        let e = rel_err(&minv, &rows(&reference_minv));
        assert!(e < tol, "{label}: M⁻¹ off by {e:e} (tolerance {tol:e})");
        let (values, ok) = trace(&model, Output::ForwardDynamicsDerivatives).eval(input);
        assert!(ok, "{label}: forward derivatives refused");
        let [rq, rv, rminv] = r.forward_dynamics_derivatives(&q, &v, &tau).unwrap();
        // Values: q̈, then ∂q̈/∂q, ∂q̈/∂v, M⁻¹.
        let e = [rq, rv, rminv]
            .iter()
            .enumerate()
            .map(|(k, m)| rel_err(&values[nv + k * nv * nv..nv + (k + 1) * nv * nv], &rows(m)))
            .fold(0.0, f64::max);
        println!("{label}: forward derivatives {e:.1e} (tolerance {tol:.1e})");
        assert!(
            e < tol,
            "{label}: forward derivatives off by {e:e} (tolerance {tol:e})"
        );
    }
}
