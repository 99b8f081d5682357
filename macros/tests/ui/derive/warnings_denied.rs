// The loader's warnings reach the user as compiler warnings at the file's path (here denied,
// so that the expected output shows them): an inertia no rigid body has, and a `<mimic>` on a
// fixed joint.
#![deny(deprecated)]

use articulated::Chain;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/odd_inertia.urdf", outputs = [mass_matrix])]
struct Arm;

fn main() {}
