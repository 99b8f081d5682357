use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.urdf")]
struct Arm;

fn main() {}
