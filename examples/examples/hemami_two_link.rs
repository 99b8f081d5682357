//! Hemami, Dariush & Barin (2005) on their two-link system (legs on a spherical ankle, trunk on a
//! spherical hip), with dynamics generated at compile time:
//!
//! 1. the chain swings free (hanging from the ankle, τ = 0): RK4 keeps its energy;
//! 2. it balances upright under feedback after a push (§4): an LQR design on the linearization
//!    about upright, and computed torque with PD, each from the same push; then, over 16
//!    directions, the largest initial lean each one recovers from;
//! 3. it recovers the couples it applied from its own recorded, noise-added trajectory (§5):
//!    Savitzky–Golay derivatives, generated inverse dynamics, and the joint wrenches top-down
//!    and bottom-up from the measured ground reaction.
//!
//! It prints a short report and writes three plots to `figures/` in the folder given as its
//! argument (default `target/docs/`; `articulated_examples::output`). The README shows those
//! in `docs/figures/`, which `scripts/figures.sh` regenerates.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example hemami_two_link [-- OUT]
//! ```

use std::f64::consts::PI;
use std::path::Path;

use articulated::control::computed_torque::{computed_torque, hold};
use articulated::control::riccati::spectral_abscissa;
use articulated::control::state_feedback::{split_gain, state_feedback};
use articulated::control::Controller;
use articulated::differentiate::SavitzkyGolay;
use articulated::integrate::{ControlledChain, Rk4, SecondOrder, State};
use articulated::invert::couples;
use articulated::nalgebra::{SMatrix, SVector};
use articulated::plot::{svg, Panel};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated::trajectory::Trajectory;
use articulated_dynamics::random::Rng;
use articulated_examples::hemami::upright_lqr;
use articulated_examples::output::Output;

/// Hemami's two-link system, generated from its description, with its joint wrenches.
#[derive(Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [mass_matrix, gravity, inverse_dynamics, forward_dynamics, joint_wrenches,
               joint_wrenches_bottom_up, forward_dynamics_derivatives]
)]
struct TwoLink;

type V6 = SVector<f64, 6>;
type M6 = SMatrix<f64, 6, 6>;
type C6 = articulated::nalgebra::Const<6>;
type Path6 = Trajectory<f64, C6, C6>;

/// Coordinates: ankle roll, pitch, yaw, hip roll, pitch, yaw (`xyz` Euler angles each).
const NAMES: [&str; 6] = [
    "ankle roll",
    "ankle pitch",
    "ankle yaw",
    "hip roll",
    "hip pitch",
    "hip yaw",
];

/// Steps `system` with RK4 from `(q0, v0)` for `t_end` s; the states every `dt`.
fn simulate<S: SecondOrder<f64, C6, C6>>(
    system: &mut S,
    q0: V6,
    v0: V6,
    t_end: f64,
    dt: f64,
) -> Result<Path6, String> {
    let mut path = Trajectory::new();
    articulated::simulate::Simulation::new(0.0, t_end, dt)
        .record(
            system,
            &mut Rk4,
            State::new(0.0, q0, v0),
            &mut path,
            |_, _| {},
        )
        .map_err(|f| f.to_string())?;
    Ok(path)
}

/// The LQR gains about upright: `A`, `B` from the generated exact derivatives of forward
/// dynamics (`forward_dynamics_derivatives`), `Q = diag(100·I, 10·I)`, `R = 0.01·I`.
fn lqr_gains() -> Result<(M6, M6, f64, f64), String> {
    let (lin, design) = upright_lqr::<TwoLink, 6>()?;
    let open = spectral_abscissa(&lin.a).unwrap_or(f64::NAN);
    let closed = spectral_abscissa(&(&lin.a - &lin.b * &design.k)).unwrap_or(f64::NAN);
    let (kq, kv) = split_gain::<6>(&design.k).ok_or("the gain is not 6 × 12")?;
    Ok((kq, kv, open, closed))
}

/// What a person's joints can give: each coordinate's couple is held to ±250 N·m (of the order
/// of an adult's ankle and hip strength), so how far a controller can lean back is a question of
/// its strategy, not of unlimited torque.
const COUPLE_LIMIT: f64 = 250.0;

/// The two controllers, as closures of `(t, q, v)`, their couples held to [`COUPLE_LIMIT`].
struct Controllers {
    kq: M6,
    kv: M6,
}

/// `law`'s couples clamped to `±limit`.
fn saturated(mut law: impl Controller<6, 6>, limit: f64) -> impl Controller<6, 6> {
    move |t: f64, q: &V6, v: &V6| law(t, q, v).map(|x| x.clamp(-limit, limit))
}

impl Controllers {
    /// `τ = g(0) − K_q·q − K_v·v`, saturated.
    fn lqr(&self) -> impl Controller<6, 6> {
        let law = state_feedback(
            TwoLink::COORDINATES,
            V6::zeros(),
            V6::zeros(),
            TwoLink::gravity(&V6::zeros()),
            self.kq,
            self.kv,
        );
        let law = law.unwrap_or_else(|e| unreachable!("the two-link's coordinates: {e}"));
        saturated(law, COUPLE_LIMIT)
    }

    /// `τ = ID(q, v, −25·q − 10·v)` (each coordinate's error obeys `ë + 10·ė + 25·e = 0` while
    /// no couple saturates), saturated.
    fn computed_torque(&self) -> impl Controller<6, 6> {
        let (kp, kd) = (M6::identity() * 25.0, M6::identity() * 10.0);
        let law = computed_torque(
            TwoLink::COORDINATES,
            kp,
            kd,
            hold(V6::zeros()),
            TwoLink::inverse_dynamics,
        );
        let law = law.unwrap_or_else(|e| unreachable!("the two-link's coordinates: {e}"));
        saturated(law, COUPLE_LIMIT)
    }
}

/// A lean of `tilt` at the ankle in the direction `phi` (0: forward, about y).
fn lean(tilt: f64, phi: f64) -> V6 {
    V6::from_column_slice(&[tilt * phi.sin(), tilt * phi.cos(), 0.0, 0.0, 0.0, 0.0])
}

/// Whether `law` brings the chain back upright (|q|, |v| < 1e-3 after 6 s) from `q0` at rest.
fn recovers(law: impl FnMut(f64, &V6, &V6) -> V6, q0: V6) -> bool {
    let mut system = ControlledChain::<f64, TwoLink, _>::new(law);
    match simulate(&mut system, q0, V6::zeros(), 6.0, 2e-3) {
        Ok(path) => path
            .states()
            .last()
            .is_some_and(|s| s.q.amax() < 1e-3 && s.v.amax() < 1e-3),
        Err(_) => false,
    }
}

/// The largest lean in direction `phi` that `make()`'s law recovers from, to 0.1°, up to 85°
/// (the Euler angles' gimbal lock is at 90°).
fn largest_lean<F: FnMut(f64, &V6, &V6) -> V6>(mut make: impl FnMut() -> F, phi: f64) -> f64 {
    let (mut ok, mut bad) = (0.0f64, 85f64.to_radians());
    if recovers(make(), lean(bad, phi)) {
        return bad;
    }
    while bad - ok > 0.1f64.to_radians() {
        let mid = 0.5 * (ok + bad);
        if recovers(make(), lean(mid, phi)) {
            ok = mid;
        } else {
            bad = mid;
        }
    }
    ok
}

/// The series of coordinate `k` of a path's positions.
fn positions(path: &Path6, k: usize) -> Vec<(f64, f64)> {
    path.states().iter().map(|s| (s.t, s.q[k])).collect()
}

/// Writes a figure to `figures/name` in the folder the user chose; the path written.
fn save(out: &Output, name: &str, panels: &[Panel]) -> Result<String, String> {
    let text = svg(panels, 900, 330).map_err(|e| e.to_string())?;
    out.write(&out.figure(name), text.as_bytes())
}

/// Part 1: the free swing and its energy, by the reference's energy functions.
fn free_swing(out: &Output, reference: &Reference) -> Result<(), String> {
    let q0 = V6::from_column_slice(&[PI - 0.4, 0.2, 0.0, 0.0, -0.3, 0.0]);
    let v0 = V6::from_column_slice(&[0.0, 0.0, 0.5, 0.0, 0.0, 0.0]);
    let path = simulate(
        &mut ControlledChain::<f64, TwoLink, _>::unforced(),
        q0,
        v0,
        10.0,
        1e-3,
    )?;
    let energy = |s: &State<f64, C6, C6>| -> Result<(f64, f64), String> {
        let q = s.q.as_slice();
        let k = reference
            .kinetic_energy(q, s.v.as_slice())
            .map_err(|e| e.to_string())?;
        let p = reference.potential_energy(q).map_err(|e| e.to_string())?;
        Ok((k, p))
    };
    let e: Vec<(f64, (f64, f64))> = path
        .states()
        .iter()
        .step_by(10)
        .map(|s| energy(s).map(|e| (s.t, e)))
        .collect::<Result<_, _>>()?;
    let total = |&(t, (k, p)): &(f64, (f64, f64))| (t, k + p);
    let e0 = total(&e[0]).1;
    let swing = e.iter().map(|(_, (k, _))| *k).fold(0.0, f64::max);
    let drift = e
        .iter()
        .map(|x| (total(x).1 - e0).abs())
        .fold(0.0, f64::max);
    println!(
        "1. Free swing, hanging from the ankle, 10 s by RK4 at dt = 1 ms: energy kept to {:.1e} \
         of the swing's {swing:.1} J",
        drift / swing
    );
    let mut angles = Panel::new("Free swing: joint angles", "t (s)", "angle (rad)");
    for k in [0, 1, 2, 4] {
        angles = angles.with(NAMES[k], positions(&path, k));
    }
    let energies = Panel::new("Free swing: energy", "t (s)", "energy (J)")
        .with("kinetic", e.iter().map(|&(t, (k, _))| (t, k)).collect())
        .with(
            "potential − its start",
            e.iter().map(|&(t, (_, p))| (t, p - e[0].1 .1)).collect(),
        )
        .with(
            "total − its start",
            e.iter().map(|x| (x.0, total(x).1 - e0)).collect(),
        );
    let file = save(out, "hemami_free_swing.svg", &[angles, energies])?;
    println!("   plot: {file}");
    Ok(())
}

/// Part 2: balancing after a push, and the largest lean each controller recovers from.
fn balance(out: &Output, laws: &Controllers) -> Result<Path6, String> {
    // Leaning 5° forward when a push at the hip sets the trunk pitching forward at 1 rad/s
    // and the legs back at 0.3 rad/s; recorded at 1 kHz.
    let (q0, push) = (
        lean(5f64.to_radians(), 0.0),
        V6::from_column_slice(&[0.0, -0.3, 0.0, 0.0, 1.0, 0.0]),
    );
    let lqr_path = simulate(
        &mut ControlledChain::<f64, TwoLink, _>::new(laws.lqr()),
        q0,
        push,
        4.0,
        1e-3,
    )?;
    let ct_path = simulate(
        &mut ControlledChain::<f64, TwoLink, _>::new(laws.computed_torque()),
        q0,
        push,
        4.0,
        1e-3,
    )?;
    for (name, path) in [("LQR", &lqr_path), ("computed torque + PD", &ct_path)] {
        let peak = path.states().iter().map(|s| s.q.amax()).fold(0.0, f64::max);
        let end = path.states().last().map_or(f64::NAN, |s| s.q.amax());
        println!(
            "   {name:<21} after the push: largest angle {:.1}°, {:.1e} rad after 4 s",
            peak.to_degrees(),
            end
        );
    }
    let mut panel = Panel::new("Balancing after a push at the hip", "t (s)", "angle (rad)");
    for (name, path) in [("LQR", &lqr_path), ("computed torque", &ct_path)] {
        panel = panel.with(&format!("{name}: ankle pitch"), positions(path, 1));
        panel = panel.with(&format!("{name}: hip pitch"), positions(path, 4));
    }
    // The largest lean recovered, over 16 directions.
    let (mut lqr_min, mut ct_min) = (f64::INFINITY, f64::INFINITY);
    let mut rows = Vec::new();
    for i in 0..16 {
        let phi = 2.0 * PI * f64::from(i) / 16.0;
        let a = largest_lean(|| laws.lqr(), phi);
        let b = largest_lean(|| laws.computed_torque(), phi);
        lqr_min = lqr_min.min(a);
        ct_min = ct_min.min(b);
        rows.push((phi.to_degrees(), a.to_degrees(), b.to_degrees()));
    }
    println!(
        "   largest lean recovered from rest, couples held to ±{COUPLE_LIMIT} N·m (16 directions, \
         0° = forward):"
    );
    println!("   direction   LQR     computed torque");
    for (phi, a, b) in &rows {
        println!("   {phi:>7.1}°  {a:>5.1}°  {b:>5.1}°");
    }
    println!(
        "   worst direction: LQR {:.1}°, computed torque {:.1}°",
        lqr_min.to_degrees(),
        ct_min.to_degrees()
    );
    let mut leans = Panel::new(
        "Largest lean recovered, by direction (0° = forward)",
        "direction (°)",
        "lean (°)",
    );
    leans = leans.with("LQR", rows.iter().map(|r| (r.0, r.1)).collect());
    leans = leans.with("computed torque", rows.iter().map(|r| (r.0, r.2)).collect());
    let file = save(out, "hemami_balance.svg", &[panel, leans])?;
    println!("   plot: {file}");
    Ok(lqr_path)
}

/// Part 3: the couples behind the balancing motion, from its samples with noise added.
fn inversion(out: &Output, laws: &Controllers, path: &Path6) -> Result<(), String> {
    let mut law = laws.lqr();
    let t: Vec<f64> = path.states().iter().map(|s| s.t).collect();
    let applied: Vec<V6> = path.states().iter().map(|s| law(s.t, &s.q, &s.v)).collect();
    let mut rng = Rng::new(2005);
    let sigma = 1e-4;
    let mut report = Vec::new();
    let mut recovered_panel = None;
    for (label, noise, half_window, degree) in
        [("no noise", 0.0, 5, 4), ("σ = 1e-4 rad", sigma, 100, 3)]
    {
        let q: Vec<f64> = path
            .states()
            .iter()
            .flat_map(|s| s.q.iter().copied().collect::<Vec<_>>())
            .map(|x| x + noise * gaussian(&mut rng))
            .collect();
        let sg = SavitzkyGolay::new(half_window, degree).map_err(|e| e.to_string())?;
        let got = couples::<6, 6, _>(TwoLink::COORDINATES, &t, &q, &sg, |q, v, a| {
            TwoLink::inverse_dynamics(q, v, a)
        })
        .map_err(|e| e.to_string())?;
        let want = &applied[got.first_sample..got.first_sample + got.t.len()];
        let errors: Vec<V6> = (0..got.t.len())
            .map(|r| V6::from_column_slice(got.row(r).unwrap_or(&[f64::NAN; 6])) - want[r])
            .collect();
        let scale = want.iter().map(|w| w.amax()).fold(0.0, f64::max);
        let worst = errors.iter().map(|e| e.amax()).fold(0.0, f64::max);
        let rms =
            |x: &[V6]| (x.iter().map(|e| e.norm_squared()).sum::<f64>() / x.len() as f64).sqrt();
        report.push(format!(
            "   {label:<13} (window ±{half_window} samples, degree {degree}): error {:.1e} of the \
             largest couple ({scale:.0} N·m) at worst, {:.1e} rms of the rms couple",
            worst / scale,
            rms(&errors) / rms(want)
        ));
        if noise > 0.0 {
            recovered_panel = Some((got, want.to_vec()));
        }
    }
    println!("3. Inverse plant on the LQR balancing run, sampled at 1 kHz:");
    for line in report {
        println!("{line}");
    }
    // The joint wrenches at the true states, top-down and bottom-up from the measured ground
    // reaction (the force plate under the ankle): they agree to rounding.
    let worst = path
        .states()
        .iter()
        .zip(&applied)
        .map(|(s, tau)| -> Result<f64, String> {
            let a = TwoLink::forward_dynamics(&s.q, &s.v, tau).map_err(|e| e.to_string())?;
            let down = TwoLink::joint_wrenches(&s.q, &s.v, &a);
            let ground = down.column(0).into_owned();
            let up = TwoLink::joint_wrenches_bottom_up(&s.q, &s.v, &a, &ground);
            Ok((up - down).amax() / down.amax())
        })
        .collect::<Result<Vec<f64>, _>>()?
        .into_iter()
        .fold(0.0, f64::max);
    println!("   joint wrenches from the ground up and from the trunk down agree to {worst:.1e}");
    if let Some((got, want)) = recovered_panel {
        let mut panel = Panel::new(
            "Couples applied by LQR and recovered from noisy samples (σ = 1e-4 rad)",
            "t (s)",
            "couple (N·m)",
        );
        for k in [1, 4] {
            panel = panel.with(
                &format!("{} applied", NAMES[k]),
                got.t.iter().zip(&want).map(|(&t, w)| (t, w[k])).collect(),
            );
            panel = panel.with(
                &format!("{} recovered", NAMES[k]),
                (0..got.t.len())
                    .map(|r| (got.t[r], got.row(r).map_or(f64::NAN, |c| c[k])))
                    .collect(),
            );
        }
        let file = save(out, "hemami_couples.svg", &[panel])?;
        println!("   plot: {file}");
    }
    Ok(())
}

/// A standard normal number (Box–Muller).
fn gaussian(rng: &mut Rng) -> f64 {
    let (u, v) = (rng.unit().max(f64::MIN_POSITIVE), rng.unit());
    (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
}

fn main() -> Result<(), String> {
    let out = Output::from_args()?;
    let model_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/two_link.chain");
    let model =
        articulated_codegen::load::load_model(&model_path, false).map_err(|e| e.to_string())?;
    let reference = Reference::new(&model).map_err(|e| e.to_string())?;
    println!(
        "Hemami's two-link system: {} coordinates, generated code ({} operations for forward \
         dynamics, {} for inverse dynamics).",
        TwoLink::NV,
        TwoLink::FORWARD_DYNAMICS_OPS.total(),
        TwoLink::INVERSE_DYNAMICS_OPS.total()
    );
    free_swing(&out, &reference)?;
    let (kq, kv, open, closed) = lqr_gains()?;
    println!(
        "2. Balancing upright: upright is unstable (the linearization's largest real part is \
         {open:.2}/s); LQR brings it to {closed:.2}/s"
    );
    let laws = Controllers { kq, kv };
    let path = balance(&out, &laws)?;
    inversion(&out, &laws, &path)
}
