// Only the outputs asked for are generated: `bias` was not.
use articulated::nalgebra::SVector;
use articulated::prelude::*;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", outputs = [mass_matrix, gravity])]
struct Arm;

fn main() {
    let q = SVector::<f64, 1>::new(0.3);
    let _ = Arm::bias(&q, &q);
}
