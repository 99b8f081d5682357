//! The models for scale, generated: the floating-base humanoid (`models/humanoid.chain`, a free
//! quaternion base and 31 joints, 37 velocity coordinates) and the 50-body serial chain
//! (`models/chain50.chain`), against Pinocchio's values (`tests/data/pinocchio-scale.json`,
//! written by `tests/data/make_scale_reference.py`: Pinocchio's free flyer for the humanoid) to
//! 1e-10 relative, and against the interpreted reference on random states to 1e-12 (as every
//! shipped model: `tests/generated_models.rs`). The humanoid also generates
//! `nonlinear_effects` and `mass_matrix_and_nonlinear_effects`, checked against Pinocchio's
//! `nonLinearEffects` and `crba`.
//!
//! Their build is also the check that large generated functions compile in reasonable time:
//! the 50-body chain's mass matrix is tens of thousands of operations in one function
//! (`docs/size.md` has the count).
//!
//! `cargo test -p articulated-tests --test generated_scale -- --nocapture` prints the worst
//! errors.

mod common;

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::{check_chain, compare_pinocchio, read_json, rel_err, rows_of, vec_of, Worst};

/// Relative to the largest entry of each of Pinocchio's values.
const TOL: f64 = 1e-10;

/// Random states per model against the reference.
const CASES: u32 = 16;

#[derive(Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [
        mass_matrix,
        bias,
        gravity,
        inverse_dynamics,
        forward_dynamics,
        nonlinear_effects,
        mass_matrix_and_nonlinear_effects
    ]
)]
struct Humanoid;

#[derive(Chain)]
#[chain(file = "../models/chain50.chain")]
struct Chain50;

#[test]
fn humanoid_and_chain50_match_pinocchio() {
    let json = read_json("data/pinocchio-scale.json");
    let models = &json["models"];
    let mut failures = compare_pinocchio::<Humanoid, 38, 37>(
        "humanoid (free flyer)",
        &models["humanoid"]["free_flyer"],
        TOL,
    );
    failures.extend(compare_pinocchio::<Chain50, 50, 50>(
        "chain50",
        &models["chain50"]["fixed"],
        TOL,
    ));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn humanoid_nonlinear_effects_match_pinocchio() {
    let json = read_json("data/pinocchio-scale.json");
    let states = json["models"]["humanoid"]["free_flyer"]["states"]
        .as_array()
        .unwrap();
    assert!(!states.is_empty());
    for (i, s) in states.iter().enumerate() {
        let q = SVector::<f64, 38>::from_column_slice(&vec_of(&s["q"]));
        let v = SVector::<f64, 37>::from_column_slice(&vec_of(&s["v"]));
        let nle_theirs = vec_of(&s["nonlinear_effects"]);
        let m_theirs = rows_of(&s["mass_matrix"]);
        let nle = Humanoid::nonlinear_effects(&q, &v);
        let (m, nle2) = Humanoid::mass_matrix_and_nonlinear_effects(&q, &v);
        // Pinocchio's M is stored by rows: compare with the column-major slice of Mᵀ.
        for (what, e) in [
            ("nonlinear_effects", rel_err(nle.as_slice(), &nle_theirs)),
            ("(M, nle).1", rel_err(nle2.as_slice(), &nle_theirs)),
            ("(M, nle).0", rel_err(m.transpose().as_slice(), &m_theirs)),
        ] {
            assert!(
                e <= TOL,
                "state {i}: {what} differs from Pinocchio by {e:e}"
            );
        }
    }
}

/// Checks the generated chain `C` of the `.chain` file `path` against the reference.
fn against_reference<C, const NQ: usize, const NV: usize>(path: &str) -> Worst
where
    C: DefaultOutputs<f64, NQ, NV>,
{
    let model = load_model(Path::new(path), false).unwrap_or_else(|e| panic!("{e}"));
    let r = Reference::new(&model).unwrap();
    check_chain::<C, NQ, NV>(
        <C as Chain<f64>>::NAME,
        &r,
        &C::default_params(),
        CASES,
        |seed| random_state(&model, seed),
    )
}

#[test]
fn humanoid_and_chain50_match_the_reference() {
    for w in [
        against_reference::<Humanoid, 38, 37>(articulated_models::HUMANOID.chain),
        against_reference::<Chain50, 50, 50>(articulated_models::CHAIN50.chain),
    ] {
        assert_eq!(w.states, CASES as usize);
        assert_eq!(w.singular, 0, "random_state should keep M regular");
    }
}

/// The emitted mass matrix is cut into basic blocks (`articulated::math::block_boundary`, about
/// every 200 statements in a long function, every 80 in a short one), and no other output is:
/// the cuts measured faster only there (`articulated_codegen`'s `emit::with_boundaries`).
#[test]
fn only_the_mass_matrix_is_cut_into_blocks() {
    use articulated_codegen::options::Output;
    let cuts = |file: &str, output: Output| -> (usize, usize) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(file);
        let mut chain = articulated_codegen::load::load(&path, false).unwrap();
        chain.options.set_outputs([output]);
        let code = articulated_codegen::generate::generate_file(&chain.model, &chain.options, file)
            .unwrap_or_else(|e| panic!("{e}"));
        let body = &code[code.find(&format!("fn {}_with", output.name())).unwrap()..];
        let statements = body.matches(';').count();
        (body.matches("block_boundary()").count(), statements)
    };
    for output in [Output::MassMatrix, Output::MassMatrixUpdate] {
        let (n, statements) = cuts("models/humanoid.chain", output);
        assert!(statements > 3_000, "{statements}");
        // One per 200 statements, give or take the quarter each may move.
        let (low, high) = (statements / 250 - 1, statements / 150);
        assert!((low..=high).contains(&n), "humanoid {output:?}: {n} cuts");
        let (n, statements) = cuts("models/arm7.chain", output);
        let (low, high) = (statements / 100 - 1, statements / 60);
        assert!(
            (low..=high).contains(&n),
            "arm7 {output:?}: {n} cuts in {statements}"
        );
    }
    for output in [
        Output::ForwardDynamics,
        Output::InverseDynamics,
        Output::NonlinearEffects,
    ] {
        assert_eq!(cuts("models/humanoid.chain", output).0, 0, "{output:?}");
    }
}
