//! One integration step of the generated two-link against the dynamics calls it makes, side by
//! side in one criterion run: the group `"simulate/two_link/<method>"` holds `step` (one
//! `Integrator::advance` of 1 ms, unforced: the controller returns zeros) and `calls` (that
//! many `TwoLink::forward_dynamics` calls on as many different states, inputs and results
//! through `black_box`):
//!
//! | method | calls per step |
//! |---|---|
//! | `euler` | 1 |
//! | `rk4` | 4 |
//! | `dopri5` | 6 (FSAL: the seventh stage is the next step's first; loose tolerance, no rejection) |
//!
//! The ratio `step / calls` is the integrator's overhead; the target is at most 1.2.
//! Each step continues from the last (so Dormand–Prince reuses its last stage), from the
//! two-link hanging and swinging, restarted every 4096 steps so that explicit Euler's energy
//! growth never matters.
//!
//! `cargo bench -p articulated-bench --bench simulate`.

use std::hint::black_box;
use std::time::Duration;

use articulated::integrate::{ControlledChain, Dopri5, Euler, Integrator, Rk4, State};
use articulated::prelude::ForwardDynamics;
use articulated_bench::TwoLink;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Const, SVector};

type S = State<f64, Const<6>, Const<6>>;

const STEP: f64 = 1e-3;
const RESTART: usize = 4096;

fn start() -> S {
    State::new(
        0.0,
        SVector::from([3.0, 0.15, 0.1, 0.3, -0.2, 0.15]),
        SVector::from([0.4, -0.3, 0.5, 0.2, 0.3, -0.4]),
    )
}

/// `n` states along the swing, as a step's stages would see them.
fn stage_states(n: usize) -> Vec<S> {
    let mut system = ControlledChain::<f64, TwoLink, _>::unforced();
    let mut s = start();
    let mut out = vec![s];
    for k in 0..n - 1 {
        let t = s.t + STEP / n as f64;
        Rk4.advance(&mut system, &mut s, t, k)
            .unwrap_or_else(|f| panic!("{f}"));
        out.push(s);
    }
    out
}

fn zero(_t: f64, _q: &SVector<f64, 6>, _v: &SVector<f64, 6>) -> SVector<f64, 6> {
    SVector::zeros()
}

fn group<I: Integrator<f64, Const<6>, Const<6>>>(
    c: &mut Criterion,
    name: &str,
    calls: usize,
    mut make: impl FnMut() -> I,
) {
    let mut group = c.benchmark_group(format!("simulate/two_link/{name}"));
    group.bench_function("step", |b| {
        let mut system = ControlledChain::<f64, TwoLink, _>::new(zero);
        let mut integrator = make();
        let mut s = start();
        let mut n = 0;
        b.iter(|| {
            if n == RESTART {
                (s, n, integrator) = (start(), 0, make());
            }
            let t_to = s.t + STEP;
            if let Err(f) = integrator.advance(&mut system, black_box(&mut s), t_to, n) {
                panic!("{name}: {f}");
            }
            n += 1;
            black_box(&s);
        })
    });
    let states = stage_states(calls);
    let tau = SVector::<f64, 6>::zeros();
    group.bench_function("calls", |b| {
        b.iter(|| {
            for s in &states {
                let a =
                    TwoLink::forward_dynamics(black_box(&s.q), black_box(&s.v), black_box(&tau));
                black_box(a.unwrap_or_else(|e| panic!("{e}")));
            }
        })
    });
    group.finish();
}

fn simulate(c: &mut Criterion) {
    group(c, "euler", 1, || Euler);
    group(c, "rk4", 4, || Rk4);
    group(c, "dopri5", 6, || {
        let mut dp = Dopri5::new(1e-3, 1e-3);
        dp.initial_step = Some(STEP);
        dp
    });
}

/// Private, so the `pub fn benches` that `criterion_group!` writes needs no docs.
mod benches {
    use super::*;

    criterion_group! {
        name = benches;
        config = Criterion::default()
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_millis(2000))
            .sample_size(40);
        targets = simulate
    }
}
criterion_main!(benches::benches);
