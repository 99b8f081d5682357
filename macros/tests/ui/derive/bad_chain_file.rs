// The error names the file, line and column; the span is the path in the attribute. Code using
// the type (its functions, its operation counts) adds no error.
use articulated::nalgebra::SVector;
use articulated::prelude::*;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/unknown_parent.chain")]
struct Arm;

fn main() {
    let q = SVector::<f64, { Arm::NQ }>::zeros();
    let _ = Arm::gravity(&q);
    let _ = Arm::GRAVITY_OPS.total();
}
