// A path written from above the crate's directory (a workspace's root, say): the file is found
// there, and the error gives the path that reaches it from the crate. (ui.rs puts the file one
// directory above the crate these cases build in.)
use articulated::Chain;

#[derive(Chain)]
#[chain(file = "shared_models/pendulum.chain")]
struct Arm;

fn main() {}
