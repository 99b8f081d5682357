//! Batch functions (`C::x_batch`, `C::x_par_batch`) against the scalar function of the same
//! output, state by state (`common::batch`): in lanes (`lanes: N`) for every lane type, and state
//! by state (a generic chain, and the outputs no lane code is generated for). The random trees'
//! batches are checked in `generated_random.rs`.

mod common;

use articulated::lanes::BatchLengths;
use articulated::nalgebra::SVector;
use articulated::prelude::*;
use common::batch::{same, states};

#[derive(articulated::Chain)]
#[chain(
    file = "../models/arm7.chain",
    outputs = [dynamics, whole_body, derivatives, wrenches, joint_wrenches_bottom_up, kept],
    lanes = 4
)]
struct Arm7;

#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain", outputs = [dynamics], lanes = 8)]
struct Arm7x8;

#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain", outputs = [inverse_dynamics, forward_dynamics], scalar = f32, lanes = 16)]
struct Arm7f32x16;

#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain", outputs = [dynamics], scalar = f32, lanes = 4)]
struct Arm7f32x4;

#[derive(articulated::Chain)]
#[chain(file = "../models/tree.chain", outputs = [dynamics, whole_body], lanes = 2)]
struct Tree;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain", outputs = [dynamics, whole_body], scalar = f32, lanes = 8)]
struct TwoLinkF32;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain", outputs = [dynamics], scalar = generic)]
struct TwoLinkGeneric;

// Its own outputs: the frames' placements, Jacobians, velocities and accelerations.
#[derive(articulated::Chain)]
#[chain(file = "../models/two_link_foot.chain", lanes = 4)]
struct TwoLinkFoot;

#[derive(articulated::Chain)]
#[chain(file = "../models/humanoid.chain", outputs = [dynamics], lanes = 4)]
struct Humanoid;

// The other shipped models, their dynamics in four lanes.
#[derive(articulated::Chain)]
#[chain(file = "../models/inverted_pendulum.chain", outputs = [dynamics], lanes = 4)]
struct InvertedPendulum;

#[derive(articulated::Chain)]
#[chain(file = "../models/double_pendulum.chain", outputs = [dynamics], lanes = 4)]
struct DoublePendulum;

#[derive(articulated::Chain)]
#[chain(file = "../models/biped.chain", outputs = [dynamics], lanes = 4)]
struct Biped;

#[derive(articulated::Chain)]
#[chain(file = "../models/falling_cat.chain", outputs = [dynamics], lanes = 4)]
struct FallingCat;

#[derive(articulated::Chain)]
#[chain(file = "../models/four_bar.chain", outputs = [dynamics, frames], lanes = 4)]
struct FourBar;

/// 11 states: two whole groups of four and a partial one (three of eight, of sixteen).
const N: usize = 11;

/// Every `(output, difference)` at most `tol`.
fn assert_within(label: &str, results: &[(&str, f64)], tol: f64) {
    for (output, d) in results {
        assert!(
            *d <= tol,
            "{label} {output}: batch differs from the scalar function by {d:e}"
        );
    }
}

#[test]
fn arm7_batches_in_four_lanes_are_the_scalar_functions() {
    let (q, v, a) = (states::<7>(N, 1), states::<7>(N, 2), states::<7>(N, 3));
    let base = states::<6>(N, 4);
    let results = [
        same!(Arm7, mass_matrix, mass_matrix_batch, q),
        same!(Arm7, bias, bias_batch, q, v),
        same!(Arm7, gravity, gravity_batch, q),
        same!(Arm7, inverse_dynamics, inverse_dynamics_batch, q, v, a),
        same!(Arm7, forward_dynamics, forward_dynamics_batch, q, v, a),
        same!(Arm7, nonlinear_effects, nonlinear_effects_batch, q, v),
        same!(
            Arm7,
            mass_matrix_and_nonlinear_effects,
            mass_matrix_and_nonlinear_effects_batch,
            q,
            v
        ),
        same!(Arm7, joint_wrenches, joint_wrenches_batch, q, v, a),
        same!(
            Arm7,
            joint_wrenches_bottom_up,
            joint_wrenches_bottom_up_batch,
            q,
            v,
            a,
            base
        ),
        same!(Arm7, center_of_mass, center_of_mass_batch, q),
        same!(
            Arm7,
            center_of_mass_velocity,
            center_of_mass_velocity_batch,
            q,
            v
        ),
        same!(
            Arm7,
            center_of_mass_jacobian,
            center_of_mass_jacobian_batch,
            q
        ),
        same!(Arm7, centroidal_momentum, centroidal_momentum_batch, q, v),
        same!(
            Arm7,
            centroidal_momentum_matrix,
            centroidal_momentum_matrix_batch,
            q
        ),
        same!(
            Arm7,
            centroidal_momentum_rate,
            centroidal_momentum_rate_batch,
            q,
            v,
            a
        ),
        same!(
            Arm7,
            centroidal_momentum_drift,
            centroidal_momentum_drift_batch,
            q,
            v
        ),
        same!(Arm7, kinetic_energy, kinetic_energy_batch, q, v),
        same!(Arm7, potential_energy, potential_energy_batch, q),
        same!(Arm7, coriolis_matrix, coriolis_matrix_batch, q, v),
        same!(
            Arm7,
            inverse_dynamics_derivatives,
            inverse_dynamics_derivatives_batch,
            q,
            v,
            a
        ),
        same!(
            Arm7,
            forward_dynamics_derivatives,
            forward_dynamics_derivatives_batch,
            q,
            v,
            a
        ),
        same!(Arm7, mass_matrix_inverse, mass_matrix_inverse_batch, q),
    ];
    assert_within("arm7 (f64, 4 lanes)", &results, 1e-14);
}

#[test]
fn batches_in_every_lane_type_are_the_scalar_functions() {
    let (q, v, a) = (states::<7>(N, 5), states::<7>(N, 6), states::<7>(N, 7));
    assert_within(
        "arm7 (f64, 8 lanes)",
        &[
            same!(Arm7x8, mass_matrix, mass_matrix_batch, q),
            same!(Arm7x8, inverse_dynamics, inverse_dynamics_batch, q, v, a),
            same!(Arm7x8, forward_dynamics, forward_dynamics_batch, q, v, a),
        ],
        1e-14,
    );
    // `f32`: the lanes' sines and cosines are those of `f64` rounded, within an ulp of the
    // scalar code's `libm::sincosf`; what follows carries that ulp.
    let f32s =
        |x: &[SVector<f64, 7>]| -> Vec<SVector<f32, 7>> { x.iter().map(|x| x.cast()).collect() };
    let (qf, vf, af) = (f32s(&q), f32s(&v), f32s(&a));
    assert_within(
        "arm7 (f32, 16 lanes)",
        &[
            same!(
                Arm7f32x16,
                inverse_dynamics,
                inverse_dynamics_batch,
                qf,
                vf,
                af
            ),
            same!(
                Arm7f32x16,
                forward_dynamics,
                forward_dynamics_batch,
                qf,
                vf,
                af
            ),
        ],
        1e-4,
    );
    assert_within(
        "arm7 (f32, 4 lanes)",
        &[
            same!(Arm7f32x4, mass_matrix, mass_matrix_batch, qf),
            same!(
                Arm7f32x4,
                inverse_dynamics,
                inverse_dynamics_batch,
                qf,
                vf,
                af
            ),
            same!(
                Arm7f32x4,
                forward_dynamics,
                forward_dynamics_batch,
                qf,
                vf,
                af
            ),
        ],
        1e-4,
    );
    let (q, v, a) = (
        states::<{ Tree::NQ }>(N, 8),
        states::<{ Tree::NV }>(N, 9),
        states::<{ Tree::NV }>(N, 10),
    );
    assert_within(
        "tree (f64, 2 lanes)",
        &[
            same!(Tree, mass_matrix, mass_matrix_batch, q),
            same!(Tree, inverse_dynamics, inverse_dynamics_batch, q, v, a),
            same!(Tree, forward_dynamics, forward_dynamics_batch, q, v, a),
            same!(
                Tree,
                centroidal_momentum_matrix,
                centroidal_momentum_matrix_batch,
                q
            ),
            same!(Tree, kinetic_energy, kinetic_energy_batch, q, v),
        ],
        1e-14,
    );
    let f32s6 =
        |x: Vec<SVector<f64, 6>>| -> Vec<SVector<f32, 6>> { x.iter().map(|x| x.cast()).collect() };
    let (q, v, a) = (
        f32s6(states(N, 11)),
        f32s6(states(N, 12)),
        f32s6(states(N, 13)),
    );
    assert_within(
        "two-link (f32, 8 lanes)",
        &[
            same!(TwoLinkF32, mass_matrix, mass_matrix_batch, q),
            same!(
                TwoLinkF32,
                inverse_dynamics,
                inverse_dynamics_batch,
                q,
                v,
                a
            ),
            same!(
                TwoLinkF32,
                forward_dynamics,
                forward_dynamics_batch,
                q,
                v,
                a
            ),
            same!(TwoLinkF32, center_of_mass, center_of_mass_batch, q),
            same!(TwoLinkF32, coriolis_matrix, coriolis_matrix_batch, q, v),
        ],
        1e-4,
    );
}

#[test]
fn frames_and_a_floating_base_in_lanes_are_the_scalar_functions() {
    let (q, v, a) = (
        states::<{ TwoLinkFoot::NQ }>(N, 14),
        states::<{ TwoLinkFoot::NV }>(N, 15),
        states::<{ TwoLinkFoot::NV }>(N, 16),
    );
    assert_within(
        "two-link on a foot (f64, 4 lanes)",
        &[
            same!(TwoLinkFoot, frame_placements, frame_placements_batch, q),
            same!(
                TwoLinkFoot,
                frame_jacobians_local,
                frame_jacobians_local_batch,
                q
            ),
            same!(TwoLinkFoot, frame_velocities, frame_velocities_batch, q, v),
            same!(
                TwoLinkFoot,
                frame_accelerations,
                frame_accelerations_batch,
                q,
                v,
                a
            ),
            same!(
                TwoLinkFoot,
                mass_matrix_and_nonlinear_effects,
                mass_matrix_and_nonlinear_effects_batch,
                q,
                v
            ),
        ],
        1e-14,
    );
    let (q, v, a) = (
        states::<{ Humanoid::NQ }>(N, 17),
        states::<{ Humanoid::NV }>(N, 18),
        states::<{ Humanoid::NV }>(N, 19),
    );
    assert_within(
        "humanoid (f64, 4 lanes)",
        &[
            same!(Humanoid, mass_matrix, mass_matrix_batch, q),
            same!(Humanoid, inverse_dynamics, inverse_dynamics_batch, q, v, a),
            same!(Humanoid, forward_dynamics, forward_dynamics_batch, q, v, a),
        ],
        1e-14,
    );
}

#[test]
fn batches_without_lanes_run_state_by_state() {
    let (q, v, a) = (states::<6>(N, 20), states::<6>(N, 21), states::<6>(N, 22));
    assert_within(
        "two-link (generic scalar)",
        &[
            same!(TwoLinkGeneric, mass_matrix, mass_matrix_batch, q),
            same!(
                TwoLinkGeneric,
                forward_dynamics,
                forward_dynamics_batch,
                q,
                v,
                a
            ),
        ],
        0.0,
    );
    // The kept matrix: no lane code, the provided method.
    let q = states::<7>(N, 23);
    let mut kept = vec![KeptMassMatrix::<Arm7, f64, 7>::new(); N];
    Arm7::mass_matrix_update_batch(&q, &mut kept).unwrap();
    for (k, q) in kept.iter().zip(&q) {
        assert_eq!(*k.matrix(), Arm7::mass_matrix(q));
    }
}

#[test]
fn a_state_that_fails_gets_its_error_and_its_neighbours_their_values() {
    // State 5 has a NaN torque: its accelerations are not finite, so its forward dynamics is an
    // error at the first velocity whose acceleration is NaN; the others are unaffected.
    let (q, v, mut tau) = (states::<7>(N, 24), states::<7>(N, 25), states::<7>(N, 26));
    tau[5][3] = f64::NAN;
    let mut out = vec![Ok(SVector::<f64, 7>::zeros()); N];
    Arm7::forward_dynamics_batch(&q, &v, &tau, &mut out).unwrap();
    for i in 0..N {
        assert_eq!(
            out[i],
            Arm7::forward_dynamics(&q[i], &v[i], &tau[i]),
            "state {i}"
        );
        assert_eq!(out[i].is_err(), i == 5, "state {i}");
    }
}

#[test]
fn arguments_of_another_length_are_refused() {
    let (q, v, a) = (
        states::<7>(N, 27),
        states::<7>(N, 28),
        states::<7>(N - 1, 29),
    );
    let mut out = vec![SVector::<f64, 7>::zeros(); N];
    let err = Arm7::inverse_dynamics_batch(&q, &v, &a, &mut out).unwrap_err();
    assert_eq!(
        err,
        BatchLengths {
            argument: "a",
            expected: N,
            found: N - 1
        }
    );
    assert!(err.to_string().contains("`a` holds 10 states"), "{err}");
    // Nothing was written.
    assert!(out.iter().all(|x| *x == SVector::<f64, 7>::zeros()));
    let mut out = vec![SVector::<f64, 7>::zeros(); N - 1];
    let err = Arm7::gravity_batch(&q, &mut out).unwrap_err();
    assert_eq!((err.argument, err.found, err.expected), ("q", N, N - 1));
}

#[test]
fn batches_on_every_thread_are_the_batches() {
    // 1000 states: whole groups and a partial one (`lanes::par_chunk`), over rayon's threads.
    let n = 1000;
    let (q, v, a) = (states::<7>(n, 30), states::<7>(n, 31), states::<7>(n, 32));
    let mut serial = vec![Ok(SVector::<f64, 7>::zeros()); n];
    let mut parallel = serial.clone();
    Arm7::forward_dynamics_batch(&q, &v, &a, &mut serial).unwrap();
    Arm7::forward_dynamics_par_batch(&q, &v, &a, &mut parallel).unwrap();
    assert_eq!(serial, parallel);
    let mut m = vec![Arm7::mass_matrix(&q[0]); n];
    Arm7::mass_matrix_par_batch(&q, &mut m).unwrap();
    for (m, q) in m.iter().zip(&q) {
        assert_eq!(*m, Arm7::mass_matrix(q));
    }
    let short = &a[..n - 1];
    let mut out = vec![SVector::<f64, 7>::zeros(); n];
    assert!(Arm7::inverse_dynamics_par_batch(&q, &v, short, &mut out).is_err());
}

/// `n` random states of the humanoid: positions in `[-2, 2]` with a unit base quaternion.
fn humanoid_states(n: usize, seed: u64) -> Vec<SVector<f64, { Humanoid::NQ }>> {
    states::<{ Humanoid::NQ }>(n, seed)
        .into_iter()
        .map(|mut q| {
            let r = q.fixed_rows::<4>(3).normalize();
            q.fixed_rows_mut::<4>(3).copy_from(&r);
            q
        })
        .collect()
}

#[test]
fn an_ensemble_steps_each_copy_as_rk4_steps_it_alone() {
    use articulated::integrate::{ControlledChain, Ensemble, Integrator, Rk4, State};
    // The humanoid: a quaternion base, so the Munthe-Kaas stages on its manifold; 11 copies,
    // three groups of four lanes per stage; the seventh with a NaN force.
    let (mut q, mut v) = (humanoid_states(N, 33), states::<{ Humanoid::NV }>(N, 34));
    let mut tau = states::<{ Humanoid::NV }>(N, 35);
    tau[6][10] = f64::NAN;
    let (q0, v0) = (q.clone(), v.clone());
    let mut faults = vec![None; N];
    let mut ensemble = Ensemble::new();
    let h = 1e-3;
    for _ in 0..3 {
        ensemble
            .rk4::<Humanoid>(&mut q, &mut v, &tau, &(), h, &mut faults)
            .unwrap();
    }
    for i in 0..N {
        let t = tau[i];
        let mut alone = ControlledChain::<f64, Humanoid, _>::new(move |_t: f64, _q: &_, _v: &_| t);
        let mut state = State::new(0.0, q0[i], v0[i]);
        let mut result = Ok(());
        for step in 0..3 {
            result = Rk4.advance(&mut alone, &mut state, h * (step + 1) as f64, step);
            if result.is_err() {
                break;
            }
        }
        match result {
            Ok(()) => {
                assert!(faults[i].is_none(), "copy {i}: {:?}", faults[i]);
                let d = common::batch::difference(state.q.as_slice(), q[i].as_slice()).max(
                    common::batch::difference(state.v.as_slice(), v[i].as_slice()),
                );
                assert!(
                    d <= 1e-15,
                    "copy {i}: the ensemble differs from Rk4 by {d:e}"
                );
            }
            Err(_) => {
                assert_eq!(i, 6);
                assert!(faults[i].is_some());
                assert_eq!(
                    (q[i], v[i]),
                    (q0[i], v0[i]),
                    "a faulty copy is left as it was"
                );
            }
        }
    }
    let mut short = vec![None; N - 1];
    assert!(ensemble
        .rk4::<Humanoid>(&mut q, &mut v, &tau, &(), h, &mut short)
        .is_err());
}

#[test]
fn every_shipped_model_in_lanes_is_its_scalar_functions() {
    macro_rules! model {
        ($c:ty, $seed:expr) => {{
            let (q, v, a) = (
                states::<{ <$c>::NQ }>(N, $seed),
                states::<{ <$c>::NV }>(N, $seed + 1),
                states::<{ <$c>::NV }>(N, $seed + 2),
            );
            assert_within(
                stringify!($c),
                &[
                    same!($c, mass_matrix, mass_matrix_batch, q),
                    same!($c, bias, bias_batch, q, v),
                    same!($c, gravity, gravity_batch, q),
                    same!($c, inverse_dynamics, inverse_dynamics_batch, q, v, a),
                    same!($c, forward_dynamics, forward_dynamics_batch, q, v, a),
                    same!($c, nonlinear_effects, nonlinear_effects_batch, q, v),
                ],
                1e-14,
            );
        }};
    }
    model!(InvertedPendulum, 40);
    model!(DoublePendulum, 43);
    model!(Biped, 46);
    model!(FallingCat, 49);
    model!(FourBar, 52);
}
