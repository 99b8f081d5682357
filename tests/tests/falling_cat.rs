//! The falling cat (Wieber 2005, §4.2 and §5.2) on its generated dynamics, held to facts that do
//! not come from the code under test:
//!
//! - a nonholonomic turn depends on the path, not its speed: one cycle at the periods T, 2T and
//!   4T turns the cat by the same angle to 1e-7 rad, and by more than 0.1 rad (so a cat that
//!   does not turn at all fails);
//! - the planner's manoeuvre, simulated afresh, turns the cat by π to 1e-6 rad, and leaves its
//!   back pointing up in the world;
//! - the angular momentum about the centre of mass stays zero to 1e-9 of the bodies' own momenta,
//!   and the centre of mass falls as `x_G0 + ½·g·t²` (closed form) to 1e-8 m, the linear
//!   momentum as `m·g·t`: measured by the generated `centroidal_momentum` and `center_of_mass`
//!   and again from the reference's body Jacobians (plain 3D kinematics, no generated code).
//!
//! A wrong sign or term in the path's derivatives breaks the first (the integrated path then
//! depends on the speed), a wrong base acceleration the third.
//!
//! Runtime: about 1 s in the test profile on a 2-core machine (each simulated cycle is a few
//! thousand evaluations of the generated `M` and `nle`).

use std::f64::consts::PI;
use std::path::Path;

use articulated::model::Model;
use articulated::nalgebra::Vector3;
use articulated_examples::falling_cat::{conservation, fall, plan, ConeCycles, Settings};
use articulated_examples::free_floating::base_orientation;

fn model() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/falling_cat.chain");
    articulated_codegen::load::load_model(&path, false).unwrap_or_else(|e| panic!("{e}"))
}

/// Tolerances for the tests: tight enough for the asserted 1e-7 and 1e-9, states recorded
/// `samples` times per cycle.
fn settings(samples: usize) -> Settings {
    Settings {
        rtol: 1e-11,
        atol: 1e-12,
        samples,
    }
}

#[test]
fn one_cycle_turns_the_cat_by_the_same_angle_at_three_speeds() {
    let turns: Vec<_> = [0.3, 0.6, 1.2]
        .into_iter()
        .map(|period| {
            let motion = ConeCycles {
                bend: 40f64.to_radians(),
                period,
                cycles: 1,
            };
            fall(motion, settings(1)).unwrap().turn()
        })
        .collect();
    let roll = turns[0].roll;
    println!(
        "roll per cycle at T, 2T, 4T: {:?} rad",
        turns.iter().map(|c| c.roll).collect::<Vec<_>>()
    );
    assert!(roll > 0.1, "the cycle should turn the cat: {roll} rad");
    for c in &turns[1..] {
        assert!((c.roll - roll).abs() < 1e-7, "{} vs {roll}", c.roll);
        // The whole rotation, not only its roll.
        assert!(
            (c.net - turns[0].net).norm() < 1e-7,
            "{:?} vs {:?}",
            c.net,
            turns[0].net
        );
    }
}

#[test]
fn the_planned_manoeuvre_turns_the_cat_over() {
    let plan = plan(PI, 8, settings(1)).unwrap();
    println!(
        "plan: {} cycles of bend {:.4}°",
        plan.cycles,
        plan.bend.to_degrees()
    );
    // Simulated afresh, at another period than the planner's, with states along the way.
    let motion = ConeCycles {
        bend: plan.bend,
        period: 0.4,
        cycles: plan.cycles,
    };
    let run = fall(motion, settings(4)).unwrap();
    let roll = run.turn().roll;
    assert!((roll - PI).abs() < 1e-6, "roll {roll} rad");
    // It started on its back (its z axis, out of its back, pointing down) and lands on its feet.
    let first = base_orientation(run.states[0].q.as_slice());
    let last = base_orientation(run.states[run.states.len() - 1].q.as_slice());
    assert!((first * Vector3::z()).z < -0.999_999);
    assert!(
        (last * Vector3::z()).z > 0.999,
        "back towards {:?}",
        last * Vector3::z()
    );
}

#[test]
fn momentum_about_the_centre_of_mass_stays_zero_and_the_centre_of_mass_falls_freely() {
    let model = model();
    let motion = ConeCycles {
        bend: 50f64.to_radians(),
        period: 0.5,
        cycles: 2,
    };
    let run = fall(motion, settings(25)).unwrap();
    let c = conservation(&model, &run).unwrap();
    println!("{c:?}");
    assert!(c.momentum_scale > 0.01, "the bodies should move");
    // Generated, and from body Jacobians.
    assert!(c.momentum <= 1e-9 && c.momentum_check <= 1e-9, "{c:?}");
    assert!(c.com <= 1e-8 && c.com_check <= 1e-8, "{c:?}");
    assert!(c.linear_momentum <= 1e-8, "{c:?}");
}
