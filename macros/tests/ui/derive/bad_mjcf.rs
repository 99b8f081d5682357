// An MJCF model's error is reported at the file's line, under the path in the attribute.
use articulated::Chain;

#[derive(Chain)]
#[chain(mjcf = "tests/ui/fixtures/bad_class.xml")]
struct Arm;

fn main() {}
