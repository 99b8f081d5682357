//! Operational-space control (Khatib 1987) of arm7's flange tracing a circle of 0.1 m radius
//! in 2 s, in a vertical plane in front of the arm, its orientation held, with a posture kept
//! in the null space:
//!
//! ```text
//! τ = Jᵀ·Λ·(ẍ_d + K_d·ė + K_p·e − J̇·v) + nle + (I − Jᵀ·J̄ᵀ)·M·(k_p·(q_post − q) − k_d·v)
//! ```
//!
//! with `J` the flange's LOCAL_WORLD_ALIGNED Jacobian (`6 × 7`, angular rows first) and `J̇` its
//! rate, `Λ` and `J̄` from `articulated::control::operational_space`, the error
//! `e = [log3(R_d·Rᵀ); x_d − x]` (world axes), `ė = [−ω; ẋ_d − ẋ]`, `K_p = 100 s⁻²` and
//! `K_d = 20 s⁻¹` (critically damped); the posture term is scaled by `M` so that its gains
//! are accelerations too (`k_p = 25 s⁻²`, `k_d = 10 s⁻¹`). The arm starts at rest where
//! inverse kinematics (`articulated::ik`, from the posture) puts the flange on the circle's
//! first point; the circle moves off at 0.31 m/s, so the error has a transient, then decays as
//! `ë + K_d·ė + K_p·e = 0`. The same run without the posture term shows what the one
//! redundant degree of freedom (the elbow's swivel) does unattended: the flange is tracked just
//! as well, while the arm drifts.
//!
//! Dynamics generated from `models/arm7.urdf` (`#[derive(Chain)]`, `frames = [link7]`),
//! simulated by RK4 at 1 ms. Prints the worst tracking error after the transient and writes
//! `figures/operational_space.svg` (the tracking error and the posture's deviation against
//! time) into the folder given as its argument (default `target/docs/`;
//! `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example operational_space [-- OUT]
//! ```

use std::f64::consts::PI;

use articulated::control::operational_space::{OperationalSpace, RANK_TOLERANCE};
use articulated::ik::{self, log3, Options, Task, Vec6};
use articulated::integrate::{ControlledChain, Integrator, Rk4, State};
use articulated::nalgebra::{SVector, Vector3};
use articulated::plot::{svg, Panel};
use articulated::prelude::*;
use articulated::FramePlacement;

/// arm7 with what the controller and the simulation need.
#[derive(articulated::Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    outputs = [
        mass_matrix, nonlinear_effects, forward_dynamics, frame_placements, frame_velocities,
        frame_jacobians_local_world_aligned, frame_jacobian_time_variations_local_world_aligned
    ],
    frames = [link7]
)]
struct Arm7;

type Q = SVector<f64, 7>;

/// The circle: radius (m) and period (s).
const RADIUS: f64 = 0.1;
const PERIOD: f64 = 2.0;
/// Task gains (s⁻², s⁻¹) and posture gains.
const KP: f64 = 100.0;
const KD: f64 = 20.0;
const KP_POSTURE: f64 = 25.0;
const KD_POSTURE: f64 = 10.0;
/// Step, duration (three turns), and the end of the transient: one turn, after which the
/// error's envelope `t·e^(−10 t)` is about 10⁻⁷ of its peak.
const DT: f64 = 1e-3;
const T_END: f64 = 3.0 * PERIOD;
const TRANSIENT: f64 = PERIOD;

/// The posture: elbow bent, the flange in front of the arm, pointing forward and down.
fn posture() -> Q {
    Q::from([0.0, 0.5, 0.0, -1.6, 0.0, 0.6, 0.0])
}

/// `(x_d, ẋ_d, ẍ_d)` at `t`: the circle in the plane `x = centre.x`, starting at its top.
fn circle(centre: &Vector3<f64>, t: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let w = 2.0 * PI / PERIOD;
    let (s, c) = (w * t).sin_cos();
    let x = centre + Vector3::new(0.0, RADIUS * s, RADIUS * c);
    let v = Vector3::new(0.0, RADIUS * w * c, -RADIUS * w * s);
    let a = Vector3::new(0.0, -RADIUS * w * w * s, -RADIUS * w * w * c);
    (x, v, a)
}

/// The law of the module docs at `(t, q, v)`, with or without the posture term; NaN couples
/// (which the integrator reports as a fault) where `J·M⁻¹·Jᵀ` loses rank.
fn control(target: &FramePlacement<f64>, posture_task: bool, t: f64, q: &Q, v: &Q) -> Q {
    let [flange] = Arm7::frame_placements(q);
    let [velocity] = Arm7::frame_velocities(q, v);
    let [j] = Arm7::frame_jacobians_local_world_aligned(q);
    let [rate] = Arm7::frame_jacobian_time_variations_local_world_aligned(q, v);
    // The velocity `[ω; ṗ]` in world axes (it is LOCAL), the desired one, and the errors:
    // the rotation from where the flange is turned to where it should be, in world axes, and
    // the position.
    let r = flange.rotation;
    let omega = r * velocity.fixed_rows::<3>(0);
    let x_dot = r * velocity.fixed_rows::<3>(3);
    let (x_d, v_d, a_d) = circle(&target.translation, t);
    let rotation_error = log3(&(target.rotation * r.transpose()));
    let e = stack(&rotation_error, &(x_d - flange.translation));
    let e_dot = stack(&-omega, &(v_d - x_dot));
    let a_d = stack(&Vector3::zeros(), &a_d);
    let m = Arm7::mass_matrix(q);
    let Ok(os) = OperationalSpace::from_mass_matrix(&m, &j, RANK_TOLERANCE) else {
        return Q::from_element(f64::NAN);
    };
    let force = os.inertia * (a_d + e_dot * KD + e * KP - rate * v);
    let mut tau = j.transpose() * force + Arm7::nonlinear_effects(q, v);
    if posture_task {
        let tau_posture = m * ((posture() - q) * KP_POSTURE - v * KD_POSTURE);
        tau += os.project_torque(&j, &tau_posture);
    }
    tau
}

/// `[a; b]`.
fn stack(a: &Vector3<f64>, b: &Vector3<f64>) -> Vec6 {
    Vec6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

/// One run: `(t, |e| in mm)` and `(t, |q − q_post| in rad)` every 10 ms.
struct Run {
    error: Vec<(f64, f64)>,
    posture: Vec<(f64, f64)>,
    /// The largest `|e|` after the transient (m).
    worst_after: f64,
    /// The largest `|e|` over the last turn (m): what integration and rounding leave.
    worst_last: f64,
    /// The largest `|e|` during it (m).
    worst_transient: f64,
    /// The largest angle from the held orientation after the transient (rad).
    worst_angle_after: f64,
}

fn run(q0: &Q, target: &FramePlacement<f64>, posture_task: bool) -> Result<Run, String> {
    let centre = &target.translation;
    let controller = |t: f64, q: &Q, v: &Q| control(target, posture_task, t, q, v);
    let mut system = ControlledChain::<f64, Arm7, _>::new(controller);
    let mut state = State::new(0.0, *q0, Q::zeros());
    let steps = (T_END / DT).round() as usize;
    let mut out = Run {
        error: Vec::new(),
        posture: Vec::new(),
        worst_after: 0.0,
        worst_last: 0.0,
        worst_transient: 0.0,
        worst_angle_after: 0.0,
    };
    for k in 0..=steps {
        let [flange] = Arm7::frame_placements(&state.q);
        let e = (circle(centre, state.t).0 - flange.translation).norm();
        if state.t >= TRANSIENT - 1e-9 {
            out.worst_after = out.worst_after.max(e);
            let angle = log3(&(target.rotation * flange.rotation.transpose())).norm();
            out.worst_angle_after = out.worst_angle_after.max(angle);
            if state.t >= T_END - PERIOD - 1e-9 {
                out.worst_last = out.worst_last.max(e);
            }
        } else {
            out.worst_transient = out.worst_transient.max(e);
        }
        if k % 10 == 0 {
            out.error.push((state.t, 1e3 * e));
            out.posture.push((state.t, (state.q - posture()).norm()));
        }
        if k < steps {
            Rk4.advance(&mut system, &mut state, (k + 1) as f64 * DT, k)
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(out)
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    // The circle's centre: where the flange is at the posture; its orientation, held.
    let [target] = Arm7::frame_placements(&posture());
    let centre = target.translation;
    // Start on the circle: the flange at its first point with that orientation, by inverse
    // kinematics from the posture.
    let start = FramePlacement {
        translation: circle(&centre, 0.0).0,
        ..target
    };
    let solved = ik::solve::<Arm7, 7, 7, 1>(&[Task::pose(start)], &posture(), &Options::default())
        .map_err(|e| e.to_string())?;
    println!(
        "arm7's flange on a circle of {RADIUS} m radius in {PERIOD} s around {:.3?} m, its \
         orientation held, operational-space control (K_p = {KP} s⁻², K_d = {KD} s⁻¹), RK4 at {DT} s for {T_END} s",
        centre.as_slice()
    );
    println!(
        "start by inverse kinematics: {} iterations, {:.1e} m and {:.1e} rad from the target, \
         {:.3} rad from the posture",
        solved.iterations,
        solved.residual.position,
        solved.residual.rotation,
        (solved.q - posture()).norm()
    );
    let with = run(&solved.q, &target, true)?;
    let without = run(&solved.q, &target, false)?;
    for (name, r) in [("with the posture task", &with), ("without it", &without)] {
        println!(
            "{name}: tracking error up to {:.2} mm in the first {TRANSIENT} s, then at most \
             {:.1e} m and {:.1e} rad ({:.1e} m over the last turn); posture deviation up to \
             {:.3} rad",
            1e3 * r.worst_transient,
            r.worst_after,
            r.worst_angle_after,
            r.worst_last,
            r.posture.iter().map(|p| p.1).fold(0.0, f64::max)
        );
    }
    let error = Panel::new(
        "Tracking error of the flange on its circle",
        "t (s)",
        "|x_d − x| (mm)",
    )
    .with("with the posture task", with.error)
    .with("without it", without.error);
    let posture = Panel::new(
        "The posture's deviation, left to the null space",
        "t (s)",
        "|q − q_posture| (rad)",
    )
    .with("with the posture task", with.posture)
    .with("without it", without.posture);
    let text = svg(&[error, posture], 900, 320).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("operational_space.svg"), text.as_bytes())?;
    println!("wrote {file}");
    Ok(())
}
