//! What a joint's drive does in a simulation: a 1 kg pendulum thrown at 2 rad/s from 0.4 rad,
//! free; with viscous damping; with damping, dry friction and stops at ±0.5 rad; and with a
//! heavy rotor (armature) on top, which the generated dynamics already contain. Writes
//! `figures/drives.svg` (the angle and the energy against time), whole or not at all, into the
//! folder given as its argument (default `target/docs/`; `articulated_examples::output`).
//!
//! ```sh
//! cargo run --release -p articulated-examples --example drives [-- OUT]
//! ```

use articulated::drives::Drives;
use articulated::integrate::{ControlledChain, Integrator, Rk4, State};
use articulated::nalgebra::SVector;
use articulated::plot::{svg, Panel};
use articulated::prelude::*;

articulated::chain! {
    /// The pendulum, free.
    chain Free {
        outputs: [forward_dynamics, kinetic_energy, potential_energy];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) { parent: world, child: bob }
    }
}

articulated::chain! {
    /// The pendulum with a damper.
    chain Damped {
        outputs: [forward_dynamics, kinetic_energy, potential_energy];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) { parent: world, child: bob, damping: 0.2 }
    }
}

articulated::chain! {
    /// The pendulum with a damper, dry friction and stops.
    chain Stopped {
        outputs: [forward_dynamics, kinetic_energy, potential_energy];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) {
            parent: world, child: bob, damping: 0.2, friction: 0.3, lower: -0.5, upper: 0.5
        }
    }
}

articulated::chain! {
    /// The same with a rotor of 1 kg·m² reflected to the joint (the bob's own is 1.01).
    chain Geared {
        outputs: [forward_dynamics, kinetic_energy, potential_energy];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
        joint pivot: revolute(y) {
            parent: world, child: bob, armature: 1.0, damping: 0.2, friction: 0.3, lower: -0.5,
            upper: 0.5
        }
    }
}

type V1 = SVector<f64, 1>;

const DT: f64 = 1e-4;
const STEPS: usize = 60_000;
const EVERY: usize = 50;

/// Points `(t, y)` of a curve.
type Curve = Vec<(f64, f64)>;

/// `(t, q)` and `(t, T + V + the stops' spring energy)` every `EVERY` steps of RK4 for the chain
/// `C` through its drives.
fn run<C>() -> (Curve, Curve)
where
    C: ForwardDynamics<f64, 1, 1> + KineticEnergy<f64, 1, 1> + PotentialEnergy<f64, 1, 1>,
{
    let drives = match Drives::<f64, 1, 1>::of::<C>() {
        Ok(drives) => drives,
        Err(e) => panic!("{e}"),
    };
    let unforced = |_t: f64, _q: &V1, _v: &V1| V1::zeros();
    let mut system = ControlledChain::<f64, C, _>::new(drives.around(unforced));
    let mut state = State::new(0.0, V1::new(0.4), V1::new(2.0));
    let (mut angle, mut energy) = (Vec::new(), Vec::new());
    for k in 0..=STEPS {
        if k % EVERY == 0 {
            angle.push((state.t, state.q[0]));
            let e = C::kinetic_energy(&state.q, &state.v)
                + C::potential_energy(&state.q)
                + drives.stop_energy(&state.q);
            energy.push((state.t, e));
        }
        if k < STEPS {
            if let Err(e) = Rk4.advance(&mut system, &mut state, (k + 1) as f64 * DT, k) {
                panic!("{e}");
            }
        }
    }
    (angle, energy)
}

fn main() -> Result<(), String> {
    let out = articulated_examples::output::Output::from_args()?;
    let runs = [
        ("free", run::<Free>()),
        ("damping 0.2 N·m·s", run::<Damped>()),
        ("+ friction 0.3 N·m, stops ±0.5 rad", run::<Stopped>()),
        ("+ rotor 1 kg·m²", run::<Geared>()),
    ];
    let mut angle = Panel::new(
        "A pendulum thrown at 2 rad/s from 0.4 rad",
        "t (s)",
        "angle (rad)",
    );
    let mut energy = Panel::new(
        "Its energy T + V, the stops' springs included",
        "t (s)",
        "energy (J)",
    );
    for (name, (a, e)) in runs {
        println!(
            "{name}: final angle {:.4} rad, energy {:.4} J",
            a.last().map_or(f64::NAN, |p| p.1),
            e.last().map_or(f64::NAN, |p| p.1)
        );
        angle = angle.with(name, a);
        energy = energy.with(name, e);
    }
    let text = svg(&[angle, energy], 900, 320).map_err(|e| e.to_string())?;
    let file = out.write(&out.figure("drives.svg"), text.as_bytes())?;
    println!("wrote {file}");
    Ok(())
}
