//! Shared by the CLI tests: where the repository is, and running the `articulated` binary.

// Each test crate that includes this module uses part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root (the CLI crate's parent), where `models/` and `tests/data/` are.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Runs `articulated <subcommand> <args>` from the repository root; (exit success, stdout,
/// stderr).
pub fn run(subcommand: &str, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_articulated"))
        .arg(subcommand)
        .args(args)
        .current_dir(repo())
        .output()
        .expect("the binary runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
