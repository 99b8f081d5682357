//! The falling cat (Wieber 2005, §4.2 and §5.2): dropped on its back at rest, a cat turns over
//! in the air by moving its waist alone, its angular momentum zero throughout.
//!
//! The cat is two cylinders joined at the waist (`models/falling_cat.chain`): the front half on a
//! free base with a quaternion, the rear half on a spherical joint. The waist follows a
//! prescribed bend-and-swing cycle; the base is free and unactuated, its acceleration solved at
//! each instant from the first six rows of `M(q)·a + nle(q, v) = [0; τ]` with the generated `M`
//! and `nle` (`articulated_examples::free_floating`). Dormand–Prince 5(4) at `rtol = 1e-11`.
//!
//! 1. The same cycle at three speeds turns the cat by the same angle: the turn depends on the
//!    path's shape, not its speed (a nonholonomic constraint).
//! 2. The turn per cycle grows with the bend: the shape is what matters.
//! 3. A planner turns the cat by 180° (on its feet): it chooses the number of cycles and solves
//!    the bend by regula falsi on the simulated turn. Feedback could not: Brockett's theorem
//!    rules out continuous time-invariant laws (`articulated_examples::falling_cat` says why).
//!
//! Throughout, the angular momentum about the centre of mass stays zero to rounding and the
//! centre of mass falls as `x_G0 + ½·g·t²`: measured by the generated `centroidal_momentum` and
//! `center_of_mass`, and again from the reference's body Jacobians (independent of the generated
//! code). It prints a report and writes `figures/falling_cat.svg` into the folder given as its
//! argument (default `target/docs/`; `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example falling_cat [-- OUT]
//! ```

use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

use articulated::model::Model;
use articulated::plot::{svg, Panel};
use articulated_examples::falling_cat::{
    bend_angle, conservation, fall, one_cycle, plan, ConeCycles, Conservation, Fall, FallingCat,
    Settings, MAX_BEND,
};

/// The period of one cycle for the planned manoeuvre and the slowest of the three speeds (s).
const PERIOD: f64 = 0.25;
/// The bend of the cycle run at three speeds (rad).
const BEND: f64 = PI / 4.0;

/// Prints how a fall kept the conservation laws.
fn report(c: &Conservation) {
    println!(
        "   |k_G| ≤ {:.1e} of Σ|k_k| (≤ {:.3} kg·m²/s; body Jacobians: {:.1e}); centre of mass \
         within {:.1e} m of x_G0 + ½·g·t² ({:.1e}), p within {:.1e} kg·m/s of m·g·t",
        c.momentum, c.momentum_scale, c.momentum_check, c.com, c.com_check, c.linear_momentum
    );
}

/// Part 1: one cycle at the periods T, 2T, 4T.
fn three_speeds(model: &Model, settings: Settings) -> Result<(Panel, Conservation), String> {
    println!(
        "1. One cycle of bend {:.0}° at three speeds:",
        BEND.to_degrees()
    );
    let mut panel = Panel::new(
        "One cycle at three speeds (the three curves coincide)",
        "t / T",
        "roll (°)",
    );
    let mut rolls = Vec::new();
    let mut worst = None::<Conservation>;
    for k in [1.0, 2.0, 4.0] {
        let period = PERIOD * k;
        let motion = ConeCycles {
            bend: BEND,
            period,
            cycles: 1,
        };
        let run = fall(motion, settings)?;
        let roll = run.turn().roll;
        let c = conservation(model, &run)?;
        println!(
            "   T = {period:.2} s: roll {:.9}°, {} steps ({} rejected)",
            roll.to_degrees(),
            run.stats.accepted,
            run.stats.rejected
        );
        worst = Some(match worst {
            Some(w) if w.momentum >= c.momentum => w,
            _ => c,
        });
        rolls.push(roll);
        panel = panel.with(
            &format!("T = {period:.2} s"),
            run.roll()
                .into_iter()
                .map(|(t, a)| (t / period, a.to_degrees()))
                .collect(),
        );
    }
    let spread = rolls.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
        - rolls.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    println!("   spread {spread:.1e} rad: the shape of the path sets the turn, not its speed");
    let worst = worst.ok_or("no run")?;
    report(&worst);
    Ok((panel, worst))
}

/// Part 2: the turn per cycle against the bend.
fn turn_by_bend(settings: Settings) -> Result<Panel, String> {
    println!("2. Turn per cycle against the bend β:");
    let mut points = Vec::new();
    let mut line = String::from("  ");
    for deg in (0..=15).map(|i| 5.0 * f64::from(i)) {
        let c = one_cycle(deg.to_radians(), settings)?;
        points.push((deg, c.roll.to_degrees()));
        if deg % 15.0 == 0.0 {
            line += &format!(" {deg:.0}°: {:.1}°,", c.roll.to_degrees());
        }
    }
    println!("{}", line.trim_end_matches(','));
    println!(
        "   (about ∝ β² for small bends: the area the path encloses in shape space; the largest \
         bend allowed is {:.0}°)",
        MAX_BEND.to_degrees()
    );
    Ok(Panel::new(
        "Turn per cycle against the bend",
        "bend β (°)",
        "roll per cycle (°)",
    )
    .with("simulated", points))
}

/// Part 3: the planned 180° turn.
fn turn_over(model: &Model, settings: Settings) -> Result<(Panel, Fall, Conservation), String> {
    let clock = Instant::now();
    let plan = plan(PI, 8, settings)?;
    println!(
        "3. Planner, 180° asked: {} cycles of bend {:.4}° (found in {} simulated cycles, {:.0} ms); \
         predicted roll {:.10}°",
        plan.cycles,
        plan.bend.to_degrees(),
        plan.evaluations,
        clock.elapsed().as_secs_f64() * 1e3,
        plan.predicted.roll.to_degrees()
    );
    let motion = ConeCycles {
        bend: plan.bend,
        period: PERIOD,
        cycles: plan.cycles,
    };
    let run = fall(motion, settings)?;
    let turn = run.turn();
    let c = conservation(model, &run)?;
    let end = run.states.last().ok_or("no states")?;
    println!(
        "   simulated over {:.2} s: roll {:.10}° (off by {:.1e} rad), long axis tilted by {:.3}°, \
         waist back to {:.1e} rad; fell {:.2} m",
        motion.duration(),
        turn.roll.to_degrees(),
        (turn.roll - PI).abs(),
        turn.swing.to_degrees(),
        end.q.fixed_rows::<3>(7).amax(),
        -end.q[2]
    );
    report(&c);
    let roll = run.roll();
    let bend: Vec<(f64, f64)> = run
        .states
        .iter()
        .map(|s| (s.t, bend_angle(&s.q.as_slice()[7..10]).to_degrees()))
        .collect();
    let panel = Panel::new(
        "Turning over: the planned 180° (on its back at 0°, on its feet at 180°)",
        "t (s)",
        "angle (°)",
    )
    .with(
        "roll about the long axis",
        roll.into_iter().map(|(t, a)| (t, a.to_degrees())).collect(),
    )
    .with("bend at the waist", bend)
    .with("target", vec![(0.0, 180.0), (motion.duration(), 180.0)]);
    Ok((panel, run, c))
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/falling_cat.chain");
    let model = articulated_codegen::load::load_model(&path, false).map_err(|e| e.to_string())?;
    println!(
        "The falling cat: two halves of 2 kg on a free base (quaternion) and a spherical waist, \
         {} velocities; M and nle generated ({} operations).",
        FallingCat::NV,
        FallingCat::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS.total()
    );
    println!(
        "Dropped on its back at rest; the waist bends and swings round a cone, the body is free.\n"
    );
    let settings = Settings::default();
    let (speeds, c1) = three_speeds(&model, settings)?;
    let by_bend = turn_by_bend(Settings {
        samples: 1,
        ..settings
    })?;
    let (manoeuvre, run, c3) = turn_over(&model, settings)?;
    let text = svg(&[manoeuvre, speeds, by_bend], 900, 330).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("falling_cat.svg"), text.as_bytes())?;
    println!("   plot: {file}\n");
    println!(
        "Summary: the turn depends on the path, not the speed; {} cycles of {:.1}° bend turn the \
         cat over to {:.1e} rad; |k_G| stays ≤ {:.1e} of the bodies' momenta.",
        run.motion.cycles,
        run.motion.bend.to_degrees(),
        (run.turn().roll - PI).abs(),
        [
            c1.momentum,
            c1.momentum_check,
            c3.momentum,
            c3.momentum_check
        ]
        .into_iter()
        .fold(0.0, f64::max)
    );
    Ok(())
}
