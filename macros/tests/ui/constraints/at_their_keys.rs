// Constraints given in `#[chain(…)]` are judged against the file's model at the attribute's
// tokens: an unknown frame at its name, a malformed loop at its value, a frame that cannot move
// at the contact.
#[derive(articulated::Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", contacts = [bobb: point])]
pub struct Pendulum;

#[derive(articulated::Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", loops = [rod: point(bob)])]
pub struct Looped;

#[derive(articulated::Chain)]
#[chain(urdf = "tests/ui/fixtures/pendulum.urdf", contacts = [base: point])]
pub struct Fixed;

fn main() {}
