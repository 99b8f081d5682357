use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/no_such_file.chain")]
struct Arm;

fn main() {}
