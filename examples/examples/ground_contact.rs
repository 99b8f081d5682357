//! Bodies on the ground with unilateral contacts and exact Coulomb friction
//! (`articulated::contact`), stepped at 1 ms:
//!
//! 1. Hemami's two-link system on its foot (`models/two_link_foot.chain`), the foot held by
//!    nothing but four contact points, heel and toes on each side, free to lift and slide:
//!    after the push of `hemami_two_link` under the same LQR law it balances, the contact
//!    forces and the centre of pressure coming from the points' forces. Unlike the
//!    six-dimensional contact of `hemami_standing`, a heel can lift here.
//! 2. The walker (`models/biped.chain`) dropped from 5 cm onto the ground, its joints held by
//!    springs and dampers about standing: it lands and comes to rest standing.
//! 3. The same walker pushed forward with soft joints: it folds and falls over, landing on its
//!    knees, hands and head, which carry contact spheres as its feet do.
//!
//! Prints a short report and writes `figures/ground_contact.svg` into the folder given as its
//! argument (default `target/docs/`; `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example ground_contact [-- OUT]
//! ```

use articulated::contact::{Ground, Settings, Sphere, StepReport, TimeStepper};
use articulated::integrate::State;
use articulated::nalgebra::SVector;
use articulated::plot::{svg, Panel};
use articulated::prelude::*;
use articulated_examples::hemami::{foot_law, Standing};

/// The walker with the frames that carry its contact spheres.
#[derive(Chain)]
#[chain(
    file = "../models/biped.chain",
    outputs = [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local],
    frames = [left_foot, right_foot, left_shank, right_shank, left_hand, right_hand, head, trunk]
)]
struct Walker;

const DT: f64 = 1e-3;
/// A plotted line.
type Points = Vec<(f64, f64)>;

/// The sole's corners in the frame `sole` (m): heel and toes along x, the feet's outer edges
/// along y.
const HEEL: f64 = -0.07;
const TOES: f64 = 0.19;
const SIDE: f64 = 0.12;

fn ground() -> Result<[Ground; 1], String> {
    Ok([Ground::new([0.0, 0.0, 1.0], 0.0).map_err(|e| e.to_string())?])
}

/// Steps until `t_end`, counting the steps whose solve did not converge; `each` sees every state
/// and the stepper after it.
fn run<C, F, const NQ: usize, const NV: usize, const NF: usize, const P: usize>(
    stepper: &mut TimeStepper<'_, C, F, NQ, NV, NF, P>,
    state: &mut State<f64, articulated::nalgebra::Const<NQ>, articulated::nalgebra::Const<NV>>,
    t_end: f64,
    mut each: impl FnMut(
        &State<f64, articulated::nalgebra::Const<NQ>, articulated::nalgebra::Const<NV>>,
        &TimeStepper<'_, C, F, NQ, NV, NF, P>,
        &StepReport,
    ),
) -> Result<(usize, usize, f64), String>
where
    C: articulated::contact::ContactOutputs<NQ, NV, NF>,
    F: FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
{
    let (mut missed, mut sweeps, mut worst) = (0, 0, 0.0_f64);
    let steps = ((t_end - state.t) / DT).round() as usize;
    for _ in 0..steps {
        let report = stepper.step(state, DT).map_err(|e| e.to_string())?;
        missed += usize::from(!report.converged);
        if !report.converged {
            worst = worst.max(report.residual);
        }
        sweeps += report.iterations;
        each(state, stepper, &report);
    }
    Ok((missed, sweeps / steps.max(1), worst))
}

/// 1. The two-link system balancing on four points.
fn two_link(panels: &mut Vec<Panel>) -> Result<(), String> {
    let grounds = ground()?;
    let spheres: [Sphere; 4] = core::array::from_fn(|k| Sphere {
        frame: 0,
        offset: [
            if k < 2 { HEEL } else { TOES },
            if k.is_multiple_of(2) { -SIDE } else { SIDE },
            0.0,
        ],
        radius: 0.0,
        friction: 0.8,
        restitution: 0.0,
    });
    let law = foot_law()?;
    let mut stepper: TimeStepper<'_, Standing, _, 13, 12, 1, 4> =
        TimeStepper::new(&grounds, &spheres, Settings::default(), law)
            .map_err(|e| e.to_string())?;
    // The push of `hemami_two_link`: leaning 5° forward, the legs pitching back, the trunk forward.
    let mut q0 = SVector::<f64, 13>::zeros();
    q0[3] = 1.0;
    q0[8] = 5f64.to_radians();
    let mut v0 = SVector::<f64, 12>::zeros();
    v0[7] = -0.3;
    v0[10] = 1.0;
    let mut state = State::new(0.0, q0, v0);
    let (mut heel, mut toes, mut friction, mut pressure) =
        (Points::new(), Points::new(), Points::new(), Points::new());
    let (mut lifted, mut slid) = (0.0_f64, 0.0_f64);
    let (missed, sweeps, worst) = run(&mut stepper, &mut state, 3.0, |s, stepper, _| {
        let (mut h, mut t, mut fx, mut moment) = (0.0, 0.0, 0.0, 0.0);
        for f in stepper.forces() {
            if f.sphere < 2 {
                h += f.force[2];
            } else {
                t += f.force[2];
            }
            fx += f.force[0];
            moment += f.force[2] * f.point[0];
        }
        heel.push((s.t, h));
        toes.push((s.t, t));
        friction.push((s.t, fx));
        if h + t > 0.0 {
            pressure.push((s.t, moment / (h + t)));
        }
        lifted = lifted.max(s.q[2]);
        slid = slid.max(s.q[0].abs().max(s.q[1].abs()));
    })?;
    println!(
        "1. Hemami's two-link on four contact points, LQR after a push, 3 s: the joints back to \
         {:.1e} rad; the foot rose at most {:.2e} m and slid {:.2e} m; {sweeps} Gauss-Seidel \
         sweeps per step on average, {missed} steps not converged (worst residual {worst:.1e} m/s); the centre of pressure \
         within [{:.3}, {:.3}] m (the sole spans [{HEEL}, {TOES}] m)",
        state.q.fixed_rows::<6>(7).amax(),
        lifted,
        slid,
        pressure.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
        pressure.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
    );
    panels.push(
        Panel::new(
            "Hemami's two-link on four points: contact forces after the push",
            "t (s)",
            "force (N)",
        )
        .with("both heels", heel)
        .with("both toes", toes)
        .with("friction, forward", friction),
    );
    let span = |x: f64| pressure.iter().map(|p| (p.0, x)).collect::<Points>();
    panels.push(
        Panel::new(
            "Its centre of pressure along the sole",
            "t (s)",
            "x (m, ankle at 0)",
        )
        .with("centre of pressure", pressure.clone())
        .with("heel", span(HEEL))
        .with("toes", span(TOES)),
    );
    Ok(())
}

/// The walker's spheres: four under each sole, then its knees, hands, head and hips.
fn walker_spheres() -> [Sphere; 14] {
    let point = |frame: usize, offset: [f64; 3], radius: f64| Sphere {
        frame,
        offset,
        radius,
        friction: 0.8,
        restitution: 0.0,
    };
    let sole = |frame: usize, k: usize| {
        point(
            frame,
            [
                if k < 2 { -0.05 } else { 0.2 },
                if k.is_multiple_of(2) { -0.05 } else { 0.05 },
                -0.07,
            ],
            0.0,
        )
    };
    [
        sole(0, 0),
        sole(0, 1),
        sole(0, 2),
        sole(0, 3),
        sole(1, 0),
        sole(1, 1),
        sole(1, 2),
        sole(1, 3),
        point(2, [0.0; 3], 0.05),
        point(3, [0.0; 3], 0.05),
        point(4, [0.0, 0.0, -0.07], 0.04),
        point(5, [0.0, 0.0, -0.07], 0.04),
        point(6, [0.0, 0.0, 0.1], 0.11),
        point(7, [0.0; 3], 0.12),
    ]
}

type WalkerQ = SVector<f64, 13>;
type WalkerV = SVector<f64, 12>;

/// Springs about standing on the walker's six joints (`stiffness`, N·m/rad).
fn hold(stiffness: f64) -> impl FnMut(f64, &WalkerQ, &WalkerV) -> WalkerV {
    move |_, q, _| WalkerV::from_fn(|k, _| if k < 6 { 0.0 } else { -stiffness * q[k + 1] })
}

/// Heights (m) of the walker's head, hips and knees at a state.
fn heights(q: &WalkerQ) -> [f64; 3] {
    let p = Walker::frame_placements(q);
    [
        p[6].translation.z,
        p[7].translation.z,
        0.5 * (p[2].translation.z + p[3].translation.z),
    ]
}

/// 2. and 3.: the walker dropped, and pushed over.
fn walker(panels: &mut Vec<Panel>) -> Result<(), String> {
    let grounds = ground()?;
    let spheres = walker_spheres();
    // Standing: the soles (0.07 m under the ankles, 0.856 m under the hips) on the ground.
    let standing_height = 0.4222 + 0.434 + 0.07;
    let damping = SVector::from_fn(|k, _| if k < 6 { 0.0 } else { 30.0 });
    let start = |drop: f64| {
        let mut q = WalkerQ::zeros();
        q[2] = standing_height + drop;
        q[3] = 1.0;
        q
    };
    let mut dropped: TimeStepper<'_, Walker, _, 13, 12, 8, 14> =
        TimeStepper::new(&grounds, &spheres, Settings::default(), hold(1500.0))
            .map_err(|e| e.to_string())?;
    dropped.set_damping(damping).map_err(|e| e.to_string())?;
    let mut state = State::new(0.0, start(0.05), WalkerV::zeros());
    let mut height = Points::new();
    let (missed, sweeps, worst) = run(&mut dropped, &mut state, 2.0, |s, _, _| {
        height.push((s.t, s.q[2] - standing_height));
    })?;
    let weight = 75.0 * 9.81;
    let carried: f64 = dropped.forces().map(|f| f.force[2]).sum();
    println!(
        "2. The walker dropped from 5 cm, joints on springs: at 2 s its hips {:.1} mm from \
         standing, moving at {:.1e} m/s, the ground carrying {:.1} % of its weight on {} points; \
         {sweeps} sweeps per step on average, {missed} steps not converged (worst residual {worst:.1e} m/s)",
        (state.q[2] - standing_height) * 1e3,
        state.v.fixed_rows::<3>(0).norm(),
        100.0 * carried / weight,
        dropped.forces().count(),
    );
    panels.push(
        Panel::new(
            "The walker dropped from 5 cm: its hips' height from standing",
            "t (s)",
            "height (m)",
        )
        .with("hips", height),
    );

    let mut pushed: TimeStepper<'_, Walker, _, 13, 12, 8, 14> =
        TimeStepper::new(&grounds, &spheres, Settings::default(), hold(60.0))
            .map_err(|e| e.to_string())?;
    pushed
        .set_damping(damping / 10.0)
        .map_err(|e| e.to_string())?;
    let mut v0 = WalkerV::zeros();
    v0[4] = 1.5; // pitching forward at 1.5 rad/s
    let mut state = State::new(0.0, start(0.0), v0);
    let (mut head, mut hips, mut knees, mut load) =
        (Points::new(), Points::new(), Points::new(), Points::new());
    let mut touched = [false; 14];
    let (missed, sweeps, worst) = run(&mut pushed, &mut state, 2.5, |s, stepper, _| {
        let [h, p, k] = heights(&s.q);
        head.push((s.t, h));
        hips.push((s.t, p));
        knees.push((s.t, k));
        let mut total = 0.0;
        for f in stepper.forces() {
            total += f.force[2];
            if f.force[2] > 1.0 {
                if let Some(t) = touched.get_mut(f.sphere) {
                    *t = true;
                }
            }
        }
        load.push((s.t, total / weight));
    })?;
    let names = ["soles", "knees", "hands", "head", "hips"];
    let groups = [0..8, 8..10, 10..12, 12..13, 13..14];
    let landed: Vec<&str> = names
        .iter()
        .zip(groups)
        .filter(|(_, g)| touched[g.clone()].iter().any(|t| *t))
        .map(|(n, _)| *n)
        .collect();
    println!(
        "3. The walker pushed over with soft joints: its head from {:.2} m down to {:.2} m; it \
         touched the ground with its {}; {sweeps} sweeps per step on average, {missed} steps \
         not converged (worst residual {worst:.1e} m/s)",
        head.first().map_or(0.0, |p| p.1),
        head.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
        landed.join(", "),
    );
    panels.push(
        Panel::new("The walker pushed over: heights", "t (s)", "height (m)")
            .with("head", head)
            .with("hips", hips)
            .with("knees", knees),
    );
    // Impacts last a step: the mean over 10 ms shows what the ground carries.
    let smoothed: Points = load
        .chunks(10)
        .map(|c| {
            (
                c[c.len() / 2].0,
                c.iter().map(|p| p.1).sum::<f64>() / c.len() as f64,
            )
        })
        .collect();
    panels.push(
        Panel::new(
            "The ground's vertical force on it over its weight (10 ms means)",
            "t (s)",
            "force / weight",
        )
        .with("all contacts", smoothed),
    );
    Ok(())
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    let mut panels = Vec::new();
    two_link(&mut panels)?;
    walker(&mut panels)?;
    let text = svg(&panels, 900, 260).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("ground_contact.svg"), text.as_bytes())?;
    println!("wrote {file}");
    Ok(())
}
