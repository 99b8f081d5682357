//! Compile-fail tests of `chain!` and `#[derive(Chain)]`, one directory per kind of failure
//! (as serde's `test_suite/tests/ui`): each case shows its error at the user's token, and no
//! follow-on errors where the code after it uses the type. `pass/` uses generated chains.
//!
//! Update the expected output with `TRYBUILD=overwrite cargo test -p articulated-macros --test
//! ui`, then read the diff.

use std::path::{Path, PathBuf};

/// The directory trybuild builds the cases in: `<target>/tests/trybuild/<crate>`. It is the
/// cases' `CARGO_MANIFEST_DIR`, against which `#[chain(file = …)]` resolves.
fn trybuild_project_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    // The target directory is the nearest ancestor that cargo tagged, or where it keeps what it
    // knows of rustc: a target directory that `cargo package` created first has no tag.
    let target = exe
        .ancestors()
        .find(|d| d.join("CACHEDIR.TAG").exists() || d.join(".rustc_info.json").exists())
        .expect("the test binary is under cargo's target directory");
    target
        .join("tests")
        .join("trybuild")
        .join(env!("CARGO_PKG_NAME"))
}

/// Copies the fixture files to where the cases look for them, as in a user's crate:
/// `tests/ui/fixtures/…` relative to the manifest directory. One more goes one directory above
/// it, `../shared_models/pendulum.chain`, as a workspace's root holds the models its crates
/// read (`derive/file_above_the_crate.rs`).
fn install_fixtures() {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ui/fixtures");
    let project = trybuild_project_dir();
    let to = project.join("tests/ui/fixtures");
    std::fs::create_dir_all(&to).unwrap();
    for entry in std::fs::read_dir(&from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
    }
    let above = project.parent().unwrap().join("shared_models");
    std::fs::create_dir_all(&above).unwrap();
    std::fs::copy(from.join("pendulum.chain"), above.join("pendulum.chain")).unwrap();
}

#[test]
fn ui() {
    install_fixtures();
    let t = trybuild::TestCases::new();
    for kind in [
        "syntax",
        "names",
        "duplicates",
        "tree",
        "numbers",
        "inertia",
        "euler",
        "many",
        "derive",
        "constraints",
    ] {
        t.compile_fail(format!("tests/ui/{kind}/*.rs"));
    }
    t.pass("tests/ui/pass/*.rs");
}
