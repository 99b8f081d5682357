//! A URDF robot on a quaternion free base (`#[chain(urdf = …, floating = quaternion)]`,
//! `--floating=quaternion`): Pinocchio's free flyer, 7 positions and 6 velocities, no gimbal
//! lock. Generated code against the reference of the same import at random states, and the two
//! bases against each other where they describe the same motion.

mod common;

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::{load_model, FloatingBase};
use articulated_dynamics::random::random_state;
use common::rel_err;

#[derive(Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    floating = quaternion,
    outputs = [mass_matrix, gravity, inverse_dynamics, forward_dynamics]
)]
struct Arm7Flyer;

#[test]
fn generated_free_flyer_matches_the_reference() {
    let model = load_model(Path::new("../models/arm7.urdf"), FloatingBase::Quaternion).unwrap();
    assert_eq!((model.nq(), model.nv()), (14, 13));
    let r = Reference::new(&model).unwrap();
    for seed in 0..10 {
        let (q, v, a) = random_state(&model, seed);
        let qs = SVector::<f64, 14>::from_column_slice(&q);
        let (vs, as_) = (
            SVector::<f64, 13>::from_column_slice(&v),
            SVector::<f64, 13>::from_column_slice(&a),
        );
        let m = r.mass_matrix(&q).unwrap();
        assert!(rel_err(Arm7Flyer::mass_matrix(&qs).as_slice(), m.as_slice()) < 1e-12);
        let tau = r.inverse_dynamics(&q, &v, &a).unwrap();
        let ours = Arm7Flyer::inverse_dynamics(&qs, &vs, &as_);
        assert!(rel_err(ours.as_slice(), tau.as_slice()) < 1e-12);
        let taus = SVector::<f64, 13>::from_column_slice(tau.as_slice());
        let qdd = Arm7Flyer::forward_dynamics(&qs, &vs, &taus).unwrap();
        assert!(rel_err(qdd.as_slice(), &a) < 1e-9);
    }
}

/// At the identity orientation and at rest, the free flyer and the Euler base hold the arm up
/// with the same joint couples, and both carry the whole mass on their linear coordinates.
#[test]
fn quaternion_and_euler_bases_agree_at_rest() {
    let path = Path::new("../models/arm7.urdf");
    let flyer = Reference::new(&load_model(path, FloatingBase::Quaternion).unwrap()).unwrap();
    let euler = Reference::new(&load_model(path, true).unwrap()).unwrap();
    let joints = [0.3, -0.5, 0.2, -1.1, 0.4, 0.6, -0.2];
    let mut qf = vec![0.1, -0.2, 0.5, 1.0, 0.0, 0.0, 0.0];
    qf.extend(joints);
    let mut qe = vec![0.1, -0.2, 0.5, 0.0, 0.0, 0.0];
    qe.extend(joints);
    let (gf, ge) = (flyer.gravity(&qf).unwrap(), euler.gravity(&qe).unwrap());
    assert!(rel_err(&gf.as_slice()[6..], &ge.as_slice()[6..]) < 1e-13);
    // The base's linear force: the weight, both ways (world = body axes here).
    assert!(rel_err(&gf.as_slice()[..3], &ge.as_slice()[..3]) < 1e-13);
    let (mf, me) = (
        flyer.mass_matrix(&qf).unwrap(),
        euler.mass_matrix(&qe).unwrap(),
    );
    let total = mf[(0, 0)];
    assert!(total > 0.0 && (total - me[(0, 0)]).abs() < 1e-12 * total);
    assert!(
        (mf[(1, 1)] - total).abs() < 1e-12 * total && (mf[(2, 2)] - total).abs() < 1e-12 * total
    );
}
