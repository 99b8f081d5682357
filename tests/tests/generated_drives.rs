//! Drives (issue 14). The armature against the rigid bodies' dynamics plus `diag(armature)`:
//! the reference on the same model with its armatures removed gives `M`, `h = N·q̇ + g` and the
//! kinetic energy of the rigid bodies, and nalgebra solves `(M + diag)·q̈ = τ − h`, so nothing
//! the armature changed is checked against itself. The drives' forces in simulation against
//! closed forms (dry friction's constant deceleration, an elastic stop's penetration
//! `v·√(m/k)`, a saturated push) and an energy balance (damping dissipates `∫ d·v² dt`). And
//! against Pinocchio with `model.armature` set, on the arm with a rotor on every joint
//! (`data/pinocchio-armature.json`, made by `data/make_armature_reference.py`).

mod common;

use std::path::Path;

use articulated::drives::Drives;
use articulated::integrate::{ControlledChain, Dopri5, Integrator, Rk4, State};
use articulated::nalgebra::{DMatrix, DVector, SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated::{Coordinates, Drive};
use articulated_codegen::load::load_model;
use articulated_dynamics::model::Model;
use articulated_dynamics::random::random_state;
use common::{read_json, rel_err, rows_of, vec_of};

/// Every joint kind with a rotor; FD by CRBA and `LᵀDL` (the fastest).
#[derive(Chain)]
#[chain(
    file = "data/driven.chain",
    outputs = [
        mass_matrix, inverse_dynamics, forward_dynamics, kinetic_energy,
        forward_dynamics_derivatives
    ]
)]
struct Driven;

/// The same with FD by ABA, where the rotor enters each joint's `D` alone.
#[derive(Chain)]
#[chain(file = "data/driven.chain", accuracy = robust, outputs = [forward_dynamics])]
struct DrivenRobust;

/// The arm with a rotor, damping and friction on every joint, from URDF.
#[derive(Chain)]
#[chain(
    urdf = "data/arm7_armature.urdf",
    outputs = [mass_matrix, inverse_dynamics, forward_dynamics, forward_dynamics_derivatives]
)]
struct Arm7Armature;

const NQ: usize = 9;
const NV: usize = 8;

/// The rotor inertia on each velocity coordinate, as `data/driven.chain` gives it.
const ARMATURE: [f64; NV] = [0.5, 0.02, 0.02, 0.02, 0.05, 0.01, 0.01, 0.01];

fn driven() -> Model {
    load_model(Path::new("data/driven.chain"), false).unwrap()
}

/// The reference of the same bodies with no rotors.
fn rigid() -> Reference {
    let mut model = driven();
    for joint in &mut model.joints {
        joint.drive.armature = 0.0;
    }
    Reference::new(&model).unwrap()
}

fn rows<const N: usize>(m: &SMatrix<f64, N, N>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

fn dense_rows(m: &DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

/// `M + diag(armature)` of the rigid bodies.
fn with_rotors(m: DMatrix<f64>) -> DMatrix<f64> {
    m + DMatrix::from_diagonal(&DVector::from_row_slice(&ARMATURE))
}

/// `q̈ = (M + diag)⁻¹·(τ − h)` from the rigid bodies' `M` and `h`, by nalgebra's Cholesky.
fn expected_qdd(rigid: &Reference, q: &[f64], v: &[f64], tau: &[f64]) -> DVector<f64> {
    let m = with_rotors(rigid.mass_matrix(q).unwrap());
    let zero = vec![0.0; NV];
    let h = rigid.inverse_dynamics(q, v, &zero).unwrap();
    m.cholesky()
        .unwrap()
        .solve(&(DVector::from_row_slice(tau) - h))
}

#[test]
fn the_description_s_drives_are_the_generated_constants() {
    assert_eq!(Driven::DRIVES.len(), Driven::COORDINATES.len());
    let rail = Driven::DRIVES[0];
    assert_eq!(
        rail,
        Drive {
            armature: 0.5,
            damping: 2.0,
            friction: 1.0,
            lower: -0.5,
            upper: 0.5,
            effort: 100.0,
            ..Drive::FREE
        }
    );
    let elbow = Driven::DRIVES[2];
    assert_eq!(
        (elbow.lower, elbow.upper, elbow.velocity, elbow.effort),
        (-2.0, 2.0, 10.0, 30.0)
    );
    assert_eq!(
        Driven::DRIVES[3],
        Drive {
            armature: 0.01,
            ..Drive::FREE
        }
    );
    // The model the tests read agrees with the generated constants, joint by joint.
    let model = driven();
    let from_file: Vec<Drive> = model.joints.iter().map(|j| j.drive).collect();
    assert_eq!(from_file, Driven::DRIVES);
}

#[test]
fn armature_adds_to_the_rigid_bodies_mass_matrix_and_inverse_dynamics() {
    let (model, rigid) = (driven(), rigid());
    for seed in 0..20 {
        let (q, v, a) = random_state(&model, seed);
        let qs = SVector::<f64, NQ>::from_row_slice(&q);
        let vs = SVector::<f64, NV>::from_row_slice(&v);
        let as_ = SVector::<f64, NV>::from_row_slice(&a);

        let m = with_rotors(rigid.mass_matrix(&q).unwrap());
        let ours = Driven::mass_matrix(&qs);
        assert!(
            rel_err(&rows(&ours), &dense_rows(&m)) < 1e-14,
            "M, seed {seed}"
        );

        let rotors = DVector::from_row_slice(&ARMATURE).component_mul(&DVector::from_row_slice(&a));
        let tau = rigid.inverse_dynamics(&q, &v, &a).unwrap() + rotors;
        let ours = Driven::inverse_dynamics(&qs, &vs, &as_);
        assert!(
            rel_err(ours.as_slice(), tau.as_slice()) < 1e-13,
            "τ, seed {seed}"
        );

        let rotor_energy: f64 = ARMATURE.iter().zip(&v).map(|(i, w)| 0.5 * i * w * w).sum();
        let energy = rigid.kinetic_energy(&q, &v).unwrap() + rotor_energy;
        let ours = Driven::kinetic_energy(&qs, &vs);
        assert!((ours - energy).abs() <= 1e-13 * energy, "T, seed {seed}");
    }
}

#[test]
fn armature_in_forward_dynamics_by_ltdl_and_by_aba_and_in_its_derivatives() {
    let (model, rigid) = (driven(), rigid());
    for seed in 0..20 {
        let (q, v, tau) = random_state(&model, 100 + seed);
        let qs = SVector::<f64, NQ>::from_row_slice(&q);
        let vs = SVector::<f64, NV>::from_row_slice(&v);
        let taus = SVector::<f64, NV>::from_row_slice(&tau);
        let expected = expected_qdd(&rigid, &q, &v, &tau);

        let ltdl = Driven::forward_dynamics(&qs, &vs, &taus).unwrap();
        assert!(
            rel_err(ltdl.as_slice(), expected.as_slice()) < 1e-12,
            "LᵀDL, seed {seed}"
        );
        let aba = DrivenRobust::forward_dynamics(&qs, &vs, &taus).unwrap();
        assert!(
            rel_err(aba.as_slice(), expected.as_slice()) < 1e-12,
            "ABA, seed {seed}"
        );

        // ∂q̈/∂τ = (M + diag)⁻¹; ∂q̈/∂v against central differences of the expected q̈ (v is
        // a vector: no tangent-space convention enters).
        let (_, dv, minv) = Driven::forward_dynamics_derivatives(&qs, &vs, &taus).unwrap();
        let m = with_rotors(rigid.mass_matrix(&q).unwrap());
        let inverse = m.try_inverse().unwrap();
        assert!(
            rel_err(&rows(&minv), &dense_rows(&inverse)) < 1e-12,
            "M⁻¹, seed {seed}"
        );
        let h = 1e-6;
        let mut differences = DMatrix::<f64>::zeros(NV, NV);
        for k in 0..NV {
            let (mut up, mut down) = (v.clone(), v.clone());
            up[k] += h;
            down[k] -= h;
            let column = (expected_qdd(&rigid, &q, &up, &tau)
                - expected_qdd(&rigid, &q, &down, &tau))
                / (2.0 * h);
            differences.set_column(k, &column);
        }
        assert!(
            rel_err(&rows(&dv), &dense_rows(&differences)) < 1e-6,
            "∂q̈/∂v, seed {seed}: {dv} vs {differences}"
        );
    }
}

#[test]
fn armature_from_urdf_agrees_with_pinocchio() {
    let data = read_json("data/pinocchio-armature.json");
    let armature = vec_of(&data["armature"]);
    let from_urdf: Vec<f64> = Arm7Armature::DRIVES.iter().map(|d| d.armature).collect();
    assert_eq!(from_urdf, armature);
    assert!(Arm7Armature::DRIVES
        .iter()
        .all(|d| (d.damping, d.friction, d.upper, d.effort) == (0.5, 0.1, 2.96, 176.0)));
    let states = data["states"].as_array().unwrap();
    for (k, s) in states.iter().enumerate() {
        let q = SVector::<f64, 7>::from_row_slice(&vec_of(&s["q"]));
        let v = SVector::<f64, 7>::from_row_slice(&vec_of(&s["v"]));
        let a = SVector::<f64, 7>::from_row_slice(&vec_of(&s["a"]));
        let tau = SVector::<f64, 7>::from_row_slice(&vec_of(&s["tau"]));
        let m = Arm7Armature::mass_matrix(&q);
        assert!(
            rel_err(&rows(&m), &rows_of(&s["mass_matrix"])) < 1e-12,
            "M, state {k}"
        );
        let ours = Arm7Armature::inverse_dynamics(&q, &v, &a);
        assert!(
            rel_err(ours.as_slice(), &vec_of(&s["tau_out"])) < 1e-12,
            "τ, state {k}"
        );
        let ours = Arm7Armature::forward_dynamics(&q, &v, &tau).unwrap();
        assert!(
            rel_err(ours.as_slice(), &vec_of(&s["qdd"])) < 1e-11,
            "q̈, state {k}"
        );
        let (dq, dv, minv) = Arm7Armature::forward_dynamics_derivatives(&q, &v, &tau).unwrap();
        for (name, ours) in [("ddq_dq", dq), ("ddq_dv", dv), ("minv", minv)] {
            let err = rel_err(&rows(&ours), &rows_of(&s[name]));
            assert!(err < 1e-10, "{name}, state {k}: {err:e}");
        }
    }
}

articulated::chain! {
    /// A cart of 4 kg on a horizontal rail along x.
    chain Cart {
        outputs: [forward_dynamics];
        body cart { mass: 4.0, com: [0.0, 0.0, 0.0], inertia: diag(0.1, 0.1, 0.1) }
        joint rail: prismatic(x) { parent: world, child: cart }
    }
}

articulated::chain! {
    /// A 1 kg bob 1 m below a pivot about y, damped.
    chain Pendulum {
        outputs: [forward_dynamics, kinetic_energy, potential_energy];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) { parent: world, child: bob, damping: 0.3 }
    }
}

type V1 = SVector<f64, 1>;

fn unforced(_t: f64, _q: &V1, _v: &V1) -> V1 {
    V1::zeros()
}

/// The cart's drives: `drive` on its one coordinate.
fn cart_drives(drive: Drive) -> Drives<f64, 1, 1> {
    Drives::from_drives(&[Coordinates::Vector(1)], &[drive]).unwrap()
}

#[test]
fn a_spring_swings_the_cart_about_its_rest_position_at_sqrt_k_over_m() {
    // k = 16 N/m on 4 kg: ω = 2 rad/s about x = 0.3, released at 0.5 from rest.
    let drives = cart_drives(Drive {
        stiffness: 16.0,
        rest: 0.3,
        ..Drive::FREE
    });
    let spring = drives;
    let mut system = ControlledChain::<f64, Cart, _>::new(drives.around(unforced));
    let mut state = State::new(0.0, V1::new(0.5), V1::new(0.0));
    let dt = 1e-3;
    let mut worst = 0.0f64;
    for k in 0..3000 {
        Rk4.advance(&mut system, &mut state, (k + 1) as f64 * dt, k)
            .unwrap();
        let t = (k + 1) as f64 * dt;
        worst = worst.max((state.q[0] - (0.3 + 0.2 * (2.0 * t).cos())).abs());
        // ½·m·v² + ½·k·(x − rest)², the spring's energy from the drives.
        let energy = 2.0 * state.v[0] * state.v[0] + spring.spring_energy(&state.q);
        assert!((energy - 0.32).abs() < 1e-9, "energy at {t} s: {energy}");
    }
    assert!(worst < 1e-9, "x(t) off the closed form by {worst:e}");
}

#[test]
fn dry_friction_decelerates_the_cart_at_f_over_m_until_it_stops() {
    let drives = cart_drives(Drive {
        friction: 2.0,
        ..Drive::FREE
    });
    let mut system = ControlledChain::<f64, Cart, _>::new(drives.around(unforced));
    let mut state = State::new(0.0, V1::new(0.0), V1::new(3.0));
    let dt = 1e-3;
    for k in 0..1000 {
        Rk4.advance(&mut system, &mut state, (k + 1) as f64 * dt, k)
            .unwrap();
    }
    // v = v0 − (f/m)·t, x = v0·t − ½(f/m)·t² while v ≫ friction_speed (tanh(v/ε) = 1 − 1e-17).
    assert!((state.v[0] - 2.5).abs() < 1e-9, "v(1) = {}", state.v[0]);
    assert!((state.q[0] - 2.75).abs() < 1e-9, "x(1) = {}", state.q[0]);
    for k in 1000..8000 {
        Rk4.advance(&mut system, &mut state, (k + 1) as f64 * dt, k)
            .unwrap();
    }
    // Stopped at 6 s, ~9 m along; friction never pushes it back.
    assert!(state.v[0].abs() < 1e-3, "v(8) = {}", state.v[0]);
    assert!((state.q[0] - 9.0).abs() < 1e-2, "x(8) = {}", state.q[0]);
}

#[test]
fn an_elastic_stop_turns_the_cart_back_after_v_times_sqrt_m_over_k() {
    let mut drives = cart_drives(Drive {
        lower: -0.5,
        upper: 0.5,
        ..Drive::FREE
    });
    drives.smoothing.stop_damping = 0.0;
    let k = drives.smoothing.stop_stiffness;
    let mut system = ControlledChain::<f64, Cart, _>::new(drives.around(unforced));
    // At 1 m/s from 5 cm before the stop: in at 0.05 s, out after π·√(m/k) ≈ 0.063 s.
    let mut state = State::new(0.0, V1::new(0.45), V1::new(1.0));
    let mut deepest: f64 = 0.0;
    for step in 0..2000 {
        Rk4.advance(&mut system, &mut state, (step + 1) as f64 * 1e-4, step)
            .unwrap();
        deepest = deepest.max(state.q[0] - 0.5);
    }
    // Half an oscillation of √(k/m) inside the stop: in at 1 m/s, out at −1 m/s.
    let expected = 1.0 * (4.0 / k).sqrt();
    assert!(
        (deepest - expected).abs() < 1e-4 * expected,
        "{deepest} vs {expected}"
    );
    assert!((state.v[0] + 1.0).abs() < 1e-6, "v after = {}", state.v[0]);
    assert_eq!(drives.outside_limits(&state.q), None);
    assert_eq!(
        drives.outside_limits(&V1::new(0.6)).map(|(i, _)| i),
        Some(0)
    );
}

#[test]
fn the_commanded_force_is_saturated_at_the_effort_limit() {
    let drives = cart_drives(Drive {
        effort: 100.0,
        velocity: 5.0,
        ..Drive::FREE
    });
    let push = |_t: f64, _q: &V1, _v: &V1| V1::new(1e6);
    let mut system = ControlledChain::<f64, Cart, _>::new(drives.around(push));
    let mut state = State::new(0.0, V1::new(0.0), V1::new(0.0));
    for k in 0..100 {
        Rk4.advance(&mut system, &mut state, (k + 1) as f64 * 1e-3, k)
            .unwrap();
    }
    // a = 100 N / 4 kg for 0.1 s.
    assert!((state.v[0] - 2.5).abs() < 1e-12);
    assert!((state.q[0] - 0.125).abs() < 1e-12);
    assert_eq!(drives.over_speed(&state.v), None);
    assert_eq!(drives.over_speed(&V1::new(-5.5)), Some(0));
}

#[test]
fn damping_dissipates_the_integral_of_d_v_squared() {
    let drives = Drives::<f64, 1, 1>::of::<Pendulum>().unwrap();
    let mut system = ControlledChain::<f64, Pendulum, _>::new(drives.around(unforced));
    let mut state = State::new(0.0, V1::new(1.0), V1::new(0.0));
    let energy = |s: &State<f64, _, _>| {
        Pendulum::kinetic_energy(&s.q, &s.v) + Pendulum::potential_energy(&s.q)
    };
    let e0 = energy(&state);
    let (dt, d) = (1e-3, 0.3);
    // Simpson's rule on d·v² over pairs of steps.
    let mut dissipated = 0.0;
    for pair in 0..2500 {
        let p0 = d * state.v[0] * state.v[0];
        Rk4.advance(
            &mut system,
            &mut state,
            (2 * pair + 1) as f64 * dt,
            2 * pair,
        )
        .unwrap();
        let p1 = d * state.v[0] * state.v[0];
        Rk4.advance(
            &mut system,
            &mut state,
            (2 * pair + 2) as f64 * dt,
            2 * pair + 1,
        )
        .unwrap();
        let p2 = d * state.v[0] * state.v[0];
        dissipated += dt / 3.0 * (p0 + 4.0 * p1 + p2);
    }
    let lost = e0 - energy(&state);
    assert!(lost > 0.5, "lost {lost} J");
    assert!(
        (lost - dissipated).abs() < 1e-8 * e0.abs().max(1.0),
        "{lost} vs {dissipated}"
    );
}

#[test]
fn drives_of_a_chain_of_other_sizes_is_an_error() {
    assert!(Drives::<f64, 2, 2>::of::<Pendulum>().is_err());
}

articulated::chain! {
    /// A bead of 0.1 g on a rail along x: a fingertip-light joint.
    chain Bead {
        outputs: [forward_dynamics];
        body bead { mass: 1e-4, com: [0.0, 0.0, 0.0], inertia: diag(1e-9, 1e-9, 1e-9) }
        joint rail: prismatic(x) { parent: world, child: bead }
    }
}

/// The stop's force is continuous: its damper comes in over `stop_depth`, so the force is zero
/// at contact whatever the speed, and the full `stop_damping·v` from `stop_depth` on. An
/// adaptive integrator then takes a light joint through the stop (a force that jumped at
/// contact stalled Dormand–Prince at steps of 1e-12 s), and the bead rests at the stop.
#[test]
fn a_stop_s_force_is_continuous_so_an_adaptive_step_takes_a_light_joint_through_it() {
    let drives = cart_drives(Drive {
        upper: 0.5,
        ..Drive::FREE
    });
    let s = drives.smoothing;
    let zero = V1::zeros();
    let force = |x: f64, v: f64| drives.force(&V1::new(x), &V1::new(v), &zero)[0];
    // At contact, nothing; past the ramp, the spring and the whole damper.
    assert_eq!(force(0.5, 3.0), 0.0);
    let just_in = force(0.5 + 1e-12, 3.0);
    assert!(just_in < 0.0 && just_in > -1e-6, "{just_in}");
    let past = 2.0 * s.stop_depth;
    let deep = force(0.5 + past, 3.0);
    let expected = -s.stop_stiffness * past - s.stop_damping * 3.0;
    assert!(
        (deep - expected).abs() < 1e-12 * expected.abs(),
        "{deep} vs {expected}"
    );
    // Half-way along the ramp, half the damper.
    let half = force(0.5 + 0.5 * s.stop_depth, 3.0);
    let expected = -s.stop_stiffness * 0.5 * s.stop_depth - 0.5 * s.stop_damping * 3.0;
    assert!(
        (half - expected).abs() < 1e-12 * expected.abs(),
        "{half} vs {expected}"
    );

    // Pushed at 1 mN into the stop from 1 m/s, the 0.1 g bead (the damper alone would stop it
    // in 1e-6 s) comes to rest where the spring holds the push, 1 mN / k.
    let push = |_t: f64, _q: &V1, _v: &V1| V1::new(1e-3);
    let mut system = ControlledChain::<f64, Bead, _>::new(drives.around(push));
    let mut state = State::new(0.0, V1::new(0.4), V1::new(1.0));
    // The CLI's default tolerances.
    let mut dopri = Dopri5::new(1e-9, 1e-9);
    dopri.advance(&mut system, &mut state, 1.0, 0).unwrap();
    let rest = 0.5 + 1e-3 / s.stop_stiffness;
    assert!((state.q[0] - rest).abs() < 1e-9, "{} vs {rest}", state.q[0]);
    assert!(state.v[0].abs() < 1e-6, "v = {}", state.v[0]);
}
