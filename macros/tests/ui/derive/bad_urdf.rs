use articulated::Chain;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/missing_link.urdf")]
struct Arm;

fn main() {}
