//! The `articulated` command.
fn main() {}
