//! The long-horizon study's bounds (issue 12) over 20 s at a step of 1e-3 s (2e4 steps; the
//! example `drift` runs 1e5 and 1e6): what each integrator keeps of the energy and momenta that
//! the two-link and the floating cat conserve, measured with generated `f64` code.

use articulated::integrate::Method;
use articulated_examples::drift::{run, Model, Run};

const STEPS: usize = 20_000;
const DT: f64 = 1e-3;

fn runs(model: Model) -> Vec<Run> {
    Method::ALL
        .iter()
        .map(|&m| run(model, m, DT, STEPS, 100))
        .collect()
}

fn by(runs: &[Run], method: Method) -> &Run {
    runs.iter()
        .find(|r| r.method == method)
        .expect("every method ran")
}

/// The high-order methods hold the energy to near rounding, the implicit midpoint to its
/// second-order error without growth, and the explicit Euler methods visibly worse: the order
/// of the table, asserted.
#[test]
fn energy_error_by_method() {
    for model in [Model::TwoLink, Model::Cat] {
        let runs = runs(model);
        for r in &runs {
            assert!(
                r.fault.is_none() || r.method == Method::Euler,
                "{:?}: {:?}",
                r.method,
                r.fault
            );
            assert!(r.energy.iter().all(|&(_, e)| e.is_finite()));
        }
        let e = |m| by(&runs, m).max_energy();
        assert!(
            e(Method::Dopri5) < 1e-11,
            "{model:?} dopri5 {:e}",
            e(Method::Dopri5)
        );
        assert!(e(Method::Rk4) < 1e-10, "{model:?} rk4 {:e}", e(Method::Rk4));
        assert!(
            e(Method::ImplicitMidpoint) < 1e-5,
            "{model:?} midpoint {:e}",
            e(Method::ImplicitMidpoint)
        );
        assert!(
            e(Method::SymplecticEuler) < 0.5,
            "{model:?} symplectic {:e}",
            e(Method::SymplecticEuler)
        );
        // The ranking the table shows.
        assert!(e(Method::Rk4) < e(Method::ImplicitMidpoint));
        assert!(e(Method::ImplicitMidpoint) < e(Method::SymplecticEuler));
        // No blow-up: the second half's error within a few times the first half's.
        for m in [
            Method::Rk4,
            Method::Dopri5,
            Method::ImplicitMidpoint,
            Method::SymplecticEuler,
        ] {
            let (first, second) = by(&runs, m).halves();
            assert!(
                second <= 4.0 * first.max(1e-15),
                "{model:?} {m:?}: {first:e} then {second:e}"
            );
        }
    }
}

/// On the floating cat nothing external acts: both momenta are conserved, to near rounding by
/// the high-order methods.
#[test]
fn momenta_of_the_floating_cat() {
    let runs = runs(Model::Cat);
    for (m, bound) in [
        (Method::Dopri5, 1e-11),
        (Method::Rk4, 1e-10),
        (Method::ImplicitMidpoint, 1e-5),
    ] {
        let r = by(&runs, m);
        let k = r.max_angular_momentum();
        let p = r.linear_momentum.iter().fold(0.0f64, |a, &(_, e)| a.max(e));
        assert!(k < bound, "{m:?}: k_G {k:e}");
        assert!(p < 100.0 * bound, "{m:?}: p {p:e}");
    }
}
