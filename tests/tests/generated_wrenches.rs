//! Generated joint wrenches (Hemami's joint couples and reaction forces) against the reference's
//! `joint_wrenches`, from the free ends down and from the base up, on the shipped models and on
//! random trees, at random states.
//!
//! - Top-down (`joint_wrenches`) against `Reference::joint_wrenches`, to 1e-12 of the largest
//!   wrench entry.
//! - Bottom-up (`joint_wrenches_bottom_up`) from the true base wrench (the reference's wrench at
//!   the root joint) against the same, to 1e-12: the two directions agree, so their difference
//!   on measured data is a consistency check.
//! - A wrong base wrench changes every wrench above it by that error carried up the chain: the
//!   check can fail.

mod common;

use std::path::Path;

use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::{Reference, Wrench};
use articulated_codegen::load::load_model;
use articulated_dynamics::random::{random_model, random_state};
use common::rel_err;

/// Random states per chain.
const CASES: u64 = 40;

#[derive(Chain)]
#[chain(file = "../models/two_link.chain", outputs = [joint_wrenches, joint_wrenches_bottom_up])]
struct TwoLink;

#[derive(Chain)]
#[chain(urdf = "../models/arm7.urdf", outputs = [joint_wrenches, joint_wrenches_bottom_up])]
struct Arm7;

#[derive(Chain)]
#[chain(urdf = "../models/arm7.urdf", floating, outputs = [joint_wrenches, joint_wrenches_bottom_up])]
struct Arm7Floating;

#[derive(Chain)]
#[chain(file = "../models/tree.chain", outputs = [joint_wrenches])]
struct Tree;

#[derive(Chain)]
#[chain(file = "../models/double_pendulum.chain", scalar = f32, outputs = [joint_wrenches])]
struct DoublePendulumF32;

/// The reference's wrenches as the columns of a `6 × NB` matrix, `[n; f]` each.
fn columns(w: &[Wrench]) -> Vec<f64> {
    w.iter()
        .flat_map(|w| w.couple.into_iter().chain(w.force))
        .collect()
}

/// Top-down and bottom-up wrenches of chain `C` against the reference at random states; returns
/// the worst relative errors.
fn check<C, const NQ: usize, const NV: usize, const NB: usize>(
    path: &str,
    floating: bool,
    bottom_up: bool,
) -> (f64, f64)
where
    C: JointWrenches<f64, NQ, NV, NB> + JointWrenchesBottomUp<f64, NQ, NV, NB>,
{
    let model = load_model(Path::new(path), floating).unwrap_or_else(|e| panic!("{e}"));
    let r = Reference::new(&model).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for seed in 0..CASES {
        let (q, v, a) = random_state(&model, seed);
        let want = r.joint_wrenches(&q, &v, &a).unwrap();
        let (qs, vs, as_) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NV>::from_column_slice(&v),
            SVector::<f64, NV>::from_column_slice(&a),
        );
        let down: SMatrix<f64, 6, NB> = C::joint_wrenches(&qs, &vs, &as_);
        let e = rel_err(down.as_slice(), &columns(&want));
        assert!(e < 1e-12, "{path} seed {seed}: top-down off by {e:e}");
        worst.0 = worst.0.max(e);
        if bottom_up {
            let root = &want[0];
            let base = SVector::<f64, 6>::from_iterator(root.couple.into_iter().chain(root.force));
            let up = C::joint_wrenches_bottom_up(&qs, &vs, &as_, &base);
            let e = rel_err(up.as_slice(), &columns(&want));
            assert!(e < 1e-12, "{path} seed {seed}: bottom-up off by {e:e}");
            worst.1 = worst.1.max(e);
            // A base wrench off by one newton along x: the root's wrench shows it, and so does
            // every wrench above it (the error is carried up, never absorbed).
            let mut off = base;
            off[3] += 1.0;
            let shifted = C::joint_wrenches_bottom_up(&qs, &vs, &as_, &off) - up;
            for j in 0..NB {
                let force_error = shifted.fixed_view::<3, 1>(3, j).norm();
                assert!(
                    (force_error - 1.0).abs() < 1e-9,
                    "{path} seed {seed} joint {j}: a 1 N error at the base is {force_error} N here"
                );
            }
        }
    }
    println!(
        "{path}: top-down {:.1e}, bottom-up {:.1e}",
        worst.0, worst.1
    );
    worst
}

#[test]
fn serial_chains_top_down_and_bottom_up() {
    check::<TwoLink, 6, 6, 2>("../models/two_link.chain", false, true);
    check::<Arm7, 7, 7, 7>("../models/arm7.urdf", false, true);
    check::<Arm7Floating, 13, 13, 8>("../models/arm7.urdf", true, true);
}

#[test]
fn a_branching_tree_top_down_and_no_bottom_up() {
    let model = load_model(Path::new("../models/tree.chain"), false).unwrap();
    assert!(!model.is_serial());
    let r = Reference::new(&model).unwrap();
    const NB: usize = Tree::NB;
    for seed in 0..CASES {
        let (q, v, a) = random_state(&model, seed);
        let want = columns(&r.joint_wrenches(&q, &v, &a).unwrap());
        let got = Tree::joint_wrenches(
            &SVector::from_column_slice(&q),
            &SVector::from_column_slice(&v),
            &SVector::from_column_slice(&a),
        );
        let got: &SMatrix<f64, 6, NB> = &got;
        assert!(rel_err(got.as_slice(), &want) < 1e-12, "seed {seed}");
    }
    // Bottom-up is refused, by the reference and by the generator.
    let (q, v, a) = random_state(&model, 0);
    let base = Wrench {
        couple: [0.0; 3],
        force: [0.0; 3],
    };
    assert!(matches!(
        r.joint_wrenches_bottom_up(&q, &v, &a, base),
        Err(articulated::reference::Error::NotSerial)
    ));
    let chain = articulated_codegen::load::load(Path::new("../models/tree.chain"), false).unwrap();
    let mut options = chain.options;
    options.set_outputs([articulated_codegen::options::Output::JointWrenchesBottomUp]);
    let err = articulated_codegen::generate::generate(&chain.model, &options).unwrap_err();
    assert!(err.to_string().contains("needs a serial chain"), "{err}");
}

#[test]
fn the_reference_bottom_up_equals_its_top_down_on_random_serial_chains() {
    let mut serial = 0;
    for seed in 0..200u64 {
        let model = random_model(seed, 1 + (seed as usize % 9));
        if !model.is_serial() {
            continue;
        }
        serial += 1;
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let down = r.joint_wrenches(&q, &v, &a).unwrap();
        let up = r.joint_wrenches_bottom_up(&q, &v, &a, down[0]).unwrap();
        let e = rel_err(&columns(&up), &columns(&down));
        assert!(e < 1e-11, "seed {seed}: {e:e}");
    }
    assert!(
        serial > 20,
        "only {serial} serial chains among the random trees"
    );
}

#[test]
fn f32_wrenches_to_f32_precision() {
    let model = load_model(Path::new("../models/double_pendulum.chain"), false).unwrap();
    let r = Reference::new(&model).unwrap();
    for seed in 0..CASES {
        let (q, v, a) = random_state(&model, seed);
        let want = columns(&r.joint_wrenches(&q, &v, &a).unwrap());
        let f = |x: &[f64]| SVector::<f32, 2>::from_iterator(x.iter().map(|&y| y as f32));
        let got = DoublePendulumF32::joint_wrenches(&f(&q), &f(&v), &f(&a));
        let got: Vec<f64> = got.iter().map(|&x| f64::from(x)).collect();
        assert!(rel_err(&got, &want) < 1e-5, "seed {seed}");
    }
}
