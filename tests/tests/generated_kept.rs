//! `mass_matrix_update` (`M(q)` into a `KeptMassMatrix`, only the entries that can be non-zero
//! written) and `mass_matrix_lower` (its entries on and below the diagonal, into a
//! `KeptMassMatrixLower`) against the interpreted reference, on shipped models of every kind: a
//! serial arm, a branching tree, spherical joints, a free-floating humanoid whose `M` is half
//! zeros.
//!
//! One kept matrix per model goes through all of its states, the first of them far from the
//! others (every coordinate moved by 1), so an entry the update failed to write would keep an
//! earlier state's value and fail the comparison; the states come from
//! `articulated_dynamics::random::random_state`. Tolerance as for `M` everywhere: 1e-12 relative to
//! the largest entry.

mod common;

use std::path::Path;

use articulated::nalgebra::{Cholesky, SVector};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::rel_err;

#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain", outputs = [mass_matrix_update, mass_matrix_lower])]
struct Arm7;

#[derive(articulated::Chain)]
#[chain(file = "../models/tree.chain", outputs = [mass_matrix_update, mass_matrix_lower])]
struct Tree;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain", outputs = [mass_matrix_update, mass_matrix_lower])]
struct TwoLink;

#[derive(articulated::Chain)]
#[chain(file = "../models/humanoid.chain", outputs = [mass_matrix_update, mass_matrix_lower])]
struct Humanoid;

/// Updates one kept matrix of chain `C` (model file `path`) through `cases` random states, and
/// one kept lower triangle, and returns the worst relative errors against the reference's `M`:
/// of the whole update, and of the lower one against the reference's lower triangle (zeros above
/// the diagonal, which a store there would change).
fn worst_error<C, const NQ: usize, const NV: usize>(path: &str, cases: u64) -> (f64, f64)
where
    C: MassMatrixUpdate<f64, NQ, NV> + MassMatrixLower<f64, NQ, NV>,
{
    let model = load_model(Path::new(path), false).unwrap_or_else(|e| panic!("{e}"));
    let r = Reference::new(&model).unwrap();
    let mut kept = KeptMassMatrix::<C, f64, NV>::new();
    let mut lower = KeptMassMatrixLower::<C, f64, NV>::new();
    let (mut worst, mut worst_lower) = (0.0f64, 0.0f64);
    for seed in 0..cases {
        let (q, _, _) = random_state(&model, seed);
        if seed == 0 {
            // Far from every later state: its entries must all be overwritten.
            let far = SVector::<f64, NQ>::from_column_slice(&q).add_scalar(1.0);
            C::mass_matrix_update(&far, &mut kept);
            C::mass_matrix_lower(&far, &mut lower);
        }
        let qs = SVector::from_column_slice(&q);
        C::mass_matrix_update(&qs, &mut kept);
        C::mass_matrix_lower(&qs, &mut lower);
        let want = r.mass_matrix(&q).expect("reference mass matrix");
        // Both column-major.
        worst = worst.max(rel_err(kept.as_slice(), want.as_slice()));
        worst_lower = worst_lower.max(rel_err(lower.as_slice(), want.lower_triangle().as_slice()));
    }
    (worst, worst_lower)
}

#[test]
fn the_update_leaves_the_whole_mass_matrix() {
    let errors = [
        (
            "arm7",
            worst_error::<Arm7, 7, 7>("../models/arm7.chain", 32),
        ),
        (
            "tree",
            worst_error::<Tree, { Tree::NQ }, { Tree::NV }>("../models/tree.chain", 32),
        ),
        (
            "two_link",
            worst_error::<TwoLink, { TwoLink::NQ }, { TwoLink::NV }>(
                "../models/two_link.chain",
                32,
            ),
        ),
        (
            "humanoid",
            worst_error::<Humanoid, { Humanoid::NQ }, { Humanoid::NV }>(
                "../models/humanoid.chain",
                16,
            ),
        ),
    ];
    for (name, (e, lower)) in errors {
        assert!(e <= 1e-12, "{name}: M into a kept matrix off by {e:e}");
        assert!(
            lower <= 1e-12,
            "{name}: M's lower triangle off by {lower:e}"
        );
    }
}

/// A kept matrix starts at zero and is only read: the humanoid's entries that no update writes
/// (zero for every `q`: a leg's coordinates against an arm's) stay exactly zero, and the others
/// are not all zero, so the test above compares something.
#[test]
fn the_zeros_stay_and_the_rest_is_written() {
    let model = load_model(Path::new("../models/humanoid.chain"), false).unwrap();
    let (q, _, _) = random_state(&model, 7);
    let mut kept = KeptMassMatrix::<Humanoid, f64, { Humanoid::NV }>::default();
    Humanoid::mass_matrix_update(&SVector::from_column_slice(&q), &mut kept);
    let zeros = kept.iter().filter(|x| **x == 0.0).count();
    // 700 of the 1,369 entries of this humanoid's M are zero for every q.
    assert!((600..1369 - 37).contains(&zeros), "{zeros} zero entries");
    let want = Reference::new(&model).unwrap().mass_matrix(&q).unwrap();
    for (k, (x, w)) in kept.iter().zip(want.iter()).enumerate() {
        if *x == 0.0 {
            assert!(
                w.abs() < 1e-14,
                "entry {k} left at zero, the reference has {w}"
            );
        }
    }
}

/// The lower triangle is what nalgebra's Cholesky reads: solving with it gives `x` with
/// `M·x = b` for the reference's `M`, and `symmetric()` is the reference's `M`.
#[test]
fn the_lower_triangle_solves_with_cholesky() {
    let model = load_model(Path::new("../models/humanoid.chain"), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let mut lower = KeptMassMatrixLower::<Humanoid, f64, { Humanoid::NV }>::new();
    for seed in 0..8 {
        let (q, v, _) = random_state(&model, seed);
        Humanoid::mass_matrix_lower(&SVector::from_column_slice(&q), &mut lower);
        let want = r.mass_matrix(&q).unwrap();
        let whole = lower.symmetric();
        assert!(
            rel_err(whole.as_slice(), want.as_slice()) <= 1e-12,
            "seed {seed}"
        );
        let b = SVector::<f64, { Humanoid::NV }>::from_column_slice(&v);
        let x = Cholesky::new(*lower)
            .expect("M is positive definite")
            .solve(&b);
        let residual = (&want * x - b).norm() / b.norm();
        assert!(
            residual <= 1e-10,
            "seed {seed}: M·x − b off by {residual:e}"
        );
    }
}

#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = f32,
    outputs = [mass_matrix_update, mass_matrix_lower]
)]
struct TwoLinkF32;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = generic,
    outputs = [mass_matrix_update, mass_matrix_lower]
)]
struct TwoLinkGeneric;

/// Both updates in `f32` (to 1e-4 relative, as every `f32` output) and generic over `f64` (to
/// 1e-12), against the `f64` reference on inputs exactly representable in `f32`.
#[test]
fn the_update_in_every_scalar() {
    let model = load_model(Path::new("../models/two_link.chain"), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let mut kept32 = KeptMassMatrix::<TwoLinkF32, f32, 6>::new();
    let mut kept64 = KeptMassMatrix::<TwoLinkGeneric, f64, 6>::new();
    let mut lower32 = KeptMassMatrixLower::<TwoLinkF32, f32, 6>::new();
    let mut lower64 = KeptMassMatrixLower::<TwoLinkGeneric, f64, 6>::new();
    let (mut worst32, mut worst64) = (0.0f64, 0.0f64);
    for seed in 0..32 {
        let (q, _, _) = random_state(&model, seed);
        let qf = SVector::<f32, 6>::from_iterator(q.iter().map(|&x| x as f32));
        let qd = qf.map(f64::from);
        let want = r.mass_matrix(qd.as_slice()).unwrap();
        TwoLinkF32::mass_matrix_update(&qf, &mut kept32);
        <TwoLinkGeneric as MassMatrixUpdate<f64, 6, 6>>::mass_matrix_update(&qd, &mut kept64);
        TwoLinkF32::mass_matrix_lower(&qf, &mut lower32);
        <TwoLinkGeneric as MassMatrixLower<f64, 6, 6>>::mass_matrix_lower(&qd, &mut lower64);
        let got32: Vec<f64> = kept32.iter().map(|&x| f64::from(x)).collect();
        let lower_got32: Vec<f64> = lower32.iter().map(|&x| f64::from(x)).collect();
        let want_lower = want.lower_triangle();
        worst32 = worst32
            .max(rel_err(&got32, want.as_slice()))
            .max(rel_err(&lower_got32, want_lower.as_slice()));
        worst64 = worst64
            .max(rel_err(kept64.as_slice(), want.as_slice()))
            .max(rel_err(lower64.as_slice(), want_lower.as_slice()));
    }
    assert!(worst32 <= 1e-4, "f32: {worst32:e}");
    assert!(worst64 <= 1e-12, "generic over f64: {worst64:e}");
}
