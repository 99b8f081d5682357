use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain")]
struct Arm {
    links: usize,
}

fn main() {}
