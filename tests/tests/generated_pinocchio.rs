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

use articulated::nalgebra::{DMatrix, SVector};
use articulated::prelude::*;
use common::{read_json, rel_err, vec_of};
use serde_json::Value as Json;

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

const NAMES: [&str; 5] = ["mass_matrix", "bias", "gravity", "tau", "qdd"];

/// Compares the generated chain `C` with one model's Pinocchio states; returns the failures.
fn compare<C, const NQ: usize, const NV: usize>(label: &str, case: &Json) -> Vec<String>
where
    C: MassMatrix<f64, NQ, NV>
        + Bias<f64, NQ, NV>
        + Gravity<f64, NQ, NV>
        + InverseDynamics<f64, NQ, NV>
        + ForwardDynamics<f64, NQ, NV>,
{
    assert_eq!(case["nq"].as_u64(), Some(NQ as u64), "{label}: nq");
    assert_eq!(case["nv"].as_u64(), Some(NV as u64), "{label}: nv");
    let mut worst = [0.0f64; 5];
    let mut failures = Vec::new();
    let (mut singular, mut states) = (0, 0);
    for s in case["states"].as_array().unwrap() {
        states += 1;
        let q = SVector::<f64, NQ>::from_column_slice(&vec_of(&s["q"]));
        let v = SVector::<f64, NV>::from_column_slice(&vec_of(&s["v"]));
        let a = SVector::<f64, NV>::from_column_slice(&vec_of(&s["a"]));
        let tau = SVector::<f64, NV>::from_column_slice(&vec_of(&s["tau"]));
        let m_theirs: Vec<f64> = s["mass_matrix"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(vec_of)
            .collect();
        let m = C::mass_matrix(&q);
        // Row-major on both sides (M is symmetric, but compare the layout honestly).
        let m_ours: Vec<f64> = (0..NV)
            .flat_map(|i| (0..NV).map(move |j| (i, j)))
            .map(|(i, j)| m[(i, j)])
            .collect();
        let mut e = [
            rel_err(&m_ours, &m_theirs),
            rel_err(C::bias(&q, &v).as_slice(), &vec_of(&s["bias"])),
            rel_err(C::gravity(&q).as_slice(), &vec_of(&s["gravity"])),
            rel_err(
                C::inverse_dynamics(&q, &v, &a).as_slice(),
                &vec_of(&s["tau_out"]),
            ),
            0.0,
        ];
        let qdd_theirs = vec_of(&s["qdd"]);
        let eig = DMatrix::from_row_slice(NV, NV, &m_theirs).symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
            (lo.min(*x), hi.max(x.abs()))
        });
        let fd = C::forward_dynamics(&q, &v, &tau);
        if lo <= 1e-12 * hi || qdd_theirs.iter().any(|x| x.is_nan()) {
            singular += 1;
            if let Ok(qdd) = fd {
                failures.push(format!(
                    "{label}: Pinocchio's M is singular (eigenvalues {lo:e} .. {hi:e}) but \
                     generated forward dynamics returned Ok({:?})",
                    qdd.as_slice()
                ));
            }
        } else {
            e[4] = match fd {
                Ok(qdd) => rel_err(qdd.as_slice(), &qdd_theirs),
                Err(err) => {
                    failures.push(format!("{label}: forward dynamics refused: {err}"));
                    f64::INFINITY
                }
            };
        }
        for (w, x) in worst.iter_mut().zip(e) {
            *w = if x.is_nan() { f64::INFINITY } else { w.max(x) };
        }
    }
    let mut line = format!("{label:<26} states={states}");
    for (name, w) in NAMES.iter().zip(worst) {
        line += &format!(" {name}={w:.1e}");
        if w.is_nan() || w > TOL {
            failures.push(format!("{label}: {name} differs from Pinocchio by {w:e}"));
        }
    }
    if singular > 0 {
        line += &format!(" (M singular at {singular} states: Err required)");
    }
    println!("{line}");
    failures
}

#[test]
fn arm7_generated_matches_pinocchio() {
    let json = read_json("data/pinocchio-arm7.json");
    let arm = &json["models"]["arm7"];
    let mut failures = compare::<Arm7, 7, 7>("arm7 (fixed)", &arm["fixed"]);
    failures.extend(compare::<Arm7Floating, 13, 13>(
        "arm7 (floating)",
        &arm["floating"],
    ));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn shared_models_generated_match_pinocchio() {
    let json = read_json("data/pinocchio/pinocchio-values.json");
    let models = &json["models"];
    assert_eq!(models.as_object().unwrap().len(), 4);
    let mut failures = Vec::new();
    failures.extend(compare::<TwoLinkXyz, 6, 6>(
        "two_link_xyz (fixed)",
        &models["two_link_xyz"]["fixed"],
    ));
    failures.extend(compare::<TwoLinkXyzFloating, 12, 12>(
        "two_link_xyz (floating)",
        &models["two_link_xyz"]["floating"],
    ));
    failures.extend(compare::<Arm6Mixed, 6, 6>(
        "arm6_mixed (fixed)",
        &models["arm6_mixed"]["fixed"],
    ));
    failures.extend(compare::<Arm6MixedFloating, 12, 12>(
        "arm6_mixed (floating)",
        &models["arm6_mixed"]["floating"],
    ));
    failures.extend(compare::<TreeTwoArms, 7, 7>(
        "tree_two_arms (fixed)",
        &models["tree_two_arms"]["fixed"],
    ));
    failures.extend(compare::<DoublePendulum, 2, 2>(
        "double_pendulum (fixed)",
        &models["double_pendulum"]["fixed"],
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
