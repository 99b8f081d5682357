//! Hemami, Dariush & Barin (2005), inversion on the two-link system: from a prescribed sway of
//! the legs and trunk, compute the joint couples that produce it (inverse dynamics), then drive
//! the forward dynamics with those couples and check that the same motion comes back.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example hemami_inversion
//! ```

use std::f64::consts::PI;
use std::path::Path;

use articulated::reference::Reference;
use articulated_codegen::load::load_model;

/// The prescribed motion: the ankle sways forward and sideways, the hip counter-rotates.
/// Returns (q, q̇, q̈) at time t; coordinates [ankle x, y, z, hip x, y, z] (roll, pitch, yaw).
fn sway(t: f64) -> ([f64; 6], [f64; 6], [f64; 6]) {
    // amplitude (rad) and angular frequency (rad/s) of each coordinate
    let amp = [0.03, 0.08, 0.0, -0.02, -0.15, 0.05];
    let w = [
        2.0 * PI * 0.4,
        2.0 * PI * 0.5,
        0.0,
        2.0 * PI * 0.4,
        2.0 * PI * 0.5,
        2.0 * PI * 0.3,
    ];
    let mut q = [0.0; 6];
    let mut v = [0.0; 6];
    let mut a = [0.0; 6];
    for i in 0..6 {
        q[i] = amp[i] * (w[i] * t).sin();
        v[i] = amp[i] * w[i] * (w[i] * t).cos();
        a[i] = -amp[i] * w[i] * w[i] * (w[i] * t).sin();
    }
    (q, v, a)
}

/// How the couples are chosen during the replay.
#[derive(Clone, Copy)]
enum Drive {
    /// The inverted couples alone.
    OpenLoop,
    /// Inverse dynamics at the measured state with a corrected acceleration
    /// `q̈_ref + kp·(q_ref − q) + kd·(q̇_ref − q̇)`: the error then obeys `ë + kd·ė + kp·e = 0`.
    ComputedTorque { kp: f64, kd: f64 },
}

/// Replays the sway with RK4 (step `dt`, `steps` steps) and returns the largest deviation from it
/// at each printed time (every `every` steps), with the couples applied there.
fn replay(
    dynamics: &Reference,
    drive: Drive,
    dt: f64,
    steps: usize,
    every: usize,
) -> Result<Vec<(f64, Vec<f64>, f64)>, articulated::reference::Error> {
    let couples = |t: f64, x: &[f64]| -> Result<Vec<f64>, articulated::reference::Error> {
        let (q, v, a) = sway(t);
        let tau = match drive {
            Drive::OpenLoop => dynamics.inverse_dynamics(&q, &v, &a)?,
            Drive::ComputedTorque { kp, kd } => {
                let a_cmd: Vec<f64> = (0..6)
                    .map(|i| a[i] + kp * (q[i] - x[i]) + kd * (v[i] - x[6 + i]))
                    .collect();
                dynamics.inverse_dynamics(&x[..6], &x[6..], &a_cmd)?
            }
        };
        Ok(tau.as_slice().to_vec())
    };
    let deriv = |t: f64, x: &[f64]| -> Result<Vec<f64>, articulated::reference::Error> {
        let qdd = dynamics.forward_dynamics(&x[..6], &x[6..], &couples(t, x)?)?;
        Ok(x[6..].iter().copied().chain(qdd.iter().copied()).collect())
    };
    let (q0, v0, _) = sway(0.0);
    let mut x: Vec<f64> = q0.iter().chain(&v0).copied().collect();
    let mut rows = Vec::new();
    for k in 0..=steps {
        let t = k as f64 * dt;
        if k % every == 0 {
            let (q_ref, _, _) = sway(t);
            let err = q_ref
                .iter()
                .zip(&x)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            rows.push((t, couples(t, &x)?, err));
        }
        if k == steps {
            break;
        }
        let k1 = deriv(t, &x)?;
        let x2: Vec<f64> = x.iter().zip(&k1).map(|(a, b)| a + 0.5 * dt * b).collect();
        let k2 = deriv(t + 0.5 * dt, &x2)?;
        let x3: Vec<f64> = x.iter().zip(&k2).map(|(a, b)| a + 0.5 * dt * b).collect();
        let k3 = deriv(t + 0.5 * dt, &x3)?;
        let x4: Vec<f64> = x.iter().zip(&k3).map(|(a, b)| a + dt * b).collect();
        let k4 = deriv(t + dt, &x4)?;
        for i in 0..12 {
            x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    Ok(rows)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/two_link.chain");
    let model = load_model(&path, false)?;
    let dynamics = Reference::new(&model)?;
    let (dt, steps, every) = (1e-3, 4000, 500);

    println!("Hemami two-link: the couples that produce a sway (inverse dynamics), replayed");
    println!("through forward dynamics (RK4, dt = {dt} s).\n");
    let open = replay(&dynamics, Drive::OpenLoop, dt, steps, every)?;
    let closed = replay(
        &dynamics,
        Drive::ComputedTorque {
            kp: 100.0,
            kd: 20.0,
        },
        dt,
        steps,
        every,
    )?;
    println!(
        "{:>5}  {:>22}  {:>22}  {:>11}  {:>11}",
        "t (s)", "ankle couple (N·m)", "hip couple (N·m)", "open loop", "feedback"
    );
    println!(
        "{:>5}  {:>22}  {:>22}  {:>11}  {:>11}",
        "", "roll   pitch   yaw", "roll   pitch   yaw", "|Δq| (rad)", "|Δq| (rad)"
    );
    for ((t, tau, err_open), (_, _, err_closed)) in open.iter().zip(&closed) {
        println!(
            "{t:5.2}  {:7.2} {:7.2} {:6.2}  {:7.2} {:7.2} {:6.2}  {err_open:11.2e}  {err_closed:11.2e}",
            tau[0], tau[1], tau[2], tau[3], tau[4], tau[5]
        );
    }
    println!(
        "\nThe upright two-link is unstable: open loop, the integration error grows about e-fold every\n\
         0.13 s until the chain falls. Computed-torque feedback (kp = 100, kd = 20) holds it on the\n\
         sway: inversion gives the couples, stabilization needs feedback."
    );
    Ok(())
}
