//! Mimic joints (issue 14), generated: the gripper of `data/gripper_mimic.urdf`, whose second
//! finger mirrors the first, whose fingertip follows the elbow (an ancestor) with a multiplier
//! and an offset, whose thumb turns with the first finger's travel, and with an independent
//! knuckle below a mimic joint. Held to:
//! - Pinocchio 4.1 with `buildModelFromUrdf(…, mimic=True)` (`data/pinocchio-mimic.json`, made
//!   by `data/make_mimic_reference.py`): M, bias, gravity, τ and q̈ to 1e-12;
//! - the hand-written equivalent: the same URDF with the `<mimic>` elements removed, generated
//!   as an independent 8-coordinate arm, and `G` written out here: `M = Gᵀ·M_tree·G`,
//!   `τ = Gᵀ·τ_tree(G·q + o, G·v, G·a)`, the whole-body quantities at the tree's state, the
//!   derivatives `Gᵀ·∂τ_tree·G`;
//! - the reference on random states, every generated output;
//! - closed forms, on a parallelogram written in the `.chain` grammar
//!   (`data/parallelogram.chain`).

mod common;

use articulated::nalgebra::{DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::urdf::from_urdf_str;
use articulated_dynamics::random::random_state;
use common::{
    centroidal_rate_by_differences, centroidal_rate_errors, check_chain, compare_pinocchio,
    coriolis_error, read_json, rel_err, whole_body_errors,
};

/// Every output there is.
#[derive(Chain)]
#[chain(
    urdf = "data/gripper_mimic.urdf",
    outputs = [
        mass_matrix, bias, gravity, inverse_dynamics, nonlinear_effects, forward_dynamics,
        center_of_mass, center_of_mass_velocity, center_of_mass_jacobian, centroidal_momentum,
        centroidal_momentum_matrix, centroidal_momentum_rate, centroidal_momentum_drift,
        kinetic_energy, potential_energy, coriolis_matrix, inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse
    ]
)]
struct Gripper;

/// The gripper with every `<mimic>` removed: eight independent coordinates.
#[derive(Chain)]
#[chain(
    urdf = "data/gripper_independent.urdf",
    outputs = [
        mass_matrix, inverse_dynamics, kinetic_energy, center_of_mass_jacobian,
        inverse_dynamics_derivatives
    ]
)]
struct Independent;

/// The parallelogram: one coordinate, its platform following the bar by `−θ`.
#[derive(Chain)]
#[chain(
    file = "data/parallelogram.chain",
    outputs = [mass_matrix, gravity, bias, forward_dynamics, kinetic_energy]
)]
struct Parallelogram;

/// The arm with its gripper locked half open: `finger_left` at 2 cm, and with it the joints
/// that follow it (`finger_right`, `thumb`).
#[derive(Chain)]
#[chain(
    urdf = "data/gripper_mimic.urdf",
    lock = [finger_left(0.02)],
    outputs = [mass_matrix, inverse_dynamics]
)]
struct GripperHeld;

const NQ: usize = 5;
const NT: usize = 8;

/// Tree coordinate `k` = `Σ_j G[k][j]·q_j + o[k]`. Tree order: shoulder, elbow, wrist,
/// finger_left, left_tip (= −0.5·elbow + 0.3), finger_right (= finger_left), right_knuckle,
/// thumb (= 12·finger_left − 0.2).
fn coupling() -> (SMatrix<f64, NT, NQ>, SVector<f64, NT>) {
    let mut g = SMatrix::<f64, NT, NQ>::zeros();
    for (row, (col, k)) in [
        (0, 1.0),
        (1, 1.0),
        (2, 1.0),
        (3, 1.0),
        (1, -0.5),
        (3, 1.0),
        (4, 1.0),
        (3, 12.0),
    ]
    .into_iter()
    .enumerate()
    {
        g[(row, col)] = k;
    }
    let mut o = SVector::<f64, NT>::zeros();
    o[4] = 0.3;
    o[7] = -0.2;
    (g, o)
}

fn reference() -> Reference {
    let xml = std::fs::read_to_string("data/gripper_mimic.urdf").unwrap();
    Reference::new(&from_urdf_str(&xml, false).unwrap().model).unwrap()
}

#[test]
fn against_pinocchio_with_mimic_joints() {
    let case = read_json("data/pinocchio-mimic.json");
    let failures = compare_pinocchio::<Gripper, NQ, NQ>("gripper_mimic", &case, 1e-12);
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn against_the_hand_written_independent_tree() {
    let (g, o) = coupling();
    let r = reference();
    for seed in 0..20 {
        let (q, v, a) = random_state(r.model(), seed);
        let (q, v, a) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NQ>::from_column_slice(&v),
            SVector::<f64, NQ>::from_column_slice(&a),
        );
        let (qt, vt, at) = (g * q + o, g * v, g * a);
        let m = Gripper::mass_matrix(&q);
        let m_hand = g.transpose() * Independent::mass_matrix(&qt) * g;
        assert!(
            rel_err(m.as_slice(), m_hand.as_slice()) < 1e-14,
            "M, seed {seed}"
        );
        let tau = Gripper::inverse_dynamics(&q, &v, &a);
        let tau_hand = g.transpose() * Independent::inverse_dynamics(&qt, &vt, &at);
        assert!(
            rel_err(tau.as_slice(), tau_hand.as_slice()) < 1e-13,
            "τ, seed {seed}"
        );
        let e = Gripper::kinetic_energy(&q, &v);
        assert!((e - Independent::kinetic_energy(&qt, &vt)).abs() < 1e-14 * e.max(1.0));
        let j = Gripper::center_of_mass_jacobian(&q);
        let j_hand = Independent::center_of_mass_jacobian(&qt) * g;
        assert!(
            rel_err(j.as_slice(), j_hand.as_slice()) < 1e-14,
            "J_G, seed {seed}"
        );
        let (dq, dv) = Gripper::inverse_dynamics_derivatives(&q, &v, &a);
        let (dq_t, dv_t) = Independent::inverse_dynamics_derivatives(&qt, &vt, &at);
        let (dq_hand, dv_hand) = (g.transpose() * dq_t * g, g.transpose() * dv_t * g);
        assert!(
            rel_err(dq.as_slice(), dq_hand.as_slice()) < 1e-12,
            "∂τ/∂q, seed {seed}"
        );
        assert!(
            rel_err(dv.as_slice(), dv_hand.as_slice()) < 1e-12,
            "∂τ/∂v, seed {seed}"
        );
        // Forward dynamics inverts inverse dynamics, and its derivatives are −M⁻¹·∂τ.
        let qdd = Gripper::forward_dynamics(&q, &v, &tau).unwrap();
        assert!(
            rel_err(qdd.as_slice(), a.as_slice()) < 1e-10,
            "q̈, seed {seed}"
        );
        let (ddq_dq, ddq_dv, minv) = Gripper::forward_dynamics_derivatives(&q, &v, &tau).unwrap();
        assert!((minv * m - SMatrix::<f64, NQ, NQ>::identity()).amax() < 1e-10);
        let scale = dq.amax() * minv.amax();
        assert!(
            (ddq_dq + minv * dq).amax() < 1e-10 * scale,
            "∂q̈/∂q, seed {seed}"
        );
        assert!(
            (ddq_dv + minv * dv).amax() < 1e-10 * scale.max(1.0),
            "∂q̈/∂v"
        );
        let minv_alone = Gripper::mass_matrix_inverse(&q).unwrap();
        assert!(rel_err(minv_alone.as_slice(), minv.as_slice()) < 1e-12);
    }
}

#[test]
fn every_output_against_the_reference() {
    let r = reference();
    check_chain::<Gripper, NQ, NQ>("gripper_mimic", &r, &(), 40, |seed| {
        random_state(r.model(), seed)
    });
    for seed in 0..20 {
        let (q, v, a) = random_state(r.model(), seed);
        let e = whole_body_errors::<Gripper, NQ, NQ>(&r, &q, &v);
        assert!(e.iter().all(|&e| e < 1e-12), "{e:?}");
        let e = centroidal_rate_errors::<Gripper, NQ, NQ>(&r, &q, &v, &a);
        assert!(e.iter().all(|&e| e < 1e-12), "{e:?}");
        // The mimic joints' accelerations too, independently of the coupling's code: the rate
        // against differences of the generated momentum along the motion.
        let [differences, drift] =
            centroidal_rate_by_differences::<Gripper, NQ, NQ>(&q, &v, &a, 1e-3);
        assert!(
            differences < 1e-9 && drift < 1e-12,
            "{differences:e} {drift:e}"
        );
        assert!(coriolis_error::<Gripper, NQ, NQ>(&r, &q, &v) < 1e-12);
        let qs = SVector::<f64, NQ>::from_column_slice(&q);
        let vs = SVector::<f64, NQ>::from_column_slice(&v);
        let nle = Gripper::nonlinear_effects(&qs, &vs);
        let want = r.bias(&q, &v).unwrap() + r.gravity(&q).unwrap();
        assert!(rel_err(nle.as_slice(), want.as_slice()) < 1e-12);
        let minv = Gripper::mass_matrix_inverse(&qs).unwrap();
        let want: DMatrix<f64> = r.mass_matrix_inverse(&q).unwrap();
        assert!(rel_err(minv.as_slice(), want.as_slice()) < 1e-10);
    }
}

#[test]
fn a_mimic_joint_has_no_coordinate_or_drive_of_its_own() {
    // shoulder, elbow, wrist, finger_left, right_knuckle.
    assert_eq!(Gripper::COORDINATES.len(), NQ);
    assert_eq!(Gripper::DRIVES.len(), NQ);
    assert_eq!(Gripper::DRIVES[3].upper, 0.04);
}

#[test]
fn a_parallelogram_from_the_grammar_has_its_closed_forms() {
    let (m_bar, c, i_bar, m_platform, l, rotor) = (2.0, 0.4, 0.05, 3.0, 0.9, 0.02);
    // The platform only translates: a point mass at the bar's tip, plus the rotor, which turns
    // at −θ̇ relative to the bar.
    let inertia = i_bar + m_bar * c * c + m_platform * l * l + rotor;
    for theta in [-2.5, -0.4, 0.0, 0.6, 2.0] {
        let q = SVector::<f64, 1>::new(theta);
        let v = SVector::<f64, 1>::new(2.0);
        let m = Parallelogram::mass_matrix(&q)[(0, 0)];
        assert!((m - inertia).abs() < 1e-14, "M {m} vs {inertia}");
        let g = Parallelogram::gravity(&q)[0];
        let closed = -(m_bar * c + m_platform * l) * 9.81 * theta.cos();
        assert!((g - closed).abs() < 1e-13, "g {g} vs {closed}");
        assert!(Parallelogram::bias(&q, &v)[0].abs() < 1e-13);
        let e = Parallelogram::kinetic_energy(&q, &v);
        assert!((e - 0.5 * inertia * 4.0).abs() < 1e-13);
        let tau = SVector::<f64, 1>::new(1.0);
        let qdd = Parallelogram::forward_dynamics(&q, &v, &tau).unwrap()[0];
        assert!((qdd - (1.0 - closed) / inertia).abs() < 1e-13, "q̈ {qdd}");
    }
}

#[test]
fn a_held_gripper_is_the_coupled_arm_with_its_finger_still() {
    // shoulder, elbow, wrist, right_knuckle move; finger_left is held at 0.02 with zero rate.
    for seed in 0..10 {
        let (q, v, a) = random_state(reference().model(), seed);
        let full = |x: &[f64], finger: f64| {
            SVector::<f64, NQ>::from_column_slice(&[x[0], x[1], x[2], finger, x[4]])
        };
        let (qf, vf, af) = (full(&q, 0.02), full(&v, 0.0), full(&a, 0.0));
        let pick = |x: &[f64]| SVector::<f64, 4>::from_column_slice(&[x[0], x[1], x[2], x[4]]);
        let (qh, vh, ah) = (pick(&q), pick(&v), pick(&a));
        let m = Gripper::mass_matrix(&qf);
        let sub = m.select_rows(&[0, 1, 2, 4]).select_columns(&[0, 1, 2, 4]);
        let held = GripperHeld::mass_matrix(&qh);
        assert!(
            rel_err(held.as_slice(), sub.as_slice()) < 1e-14,
            "M, seed {seed}"
        );
        let tau = Gripper::inverse_dynamics(&qf, &vf, &af);
        let sub: Vec<f64> = [0, 1, 2, 4].iter().map(|&k| tau[k]).collect();
        let held = GripperHeld::inverse_dynamics(&qh, &vh, &ah);
        assert!(rel_err(held.as_slice(), &sub) < 1e-13, "τ, seed {seed}");
    }
}
