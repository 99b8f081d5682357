//! Generated code of seeded random trees (`articulated_dynamics::random::random_model`, written by
//! `tests/build.rs` through `articulated_codegen::Builder`) against the reference on random
//! states from `random_state`, to the tolerances of `generated_common`; the rate of the
//! centroidal momentum also against five-point central differences of the generated
//! `centroidal_momentum` along the motion, to 1e-9.
//!
//! The trees are included below in a module with no `#[allow]`: rustc's and clippy's warnings on
//! the emitted code are errors under `cargo clippy --workspace --all-targets -- -D warnings`.
//!
//! Sizes: 2 to 4 bodies only, for now. rustc 1.95 overflows its stack in LLVM's DWARF emission
//! (`DwarfCompileUnit::createAndAddScopeChildren`, one nested lexical scope per `let`) on a
//! function of roughly 2,600 or more `let` statements compiled with debug info, as the test
//! profile does; macro output escapes it (its statements share the call site's span), a
//! Builder file does not. A 5-body tree's forward dynamics is already ~3,300 statements and a
//! 30-body tree's ~31,000, so larger trees wait for the generator to emit fewer nested scopes.

mod common;

use std::collections::BTreeSet;

use articulated::model::JointKind;
use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_dynamics::random::{random_model, random_state};
use common::batch::same;
use common::{
    centroidal_rate_by_differences, centroidal_rate_errors, check_chain, coriolis_error, rel_err,
    whole_body_errors, WHOLE_BODY_OUTPUTS,
};

/// The generated trees, exactly as the Builder wrote them.
mod trees {
    include!(concat!(env!("OUT_DIR"), "/random_trees.rs"));
}

include!(concat!(env!("OUT_DIR"), "/random_trees_list.rs"));

/// Random states per tree.
const CASES: u32 = 32;

/// The generated joint wrenches against the reference's at random states, to 1e-12 of the
/// largest entry.
fn check_wrenches<C, const NQ: usize, const NV: usize, const NB: usize>(
    label: &str,
    r: &Reference,
    state: impl Fn(u64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
) where
    C: JointWrenches<f64, NQ, NV, NB>,
{
    for seed in 0..u64::from(CASES) {
        let (q, v, a) = state(seed);
        let want: Vec<f64> = r
            .joint_wrenches(&q, &v, &a)
            .unwrap()
            .iter()
            .flat_map(|w| w.couple.into_iter().chain(w.force))
            .collect();
        let got = C::joint_wrenches(
            &SVector::from_column_slice(&q),
            &SVector::from_column_slice(&v),
            &SVector::from_column_slice(&a),
        );
        let e = rel_err(got.as_slice(), &want);
        assert!(
            e < 1e-12,
            "{label} seed {seed}: joint wrenches off by {e:e}"
        );
    }
}

/// The generated centre of mass, momenta and energies against the reference's at random
/// states, to 1e-12 (relative, see `common::whole_body_errors`).
fn check_whole_body<C, const NQ: usize, const NV: usize>(
    label: &str,
    r: &Reference,
    state: impl Fn(u64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
) where
    C: WholeBodyOutputs<f64, NQ, NV>,
{
    let mut worst = [0.0f64; 7];
    // The rate and the drift against the reference, the rate against differences of `h_G`,
    // the drift against the rate at `a = 0`.
    let mut rate = [0.0f64; 4];
    for seed in 0..u64::from(CASES) {
        let (q, v, a) = state(seed);
        let e = whole_body_errors::<C, NQ, NV>(r, &q, &v);
        for (w, e) in worst.iter_mut().zip(e) {
            *w = w.max(e);
        }
        let e = centroidal_rate_errors::<C, NQ, NV>(r, &q, &v, &a);
        let d = centroidal_rate_by_differences::<C, NQ, NV>(&q, &v, &a, 1e-3);
        for (w, e) in rate.iter_mut().zip(e.into_iter().chain(d)) {
            *w = w.max(e);
        }
    }
    for (name, e) in WHOLE_BODY_OUTPUTS.iter().zip(worst) {
        assert!(e < 1e-12, "{label}: {name} off by {e:e}");
    }
    let [reference, drift_reference, differences, drift] = rate;
    assert!(
        reference < 1e-12 && drift_reference < 1e-12,
        "{label}: centroidal_momentum_rate, _drift off the reference by {reference:e}, \
         {drift_reference:e}"
    );
    assert!(
        differences < 1e-9,
        "{label}: centroidal_momentum_rate off the differences of h_G by {differences:e}"
    );
    assert!(
        drift < 1e-12,
        "{label}: centroidal_momentum_drift off the rate at a = 0 by {drift:e}"
    );
    let worst: Vec<String> = worst.iter().map(|e| format!("{e:.1e}")).collect();
    println!("    whole body, worst relative errors {}", worst.join(" "));
    println!(
        "    centroidal_momentum_rate, _drift vs reference {reference:.1e}, \
         {drift_reference:.1e}; rate vs differences of h_G {differences:.1e}; drift vs rate at \
         a = 0 {drift:.1e}"
    );
}

/// The generated Coriolis matrix against the reference's at random states, to 1e-12.
fn check_coriolis<C, const NQ: usize, const NV: usize>(
    label: &str,
    r: &Reference,
    state: impl Fn(u64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
) where
    C: CoriolisMatrix<f64, NQ, NV>,
{
    let mut worst = 0.0f64;
    for seed in 0..u64::from(CASES) {
        let (q, v, _) = state(seed);
        worst = worst.max(coriolis_error::<C, NQ, NV>(r, &q, &v));
    }
    assert!(worst < 1e-12, "{label}: coriolis_matrix off by {worst:e}");
    println!("    coriolis_matrix, worst relative error {worst:.1e}");
}

#[test]
fn random_trees_match_the_reference() {
    let mut kinds = BTreeSet::new();
    let mut largest = 0;
    // The quantities of the whole system, where the tree has them (see `build.rs`).
    macro_rules! whole_body {
        (whole_body, $name:ident, $nq:expr, $nv:expr, $label:expr, $r:expr, $model:expr) => {
            check_whole_body::<trees::$name, $nq, $nv>($label, $r, |s| random_state($model, s));
            check_coriolis::<trees::$name, $nq, $nv>($label, $r, |s| random_state($model, s));
            println!(
                "    ops: center_of_mass {} | center_of_mass_velocity {} | center_of_mass_jacobian {} | centroidal_momentum {} | centroidal_momentum_matrix {} | centroidal_momentum_rate {} | centroidal_momentum_drift {} | kinetic_energy {} | potential_energy {} | coriolis_matrix {}",
                trees::$name::CENTER_OF_MASS_OPS.total(),
                trees::$name::CENTER_OF_MASS_VELOCITY_OPS.total(),
                trees::$name::CENTER_OF_MASS_JACOBIAN_OPS.total(),
                trees::$name::CENTROIDAL_MOMENTUM_OPS.total(),
                trees::$name::CENTROIDAL_MOMENTUM_MATRIX_OPS.total(),
                trees::$name::CENTROIDAL_MOMENTUM_RATE_OPS.total(),
                trees::$name::CENTROIDAL_MOMENTUM_DRIFT_OPS.total(),
                trees::$name::KINETIC_ENERGY_OPS.total(),
                trees::$name::POTENTIAL_ENERGY_OPS.total(),
                trees::$name::CORIOLIS_MATRIX_OPS.total(),
            );
        };
        (basic, $($rest:tt)*) => {};
    }
    macro_rules! check {
        ($name:ident, $seed:expr, $n:expr, $nq:expr, $nv:expr, $whole:ident) => {{
            let model = random_model($seed, $n);
            for j in &model.joints {
                kinds.insert(match j.kind {
                    JointKind::Revolute { .. } => "revolute",
                    JointKind::Prismatic { .. } => "prismatic",
                    JointKind::SphericalEuler { .. } => "spherical Euler",
                    JointKind::SphericalQuaternion => "spherical quaternion",
                    JointKind::FreeEuler { .. } => "free Euler",
                    JointKind::FreeQuaternion => "free quaternion",
                    JointKind::Fixed => "fixed",
                });
            }
            largest = largest.max($n);
            assert_eq!((trees::$name::NQ, trees::$name::NV), ($nq, $nv));
            let r = Reference::new(&model).unwrap();
            let label = format!("{} (seed {}, {} bodies)", stringify!($name), $seed, $n);
            let w = check_chain::<trees::$name, $nq, $nv>(&label, &r, &(), CASES, |s| {
                random_state(&model, s)
            });
            assert_eq!(w.states, CASES as usize);
            check_wrenches::<trees::$name, $nq, $nv, { trees::$name::NB }>(&label, &r, |s| {
                random_state(&model, s)
            });
            whole_body!($whole, $name, $nq, $nv, &label, &r, &model);
            println!(
                "    ops: mass_matrix {} | bias {} | gravity {} | inverse_dynamics {} | forward_dynamics {} | joint_wrenches {}",
                trees::$name::MASS_MATRIX_OPS.total(),
                trees::$name::BIAS_OPS.total(),
                trees::$name::GRAVITY_OPS.total(),
                trees::$name::INVERSE_DYNAMICS_OPS.total(),
                trees::$name::FORWARD_DYNAMICS_OPS.total(),
                trees::$name::JOINT_WRENCHES_OPS.total(),
            );
        }};
    }
    for_each_random_tree!(check);
    assert_eq!(
        kinds.len(),
        7,
        "every joint kind must appear among the trees, found {kinds:?}"
    );
    assert!(largest >= 3);
}

/// Each tree's batch functions (in four lanes up to 8 bodies, `build.rs`; state by state for the
/// 30-body tree) against its scalar functions, on 11 random states (two whole groups of four
/// and a partial one).
#[test]
fn random_trees_batches_are_their_scalar_functions() {
    macro_rules! whole_body {
        (whole_body, $name:ident, $q:ident, $v:ident, $a:ident) => {
            vec![
                same!(trees::$name, center_of_mass, center_of_mass_batch, $q),
                same!(
                    trees::$name,
                    centroidal_momentum_matrix,
                    centroidal_momentum_matrix_batch,
                    $q
                ),
                same!(
                    trees::$name,
                    centroidal_momentum_rate,
                    centroidal_momentum_rate_batch,
                    $q,
                    $v,
                    $a
                ),
                same!(trees::$name, kinetic_energy, kinetic_energy_batch, $q, $v),
                same!(trees::$name, coriolis_matrix, coriolis_matrix_batch, $q, $v),
            ]
        };
        (basic, $($rest:tt)*) => {
            Vec::<(&str, f64)>::new()
        };
    }
    macro_rules! check {
        ($name:ident, $seed:expr, $n:expr, $nq:expr, $nv:expr, $whole:ident) => {{
            let model = random_model($seed, $n);
            let (mut q, mut v, mut a) = (Vec::new(), Vec::new(), Vec::new());
            for s in 0..11 {
                let (qs, vs, as_) = random_state(&model, s);
                q.push(SVector::<f64, $nq>::from_column_slice(&qs));
                v.push(SVector::<f64, $nv>::from_column_slice(&vs));
                a.push(SVector::<f64, $nv>::from_column_slice(&as_));
            }
            let mut results = vec![
                same!(trees::$name, mass_matrix, mass_matrix_batch, q),
                same!(trees::$name, bias, bias_batch, q, v),
                same!(trees::$name, gravity, gravity_batch, q),
                same!(
                    trees::$name,
                    inverse_dynamics,
                    inverse_dynamics_batch,
                    q,
                    v,
                    a
                ),
                same!(
                    trees::$name,
                    forward_dynamics,
                    forward_dynamics_batch,
                    q,
                    v,
                    a
                ),
                same!(trees::$name, joint_wrenches, joint_wrenches_batch, q, v, a),
            ];
            results.extend(whole_body!($whole, $name, q, v, a));
            for (output, d) in results {
                assert!(
                    d <= 1e-14,
                    "{} {output}: batch differs from the scalar function by {d:e}",
                    stringify!($name)
                );
            }
        }};
    }
    for_each_random_tree!(check);
}
