//! The shipped models' batch functions in lanes against their scalar functions, state by state
//! (`common::batch`): the frames and the quaternion base of the two-link on a foot and the
//! humanoid, an ensemble of humanoids against RK4 alone, and the dynamics of every other model.
//! Beside `batch.rs` (the lane types, parameters, errors and threads on the arm and small
//! chains), in a crate of its own so that the two build side by side.

mod common;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use common::batch::{assert_within, same, states};

// Its own outputs: the frames' placements, Jacobians, velocities and accelerations.
#[derive(articulated::Chain)]
#[chain(file = "../models/two_link_foot.chain", lanes = 4)]
struct TwoLinkFoot;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [mass_matrix, inverse_dynamics, forward_dynamics],
    lanes = 4
)]
struct Humanoid;

// The humanoid's legs on its free base (`tests/data/legs.chain`): large enough that its
// `forward_dynamics_derivatives` is composed (`codegen/src/generate/composed.rs`), and its batch
// twin then composes the parts in lanes.
#[derive(articulated::Chain)]
#[chain(
    file = "data/legs.chain",
    outputs = [forward_dynamics_derivatives],
    lanes = 4
)]
struct Legs;

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

/// 11 states: two whole groups of four and a partial one.
const N: usize = 11;

/// Runs `test` on a thread of 8 MiB, what a program's main thread has on Linux. The integration
/// tests build at opt-level 0 (the workspace's Cargo.toml), where every temporary of the
/// humanoid's functions in lanes keeps a stack slot of its own: more than the 2 MiB of a test's
/// thread.
fn on_a_large_stack(test: fn()) {
    std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(test)
        .expect("a thread for the test")
        .join()
        .unwrap_or_else(|failure| std::panic::resume_unwind(failure));
}

#[test]
fn frames_and_a_floating_base_in_lanes_are_the_scalar_functions() {
    on_a_large_stack(frames_and_a_floating_base);
}

fn frames_and_a_floating_base() {
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
    on_a_large_stack(ensemble_against_rk4);
}

fn ensemble_against_rk4() {
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
            .rk4::<Humanoid>(&mut q, &mut v, &tau, &[()], h, &mut faults)
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
        .rk4::<Humanoid>(&mut q, &mut v, &tau, &[()], h, &mut short)
        .is_err());
}

#[test]
fn composed_derivatives_in_lanes_are_the_scalar_function() {
    on_a_large_stack(composed_derivatives_in_lanes);
}

fn composed_derivatives_in_lanes() {
    // Bit for bit the scalar (composed) function, state by state: the parts in lanes and the
    // products lane by lane sum in the scalar order. State 6's torque is NaN (its forward
    // dynamics fails, in the second group of four): its error, its neighbours their values.
    let mut q = states::<{ Legs::NQ }>(N, 60);
    for q in &mut q {
        let r = q.fixed_rows::<4>(3).normalize();
        q.fixed_rows_mut::<4>(3).copy_from(&r);
    }
    let (v, mut tau) = (states::<{ Legs::NV }>(N, 61), states::<{ Legs::NV }>(N, 62));
    tau[6][9] = f64::NAN;
    let (label, worst) = same!(
        Legs,
        forward_dynamics_derivatives,
        forward_dynamics_derivatives_batch,
        q,
        v,
        tau
    );
    assert_within("legs (f64, 4 lanes)", &[(label, worst)], 0.0);
    let mut out = vec![Legs::forward_dynamics_derivatives(&q[0], &v[0], &tau[0]); N];
    Legs::forward_dynamics_derivatives_batch(&q, &v, &tau, &mut out).unwrap();
    for (i, o) in out.iter().enumerate() {
        assert_eq!(o.is_err(), i == 6, "state {i}");
    }
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
