//! Steps per second of the contact simulation (`articulated::contact`) on the humanoid standing
//! on eight points, and what our stepping and MuJoCo's agree on: the scenes of
//! `bench/peers/contact_mujoco.py`, with the same numbers.
//!
//! ```text
//! cargo run --release -p articulated-bench --bin contact_steps -- [--json FILE]
//! ```
//!
//! `bench/peers/run.sh` runs it beside the MuJoCo script and writes both to `BENCHMARKS.md`
//! ("Simulation with contacts"). The scenes, at 1 ms steps:
//! - **humanoid standing**: `models/humanoid.chain` on its free base, the pelvis at 1.11 m, four
//!   points under each foot (heel and toes, 0.05 m to each side, 0.09 m below the foot's
//!   frame), μ = 0.8; every joint held about zero by a spring of 2,000 N·m/rad (the controller,
//!   explicit) and a damper of 50 N·m·s/rad (implicit, as MuJoCo's joint damping). Timed: the
//!   best of 5 runs of 2,000 steps after 100 steps of warm-up, one thread;
//! - **sliding block**: `models/block.chain` with its eight corners as points, μ = 0.5, on the
//!   level ground at 2 m/s: the deceleration (`μ·g` in closed form), the stopping distance
//!   (`v²/(2μg)`), how high it lifts while sliding;
//! - **resting block**: the same at rest: the normal forces over `m·g`.

use std::hint::black_box;
use std::time::Instant;

use articulated::contact::{Ground, Settings, Sphere, TimeStepper};
use articulated::integrate::State;
use articulated::nalgebra::SVector;
use clap::Parser;
use serde::Serialize;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local],
    frames = [left_foot, right_foot]
)]
struct Humanoid;

#[derive(articulated::Chain)]
#[chain(file = "../models/block.chain")]
struct Block;

#[derive(Parser)]
struct Args {
    /// Write the figures as JSON to this file (else print them).
    #[arg(long)]
    json: Option<std::path::PathBuf>,
}

const H: f64 = 1e-3;
const G: f64 = 9.81;

#[derive(Serialize)]
struct Standing {
    steps_per_second: f64,
    microseconds_per_step: f64,
    iterations_mean: f64,
    iterations_max: usize,
    not_converged: usize,
    pelvis_height_drift: f64,
    normal_sum_over_mg: f64,
    max_penetration: f64,
    tree_factorization: bool,
}

#[derive(Serialize)]
struct Sliding {
    deceleration: f64,
    deceleration_closed_form: f64,
    stop_distance: f64,
    stop_distance_closed_form: f64,
    stop_time: f64,
    max_lift_while_sliding: f64,
    max_penetration: f64,
}

#[derive(Serialize)]
struct Resting {
    normal_sum_over_mg: f64,
    height_error: f64,
}

#[derive(Serialize)]
struct Report {
    engine: &'static str,
    tolerance: f64,
    humanoid_standing: Standing,
    sliding_box: Sliding,
    resting_box: Resting,
}

type Hold = fn(f64, &SVector<f64, 38>, &SVector<f64, 37>) -> SVector<f64, 37>;

/// The joints' springs about zero (the dampers are the stepper's, implicit).
fn hold(_t: f64, q: &SVector<f64, 38>, _v: &SVector<f64, 37>) -> SVector<f64, 37> {
    SVector::from_fn(|k, _| if k < 6 { 0.0 } else { -2000.0 * q[k + 1] })
}

fn standing() -> Standing {
    let grounds = [Ground::new([0.0, 0.0, 1.0], 0.0).expect("a ground")];
    let spheres: [Sphere; 8] = core::array::from_fn(|k| Sphere {
        frame: k / 4,
        offset: [
            if k & 1 == 0 { -0.06 } else { 0.16 },
            if k & 2 == 0 { -0.05 } else { 0.05 },
            -0.09,
        ],
        radius: 0.0,
        friction: 0.8,
        restitution: 0.0,
    });
    let mut start = SVector::<f64, 38>::zeros();
    start[2] = 1.11;
    start[3] = 1.0;
    let fresh = || {
        let mut s: TimeStepper<'_, Humanoid, Hold, 38, 37, 2, 8> =
            TimeStepper::new(&grounds, &spheres, Settings::default(), hold as Hold)
                .expect("the scene");
        s.set_damping(SVector::from_fn(|k, _| if k < 6 { 0.0 } else { 50.0 }))
            .expect("dampers");
        s
    };
    // Untimed: 2,000 steps recorded.
    let mut stepper = fresh();
    let tree = stepper.factors_along_the_tree();
    let mut state = State::new(0.0, start, SVector::zeros());
    let (mut sum, mut max, mut missed, mut deepest) = (0, 0, 0, 0.0_f64);
    for _ in 0..2000 {
        let r = stepper.step(&mut state, H).expect("a step");
        sum += r.iterations;
        max = max.max(r.iterations);
        missed += usize::from(!r.converged);
        for f in stepper.forces() {
            deepest = deepest.max(-f.distance);
        }
    }
    let normal: f64 = stepper.forces().map(|f| f.force[2]).sum();
    let drift = state.q[2] - start[2];
    // Timed.
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let mut stepper = fresh();
        let mut state = State::new(0.0, start, SVector::zeros());
        for _ in 0..100 {
            stepper.step(&mut state, H).expect("a step");
        }
        let t0 = Instant::now();
        for _ in 0..2000 {
            black_box(stepper.step(black_box(&mut state), H).expect("a step"));
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Standing {
        steps_per_second: 2000.0 / best,
        microseconds_per_step: best / 2000.0 * 1e6,
        iterations_mean: sum as f64 / 2000.0,
        iterations_max: max,
        not_converged: missed,
        pelvis_height_drift: drift,
        normal_sum_over_mg: normal / (82.05 * G),
        max_penetration: deepest,
        tree_factorization: tree,
    }
}

type Unforced = fn(f64, &SVector<f64, 7>, &SVector<f64, 6>) -> SVector<f64, 6>;

type BlockState = State<f64, articulated::nalgebra::Const<7>, articulated::nalgebra::Const<6>>;

fn block_run(v0: f64, seconds: f64, mut each: impl FnMut(&BlockState, f64)) -> f64 {
    let grounds = [Ground::new([0.0, 0.0, 1.0], 0.0).expect("a ground")];
    let spheres: [Sphere; 8] = core::array::from_fn(|k| Sphere {
        frame: 0,
        offset: [0, 1, 2].map(|b| if k >> b & 1 == 0 { -0.1 } else { 0.1 }),
        radius: 0.0,
        friction: 0.5,
        restitution: 0.0,
    });
    let unforced: Unforced = |_, _, _| SVector::zeros();
    let mut stepper: TimeStepper<'_, Block, Unforced, 7, 6, 1, 8> =
        TimeStepper::new(&grounds, &spheres, Settings::default(), unforced).expect("the scene");
    let q = SVector::from([0.0, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0]);
    let mut state = State::new(0.0, q, SVector::from([v0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    for _ in 0..(seconds / H).round() as usize {
        stepper.step(&mut state, H).expect("a step");
        let lowest = stepper
            .forces()
            .map(|f| f.distance)
            .fold(f64::INFINITY, f64::min);
        each(&state, lowest);
    }
    stepper.forces().map(|f| f.force[2]).sum()
}

fn sliding() -> Sliding {
    let (mu, v0) = (0.5, 2.0);
    let mut samples = Vec::new();
    let (mut stop, mut lift, mut deepest) = (None, 0.0_f64, 0.0_f64);
    block_run(v0, 0.6, |s, lowest| {
        if s.t >= 0.05 && s.t <= 0.3 {
            samples.push((s.t, s.v[0]));
        }
        if stop.is_none() && s.v[0].abs() < 1e-3 {
            stop = Some((s.t, s.q[0]));
        }
        if stop.is_none() {
            lift = lift.max(s.q[2] - 0.1);
        }
        deepest = deepest.max(-lowest);
    });
    // The least-squares slope of v(t).
    let n = samples.len() as f64;
    let (st, sv) = samples
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, v)| (a + t, b + v));
    let (mt, mv) = (st / n, sv / n);
    let (num, den) = samples.iter().fold((0.0, 0.0), |(a, b), (t, v)| {
        (a + (t - mt) * (v - mv), b + (t - mt) * (t - mt))
    });
    let (t, x) = stop.unwrap_or((f64::NAN, f64::NAN));
    Sliding {
        deceleration: -num / den,
        deceleration_closed_form: mu * G,
        stop_distance: x,
        stop_distance_closed_form: v0 * v0 / (2.0 * mu * G),
        stop_time: t,
        max_lift_while_sliding: lift,
        max_penetration: deepest,
    }
}

fn resting() -> Resting {
    let mut height = 0.0;
    let normal = block_run(0.0, 0.5, |s, _| height = s.q[2] - 0.1);
    Resting {
        normal_sum_over_mg: normal / G,
        height_error: height,
    }
}

fn main() {
    let args = Args::parse();
    eprintln!("contact_steps: the humanoid standing (timed), the sliding and resting block");
    let report = Report {
        engine: "articulated",
        tolerance: Settings::default().tolerance,
        humanoid_standing: standing(),
        sliding_box: sliding(),
        resting_box: resting(),
    };
    let text = serde_json::to_string_pretty(&report).expect("JSON");
    match args.json {
        Some(path) => std::fs::write(&path, text + "\n").expect("writing the figures"),
        None => println!("{text}"),
    }
}
