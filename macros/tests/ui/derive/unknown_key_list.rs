// Any other unknown key: every key there is.
use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", fast)]
struct Arm;

fn main() {}
