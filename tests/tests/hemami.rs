//! Hemami, Dariush & Barin (2005) on the generated two-link system, with the runtime's own
//! integrators: stabilization from a 10° lean in 16 directions by both controllers (§4), the
//! couples recovered from a simulated, noise-free trajectory (§5), and the joint wrenches from
//! the ground up against those from the trunk down on simulated states.

use std::f64::consts::PI;

use articulated::control::computed_torque::{computed_torque, hold};
use articulated::control::linearize::{exact, linearize};
use articulated::control::riccati::lqr;
use articulated::control::state_feedback::{split_gain, state_feedback};
use articulated::control::Controller;
use articulated::differentiate::SavitzkyGolay;
use articulated::integrate::{ControlledChain, Rk4, State};
use articulated::invert::couples;
use articulated::nalgebra::{Const, DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated::simulate::Simulation;
use articulated::trajectory::Trajectory;

#[derive(Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [
        gravity, inverse_dynamics, forward_dynamics, joint_wrenches, joint_wrenches_bottom_up,
        forward_dynamics_derivatives
    ]
)]
struct TwoLink;

type V6 = SVector<f64, 6>;
type M6 = SMatrix<f64, 6, 6>;

/// The LQR gains about upright (`Q = diag(100·I, 10·I)`, `R = 0.01·I`), on the linearization
/// from the generated exact derivatives, which central differences of the generated forward
/// dynamics confirm (to their own accuracy, 1e-7).
fn lqr_gains() -> (M6, M6) {
    let (zero, g) = (V6::zeros(), TwoLink::gravity(&V6::zeros()));
    let lin = exact::<TwoLink, 6, 6>(&zero, &zero, &g).unwrap();
    let by_differences = linearize(&zero, &g, TwoLink::forward_dynamics).unwrap();
    let scale = lin.a.amax().max(lin.b.amax());
    let off = (&lin.a - &by_differences.a)
        .amax()
        .max((&lin.b - &by_differences.b).amax());
    assert!(
        off < 1e-7 * scale,
        "exact against central differences: {off:e} of {scale:e}"
    );
    let q = DMatrix::from_diagonal(&articulated::nalgebra::DVector::from_fn(12, |i, _| {
        if i < 6 {
            100.0
        } else {
            10.0
        }
    }));
    let design = lqr(&lin.a, &lin.b, &q, &(DMatrix::identity(6, 6) * 0.01)).unwrap();
    split_gain::<6>(&design.k).unwrap()
}

/// Simulates the two-link under `law` from `(q0, v0)` with RK4.
fn run(
    law: impl Controller<6, 6>,
    q0: V6,
    v0: V6,
    t_end: f64,
    dt: f64,
) -> Trajectory<f64, Const<6>, Const<6>> {
    let mut path = Trajectory::new();
    Simulation::new(0.0, t_end, dt)
        .record(
            &mut ControlledChain::<f64, TwoLink, _>::new(law),
            &mut Rk4,
            State::new(0.0, q0, v0),
            &mut path,
            |_, _| {},
        )
        .unwrap_or_else(|f| panic!("{f}"));
    path
}

fn lqr_law(kq: M6, kv: M6) -> impl Controller<6, 6> {
    let g = TwoLink::gravity(&V6::zeros());
    state_feedback(TwoLink::COORDINATES, V6::zeros(), V6::zeros(), g, kq, kv).unwrap()
}

#[test]
fn both_controllers_recover_from_a_10_degree_lean_in_16_directions() {
    let (kq, kv) = lqr_gains();
    let tilt = 10f64.to_radians();
    for i in 0..16 {
        let phi = 2.0 * PI * f64::from(i) / 16.0;
        let q0 = V6::from_column_slice(&[tilt * phi.sin(), tilt * phi.cos(), 0.0, 0.0, 0.0, 0.0]);
        let kp = M6::identity() * 25.0;
        let kd = M6::identity() * 10.0;
        let ct = computed_torque(
            TwoLink::COORDINATES,
            kp,
            kd,
            hold(V6::zeros()),
            TwoLink::inverse_dynamics,
        )
        .unwrap();
        for (name, path) in [
            ("LQR", run(lqr_law(kq, kv), q0, V6::zeros(), 5.0, 2e-3)),
            ("computed torque", run(ct, q0, V6::zeros(), 5.0, 2e-3)),
        ] {
            let end = path.states().last().unwrap();
            assert!(
                end.q.amax() < 1e-3 && end.v.amax() < 1e-3,
                "{name}, direction {i}: q {}, v {} after 5 s",
                end.q,
                end.v
            );
        }
    }
}

#[test]
fn couples_recovered_from_a_simulated_motion_match_the_applied_ones() {
    let (kq, kv) = lqr_gains();
    let push = V6::from_column_slice(&[0.0, -0.3, 0.0, 0.0, 1.0, 0.0]);
    let path = run(lqr_law(kq, kv), V6::zeros(), push, 3.0, 1e-3);
    let mut law = lqr_law(kq, kv);
    let t: Vec<f64> = path.states().iter().map(|s| s.t).collect();
    let q: Vec<f64> = path
        .states()
        .iter()
        .flat_map(|s| s.q.iter().copied().collect::<Vec<_>>())
        .collect();
    let applied: Vec<V6> = path.states().iter().map(|s| law(s.t, &s.q, &s.v)).collect();
    let sg = SavitzkyGolay::new(5, 4).unwrap();
    let got = couples::<6, 6, _>(TwoLink::COORDINATES, &t, &q, &sg, |q, v, a| {
        TwoLink::inverse_dynamics(q, v, a)
    })
    .unwrap();
    let scale = applied.iter().map(|a| a.amax()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for r in 0..got.t.len() {
        let want = applied[got.first_sample + r];
        let e = (V6::from_column_slice(got.row(r).unwrap()) - want).amax() / scale;
        worst = worst.max(e);
    }
    println!("couples from 1 kHz noise-free samples: {worst:.1e} of the largest ({scale:.0} N·m)");
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn wrenches_top_down_and_bottom_up_agree_on_simulated_states() {
    let (kq, kv) = lqr_gains();
    let q0 = V6::from_column_slice(&[0.1, 0.15, 0.0, 0.05, -0.2, 0.1]);
    let path = run(lqr_law(kq, kv), q0, V6::zeros(), 2.0, 2e-3);
    let mut law = lqr_law(kq, kv);
    let mut worst = 0.0f64;
    for s in path.states() {
        let a = TwoLink::forward_dynamics(&s.q, &s.v, &law(s.t, &s.q, &s.v)).unwrap();
        let down = TwoLink::joint_wrenches(&s.q, &s.v, &a);
        // The ground reaction a force plate under the ankle measures: the first joint's wrench.
        let up = TwoLink::joint_wrenches_bottom_up(&s.q, &s.v, &a, &down.column(0).into_owned());
        worst = worst.max((up - down).amax() / down.amax());
    }
    assert!(worst < 1e-9, "{worst:e}");
}
