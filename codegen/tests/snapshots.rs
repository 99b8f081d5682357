//! The emitted code of five small descriptions, as `articulated expand` prints it, locked by
//! snapshots (`insta`), beside the two-link's (`tests/tests/generated_scalar.rs`): every change to
//! generated code shows in review as a diff of these files. Each covers what the others do not:
//! a branching tree (the tree's `M` and its sparse `LᵀDL`), a free quaternion base (the falling
//! cat: the quaternion's normalization and the base's body-frame velocities), `f32` (literals,
//! `mul_add` and the pivot tolerances in that scalar), a derivative output and a declared
//! constraint (the items `constrained_forward_dynamics` needs).
//!
//! After an intended change: `cargo insta review` (or `INSTA_UPDATE=always cargo test -p
//! articulated-codegen --test snapshots`), then read the diff.

use std::path::Path;

use articulated_codegen::generate::generate_file;
use articulated_codegen::load::load;
use articulated_codegen::options::{Output, ScalarKind};

/// `articulated expand MODEL` with the given scalar and outputs (the file's own where `None`).
fn expand(rel: &str, scalar: Option<ScalarKind>, outputs: Option<&[Output]>) -> String {
    let path = format!("{}/../{rel}", env!("CARGO_MANIFEST_DIR"));
    let mut chain = load(Path::new(&path), false).unwrap_or_else(|e| panic!("{e}"));
    if let Some(scalar) = scalar {
        chain.options.scalar = scalar;
    }
    if let Some(outputs) = outputs {
        chain.options.set_outputs(outputs.iter().copied());
    }
    generate_file(&chain.model, &chain.options, rel).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn branching_tree() {
    insta::assert_snapshot!(expand("models/tree.chain", None, None));
}

#[test]
fn free_quaternion_base() {
    let outputs = [Output::MassMatrix, Output::Bias, Output::ForwardDynamics];
    insta::assert_snapshot!(expand("models/falling_cat.chain", None, Some(&outputs)));
}

#[test]
fn f32_forward_dynamics() {
    let outputs = [Output::Gravity, Output::ForwardDynamics];
    insta::assert_snapshot!(expand(
        "models/double_pendulum.chain",
        Some(ScalarKind::F32),
        Some(&outputs)
    ));
}

#[test]
fn inverse_dynamics_derivatives() {
    let outputs = [Output::InverseDynamicsDerivatives];
    insta::assert_snapshot!(expand("models/double_pendulum.chain", None, Some(&outputs)));
}

/// The four-bar with its loop declared (`--loops 'closure:point(tip,ground)'`).
fn four_bar_closed() -> articulated_codegen::options::Description {
    let path = format!("{}/../models/four_bar.chain", env!("CARGO_MANIFEST_DIR"));
    let mut chain = load(Path::new(&path), false).unwrap_or_else(|e| panic!("{e}"));
    chain.options.loops = vec![articulated_codegen::options::Loop {
        name: "closure".into(),
        kind: articulated_codegen::options::ContactKind::Point,
        a: "tip".into(),
        b: "ground".into(),
    }];
    chain
}

/// A declared constraint (the four-bar's loop): `CONTACTS`, `LOOPS`, `CONSTRAINT_ROWS` and
/// `constrained_forward_dynamics` with its docs (`articulated expand` with `--loops`).
#[test]
fn declared_loop() {
    let chain = four_bar_closed();
    let source = "models/four_bar.chain --loops 'closure:point(tip,ground)'";
    insta::assert_snapshot!(
        generate_file(&chain.model, &chain.options, source).unwrap_or_else(|e| panic!("{e}"))
    );
}

/// The constrained derivatives come with `forward_dynamics_derivatives` in `f64`, and not with
/// the other derivative outputs (what the runtime's derivatives read: on a large chain the
/// function is minutes of build) nor in another scalar (it returns the runtime's `f64` type).
#[test]
fn constrained_derivatives_come_with_forward_dynamics_derivatives() {
    let chain = four_bar_closed();
    for (outputs, scalar, expected) in [
        (Output::ForwardDynamicsDerivatives, ScalarKind::F64, true),
        (Output::InverseDynamicsDerivatives, ScalarKind::F64, false),
        (Output::MassMatrixInverse, ScalarKind::F64, false),
        (Output::ForwardDynamicsDerivatives, ScalarKind::F32, false),
    ] {
        let mut options = chain.options.clone();
        options.set_outputs([outputs]);
        options.scalar = scalar;
        let file =
            generate_file(&chain.model, &options, "four_bar").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            file.contains("pub fn constrained_forward_dynamics_derivatives("),
            expected,
            "{outputs:?} in {scalar:?}"
        );
        assert!(
            file.contains("pub fn constrained_forward_dynamics<")
                || file.contains("pub fn constrained_forward_dynamics(")
        );
    }
}

/// Past 20,000 operations traced whole, `forward_dynamics_derivatives` is composed of
/// `forward_dynamics`, `inverse_dynamics_derivatives`, `mass_matrix_inverse` and two products
/// (`generate/composed.rs`): the humanoid's legs (33,647 operations traced) are, arm7 (6,320)
/// is not. A part the description asks for as an output is called, not emitted a second time.
#[test]
fn large_forward_dynamics_derivatives_are_composed() {
    let part = "fn forward_dynamics_derivatives_part_inverse_dynamics_derivatives(";
    let alone = expand(
        "tests/data/legs.chain",
        None,
        Some(&[Output::ForwardDynamicsDerivatives]),
    );
    assert!(alone.contains("::articulated::__private::minus_product("));
    assert!(alone.contains(part));
    let both = expand(
        "tests/data/legs.chain",
        None,
        Some(&[
            Output::InverseDynamicsDerivatives,
            Output::ForwardDynamicsDerivatives,
        ]),
    );
    assert!(both.contains("::articulated::__private::minus_product("));
    assert!(!both.contains(part));
    assert_eq!(
        both.matches("fn inverse_dynamics_derivatives_with(")
            .count(),
        1
    );
    let arm = expand(
        "models/arm7.chain",
        None,
        Some(&[Output::ForwardDynamicsDerivatives]),
    );
    assert!(!arm.contains("minus_product"));
    // With lanes, the batch twin composes the parts in lanes (not the provided state-by-state
    // loop): each part a lane function, the products lane by lane.
    let path = format!("{}/../tests/data/legs.chain", env!("CARGO_MANIFEST_DIR"));
    let mut chain = load(Path::new(&path), false).unwrap_or_else(|e| panic!("{e}"));
    chain
        .options
        .set_outputs([Output::ForwardDynamicsDerivatives]);
    chain.options.lanes = Some(4);
    let lanes = generate_file(&chain.model, &chain.options, "tests/data/legs.chain")
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(lanes.contains("fn forward_dynamics_derivatives_batch_with_each("));
    for part in [
        "fn forward_dynamics_lanes(",
        "fn inverse_dynamics_derivatives_lanes(",
        "fn mass_matrix_inverse_lanes(",
    ] {
        assert!(lanes.contains(part), "{part}");
    }
    assert_eq!(
        lanes
            .matches("::articulated::__private::lanes_minus_product(")
            .count(),
        2
    );
}
