//! Generated code of URDF models against Pinocchio 4.1's values (an independent C++ library):
//! the 7-DOF arm (`tests/data/pinocchio-arm7.json`, fixed and floating base, the issue's
//! acceptance criterion) and the four shared models (`tests/data/pinocchio/`), every output to
//! 1e-10 relative to its largest entry. Where Pinocchio's own M is singular (its q̈ is NaN, or M
//! has an eigenvalue ≤ 1e-12 of the largest: a massless free base), generated forward dynamics
//! must return `Err(SingularMassMatrix)`.
//!
//! The larger functions here (arm6_mixed's floating forward dynamics: 5,449 operations) are the
//! regression test for rustc's stack overflow on thousands of nested `let`s with debug info,
//! which the emitter now avoids by binding each level of the graph in one `let` past 1,000
//! statements.
//!
//! `cargo test -p articulated-tests --test generated_pinocchio -- --nocapture` prints the worst
//! errors. Conventions as in `tests/pinocchio.rs` (bias without gravity on both sides, free base
//! = translation then Euler `zyx`, `v = q̇`).

mod common;

use common::{compare_pinocchio, read_json};

/// Relative to the largest entry of each of Pinocchio's values.
const TOL: f64 = 1e-10;

#[derive(articulated::Chain)]
#[chain(urdf = "../models/arm7.urdf")]
struct Arm7;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/arm7.urdf", floating)]
struct Arm7Floating;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/arm6_mixed.urdf")]
struct Arm6Mixed;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/arm6_mixed.urdf", floating)]
struct Arm6MixedFloating;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/two_link_xyz.urdf")]
struct TwoLinkXyz;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/two_link_xyz.urdf", floating)]
struct TwoLinkXyzFloating;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/tree_two_arms.urdf")]
struct TreeTwoArms;
#[derive(articulated::Chain)]
#[chain(urdf = "data/pinocchio/double_pendulum.urdf")]
struct DoublePendulum;

#[test]
fn arm7_generated_matches_pinocchio() {
    let json = read_json("data/pinocchio-arm7.json");
    let arm = &json["models"]["arm7"];
    let mut failures = compare_pinocchio::<Arm7, 7, 7>("arm7 (fixed)", &arm["fixed"], TOL);
    failures.extend(compare_pinocchio::<Arm7Floating, 13, 13>(
        "arm7 (floating)",
        &arm["floating"],
        TOL,
    ));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn shared_models_generated_match_pinocchio() {
    let json = read_json("data/pinocchio/pinocchio-values.json");
    let models = &json["models"];
    assert_eq!(models.as_object().unwrap().len(), 4);
    let mut failures = Vec::new();
    failures.extend(compare_pinocchio::<TwoLinkXyz, 6, 6>(
        "two_link_xyz (fixed)",
        &models["two_link_xyz"]["fixed"],
        TOL,
    ));
    failures.extend(compare_pinocchio::<TwoLinkXyzFloating, 12, 12>(
        "two_link_xyz (floating)",
        &models["two_link_xyz"]["floating"],
        TOL,
    ));
    failures.extend(compare_pinocchio::<Arm6Mixed, 6, 6>(
        "arm6_mixed (fixed)",
        &models["arm6_mixed"]["fixed"],
        TOL,
    ));
    failures.extend(compare_pinocchio::<Arm6MixedFloating, 12, 12>(
        "arm6_mixed (floating)",
        &models["arm6_mixed"]["floating"],
        TOL,
    ));
    failures.extend(compare_pinocchio::<TreeTwoArms, 7, 7>(
        "tree_two_arms (fixed)",
        &models["tree_two_arms"]["fixed"],
        TOL,
    ));
    failures.extend(compare_pinocchio::<DoublePendulum, 2, 2>(
        "double_pendulum (fixed)",
        &models["double_pendulum"]["fixed"],
        TOL,
    ));
    // Every model and base in the data was compared.
    let cases: usize = models
        .as_object()
        .unwrap()
        .values()
        .map(|m| usize::from(m.get("fixed").is_some()) + usize::from(m.get("floating").is_some()))
        .sum();
    assert_eq!(cases, 6, "compare any new model or base here");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
