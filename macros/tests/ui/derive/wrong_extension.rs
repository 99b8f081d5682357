// `file = …` reads a `.chain` file: a URDF given to it gets the key that reads it.
use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.urdf")]
struct Arm;

fn main() {}
