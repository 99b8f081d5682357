//! The two-link system (`models/two_link.chain`) generated for `f32` and for a generic scalar,
//! against the `f64` reference of the same file; and a golden snapshot of the emitted code.
//!
//! The snapshot (`tests/snapshots/generated_scalar__two_link_emitted_code.snap`) makes every
//! change in emitted code visible in review. After an intended change to the generator:
//! `INSTA_UPDATE=always cargo test -p articulated-tests --test generated_scalar` rewrites it (or
//! `cargo insta review` with cargo-insta installed); commit the new file with the change.

mod common;

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::{check_chain, rel_err};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

articulated::chain! {
    /// `models/two_link.chain` in `f32`.
    chain TwoLinkF32 {
        scalar: f32;
        gravity: [0.0, 0.0, -9.81];
        body legs { mass: 22.0, com: [0.0, 0.0, 0.54], inertia: diag(1.46, 1.29, 0.24) }
        body trunk { mass: 50.9, com: [0.0, 0.0, 0.32], inertia: diag(3.2, 2.8, 0.7) }
        joint ankle: spherical(xyz) { parent: world, child: legs }
        joint hip: spherical(xyz) { parent: legs, child: trunk, xyz: [0.0, 0.0, 0.86] }
    }
}

articulated::chain! {
    /// `models/two_link.chain` for any `T: RealField + Copy`.
    chain TwoLinkGeneric {
        scalar: generic;
        gravity: [0.0, 0.0, -9.81];
        body legs { mass: 22.0, com: [0.0, 0.0, 0.54], inertia: diag(1.46, 1.29, 0.24) }
        body trunk { mass: 50.9, com: [0.0, 0.0, 0.32], inertia: diag(3.2, 2.8, 0.7) }
        joint ankle: spherical(xyz) { parent: world, child: legs }
        joint hip: spherical(xyz) { parent: legs, child: trunk, xyz: [0.0, 0.0, 0.86] }
    }
}

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain")]
struct TwoLinkF64;

fn two_link() -> articulated::model::Model {
    load_model(Path::new(articulated_models::TWO_LINK.chain), false).unwrap()
}

fn f32s<const N: usize>(x: &[f64]) -> SVector<f32, N> {
    SVector::<f32, N>::from_iterator(x.iter().map(|&v| v as f32))
}

fn f64s(x: &[f32]) -> Vec<f64> {
    x.iter().map(|&v| f64::from(v)).collect()
}

/// The f32 chain against the f64 reference: worst relative error per output, over random states
/// whose inputs are exactly representable in f32 (rounded first, then given to both), so the
/// error measured is the generated code's own.
///
/// Bound 1e-4: f32's unit roundoff is 6e-8; each output is a few hundred operations deep
/// (a few dozen on any path from an input) and the sines and cosines of angles up to π carry
/// their own ~1e-7. M, bias, gravity and τ measured ≤ 2e-6, so 1e-4 leaves margin without hiding a
/// wrong formula (which is off by O(1)). Forward dynamics multiplies the backward error by κ(M)
/// (up to ~5e3 on these states): it is held to 1e-4·max(1, κ/100) = 8·κ·ε_f32 for κ > 100
/// (measured ≤ ~1.2e-7·κ).
#[test]
fn f32_two_link_against_the_f64_reference() {
    let model = two_link();
    let r = Reference::new(&model).unwrap();
    let mut runner = TestRunner::new(Config {
        cases: 256,
        failure_persistence: None,
        ..Config::default()
    });
    let worst = std::cell::RefCell::new([0.0f64; 5]);
    let result = runner.run(&any::<u64>(), |seed| {
        let (q, v, a) = random_state(&model, seed);
        let (qf, vf, af) = (f32s::<6>(&q), f32s::<6>(&v), f32s::<6>(&a));
        let (q, v, a) = (
            f64s(qf.as_slice()),
            f64s(vf.as_slice()),
            f64s(af.as_slice()),
        );
        let m_ref = r.mass_matrix(&q).unwrap();
        let tau_ref = r.inverse_dynamics(&q, &v, &a).unwrap();
        let tauf = f32s::<6>(tau_ref.as_slice());
        let tau_in = f64s(tauf.as_slice());
        let qdd_ref = r.forward_dynamics(&q, &v, &tau_in).unwrap();
        let kappa = common::condition(&m_ref);
        let qdd = TwoLinkF32::forward_dynamics(&qf, &vf, &tauf)
            .map_err(|e| TestCaseError::fail(format!("f32 forward dynamics refused: {e}")))?;
        let e = [
            rel_err(
                &f64s(TwoLinkF32::mass_matrix(&qf).as_slice()),
                m_ref.as_slice(),
            ),
            rel_err(
                &f64s(TwoLinkF32::bias(&qf, &vf).as_slice()),
                r.bias(&q, &v).unwrap().as_slice(),
            ),
            rel_err(
                &f64s(TwoLinkF32::gravity(&qf).as_slice()),
                r.gravity(&q).unwrap().as_slice(),
            ),
            rel_err(
                &f64s(TwoLinkF32::inverse_dynamics(&qf, &vf, &af).as_slice()),
                tau_ref.as_slice(),
            ),
            rel_err(&f64s(qdd.as_slice()), qdd_ref.as_slice()) / (kappa / 1e2).max(1.0),
        ];
        let mut w = worst.borrow_mut();
        for (w, e) in w.iter_mut().zip(e) {
            *w = if e.is_nan() { f64::INFINITY } else { w.max(e) };
        }
        match e.iter().position(|e| e.is_nan() || *e > 1e-4) {
            Some(k) => Err(TestCaseError::fail(format!(
                "output {k}: {:e} > 1e-4 (κ = {kappa:.1e}) at q = {q:?}",
                e[k]
            ))),
            None => Ok(()),
        }
    });
    let w = worst.into_inner();
    println!(
        "TwoLinkF32 vs f64 reference (256 states): mass_matrix={:.1e} bias={:.1e} gravity={:.1e} \
         inverse_dynamics={:.1e} forward_dynamics={:.1e} (the last divided by max(1, κ/100))",
        w[0], w[1], w[2], w[3], w[4]
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The generic chain instantiated with f64: against the reference (1e-12, `generated_common`)
/// and equal to the f64 chain of the same file to 1e-14 (the same expressions, in
/// `nalgebra::convert`ed constants); forward dynamics to 1e-14·κ(M).
#[test]
fn generic_two_link_with_f64() {
    let model = two_link();
    let r = Reference::new(&model).unwrap();
    check_chain::<TwoLinkGeneric, 6, 6>("TwoLinkGeneric<f64>", &r, &(), 64, |s| {
        random_state(&model, s)
    });
    let mut worst = [0.0f64; 5];
    for seed in 0..64 {
        let (q, v, a) = random_state(&model, seed);
        let q = SVector::<f64, 6>::from_column_slice(&q);
        let v = SVector::<f64, 6>::from_column_slice(&v);
        let a = SVector::<f64, 6>::from_column_slice(&a);
        let tau = TwoLinkF64::inverse_dynamics(&q, &v, &a);
        let pairs = [
            (
                TwoLinkGeneric::mass_matrix(&q).as_slice().to_vec(),
                TwoLinkF64::mass_matrix(&q).as_slice().to_vec(),
            ),
            (
                TwoLinkGeneric::bias(&q, &v).as_slice().to_vec(),
                TwoLinkF64::bias(&q, &v).as_slice().to_vec(),
            ),
            (
                TwoLinkGeneric::gravity(&q).as_slice().to_vec(),
                TwoLinkF64::gravity(&q).as_slice().to_vec(),
            ),
            (
                TwoLinkGeneric::inverse_dynamics(&q, &v, &a)
                    .as_slice()
                    .to_vec(),
                tau.as_slice().to_vec(),
            ),
            (
                TwoLinkGeneric::forward_dynamics(&q, &v, &tau)
                    .unwrap()
                    .as_slice()
                    .to_vec(),
                TwoLinkF64::forward_dynamics(&q, &v, &tau)
                    .unwrap()
                    .as_slice()
                    .to_vec(),
            ),
        ];
        let kappa = common::condition(&r.mass_matrix(q.as_slice()).unwrap());
        for (k, (g, f)) in pairs.iter().enumerate() {
            let e = rel_err(g, f);
            // Forward dynamics amplifies a last-bit difference (the generic code's sin/cos go
            // through `RealField`, the f64 code's through libm) by up to κ(M).
            let e = if k == 4 { e / kappa.max(1.0) } else { e };
            worst[k] = worst[k].max(if e.is_nan() { f64::INFINITY } else { e });
        }
    }
    println!(
        "TwoLinkGeneric<f64> vs TwoLinkF64: mass_matrix={:.1e} bias={:.1e} gravity={:.1e} \
         inverse_dynamics={:.1e} forward_dynamics/κ={:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
    for (k, w) in worst.iter().enumerate() {
        assert!(*w <= 1e-14, "generic vs f64 differ by {w:e} (output {k})");
    }
}

/// The emitted code of the two-link, as `articulated expand models/two_link.chain` prints it.
#[test]
fn two_link_emitted_code() {
    let chain =
        articulated_codegen::load::load(Path::new(articulated_models::TWO_LINK.chain), false)
            .unwrap();
    let code = articulated_codegen::generate::generate_file(
        &chain.model,
        &chain.options,
        "models/two_link.chain",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    insta::assert_snapshot!(code);
}

/// The quantities of the whole system of `models/two_link.chain` in `f32`.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = f32,
    outputs = [
        center_of_mass, center_of_mass_velocity, center_of_mass_jacobian, centroidal_momentum,
        centroidal_momentum_matrix, kinetic_energy, potential_energy, coriolis_matrix
    ]
)]
struct TwoLinkWholeF32;

/// The quantities of the whole system of `models/two_link.chain` for any scalar.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = generic,
    outputs = [
        center_of_mass, center_of_mass_velocity, center_of_mass_jacobian, centroidal_momentum,
        centroidal_momentum_matrix, kinetic_energy, potential_energy, coriolis_matrix
    ]
)]
struct TwoLinkWholeGeneric;

/// The whole-system outputs in `f32` (to 1e-4, as the basic ones above) and generic over `f64`
/// (to 1e-12) against the `f64` reference, on inputs exactly representable in `f32`.
#[test]
fn whole_body_outputs_in_every_scalar() {
    let model = two_link();
    let r = Reference::new(&model).unwrap();
    let (mut worst32, mut worst64) = (0.0f64, 0.0f64);
    for seed in 0..64 {
        let (q, v, _) = random_state(&model, seed);
        let (qf, vf) = (f32s::<6>(&q), f32s::<6>(&v));
        let (q, v) = (f64s(qf.as_slice()), f64s(vf.as_slice()));
        let (qd, vd) = (
            SVector::<f64, 6>::from_column_slice(&q),
            SVector::<f64, 6>::from_column_slice(&v),
        );
        let energy = |ours: f64, theirs: f64| (ours - theirs).abs() / theirs.abs().max(1.0);
        let want = [
            r.center_of_mass(&q).unwrap().as_slice().to_vec(),
            r.center_of_mass_velocity(&q, &v)
                .unwrap()
                .as_slice()
                .to_vec(),
            r.center_of_mass_jacobian(&q).unwrap().as_slice().to_vec(),
            r.centroidal_momentum(&q, &v).unwrap().as_slice().to_vec(),
            r.centroidal_momentum_matrix(&q)
                .unwrap()
                .as_slice()
                .to_vec(),
            r.coriolis_matrix(&q, &v).unwrap().as_slice().to_vec(),
        ];
        let (ke, pe) = (
            r.kinetic_energy(&q, &v).unwrap(),
            r.potential_energy(&q).unwrap(),
        );
        let f32_values = [
            f64s(TwoLinkWholeF32::center_of_mass(&qf).as_slice()),
            f64s(TwoLinkWholeF32::center_of_mass_velocity(&qf, &vf).as_slice()),
            f64s(TwoLinkWholeF32::center_of_mass_jacobian(&qf).as_slice()),
            f64s(TwoLinkWholeF32::centroidal_momentum(&qf, &vf).as_slice()),
            f64s(TwoLinkWholeF32::centroidal_momentum_matrix(&qf).as_slice()),
            f64s(TwoLinkWholeF32::coriolis_matrix(&qf, &vf).as_slice()),
        ];
        let f64_values = [
            <TwoLinkWholeGeneric as CenterOfMass<f64, 6, 6>>::center_of_mass(&qd).as_slice().to_vec(),
            <TwoLinkWholeGeneric as CenterOfMassVelocity<f64, 6, 6>>::center_of_mass_velocity(&qd, &vd).as_slice().to_vec(),
            <TwoLinkWholeGeneric as CenterOfMassJacobian<f64, 6, 6>>::center_of_mass_jacobian(&qd).as_slice().to_vec(),
            <TwoLinkWholeGeneric as CentroidalMomentum<f64, 6, 6>>::centroidal_momentum(&qd, &vd).as_slice().to_vec(),
            <TwoLinkWholeGeneric as CentroidalMomentumMatrix<f64, 6, 6>>::centroidal_momentum_matrix(&qd).as_slice().to_vec(),
            <TwoLinkWholeGeneric as CoriolisMatrix<f64, 6, 6>>::coriolis_matrix(&qd, &vd).as_slice().to_vec(),
        ];
        for ((w, ours32), ours64) in want.iter().zip(&f32_values).zip(&f64_values) {
            worst32 = worst32.max(rel_err(ours32, w));
            worst64 = worst64.max(rel_err(ours64, w));
        }
        worst32 = worst32
            .max(energy(
                f64::from(TwoLinkWholeF32::kinetic_energy(&qf, &vf)),
                ke,
            ))
            .max(energy(
                f64::from(TwoLinkWholeF32::potential_energy(&qf)),
                pe,
            ));
        worst64 = worst64
            .max(energy(
                <TwoLinkWholeGeneric as KineticEnergy<f64, 6, 6>>::kinetic_energy(&qd, &vd),
                ke,
            ))
            .max(energy(
                <TwoLinkWholeGeneric as PotentialEnergy<f64, 6, 6>>::potential_energy(&qd),
                pe,
            ));
    }
    println!("whole-system outputs: f32 worst {worst32:.1e}, generic f64 worst {worst64:.1e}");
    assert!(worst32 < 1e-4, "f32: {worst32:e}");
    assert!(worst64 < 1e-12, "generic f64: {worst64:e}");
}
