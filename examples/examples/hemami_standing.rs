//! Hemami, Dariush & Barin (2005)'s two-link system standing on the ground: the legs and trunk
//! on a foot that is free (`models/two_link_foot.chain`: a free base under the foot) and held by
//! a six-dimensional contact on its sole (`articulated::constraint`), not welded to the world.
//!
//! 1. It balances after the push of `hemami_two_link` (leaning 5° forward, the trunk pitching
//!    forward at 1 rad/s, the legs back at 0.3 rad/s) under the same LQR law (designed on the
//!    two-link with its ankle fixed, which is what the held foot makes of it), stepped by RK4 at
//!    1 ms with the contact's Baumgarte terms; the ground reaction is the contact's wrench.
//! 2. The ground reaction is estimated from the recorded motion with noise added (σ = 1e-4 rad
//!    on every angle, 1e-4 m on the foot's position, as Hemami's §5 inverts measured motion):
//!    Savitzky–Golay derivatives on the manifold, then inverse dynamics with the contact
//!    (`constraint::inverse_dynamics`: the free base's six equations are the contact's to
//!    supply, and one flat foot determines its wrench).
//! 3. The centre of pressure against the sole's outline: where it leaves the sole, a real foot
//!    would tip, which the bilateral contact cannot show.
//!
//! Prints a short report and writes `figures/hemami_standing.svg` (the true and estimated
//! vertical and forward forces, and the centre of pressure with the heel and the toes) into the
//! folder given as its argument (default `target/docs/`; `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example hemami_standing [-- OUT]
//! ```

use articulated::constraint::{self, Baumgarte, ConstrainedChain, Contact, Settings, System};
use articulated::control::tangent::retract;
use articulated::differentiate::{velocities, SavitzkyGolay};
use articulated::integrate::{Integrator, Rk4, State};
use articulated::nalgebra::SVector;
use articulated::plot::{svg, Panel};
use articulated::prelude::*;
use articulated::FramePlacement;
use articulated_dynamics::random::Rng;
use articulated_examples::hemami::{foot_law, Standing};

type Q = SVector<f64, 13>;
type V = SVector<f64, 12>;
/// A plotted line.
type Points = Vec<(f64, f64)>;

/// The sole's outline in the frame `sole` (m): heel and toes along x.
const HEEL: f64 = -0.07;
const TOES: f64 = 0.19;
const DT: f64 = 1e-3;
const T_END: f64 = 4.0;
/// The contact's Baumgarte gains.
const GAINS: Baumgarte = Baumgarte {
    kp: 100.0,
    kd: 20.0,
};

/// A standard normal number (Box–Muller).
fn gaussian(rng: &mut Rng) -> f64 {
    let (u, v) = (rng.unit().max(f64::MIN_POSITIVE), rng.unit());
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    let law = foot_law()?;
    let contacts = [Contact::six_d(0)];

    // 1. The balancing run, the foot at rest on the ground.
    let lean = 5f64.to_radians();
    let mut q0 = Q::zeros();
    q0[3] = 1.0; // the foot's quaternion, w first: the identity
    q0[8] = lean; // ankle pitch
    let mut v0 = V::zeros();
    v0[7] = -0.3; // legs pitching back
    v0[10] = 1.0; // trunk pitching forward
    let mut chain = ConstrainedChain::<Standing, _, 13, 12, 1, 6>::new(
        &q0,
        &contacts,
        &[],
        Some(GAINS),
        Settings::default(),
        law.clone(),
    )
    .map_err(|e| e.to_string())?;
    let references: [FramePlacement<f64>; 1] = *chain.references();
    let mut state = State::new(0.0, q0, v0);
    let mut samples = vec![(0.0, q0, v0)];
    let steps = (T_END / DT).round() as usize;
    for step in 1..=steps {
        Rk4.advance(&mut chain, &mut state, step as f64 * DT, step)
            .map_err(|e| e.to_string())?;
        samples.push((state.t, state.q, state.v));
    }
    // The true ground reaction at each sample: the contact's wrench `[n; f]` in the sole frame.
    let mut law = law;
    let truth: Vec<[f64; 6]> = samples
        .iter()
        .map(|(t, q, v)| {
            constraint::constrained_forward_dynamics::<Standing, 13, 12, 1, 6>(
                q,
                v,
                &law(*t, q, v),
                &contacts,
                Some((GAINS, &references)),
                &Settings::default(),
            )
            .map(|s| s.force::<6>(0))
            .map_err(|e| e.to_string())
        })
        .collect::<Result<_, _>>()?;
    let last = samples.last().map_or(Q::zeros(), |s| s.1);
    let weight = 75.1 * 9.81;
    println!(
        "1. Standing on a free foot held by a six-dimensional contact, LQR after a push, RK4 at \
         {DT} s for {T_END} s: joints back to {:.1e} rad; the sole's vertical force from {:.0} N \
         to {:.0} N (the weight is {weight:.0} N)",
        last.fixed_rows::<6>(7).amax(),
        truth.iter().map(|w| w[5]).fold(f64::INFINITY, f64::min),
        truth.iter().map(|w| w[5]).fold(0.0, f64::max),
    );

    // 2. The ground reaction from the noisy motion.
    let mut rng = Rng::new(2005);
    let sigma = 1e-4;
    let t: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let mut noisy = Vec::with_capacity(13 * samples.len());
    for (_, q, _) in &samples {
        let delta: V = V::from_fn(|_, _| sigma * gaussian(&mut rng));
        let mut moved = [0.0; 13];
        if !retract(
            Standing::COORDINATES,
            q.as_slice(),
            delta.as_slice(),
            &mut moved,
        ) {
            return Err("retract: sizes".into());
        }
        noisy.extend_from_slice(&moved);
    }
    let sg = SavitzkyGolay::new(100, 3).map_err(|e| e.to_string())?;
    let d = sg
        .differentiate(&t, &noisy, 13)
        .map_err(|e| e.to_string())?;
    let mut estimated = Vec::new();
    for r in 0..d.t.len() {
        let row = |x: &[f64]| x[13 * r..13 * (r + 1)].to_vec();
        let (mut q, mut v, mut a) = ([0.0; 13], [0.0; 12], [0.0; 12]);
        velocities(
            Standing::COORDINATES,
            &row(&d.value),
            &row(&d.first),
            &row(&d.second),
            &mut q,
            &mut v,
            &mut a,
        )
        .map_err(|e| e.to_string())?;
        let (q, v, a) = (Q::from(q), V::from(v), V::from(a));
        let frames = constraint::Frames::<12, 1>::of::<Standing, 13>(&q, &v);
        let system: System<12, 6> = frames
            .system(&contacts, &[], None)
            .map_err(|e| e.to_string())?;
        let (m, nle) = Standing::mass_matrix_and_nonlinear_effects(&q, &v);
        let wrench =
            constraint::inverse_dynamics(&m, &nle, &a, &system, 6).map_err(|e| e.to_string())?;
        estimated.push((d.t[r], [0, 1, 2, 3, 4, 5].map(|k| wrench.forces[k])));
    }
    let want = &truth[d.first_sample..d.first_sample + estimated.len()];
    let rms = |k: usize| {
        let e: f64 = estimated
            .iter()
            .zip(want)
            .map(|((_, e), w)| (e[k] - w[k]).powi(2))
            .sum();
        (e / estimated.len() as f64).sqrt()
    };
    println!(
        "2. The ground reaction from the motion with σ = {sigma:e} noise (Savitzky–Golay ±100 \
         samples, degree 3, then inverse dynamics with the contact): rms error {:.1} N vertical, \
         {:.1} N forward, {:.1} N·m about the sole's y axis ({:.2} % of the weight)",
        rms(5),
        rms(3),
        rms(1),
        100.0 * rms(5) / weight
    );

    // 3. The centre of pressure against the sole.
    let cop = |w: &[f64; 6]| constraint::center_of_pressure(w, 0.0).map_or(f64::NAN, |p| p[0]);
    let inside = truth.iter().map(cop).all(|x| (HEEL..=TOES).contains(&x));
    let (lo, hi) = truth
        .iter()
        .map(cop)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    println!(
        "3. The centre of pressure moves between {:.3} m and {:.3} m along the sole (heel {HEEL} m, \
         toes {TOES} m): {}",
        lo,
        hi,
        if inside {
            "inside the sole throughout, so a real foot would stay flat"
        } else {
            "it leaves the sole, where a real foot would tip"
        }
    );

    let series = |k: usize| -> [Points; 2] {
        [
            estimated
                .iter()
                .zip(want)
                .map(|((t, _), w)| (*t, w[k]))
                .collect(),
            estimated.iter().map(|(t, e)| (*t, e[k])).collect(),
        ]
    };
    let [fz_true, fz_est] = series(5);
    let [fx_true, fx_est] = series(3);
    let vertical = Panel::new("Ground reaction: vertical force", "t (s)", "f_z (N)")
        .with("the contact's", fz_true)
        .with("estimated from noisy motion", fz_est);
    let forward = Panel::new("Ground reaction: forward force", "t (s)", "f_x (N)")
        .with("the contact's", fx_true)
        .with("estimated from noisy motion", fx_est);
    let times: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let line = |y: f64| vec![(0.0, y), (T_END, y)];
    let pressure = Panel::new("Centre of pressure along the sole", "t (s)", "x (m)")
        .with(
            "centre of pressure",
            times
                .iter()
                .zip(&truth)
                .map(|(t, w)| (*t, cop(w)))
                .collect(),
        )
        .with("toes", line(TOES))
        .with("heel", line(HEEL));
    let text = svg(&[vertical, forward, pressure], 900, 300).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("hemami_standing.svg"), text.as_bytes())?;
    println!("wrote {file}");
    Ok(())
}
