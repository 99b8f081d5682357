// A description that declares its constraints, through `chain!` and `#[derive(Chain)]`: the
// generated `constrained_forward_dynamics` and constants, warning-free in the user's crate.
#![deny(warnings)]
use articulated::constraint::ConstraintError;
use articulated::nalgebra::SVector;

articulated::chain! {
    /// A free body held at a point.
    chain Held {
        contacts: [bob: point];
        body bob { mass: 2.0, inertia: diag(0.01, 0.02, 0.03) }
        joint base: free { parent: world, child: bob }
    }
}

#[derive(articulated::Chain)]
#[chain(urdf = "tests/ui/fixtures/pendulum.urdf", floating, contacts = [bob: six_d], outputs = [mass_matrix])]
struct Welded;

type Solved = Result<(SVector<f64, 7>, SVector<f64, 6>), ConstraintError>;

fn main() {
    assert_eq!(Held::CONSTRAINT_ROWS, 3);
    let z = SVector::<f64, 6>::zeros();
    // Held at rest: nothing moves, and the contact carries the body's weight.
    let (qdd, f) = Held::constrained_forward_dynamics(&z, &z, &z).unwrap();
    assert!(qdd.amax() < 1e-12 && (f[2] - 2.0 * 9.81).abs() < 1e-9, "{qdd} {f}");
    assert_eq!((Welded::LOOPS.len(), Welded::CONSTRAINT_ROWS), (0, 6));
    let solve: fn(&SVector<f64, 7>, &SVector<f64, 7>, &SVector<f64, 7>) -> Solved =
        Welded::constrained_forward_dynamics;
    let _ = solve;
}
