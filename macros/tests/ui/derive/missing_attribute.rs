use articulated::Chain;

#[derive(Chain)]
struct Arm;

fn main() {
    let _ = Arm::NQ;
}
