// Every option a description can state, stated on `#[derive(Chain)]`: the scalar and the outputs,
// for a `.chain` file and a URDF (with a free base).
use articulated::nalgebra::SVector;
use articulated::prelude::*;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", scalar = f32, outputs = [mass_matrix, gravity])]
pub struct Small;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/pendulum.urdf", floating, scalar = generic, outputs = [inverse_dynamics])]
pub struct Floating;

fn main() {
    let q = SVector::<f32, 1>::new(0.3);
    let m = Small::mass_matrix(&q);
    assert!((m[(0, 0)] - 1.01).abs() < 1e-6);
    let g = Small::gravity(&q);
    assert!((g[0] - 9.81 * 0.3_f32.sin()).abs() < 1e-5, "{g}");
    assert_eq!(Floating::NQ, 7);
    // Hanging at rest: the base carries the whole weight, the pivot nothing.
    let z = SVector::<f64, 7>::zeros();
    let tau = Floating::inverse_dynamics(&z, &z, &z);
    assert!((tau[2] - 9.81).abs() < 1e-12 && tau[6].abs() < 1e-12, "{tau}");
}
