// Options given in `#[chain(…)]` that do not go with the file's model are refused by the check
// stage at the keys that asked for them, every one at once: bottom-up wrenches on a branching
// tree at the output's name, `accuracy = robust` with a mimic joint at `robust`.
#[derive(articulated::Chain)]
#[chain(
    file = "tests/ui/fixtures/hub.chain",
    outputs = [forward_dynamics, joint_wrenches_bottom_up],
    accuracy = robust
)]
pub struct Hub;

fn main() {
    let _ = Hub::NV;
}
