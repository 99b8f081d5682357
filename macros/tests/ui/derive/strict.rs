// `strict`: every warning of the loader is an error at the file's path, all of them at once.
use articulated::Chain;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/odd_inertia.urdf", strict)]
struct Arm;

fn main() {}
