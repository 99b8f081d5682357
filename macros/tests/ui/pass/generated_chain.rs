// After an error-free expansion the type works: its constants and traits, from `chain!` and
// from a file. (Runtime parameters are left out: with `scalar: f64` the generated
// `PendulumParams<T = f64>` never uses `T`, error E0392, a generator problem reported.)
use articulated::nalgebra::SVector;
use articulated::prelude::*;

articulated::chain! {
    /// A pendulum.
    pub chain Pendulum {
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) { parent: world, child: bob }
    }
}

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain")]
struct FromFile;

fn main() {
    let q = SVector::<f64, { Pendulum::NQ }>::new(0.3);
    let v = SVector::<f64, { Pendulum::NV }>::new(0.5);
    let tau = Pendulum::inverse_dynamics(&q, &v, &SVector::zeros());
    let qdd = Pendulum::forward_dynamics(&q, &v, &tau).unwrap();
    assert!(qdd[0].abs() < 1e-12);
    // The bob 1 m below the pivot, at 0.3 rad: g(q) = m·g·l·sin(q).
    let g = Pendulum::gravity(&q);
    assert!((g[0] - 9.81 * 0.3_f64.sin()).abs() < 1e-12, "{g}");
    assert_eq!(FromFile::NQ, 1);
    let m = FromFile::mass_matrix(&q);
    assert!((m[(0, 0)] - 1.01).abs() < 1e-12);
}
