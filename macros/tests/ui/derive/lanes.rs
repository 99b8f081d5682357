// Lanes a scalar has no vector of: the error is at the number, with the counts that are.
use articulated::Chain;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", lanes = 3)]
struct NotACount;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", lanes = 16)]
struct NotF64;

#[derive(Chain)]
#[chain(file = "tests/ui/fixtures/pendulum.chain", scalar = generic, lanes = 4)]
struct Generic;

fn main() {}
