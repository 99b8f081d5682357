use articulated::Chain;

#[derive(Chain)]
#[chain(path = "tests/ui/fixtures/pendulum.chain")]
struct Arm;

fn main() {}
