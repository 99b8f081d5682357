//! Generated code of every small shipped model (`articulated_models::SMALL`, each from its `.chain` file
//! and from its `.urdf`) against the interpreted reference on random states, and a chain with
//! runtime parameters through the `_with` functions at several parameter values.
//!
//! Tolerances (see `generated_common`): M, bias, gravity and inverse dynamics to 1e-12 relative
//! to the largest entry; forward dynamics to 1e-12 as a residual of the reference's equations of
//! motion and to max(1e-12, 1e-13·κ(M)) against the reference's q̈; forward(inverse(a)) = a on
//! generated code alone to the same κ-aware bound.
//!
//! `cargo test -p articulated-tests --test generated_models -- --nocapture` prints the worst error
//! per model and output.

mod common;

use std::path::Path;

use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::{check_chain, rel_err, Worst};

/// Random states per chain: 10 chains × this many, in well under a second at `opt-level = 1`.
const CASES: u32 = 64;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain")]
struct TwoLinkChain;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/two_link.urdf")]
struct TwoLinkUrdf;

#[derive(articulated::Chain)]
#[chain(file = "../models/inverted_pendulum.chain")]
struct InvertedPendulumChain;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/inverted_pendulum.urdf")]
struct InvertedPendulumUrdf;

#[derive(articulated::Chain)]
#[chain(file = "../models/double_pendulum.chain")]
struct DoublePendulumChain;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/double_pendulum.urdf")]
struct DoublePendulumUrdf;

#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain")]
struct Arm7Chain;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/arm7.urdf")]
struct Arm7Urdf;

#[derive(articulated::Chain)]
#[chain(file = "../models/tree.chain")]
struct TreeChain;
#[derive(articulated::Chain)]
#[chain(urdf = "../models/tree.urdf")]
struct TreeUrdf;

/// Checks the generated chain `$chain` of the model file `$path` (`floating` false).
///
/// The states come from the `.chain` model (`random_state` keeps its Euler angles off gimbal
/// lock); a URDF writes a spherical joint as three revolute joints in the same order, so the
/// same `q` means the same configuration in both.
macro_rules! check_file {
    ($chain:ty, $states_from:expr, $path:expr) => {{
        let path = Path::new($path);
        let model = load_model(path, false).unwrap_or_else(|e| panic!("{e}"));
        let states_model = load_model(Path::new($states_from), false).unwrap();
        let r = Reference::new(&model).unwrap();
        let label = format!(
            "{} ({})",
            <$chain as Chain<f64>>::NAME,
            path.extension().unwrap().to_str().unwrap()
        );
        const NQ: usize = <$chain>::NQ;
        const NV: usize = <$chain>::NV;
        check_chain::<$chain, NQ, NV>(
            &label,
            &r,
            &<$chain as Chain<f64>>::default_params(),
            CASES,
            |seed| random_state(&states_model, seed),
        )
    }};
}

#[test]
fn every_shipped_model_matches_the_reference() {
    let mut checked = Vec::new();
    let mut all = Vec::<Worst>::new();
    for files in articulated_models::SMALL {
        let urdf = files.urdf.expect("every shipped model has a URDF");
        let (c, u) = match files.name {
            "two_link" => (
                check_file!(TwoLinkChain, files.chain, files.chain),
                check_file!(TwoLinkUrdf, files.chain, urdf),
            ),
            "inverted_pendulum" => (
                check_file!(InvertedPendulumChain, files.chain, files.chain),
                check_file!(InvertedPendulumUrdf, files.chain, urdf),
            ),
            "double_pendulum" => (
                check_file!(DoublePendulumChain, files.chain, files.chain),
                check_file!(DoublePendulumUrdf, files.chain, urdf),
            ),
            "arm7" => (
                check_file!(Arm7Chain, files.chain, files.chain),
                check_file!(Arm7Urdf, files.chain, urdf),
            ),
            "tree" => (
                check_file!(TreeChain, files.chain, files.chain),
                check_file!(TreeUrdf, files.chain, urdf),
            ),
            other => panic!("a new shipped model `{other}`: add its generated chains here"),
        };
        all.extend([c, u]);
        checked.push(files.name);
    }
    assert_eq!(checked.len(), articulated_models::SMALL.len());
    // Every state of every model was compared in full (none skipped as singular).
    for w in &all {
        assert_eq!(w.states, CASES as usize);
        assert_eq!(w.singular, 0, "random_state should keep M regular");
    }
}

/// `models/payload.chain` in a generic scalar: its runtime parameters are fields of
/// `PayloadParams<T>`.
#[derive(articulated::Chain)]
#[chain(file = "../models/payload.chain", scalar = generic)]
pub struct Payload;

#[test]
fn runtime_parameters_match_the_reference_with_params() {
    let model =
        load_model(Path::new("../models/payload.chain"), false).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.params.len(), 5);
    let defaults = PayloadParams::<f64>::defaults();
    assert_eq!(
        [
            defaults.payload,
            defaults.reach,
            defaults.payload_izz,
            defaults.upper_length,
            defaults.g
        ]
        .as_slice(),
        model.param_defaults().as_slice()
    );
    let values: [[f64; 5]; 4] = [
        [2.5, 0.3, 0.04, 0.6, -9.81],
        [0.01, 0.3, 0.04, 0.6, -9.81], // a light payload on a heavy arm
        [7.25, -0.15, 0.11, 1.3, -1.62],
        [0.5, 0.05, 0.005, 0.25, 0.0],
    ];
    for v in values {
        let p = PayloadParams {
            payload: v[0],
            reach: v[1],
            payload_izz: v[2],
            upper_length: v[3],
            g: v[4],
        };
        let r = match Reference::with_params(&model, &v) {
            Ok(r) => r,
            Err(e) => panic!("{v:?}: {e}"),
        };
        let label = format!("Payload {v:?}");
        let w =
            check_chain::<Payload, 2, 2>(&label, &r, &p, CASES, |seed| random_state(&model, seed));
        assert_eq!(w.states, CASES as usize);
    }
    // The plain functions use the description's defaults.
    let r = Reference::new(&model).unwrap();
    let q = articulated::nalgebra::SVector::<f64, 2>::new(0.4, -1.1);
    let m = Payload::mass_matrix(&q);
    assert!(
        rel_err(
            m.as_slice(),
            r.mass_matrix(q.as_slice()).unwrap().as_slice()
        ) <= 1e-12
    );
    assert!(
        rel_err(
            Payload::gravity(&q).as_slice(),
            r.gravity(q.as_slice()).unwrap().as_slice()
        ) <= 1e-12
    );
}
