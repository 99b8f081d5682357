//! Code generated for a scene only (issue 12): joints locked, a sub-tree kept, quasi-static
//! motion. Each against the reference of the **full** model: with the locked coordinates held at
//! their values (zero velocity and acceleration), and for quasi-static motion with `v = 0`; and
//! each with fewer operations than the full model's.

mod common;

use std::path::Path;

use articulated::nalgebra::{DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::Rng;
use common::rel_err;

/// The arm with every output the study measures.
#[derive(Chain)]
#[chain(
    file = "../models/arm7.chain",
    outputs = [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics]
)]
struct Arm7Full;

/// The arm with its wrist (`j5`, `j6`, `j7`) locked.
#[derive(Chain)]
#[chain(
    file = "../models/arm7.chain",
    lock = [j5(0.4), j6(-0.7), j7(1.1)],
    outputs = [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics]
)]
struct Arm7Locked;

/// Only the first three links move; the rest rides on `link3` at neutral.
#[derive(Chain)]
#[chain(
    file = "../models/arm7.chain",
    keep = [link1, link2, link3],
    outputs = [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics]
)]
struct Arm7Shoulder;

/// The whole arm, quasi-static.
#[derive(Chain)]
#[chain(
    file = "../models/arm7.chain",
    quasi_static,
    outputs = [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics]
)]
struct Arm7QuasiStatic;

fn arm7() -> Reference {
    let model = load_model(Path::new("../models/arm7.chain"), false).unwrap();
    Reference::new(&model).unwrap()
}

fn random(rng: &mut Rng, n: usize, r: f64) -> Vec<f64> {
    (0..n).map(|_| rng.symmetric(r)).collect()
}

/// The full arm's `q` (or `v`, `a` with `held` zeros) from the first `n` coordinates and the
/// held values of the rest.
fn full(first: &[f64], held: &[f64]) -> Vec<f64> {
    first.iter().chain(held).copied().collect()
}

fn block(m: &DMatrix<f64>, n: usize) -> Vec<f64> {
    let mut out = Vec::new();
    for r in 0..n {
        for c in 0..n {
            out.push(m[(r, c)]);
        }
    }
    out
}

fn rows<const N: usize>(m: &SMatrix<f64, N, N>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

/// A reduced arm with `N` coordinates against the full one with the rest held at `held`.
fn check_reduced<C, const N: usize>(held: &[f64])
where
    C: MassMatrix<f64, N, N>
        + Bias<f64, N, N>
        + Gravity<f64, N, N>
        + InverseDynamics<f64, N, N>
        + ForwardDynamics<f64, N, N>,
{
    let reference = arm7();
    let mut rng = Rng::new(11);
    let zeros = vec![0.0; held.len()];
    for _ in 0..20 {
        let (q, v, a) = (
            random(&mut rng, N, 2.0),
            random(&mut rng, N, 1.5),
            random(&mut rng, N, 3.0),
        );
        let (qf, vf, af) = (full(&q, held), full(&v, &zeros), full(&a, &zeros));
        let (qs, vs, as_) = (
            SVector::<f64, N>::from_column_slice(&q),
            SVector::<f64, N>::from_column_slice(&v),
            SVector::<f64, N>::from_column_slice(&a),
        );
        let m = block(&reference.mass_matrix(&qf).unwrap(), N);
        assert!(rel_err(&rows(&C::mass_matrix(&qs)), &m) < 1e-13, "M");
        let tau = reference.inverse_dynamics(&qf, &vf, &af).unwrap();
        let tau: Vec<f64> = tau.as_slice()[..N].to_vec();
        let ours = C::inverse_dynamics(&qs, &vs, &as_);
        assert!(rel_err(ours.as_slice(), &tau) < 1e-13, "τ");
        let bias = reference.bias(&qf, &vf).unwrap();
        assert!(
            rel_err(C::bias(&qs, &vs).as_slice(), &bias.as_slice()[..N]) < 1e-13,
            "bias"
        );
        let g = reference.gravity(&qf).unwrap();
        assert!(
            rel_err(C::gravity(&qs).as_slice(), &g.as_slice()[..N]) < 1e-13,
            "gravity"
        );
        // With the held coordinates still, the reduced forward dynamics undoes τ.
        let taus = SVector::<f64, N>::from_column_slice(&tau);
        let qdd = C::forward_dynamics(&qs, &vs, &taus).unwrap();
        assert!(rel_err(qdd.as_slice(), &a) < 1e-10, "q̈: {qdd} vs {a:?}");
    }
}

#[test]
fn locked_wrist_is_the_arm_with_the_wrist_held() {
    check_reduced::<Arm7Locked, 4>(&[0.4, -0.7, 1.1]);
}

#[test]
fn a_sub_tree_is_the_arm_with_the_rest_held_at_neutral() {
    check_reduced::<Arm7Shoulder, 3>(&[0.0; 4]);
}

#[test]
fn quasi_static_drops_the_velocity_terms() {
    let reference = arm7();
    let mut rng = Rng::new(5);
    let zero = vec![0.0; 7];
    for _ in 0..20 {
        let (q, v, a) = (
            random(&mut rng, 7, 2.0),
            random(&mut rng, 7, 1.5),
            random(&mut rng, 7, 3.0),
        );
        let (qs, vs, as_) = (
            SVector::<f64, 7>::from_column_slice(&q),
            SVector::<f64, 7>::from_column_slice(&v),
            SVector::<f64, 7>::from_column_slice(&a),
        );
        assert_eq!(Arm7QuasiStatic::bias(&qs, &vs), SVector::<f64, 7>::zeros());
        let tau = reference.inverse_dynamics(&q, &zero, &a).unwrap();
        let ours = Arm7QuasiStatic::inverse_dynamics(&qs, &vs, &as_);
        assert!(rel_err(ours.as_slice(), tau.as_slice()) < 1e-13);
        // The approximation is real: the full arm's τ differs by the bias.
        let full = Arm7Full::inverse_dynamics(&qs, &vs, &as_);
        assert!(rel_err(ours.as_slice(), full.as_slice()) > 1e-6);
        let taus = SVector::<f64, 7>::from_column_slice(tau.as_slice());
        let qdd = Arm7QuasiStatic::forward_dynamics(&qs, &vs, &taus).unwrap();
        assert!(rel_err(qdd.as_slice(), &a) < 1e-10);
    }
}

/// Pruning pays: every output of every scene costs at least a third fewer operations than the
/// full arm's (and the quasi-static bias none at all).
#[test]
fn each_scene_costs_fewer_operations() {
    let full = [
        Arm7Full::MASS_MATRIX_OPS.total(),
        Arm7Full::INVERSE_DYNAMICS_OPS.total(),
        Arm7Full::FORWARD_DYNAMICS_OPS.total(),
    ];
    for (name, scene) in [
        (
            "locked",
            [
                Arm7Locked::MASS_MATRIX_OPS.total(),
                Arm7Locked::INVERSE_DYNAMICS_OPS.total(),
                Arm7Locked::FORWARD_DYNAMICS_OPS.total(),
            ],
        ),
        (
            "sub-tree",
            [
                Arm7Shoulder::MASS_MATRIX_OPS.total(),
                Arm7Shoulder::INVERSE_DYNAMICS_OPS.total(),
                Arm7Shoulder::FORWARD_DYNAMICS_OPS.total(),
            ],
        ),
    ] {
        for (s, f) in scene.iter().zip(&full) {
            assert!(3 * s < 2 * *f, "{name}: {scene:?} vs {full:?}");
        }
    }
    assert!(
        Arm7QuasiStatic::INVERSE_DYNAMICS_OPS.total() * 3
            < Arm7Full::INVERSE_DYNAMICS_OPS.total() * 2
    );
    assert_eq!(Arm7QuasiStatic::BIAS_OPS.total(), 0);
}
