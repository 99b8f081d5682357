use articulated::Chain;

#[derive(Chain)]
#[chain(urdf = "tests/ui/fixtures/pendulum.urdf", outputs = [mass_matrix, mas_matrix, energy])]
struct Arm;

fn main() {
    let _ = Arm::NQ;
}
