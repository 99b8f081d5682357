use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", scalar = f16)]
struct Arm;

fn main() {
    let _ = Arm::NQ;
}
