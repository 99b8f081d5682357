// An unknown key whose value is a description's path: the key that reads it.
use articulated::Chain;

#[derive(Chain)]
#[chain(path = "tests/ui/fixtures/pendulum.chain")]
struct Arm;

fn main() {}
