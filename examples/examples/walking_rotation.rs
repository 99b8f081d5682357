//! The rotation of walking (Wieber 2005, §5.1): a free-floating walker replaying a periodic
//! walking pattern with zero momentum turns, step after step, in the sagittal plane, because its
//! legs go forward bent (short, light in inertia) and back straight (long): a nonholonomic
//! rotation, like the falling cat's. Wieber measured 1/393 of a turn per step for a recorded human
//! pattern on a simple biomechanical model (his Fig. 2) and up to 1/159 for HRP-2 at 25 cm high
//! steps (his Fig. 3).
//!
//! The walker (`models/biped.chain`: de Leva's segments for a 75 kg man) has a trunk with the
//! head on a free base (quaternion), a hip and a knee per leg and a shoulder per arm, all about
//! the mediolateral axis. The joints follow the pattern below; the trunk is free and unactuated
//! (hybrid dynamics with the generated `M` and `nle`, `articulated_examples::free_floating`),
//! started with the velocity that makes every momentum zero. Dormand–Prince 5(4), `rtol =
//! 1e-10`. For each step height it measures the trunk's net pitch per step over 8 steps, with
//! the arms still and with the arms swinging, writes the table to `walking.md` and the plot to
//! `figures/walking_rotation.svg` in the folder given as its argument (default `target/docs/`;
//! `scripts/figures.sh` passes `docs/`).
//!
//! # The pattern (ours, walking-like, not recorded data)
//! A gait cycle of period `T` is two steps, phase `ψ = 2π·t/T`, the legs in antiphase:
//! - hip flexion `H·sin ψ` on the right, `H·sin(ψ + π)` on the left (`H = 20°`);
//! - knee flexion `K·max(0, cos ψ)³` on the right (`ψ + π` on the left): the knee bends only
//!   while its hip flexes (the swing), most at mid-swing, and the stance leg stays straight;
//!   the cube keeps the joint accelerations continuous;
//! - with arm swing, shoulder flexion `A·sin(ψ + π)` on the right (`A = 15°`, the arm against
//!   its own side's leg), `A·sin ψ` on the left.
//!
//! The **step height** is how far the swing ankle rises above the stance ankle, at most over the
//! swing, in the trunk's frame (ankles from the reference's body kinematics); the peak knee
//! flexion `K` that gives each height is found by bisection. The trunk's pitch is its rotation
//! about its own mediolateral (y) axis since the start, from its quaternion (swing–twist
//! decomposition), positive leaning forward.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example walking_rotation
//! ```

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

use articulated::integrate::State;
use articulated::model::Model;
use articulated::nalgebra::{Const, SVector, UnitQuaternion, Vector3};
use articulated::plot::{svg, Panel};
use articulated::prelude::*;
use articulated::reference::jacobian::body_jacobians;
use articulated_examples::free_floating::{
    self, base_orientation, conservation, swing_angle, twist_angle, Conservation, Hybrid,
    JointMotion,
};
use articulated_examples::output::Output;

/// The walker, generated from `models/biped.chain`: `M` and `nle` move it, the centre of mass and
/// the centroidal momentum check it.
#[derive(Chain)]
#[chain(
    file = "../models/biped.chain",
    outputs = [mass_matrix_and_nonlinear_effects, center_of_mass, centroidal_momentum]
)]
struct Biped;

const NQ: usize = 13;
const NV: usize = 12;
/// Joints: right shoulder, left shoulder, right hip, right knee, left hip, left knee.
const NJ: usize = 6;
type Joints = SVector<f64, NJ>;
type WalkerState = State<f64, Const<NQ>, Const<NV>>;

/// Hip flexion amplitude (rad).
const HIP: f64 = 20.0 * PI / 180.0;
/// Shoulder flexion amplitude with arm swing (rad).
const ARMS: f64 = 15.0 * PI / 180.0;
/// The gait cycle (two steps), s.
const PERIOD: f64 = 1.1;
/// Gait cycles simulated per measurement (8 steps).
const CYCLES: usize = 4;
/// Step heights in the table (m).
const HEIGHTS: [f64; 6] = [0.0, 0.05, 0.10, 0.15, 0.20, 0.25];

/// The walking pattern (module docs).
#[derive(Clone, Copy, Debug)]
struct Gait {
    /// Peak knee flexion in the swing, `K` (rad).
    knee: f64,
    /// Shoulder flexion amplitude, `A` (rad); 0 for still arms.
    arms: f64,
    /// The gait cycle, `T` (s).
    period: f64,
}

/// `max(0, c)³` and its first two derivatives in `ψ`, with `c = cos ψ`, `s = sin ψ`:
/// `−3m²·s` and `6m·s² − 3m³` (`m = max(0, c)`).
fn swing_bump(c: f64, s: f64) -> [f64; 3] {
    let m = c.max(0.0);
    [
        m * m * m,
        -3.0 * m * m * s,
        6.0 * m * s * s - 3.0 * m * m * m,
    ]
}

impl JointMotion<NJ> for Gait {
    fn at(&self, t: f64) -> [Joints; 3] {
        let w = 2.0 * PI / self.period;
        let (s, c) = (w * t).sin_cos();
        let [kr, kr1, kr2] = swing_bump(c, s);
        // The left leg's phase is ψ + π: cos → −cos, sin → −sin.
        let [kl, kl1, kl2] = swing_bump(-c, -s);
        // q (hip and shoulder flexion are negative angles about y, knee flexion positive).
        let (a, h, k) = (self.arms, HIP, self.knee);
        let q = Joints::from([a * s, -a * s, -h * s, k * kr, h * s, k * kl]);
        let v = Joints::from([a * c, -a * c, -h * c, k * kr1, h * c, k * kl1]) * w;
        let acc = Joints::from([-a * s, a * s, h * s, k * kr2, -h * s, k * kl2]) * (w * w);
        [q, v, acc]
    }
}

/// A state `q` of the walker with the trunk upright at the origin and the joints at `joints`.
fn posture(joints: &Joints) -> SVector<f64, NQ> {
    let mut q = SVector::<f64, NQ>::zeros();
    q[3] = 1.0;
    q.fixed_rows_mut::<NJ>(7).copy_from(joints);
    q
}

/// The ankles' heights (right, left) in the trunk's frame at `joints`, from the reference's body
/// kinematics (the foot frames' origins are the ankles).
fn ankle_heights(model: &Model, joints: &Joints) -> Result<(f64, f64), String> {
    let q = posture(joints);
    let bodies = body_jacobians(model, &model.param_defaults(), q.as_slice(), &[0.0; NV])
        .map_err(|e| e.to_string())?;
    let z = |name: &str| -> Result<f64, String> {
        let i = model.body_index(name).ok_or(format!("no body {name}"))?;
        Ok(bodies[i].origin.z)
    };
    Ok((z("right_foot")?, z("left_foot")?))
}

/// The step height of `gait`: the largest rise of the right ankle over the left during the
/// right leg's swing (`cos ψ > 0`), sampled every 0.5° of phase.
fn step_height(model: &Model, gait: &Gait) -> Result<f64, String> {
    let mut best = f64::NEG_INFINITY;
    for i in -180..=180 {
        let t = f64::from(i) / 720.0 * gait.period;
        let (right, left) = ankle_heights(model, &gait.at(t)[0])?;
        best = best.max(right - left);
    }
    Ok(best)
}

/// The peak knee flexion that gives the step height `h` (bisection to 1e-6 rad, up to 120°).
fn knee_for_height(model: &Model, h: f64) -> Result<f64, String> {
    let height = |knee: f64| {
        step_height(
            model,
            &Gait {
                knee,
                arms: 0.0,
                period: PERIOD,
            },
        )
    };
    if h <= 0.0 {
        return Ok(0.0);
    }
    let (mut lo, mut hi) = (0.0, 120f64.to_radians());
    if height(hi)? < h {
        return Err(format!(
            "no knee flexion up to 120° lifts the ankle by {h} m"
        ));
    }
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if height(mid)? < h {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// One simulated walk: the recorded states and what they say.
struct Walk {
    states: Vec<WalkerState>,
    /// Trunk pitch per step (rad), positive forward.
    per_step: f64,
    /// How far the net rotation of the whole walk tilts the trunk's y axis (rad): its turn
    /// that is not about y.
    off_axis: f64,
    /// The largest yaw of the trunk along the way (rad): it swings about its vertical axis
    /// against the legs, which move forward and back beside it.
    yaw: f64,
    /// Dormand–Prince's accepted steps.
    steps: usize,
}

/// The trunk's pitch about its own y axis since the first state, positive forward (a positive
/// rotation about y takes x, forward, towards −z).
fn pitch(first: &UnitQuaternion<f64>, state: &WalkerState) -> f64 {
    let net = (first.inverse() * base_orientation(state.q.as_slice())).into_inner();
    twist_angle(&net, &Vector3::y())
}

/// Walks `cycles` gait cycles (2 steps each) of `gait`, recording 50 states per step.
fn walk(gait: Gait, cycles: usize) -> Result<Walk, String> {
    let mut system = Hybrid::<Biped, _, NJ>::new(gait);
    let start = system
        .start(0.0, [0.0; 3], UnitQuaternion::identity())
        .map_err(|e| e.to_string())?;
    let (states, stats) = free_floating::record(
        &mut system,
        start,
        (cycles as f64 * gait.period, gait.period / 100.0),
        (1e-10, 1e-12),
    )?;
    let first = base_orientation(states[0].q.as_slice());
    let last = states.last().ok_or("no states")?;
    let net = first.inverse() * base_orientation(last.q.as_slice());
    let yaw = states
        .iter()
        .map(|s| {
            let net = (first.inverse() * base_orientation(s.q.as_slice())).into_inner();
            twist_angle(&net, &Vector3::z()).abs()
        })
        .fold(0.0, f64::max);
    Ok(Walk {
        per_step: pitch(&first, last) / (2 * cycles) as f64,
        off_axis: swing_angle(&net, &Vector3::y()),
        yaw,
        steps: stats.accepted,
        states,
    })
}

/// `1/N` of a turn, as text; `0` below 1e-9 rad (a pattern without knee flexion turns the
/// walker by rounding errors only).
fn fraction(angle: f64) -> String {
    if angle.abs() < 1e-9 {
        "0".into()
    } else {
        format!("1/{:.0}", 2.0 * PI / angle.abs())
    }
}

/// An angle in degrees with its sign and 4 decimals, `0` below 1e-9 rad.
fn degrees(angle: f64) -> String {
    if angle.abs() < 1e-9 {
        "0".into()
    } else {
        format!("{:+.4}°", angle.to_degrees())
    }
}

/// One row of the table.
struct Row {
    height: f64,
    knee: f64,
    still: Walk,
    swinging: Walk,
}

fn main() -> Result<(), String> {
    let out = Output::from_args()?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let model = articulated_codegen::load::load_model(&root.join("models/biped.chain"), false)
        .map_err(|e| e.to_string())?;
    println!(
        "A free-floating walker (de Leva's segments, 75 kg): trunk on a free base, hips, knees and \
         shoulders; {} velocities, M and nle generated ({} operations).",
        Biped::NV,
        Biped::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS.total()
    );
    println!(
        "Zero momentum, the joints replaying a walking pattern (hips ±{:.0}°, gait cycle {PERIOD} \
         s); trunk pitch over {} steps per row.\n",
        HIP.to_degrees(),
        2 * CYCLES
    );
    let mut rows = Vec::new();
    let mut worst: Option<Conservation> = None;
    for h in HEIGHTS {
        let knee = knee_for_height(&model, h)?;
        let still = walk(
            Gait {
                knee,
                arms: 0.0,
                period: PERIOD,
            },
            CYCLES,
        )?;
        let swinging = walk(
            Gait {
                knee,
                arms: ARMS,
                period: PERIOD,
            },
            CYCLES,
        )?;
        for w in [&still, &swinging] {
            let c = conservation::<Biped, NQ, NV>(&model, &w.states)?;
            worst = Some(match worst {
                Some(x) if x.momentum.max(x.momentum_check) >= c.momentum.max(c.momentum_check) => {
                    x
                }
                _ => c,
            });
        }
        println!(
            "   step height {:>4.2} m (swing knee {:>4.1}°): {} per step ({}), trunk yaw ±{:.1}°; \
             arms swinging: {} ({}), ±{:.1}°; {} and {} integrator steps",
            h,
            knee.to_degrees(),
            degrees(still.per_step),
            fraction(still.per_step),
            still.yaw.to_degrees(),
            degrees(swinging.per_step),
            fraction(swinging.per_step),
            swinging.yaw.to_degrees(),
            still.steps,
            swinging.steps
        );
        rows.push(Row {
            height: h,
            knee,
            still,
            swinging,
        });
    }
    let worst = worst.ok_or("no rows")?;
    println!(
        "   |k_G| ≤ {:.1e} of Σ|k_k| (≤ {:.1} kg·m²/s; body Jacobians: {:.1e}); centre of mass \
         within {:.1e} m of free fall",
        worst.momentum.max(worst.momentum_check),
        worst.momentum_scale,
        worst.momentum_check,
        worst.com.max(worst.com_check)
    );
    let off = rows
        .iter()
        .flat_map(|r| [r.still.off_axis, r.swinging.off_axis])
        .fold(0.0, f64::max);
    println!(
        "   besides the pitch, each walk's net turn tilts the trunk's y axis by up to {:.2}° in 8 \
         steps (a slow roll: its yaw swing and its pitch do not commute)",
        off.to_degrees()
    );

    // The same pattern twice as slow turns the walker by the same angle.
    let last = rows.last().ok_or("no rows")?;
    let slow = walk(
        Gait {
            knee: last.knee,
            arms: 0.0,
            period: 2.0 * PERIOD,
        },
        CYCLES,
    )?;
    println!(
        "   at twice the period, {:.2} m steps: {:+.10}° per step against {:+.10}°: the shape of \
         the step sets the turn, not its speed",
        last.height,
        slow.per_step.to_degrees(),
        last.still.per_step.to_degrees()
    );

    let table = write_table(&out, &rows, (slow.per_step - last.still.per_step).abs())?;
    println!("   table: {table}");
    let plot = write_plot(&out, &rows)?;
    println!("   plot: {plot}\n");
    let human = rows
        .iter()
        .find(|r| (r.knee.to_degrees() - 60.0).abs() < 8.0);
    println!(
        "Summary: {} per step at 25 cm (Wieber's HRP-2: 1/159), {} at 10 cm; Wieber's recorded \
         human pattern: 1/393.{}",
        fraction(last.still.per_step),
        fraction(rows[2].still.per_step),
        human.map_or(String::new(), |r| format!(
            " Our pattern with a human-like 60° swing knee (about {:.2} m): {} with the arms \
             still, {} swinging.",
            r.height,
            fraction(r.still.per_step),
            fraction(r.swinging.per_step)
        ))
    );
    Ok(())
}

/// `walking.md`: the table, with where it comes from; the path written.
/// `speed` is how much the pitch per step changed at half the speed (rad).
fn write_table(out: &Output, rows: &[Row], speed: f64) -> Result<String, String> {
    let mut md = String::new();
    md.push_str(
        "# The rotation of walking\n\n\
         Written by `scripts/figures.sh walking_rotation`; do \
         not edit.\n\n\
         A free-floating walker (`models/biped.chain`: de Leva 1996 segments, 75 kg) replays a \
         walking pattern with zero momentum (hips ±20°, the swing knee bent, the stance knee \
         straight; gait cycle 1.1 s; Dormand–Prince at `rtol = 1e-10`). Nothing outside pushes on \
         it, yet the trunk turns in the sagittal plane at every step: the legs go forward bent \
         and back straight, with different inertias (Wieber 2005, §5.1). Net pitch per step over \
         8 steps, positive forward; the step height is the swing ankle's rise above the stance \
         ankle; arms still, or swinging ±15° against the legs.\n\n",
    );
    md.push_str(
        "| step height | swing knee | arms still: pitch per step | turn | trunk yaw | arms \
         swinging: pitch per step | turn | trunk yaw |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let _ = writeln!(
            md,
            "| {:.2} m | {:.1}° | {} | {} | ±{:.1}° | {} | {} | ±{:.1}° |",
            r.height,
            r.knee.to_degrees(),
            degrees(r.still.per_step),
            fraction(r.still.per_step),
            r.still.yaw.to_degrees(),
            degrees(r.swinging.per_step),
            fraction(r.swinging.per_step),
            r.swinging.yaw.to_degrees()
        );
    }
    md.push_str(
        "\nNegative: the trunk leans back, step after step (the stance leg, straight, carries more \
         angular momentum backwards than the bent swing leg forwards). Without knee flexion \
         (0 m) the legs are the same going and coming and the walker does not turn. The pitch \
         grows with the height; the arms, swinging at a fixed length, change it little but \
         damp the trunk's yaw, its swing about the vertical against the legs (the hips have no \
         yaw joint: the trunk alone turns against them). ",
    );
    let _ = writeln!(
        md,
        "The same pattern at half the speed turns the walker by the same angle per step (25 cm: \
         to {:.0e}°): the shape of the step sets the turn, not its speed.",
        speed.to_degrees()
    );
    md.push_str(
        "\nWieber (2005) for comparison: 1/393 of a turn per step for a recorded human walking \
         pattern replayed on a simple free-floating model (his Fig. 2: 22° in 24 steps), up to \
         1/159 for HRP-2 at 25 cm high steps (his Fig. 3). Those come from other models and \
         other patterns (recorded, not ours); what carries over is the order of magnitude and \
         the growth with the step's height.\n",
    );
    out.write(&out.page("walking.md"), md.as_bytes())
}

/// `figures/walking_rotation.svg`: the fraction of a turn per step against the step height,
/// and the trunk's pitch over the walk for three heights; the path written.
fn write_plot(out: &Output, rows: &[Row]) -> Result<String, String> {
    // Magnitudes: Wieber does not give his rotations' sense; ours lean backwards.
    let turn = |a: f64| a.abs() / (2.0 * PI);
    let mut by_height = Panel::new(
        "Turn per step against the step height (magnitude; ours lean backwards)",
        "step height (m)",
        "fraction of a turn per step",
    )
    .with(
        "arms still",
        rows.iter()
            .map(|r| (r.height, turn(r.still.per_step)))
            .collect(),
    )
    .with(
        "arms swinging ±15°",
        rows.iter()
            .map(|r| (r.height, turn(r.swinging.per_step)))
            .collect(),
    );
    // Wieber's figures as level marks: the human pattern's across, HRP-2's at 25 cm.
    by_height = by_height
        .with(
            "Wieber: human pattern, 1/393",
            vec![(0.0, 1.0 / 393.0), (0.25, 1.0 / 393.0)],
        )
        .with(
            "Wieber: HRP-2, 25 cm steps, 1/159",
            vec![(0.22, 1.0 / 159.0), (0.25, 1.0 / 159.0)],
        );
    let mut over_time = Panel::new(
        "Trunk pitch while walking (arms still)",
        "step",
        "pitch (°)",
    );
    for r in rows
        .iter()
        .filter(|r| [0.05, 0.15, 0.25].contains(&r.height))
    {
        let first = base_orientation(r.still.states[0].q.as_slice());
        over_time = over_time.with(
            &format!("{:.2} m steps", r.height),
            r.still
                .states
                .iter()
                .map(|s| (2.0 * s.t / PERIOD, pitch(&first, s).to_degrees()))
                .collect(),
        );
    }
    let text = svg(&[by_height, over_time], 900, 330).map_err(|e| e.to_string())?;
    out.write(&out.figure("walking_rotation.svg"), text.as_bytes())
}
