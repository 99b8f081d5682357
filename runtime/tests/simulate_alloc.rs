//! A step of every integrator on the generated two-link allocates nothing, and neither does a
//! whole simulation into a caller's buffer, nor a fault: counted by a global allocator that
//! counts every allocation of the process (`stats_alloc`).
//!
//! One test function only: the counter is global, so a second test running on another thread
//! would be counted too.

use std::alloc::System;

use articulated::integrate::{
    Cause, ControlledChain, Dopri5, Euler, ImplicitMidpoint, Integrator, Method, Rk4, State,
    Stepper, SymplecticEuler,
};
use articulated::nalgebra::{Const, SVector};
use articulated::simulate::Simulation;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain")]
struct TwoLink;

type S = State<f64, Const<6>, Const<6>>;

fn start() -> S {
    State::new(
        0.0,
        SVector::from([3.0, 0.15, 0.1, 0.3, -0.2, 0.15]),
        SVector::from([0.4, -0.3, 0.5, 0.2, 0.3, -0.4]),
    )
}

/// Allocations, reallocations and bytes allocated while `f` runs: the fewest of three runs.
/// The counter is process-wide and the test harness's own thread allocates now and then (a
/// few hundred bytes, seen on a loaded machine); an allocation in what `f` does shows in every
/// run (`f` runs hundreds of steps).
fn count(mut f: impl FnMut()) -> (usize, usize, usize) {
    (0..3)
        .map(|_| {
            let region = Region::new(GLOBAL);
            f();
            let stats = region.change();
            (
                stats.allocations,
                stats.reallocations,
                stats.bytes_allocated,
            )
        })
        .min()
        .unwrap_or_default()
}

fn steps<I: Integrator<f64, Const<6>, Const<6>>>(name: &str, mut integrator: I) {
    let mut system = ControlledChain::<f64, TwoLink, _>::new(
        |t: f64, _q: &SVector<f64, 6>, v: &SVector<f64, 6>| -v * (0.1 * t),
    );
    let mut s = start();
    let counted = count(|| {
        s = start();
        for n in 0..200 {
            let t_to = (n + 1) as f64 * 1e-3;
            if let Err(f) = integrator.advance(&mut system, &mut s, t_to, n) {
                panic!("{name}: {f}");
            }
        }
    });
    assert_eq!(
        counted,
        (0, 0, 0),
        "{name}: allocations, reallocations, bytes"
    );
    assert_eq!(s.t, 0.2);
}

#[test]
fn stepping_and_simulating_allocate_nothing() {
    steps("euler", Euler);
    steps("symplectic-euler", SymplecticEuler);
    steps("rk4", Rk4);
    steps("dopri5", Dopri5::new(1e-8, 1e-8));
    steps("implicit-midpoint", ImplicitMidpoint::new());
    for method in Method::ALL {
        steps(method.name(), Stepper::new(method, 1e-8, 1e-8));
    }

    // A whole simulation into a buffer on the stack, with a progress callback.
    let mut system = ControlledChain::<f64, TwoLink, _>::unforced();
    let mut buffer = [start(); 101];
    let mut last = 0;
    let counted = count(|| {
        let rows = Simulation::new(0.0, 0.1, 1e-3)
            .run_into(&mut system, &mut Rk4, start(), &mut buffer, |k, _t| {
                last = k
            })
            .unwrap_or_else(|f| panic!("{f}"));
        assert_eq!(rows, 101);
    });
    assert_eq!(counted, (0, 0, 0), "simulation into a buffer");
    assert_eq!(last, 100);

    // A fault is a value: no message is formatted, nothing allocated.
    let mut bad = start();
    bad.v[1] = f64::NAN;
    let counted = count(|| {
        let fault = Rk4
            .advance(&mut system, &mut bad, 0.01, 0)
            .expect_err("NaN in v");
        assert!(matches!(fault.cause, Cause::NonFinite { index: 1, .. }));
    });
    assert_eq!(counted, (0, 0, 0), "a fault");

    // The counter counts: a Vec allocates.
    let counted = count(|| {
        let v: Vec<f64> = std::hint::black_box(vec![1.0; 10]);
        assert_eq!(v.len(), 10);
    });
    assert_eq!(counted, (1, 0, 80));
}
