//! Batch functions (`C::x_batch`, `C::x_par_batch`) against the scalar function of the same
//! output, state by state (`common::batch`): in lanes (`lanes: N`) for every lane type, and state
//! by state (a generic chain, and the outputs no lane code is generated for); runtime parameters
//! per state. The shipped models' batches are checked in `batch_models.rs` (a crate of its own,
//! so that the two build side by side), the random trees' in `generated_random.rs`.

mod common;

use articulated::lanes::BatchLengths;
use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use common::batch::{assert_within, same, states};

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

/// The payload arm, its five runtime parameters in four lanes.
#[derive(articulated::Chain)]
#[chain(file = "../models/payload.chain", lanes = 4)]
struct Payload;

articulated::chain! {
    /// A five-link arm whose tool's mass is a runtime parameter. Its derivatives, over a
    /// thousand operations each, take the lanes that fit one of the target's registers
    /// (`articulated::lanes::fit`: two on the default target, four with AVX), with each lane's
    /// parameters gathered by that count; its forward dynamics keeps the four asked for.
    chain ToolArm {
        lanes: 4;
        outputs: [forward_dynamics, inverse_dynamics_derivatives, forward_dynamics_derivatives];
        param tool = 1.5;

        body l1 { mass: 2.0, com: [0.0, 0.0, 0.15], inertia: diag(0.03, 0.03, 0.01) }
        body l2 { mass: 1.8, com: [0.1, 0.0, 0.0], inertia: diag(0.01, 0.02, 0.02) }
        body l3 { mass: 1.5, com: [0.0, 0.02, 0.12], inertia: diag(0.02, 0.02, 0.005) }
        body l4 { mass: 1.0, com: [0.08, 0.0, 0.0], inertia: diag(0.004, 0.01, 0.01) }
        body l5 { mass: tool, com: [0.0, 0.0, 0.05], inertia: diag(0.002, 0.002, 0.001) }

        joint j1: revolute(z) { parent: world, child: l1 }
        joint j2: revolute(y) { parent: l1, child: l2, xyz: [0.0, 0.0, 0.3] }
        joint j3: revolute(x) { parent: l2, child: l3, xyz: [0.2, 0.0, 0.0], rpy: [0.0, 0.3, 0.0] }
        joint j4: revolute(y) { parent: l3, child: l4, xyz: [0.0, 0.0, 0.25] }
        joint j5: revolute(z) { parent: l4, child: l5, xyz: [0.15, 0.0, 0.0] }
    }
}

/// 11 states: two whole groups of four and a partial one (three of eight, of sixteen).
const N: usize = 11;

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
    // `f32`: the lanes' sines and cosines are `libm::sincosf`'s algorithm, the scalar code's
    // (identical to it but for a rare argument, `runtime/tests/math.rs`): on these states the
    // batch is the scalar function bit for bit, as in `f64`.
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
        0.0,
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
        0.0,
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
        0.0,
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
fn a_batch_of_one_state_is_the_scalar_function() {
    // One state goes to the scalar function rather than a padded group of lanes: its value,
    // its error, its own parameters (a batch of one that read the wrong argument or another
    // state's parameters would differ).
    let (q, v, mut a) = (states::<7>(2, 30), states::<7>(2, 31), states::<7>(2, 32));
    let mut tau = [SVector::<f64, 7>::zeros()];
    Arm7::inverse_dynamics_batch(&q[..1], &v[..1], &a[..1], &mut tau).unwrap();
    assert_eq!(tau[0], Arm7::inverse_dynamics(&q[0], &v[0], &a[0]));
    let mut m = [SMatrix::<f64, 7, 7>::zeros()];
    Arm7::mass_matrix_batch(&q[1..], &mut m).unwrap();
    assert_eq!(m[0], Arm7::mass_matrix(&q[1]));
    a[1][2] = f64::NAN;
    let mut acc = [Ok(SVector::<f64, 7>::zeros())];
    Arm7::forward_dynamics_batch(&q[1..], &v[1..], &a[1..], &mut acc).unwrap();
    assert_eq!(acc[0], Arm7::forward_dynamics(&q[1], &v[1], &a[1]));
    assert!(acc[0].is_err());
    let (qp, vp, ap) = (states::<2>(1, 33), states::<2>(1, 34), states::<2>(1, 35));
    let ps = payload_sweep(4);
    let mut t = [SVector::<f64, 2>::zeros()];
    Payload::inverse_dynamics_batch_with_each(&qp, &vp, &ap, &ps[3..], &mut t).unwrap();
    assert_eq!(
        t[0],
        Payload::inverse_dynamics_with(&qp[0], &vp[0], &ap[0], &ps[3])
    );
    assert_ne!(
        t[0],
        Payload::inverse_dynamics_with(&qp[0], &vp[0], &ap[0], &ps[0])
    );
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

/// `n` parameter sets of the payload arm, each different in every field.
fn payload_sweep(n: usize) -> Vec<PayloadParams> {
    (0..n)
        .map(|i| {
            let x = i as f64;
            PayloadParams {
                payload: 0.5 + 0.75 * x,
                reach: 0.1 + 0.05 * x,
                payload_izz: 0.01 + 0.003 * x,
                upper_length: 0.4 + 0.02 * x,
                g: -9.81 + 0.1 * x,
            }
        })
        .collect()
}

#[test]
fn a_parameter_sweep_in_lanes_gives_each_state_its_own_parameters() {
    // Eleven states, each with its own payload, reach, inertia, length and gravity: a lane
    // that read its neighbour's parameters (or the first set's) would differ from the scalar
    // function at its own.
    let (q, v, a) = (states::<2>(N, 40), states::<2>(N, 41), states::<2>(N, 42));
    let ps = payload_sweep(N);
    let mut tau = vec![SVector::<f64, 2>::zeros(); N];
    Payload::inverse_dynamics_batch_with_each(&q, &v, &a, &ps, &mut tau).unwrap();
    let mut acc = vec![Ok(SVector::<f64, 2>::zeros()); N];
    Payload::forward_dynamics_batch_with_each(&q, &v, &tau, &ps, &mut acc).unwrap();
    let mut m = vec![Payload::mass_matrix(&q[0]); N];
    Payload::mass_matrix_batch_with_each(&q, &ps, &mut m).unwrap();
    let mut g = vec![SVector::<f64, 2>::zeros(); N];
    Payload::gravity_par_batch_with_each(&q, &ps, &mut g).unwrap();
    for i in 0..N {
        let p = &ps[i];
        assert_eq!(
            tau[i],
            Payload::inverse_dynamics_with(&q[i], &v[i], &a[i], p),
            "{i}"
        );
        assert_eq!(
            acc[i],
            Payload::forward_dynamics_with(&q[i], &v[i], &tau[i], p),
            "{i}"
        );
        assert_eq!(m[i], Payload::mass_matrix_with(&q[i], p), "{i}");
        assert_eq!(g[i], Payload::gravity_with(&q[i], p), "{i}");
        // And the sweep is one: neighbouring payloads give other torques.
        if i > 0 {
            assert_ne!(g[i], Payload::gravity_with(&q[i], &ps[i - 1]), "{i}");
        }
    }
    // One set for all: the same as `_batch_with`, and as each state's scalar call.
    let one = [ps[3]];
    let mut each = vec![SVector::<f64, 2>::zeros(); N];
    Payload::inverse_dynamics_batch_with_each(&q, &v, &a, &one, &mut each).unwrap();
    for i in 0..N {
        assert_eq!(
            each[i],
            Payload::inverse_dynamics_with(&q[i], &v[i], &a[i], &ps[3])
        );
    }
    // Neither one set nor one per state: refused, nothing computed.
    let mut out = vec![SVector::<f64, 2>::zeros(); N];
    let err =
        Payload::inverse_dynamics_batch_with_each(&q, &v, &a, &ps[..2], &mut out).unwrap_err();
    assert_eq!((err.argument, err.found, err.expected), ("p", 2, N));
    assert!(err.to_string().contains("holds 2 parameter sets"), "{err}");
    assert!(out.iter().all(|x| *x == SVector::<f64, 2>::zeros()));
}

#[test]
fn an_ensemble_sweeps_a_payload_as_each_copy_alone() {
    use articulated::integrate::{ControlledChain, Ensemble, Integrator, Rk4, State};
    // Eleven copies of the arm released from one state, each with its own payload: each lands
    // where Rk4 takes it alone with its parameters.
    let ps = payload_sweep(N);
    let (q0, v0) = (
        SVector::<f64, 2>::new(0.3, -0.7),
        SVector::<f64, 2>::new(0.5, 0.2),
    );
    let (mut q, mut v) = (vec![q0; N], vec![v0; N]);
    let tau = vec![SVector::<f64, 2>::zeros(); N];
    let mut faults = vec![None; N];
    let mut ensemble = Ensemble::new();
    let h = 1e-3;
    for _ in 0..20 {
        ensemble
            .rk4::<Payload>(&mut q, &mut v, &tau, &ps, h, &mut faults)
            .unwrap();
    }
    for i in 0..N {
        let mut alone =
            ControlledChain::<f64, Payload, _>::with_params(ps[i], |_t: f64, _q: &_, _v: &_| {
                SVector::<f64, 2>::zeros()
            });
        let mut state = State::new(0.0, q0, v0);
        for step in 0..20 {
            Rk4.advance(&mut alone, &mut state, h * (step + 1) as f64, step)
                .unwrap();
        }
        let d = common::batch::difference(state.q.as_slice(), q[i].as_slice()).max(
            common::batch::difference(state.v.as_slice(), v[i].as_slice()),
        );
        assert!(d <= 1e-15, "copy {i}: {d:e}");
        assert!(faults[i].is_none());
    }
    // The payloads spread the copies apart.
    assert!((q[0] - q[N - 1]).norm() > 1e-4);
}

#[test]
fn large_outputs_in_fitting_lanes_give_each_state_its_own_parameters() {
    // The derivatives (in the lanes of `articulated::lanes::fit`) with a tool mass per state:
    // a lane that read another state's mass, or a group that took its masses at a stride other
    // than its lanes', would differ from the scalar function at its own. The forward dynamics,
    // in the four lanes asked for, beside them.
    let (q, v, a) = (states::<5>(N, 50), states::<5>(N, 51), states::<5>(N, 52));
    let ps: Vec<ToolArmParams> = (0..N)
        .map(|i| ToolArmParams {
            tool: 0.5 + 0.4 * i as f64,
        })
        .collect();
    let mut did = vec![ToolArm::inverse_dynamics_derivatives(&q[0], &v[0], &a[0]); N];
    ToolArm::inverse_dynamics_derivatives_batch_with_each(&q, &v, &a, &ps, &mut did).unwrap();
    let mut dfd = vec![ToolArm::forward_dynamics_derivatives(&q[0], &v[0], &a[0]); N];
    ToolArm::forward_dynamics_derivatives_batch_with_each(&q, &v, &a, &ps, &mut dfd).unwrap();
    let mut fd = vec![ToolArm::forward_dynamics(&q[0], &v[0], &a[0]); N];
    ToolArm::forward_dynamics_batch_with_each(&q, &v, &a, &ps, &mut fd).unwrap();
    for i in 0..N {
        let p = &ps[i];
        assert_eq!(
            did[i],
            ToolArm::inverse_dynamics_derivatives_with(&q[i], &v[i], &a[i], p),
            "{i}"
        );
        assert_eq!(
            dfd[i],
            ToolArm::forward_dynamics_derivatives_with(&q[i], &v[i], &a[i], p),
            "{i}"
        );
        assert_eq!(
            fd[i],
            ToolArm::forward_dynamics_with(&q[i], &v[i], &a[i], p),
            "{i}"
        );
        // And the masses differ: a neighbour's gives other derivatives.
        if i > 0 {
            assert_ne!(
                did[i],
                ToolArm::inverse_dynamics_derivatives_with(&q[i], &v[i], &a[i], &ps[i - 1]),
                "{i}"
            );
        }
    }
}
