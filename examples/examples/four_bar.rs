//! A closed loop: the four-bar linkage of `models/four_bar.chain` (a crank, a coupler and a
//! rocker whose far end is pinned back to the world) swinging under gravity for 20 s, the loop
//! held by `articulated::constraint`: the tree's dynamics (generated), the loop's point
//! constraint `p_tip = p_ground` (three rows of which the planar mechanism has two independent,
//! solved by proximal iterations), and Baumgarte terms `J·q̈ + γ = −K_D·J·v − K_P·e` that pull
//! the drift of the integrator back (Hemami, Dariush & Barin 2005 and Wieber 2005 both treat
//! the forces of such constraints; this is the first of our closed loops).
//!
//! Two runs from the same closed configuration (crank at 0.3 rad, at rest), RK4 at 1 ms: with
//! `K_P = 100 s⁻²`, `K_D = 20 s⁻¹`, and without stabilization (`K_P = K_D = 0`), where only
//! the acceleration is held and the integrator's error accumulates in the loop. Prints the
//! worst loop error and energy change of each, and writes `figures/four_bar.svg` (both against
//! time) into the folder given as its argument (default `target/docs/`;
//! `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example four_bar [-- OUT]
//! ```

use articulated::constraint::{Baumgarte, ConstrainedChain, Loop, Settings};
use articulated::integrate::{Integrator, Rk4, State};
use articulated::nalgebra::SVector;
use articulated::plot::{svg, Panel};
use articulated::prelude::*;

#[derive(articulated::Chain)]
#[chain(file = "../models/four_bar.chain")]
struct FourBar;

type V3 = SVector<f64, 3>;

const DT: f64 = 1e-3;
const T_END: f64 = 20.0;

/// The closed configuration at crank angle `theta`, the coupler's far end up (each link's
/// absolute angle θ about y puts it along `(cos θ, 0, −sin θ)`).
fn closed(theta: f64) -> V3 {
    let (a, b, c, d) = (0.2, 0.6, 0.5, 0.6);
    let (bx, bz) = (a * theta.cos(), -a * theta.sin());
    let l = (d - bx).hypot(bz);
    let (ux, uz) = ((d - bx) / l, -bz / l);
    let along = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - along * along).sqrt();
    let (mut cx, mut cz) = (bx + along * ux - h * uz, bz + along * uz + h * ux);
    if cz < 0.0 {
        (cx, cz) = (bx + along * ux + h * uz, bz + along * uz - h * ux);
    }
    let angle = |dx: f64, dz: f64| (-dz).atan2(dx);
    let (t1, t2, t3) = (theta, angle(cx - bx, cz - bz), angle(d - cx, -cz));
    V3::new(t1, t2 - t1, t3 - t2)
}

/// One run: the loop's gap (m) and the energy's change (J) against time.
struct Run {
    gap: Vec<(f64, f64)>,
    energy: Vec<(f64, f64)>,
}

fn run(q0: &V3, gains: Option<Baumgarte>) -> Result<Run, String> {
    let loops = [Loop::point(0, 1)];
    // The loop's third row (along the pins' axis) is identically zero: a proximal μ solves it.
    let settings = Settings {
        mu: 1e-4,
        ..Settings::default()
    };
    let mut chain = ConstrainedChain::<FourBar, _, 3, 3, 2, 3>::new(
        q0,
        &[],
        &loops,
        gains,
        settings,
        |_, _: &V3, _: &V3| V3::zeros(),
    )
    .map_err(|e| e.to_string())?;
    let energy = |q: &V3, v: &V3| FourBar::kinetic_energy(q, v) + FourBar::potential_energy(q);
    let mut state = State::new(0.0, *q0, V3::zeros());
    let e0 = energy(q0, &state.v);
    let mut out = Run {
        gap: Vec::new(),
        energy: Vec::new(),
    };
    let steps = (T_END / DT).round() as usize;
    for step in 1..=steps {
        Rk4.advance(&mut chain, &mut state, step as f64 * DT, step)
            .map_err(|e| e.to_string())?;
        if step % 20 == 0 {
            let [tip, ground] = FourBar::frame_placements(&state.q);
            let gap = (tip.translation - ground.translation).norm();
            out.gap.push((state.t, gap));
            out.energy.push((state.t, energy(&state.q, &state.v) - e0));
        }
    }
    Ok(out)
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    let q0 = closed(0.3);
    println!("four-bar from crank 0.3 rad at rest, RK4 at {DT} s for {T_END} s");
    let held = run(
        &q0,
        Some(Baumgarte {
            kp: 100.0,
            kd: 20.0,
        }),
    )?;
    let free = run(&q0, None)?;
    let worst = |x: &[(f64, f64)]| x.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    for (name, r) in [
        ("Baumgarte K_P = 100 s⁻², K_D = 20 s⁻¹", &held),
        ("no stabilization", &free),
    ] {
        println!(
            "{name}: loop open by at most {:.1e} m, energy changed by at most {:.1e} J",
            worst(&r.gap),
            worst(&r.energy)
        );
    }
    let scaled = |x: &[(f64, f64)], k: f64| x.iter().map(|&(t, y)| (t, y * k)).collect();
    let gap = Panel::new("The loop's gap |p_tip − p_ground|", "t (s)", "gap (nm)")
        .with(
            "Baumgarte (K_P = 100 s⁻², K_D = 20 s⁻¹)",
            scaled(&held.gap, 1e9),
        )
        .with("no stabilization", scaled(&free.gap, 1e9));
    let energy = Panel::new(
        "The energy's change (the loop does no work)",
        "t (s)",
        "E − E₀ (µJ)",
    )
    .with("Baumgarte", scaled(&held.energy, 1e6))
    .with("no stabilization", scaled(&free.energy, 1e6));
    let text = svg(&[gap, energy], 900, 320).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("four_bar.svg"), text.as_bytes())?;
    println!("wrote {file}");
    Ok(())
}
