// `urdf = …` reads a URDF: a `.chain` file given to it gets the key that reads it, and a word
// on `floating`, which a `.chain` file writes as a joint.
use articulated::Chain;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/pendulum.chain", floating)]
struct Arm;

fn main() {}
