//! The speed–accuracy trade (issue 12), measured: each way of simulating one second of the
//! two-link and of the 7-DOF arm — `f32` or `f64`, `accuracy: fastest` or `robust`, the
//! integrator and its step, the full model, the model pruned for its scene (a joint group
//! locked) or taken as quasi-static — timed and compared with the ground truth: the same second
//! integrated by classic Runge–Kutta at a step of 1e-4 s (the arm: 2.5e-5 s) in double-double
//! arithmetic on the full model ([`articulated_dynamics::extended`]).
//!
//! Each [`Point`] is the time per simulated second against the error of the final positions
//! (the largest over the coordinates the option keeps, in radians); the points no other beats
//! on both are the Pareto front. The example `trade` writes `docs/trade.md` and
//! `docs/figures/trade.svg`.

use std::path::Path;
use std::time::Instant;

use articulated::integrate::{ControlledChain, Ensemble, Integrator, Method, State, Stepper};
use articulated::nalgebra::{Const, RealField, SVector};
use articulated::prelude::*;
use articulated_dynamics::extended::{Dd, GroundTruth};
use articulated_dynamics::Scalar as _;

macro_rules! trade_chain {
    ($name:ident, $file:literal, $($key:ident = $value:tt),*) => {
        #[doc = concat!("`", $file, "`: ", stringify!($($key = $value),*), ".")]
        #[derive(articulated::Chain)]
        #[chain(file = $file, outputs = [forward_dynamics], $($key = $value),*)]
        pub struct $name;
    };
}

trade_chain!(TwoLinkF64, "../models/two_link.chain", scalar = f64);
trade_chain!(
    TwoLinkF64Lanes,
    "../models/two_link.chain",
    scalar = f64,
    lanes = 4
);
trade_chain!(
    TwoLinkF64Robust,
    "../models/two_link.chain",
    accuracy = robust
);
trade_chain!(TwoLinkF32, "../models/two_link.chain", scalar = f32);
trade_chain!(
    TwoLinkF32Robust,
    "../models/two_link.chain",
    scalar = f32,
    accuracy = robust
);
/// The two-link with its hip locked at the scenario's start: legs and trunk one rigid body.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [forward_dynamics],
    lock = [hip(0.1, -0.3, 0.0)]
)]
pub struct TwoLinkHipLocked;
/// The two-link, quasi-static.
#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain", outputs = [forward_dynamics], quasi_static)]
pub struct TwoLinkQuasiStatic;

trade_chain!(Arm7F64, "../models/arm7.chain", scalar = f64);
trade_chain!(
    Arm7F64Lanes,
    "../models/arm7.chain",
    scalar = f64,
    lanes = 4
);
trade_chain!(Arm7F64Robust, "../models/arm7.chain", accuracy = robust);
trade_chain!(Arm7F32, "../models/arm7.chain", scalar = f32);
trade_chain!(
    Arm7F32Robust,
    "../models/arm7.chain",
    scalar = f32,
    accuracy = robust
);
/// The arm with its wrist locked at the scenario's start.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/arm7.chain",
    outputs = [forward_dynamics],
    lock = [j5(0.4), j6(0.3), j7(0.1)]
)]
pub struct Arm7WristLocked;
/// The arm, quasi-static.
#[derive(articulated::Chain)]
#[chain(file = "../models/arm7.chain", outputs = [forward_dynamics], quasi_static)]
pub struct Arm7QuasiStatic;

/// The simulated time (s).
pub const T_END: f64 = 1.0;
/// The integrators compared.
pub const METHODS: [Method; 3] = [
    Method::SymplecticEuler,
    Method::Rk4,
    Method::ImplicitMidpoint,
];
/// Their steps (s).
pub const STEPS: [f64; 4] = [1e-2, 3e-3, 1e-3, 3e-4];

/// One of the two scenarios.
#[derive(Clone, Copy, Debug)]
pub struct Scenario {
    /// The model's name in tables.
    pub name: &'static str,
    /// Its file.
    pub file: &'static str,
    /// Initial positions (the locked joints at their lock values).
    pub q0: &'static [f64],
    /// Initial velocities (the locked joints at rest).
    pub v0: &'static [f64],
    /// How many leading coordinates the pruned model keeps.
    pub kept: usize,
    /// What the pruned model locks, for tables.
    pub pruned: &'static str,
    /// The ground truth's step (s).
    pub truth_step: f64,
}

/// The two-link swinging from a lean, the hip at rest.
pub const TWO_LINK: Scenario = Scenario {
    name: "two-link",
    file: "../models/two_link.chain",
    q0: &[0.3, 0.2, 0.0, 0.1, -0.3, 0.0],
    v0: &[0.5, -0.4, 0.3, 0.0, 0.0, 0.0],
    kept: 3,
    pruned: "hip locked",
    truth_step: 1e-4,
};

/// The arm swinging down from 0.34 rad off hanging straight (`j2 = π` hangs it), the wrist at
/// rest.
pub const ARM7: Scenario = Scenario {
    name: "7-DOF arm",
    file: "../models/arm7.chain",
    q0: &[0.3, 2.8, -0.2, -0.4, 0.4, 0.3, 0.1],
    v0: &[0.4, -0.3, 0.6, 0.2, 0.0, 0.0, 0.0],
    kept: 4,
    pruned: "wrist locked",
    truth_step: 2.5e-5,
};

/// One option measured.
#[derive(Clone, Debug)]
pub struct Point {
    /// `f64` or `f32`.
    pub scalar: &'static str,
    /// `fastest` or `robust`.
    pub accuracy: &'static str,
    /// `full`, the pruned model's description, or `quasi-static`.
    pub model: &'static str,
    /// The integrator.
    pub method: Method,
    /// Its step (s).
    pub dt: f64,
    /// Wall time per simulated second (s), the least of several repetitions.
    pub seconds: f64,
    /// The largest error of the final positions it keeps (rad); `None` if the run stopped.
    pub error: Option<f64>,
    /// On the Pareto front: no other point is both faster and more accurate.
    pub pareto: bool,
}

impl Point {
    /// A short label: `f64 robust rk4 1e-3 full`.
    pub fn label(&self) -> String {
        format!(
            "{} {} {} {:.0e} {}",
            self.scalar,
            self.accuracy,
            self.method.name(),
            self.dt,
            self.model
        )
    }
}

/// The ground truth's final positions, and its own error (the same integration at twice the
/// step, against it: RK4's error falls 16-fold when the step halves, so the truth is within a
/// fifteenth of that).
pub fn truth(s: &Scenario) -> (Vec<f64>, f64) {
    let model = articulated_codegen::load::load_model(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(s.file),
        false,
    )
    .unwrap_or_else(|e| panic!("{}: {e}", s.file));
    let gt = GroundTruth::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let fine = rk4_dd(&gt, s, s.truth_step);
    let coarse = rk4_dd(&gt, s, 2.0 * s.truth_step);
    let own = fine
        .iter()
        .zip(&coarse)
        .fold(0.0f64, |m, (a, b)| m.max((*a - *b).abs().to_f64()));
    (fine.iter().map(|x| x.to_f64()).collect(), own)
}

/// Classic Runge–Kutta in double-double on the ground truth's ABA, from the scenario's start
/// to [`T_END`] (all coordinates of these models are vectors: `q̇ = v`).
fn rk4_dd(gt: &GroundTruth, s: &Scenario, h: f64) -> Vec<Dd> {
    let n = s.v0.len();
    let lift = |x: &[f64]| -> Vec<Dd> { x.iter().map(|&x| Dd::from_f64(x)).collect() };
    let (mut q, mut v) = (lift(s.q0), lift(s.v0));
    let tau = vec![Dd::zero(); n];
    let steps = (T_END / h).round() as usize;
    let (hd, half, sixth) = (
        Dd::from_f64(h),
        Dd::from_f64(0.5),
        Dd::one() / Dd::from_f64(6.0),
    );
    let axpy = |x: &[Dd], a: Dd, y: &[Dd]| -> Vec<Dd> {
        x.iter().zip(y).map(|(&x, &y)| x + a * y).collect()
    };
    for _ in 0..steps {
        let k1v = gt.acceleration(&q, &v, &tau);
        let k1q = v.clone();
        let (q2, v2) = (axpy(&q, hd * half, &k1q), axpy(&v, hd * half, &k1v));
        let k2v = gt.acceleration(&q2, &v2, &tau);
        let k2q = v2;
        let (q3, v3) = (axpy(&q, hd * half, &k2q), axpy(&v, hd * half, &k2v));
        let k3v = gt.acceleration(&q3, &v3, &tau);
        let k3q = v3;
        let (q4, v4) = (axpy(&q, hd, &k3q), axpy(&v, hd, &k3v));
        let k4v = gt.acceleration(&q4, &v4, &tau);
        let k4q = v4;
        let two = Dd::from_f64(2.0);
        for i in 0..n {
            q[i] = q[i] + hd * sixth * (k1q[i] + two * k2q[i] + two * k3q[i] + k4q[i]);
            v[i] = v[i] + hd * sixth * (k1v[i] + two * k2v[i] + two * k3v[i] + k4v[i]);
        }
    }
    q
}

/// One generated chain simulated for [`T_END`] by `method` at about `dt` (a whole number of
/// steps), from the first `NQ` coordinates of the scenario's start: the final positions
/// (widened to `f64`), or `None` if the integration stopped.
pub fn integrate_once<T, C, const NQ: usize, const NV: usize>(
    s: &Scenario,
    method: Method,
    dt: f64,
) -> Option<Vec<f64>>
where
    T: RealField + Copy + Into<f64>,
    C: ForwardDynamics<T, NQ, NV>,
{
    let convert = |x: f64| articulated::nalgebra::convert::<f64, T>(x);
    let q0 = SVector::<T, NQ>::from_iterator(s.q0.iter().take(NQ).map(|&x| convert(x)));
    let v0 = SVector::<T, NV>::from_iterator(s.v0.iter().take(NV).map(|&x| convert(x)));
    // A whole number of steps that ends exactly at `T_END`.
    let steps = (T_END / dt).round() as usize;
    let dt = T_END / steps as f64;
    let mut system = ControlledChain::<T, C, _>::unforced();
    let mut stepper =
        Stepper::<T, Const<NQ>, Const<NV>>::new(method, convert(1e-8), convert(1e-10));
    let mut state = State::new(T::zero(), q0, v0);
    for k in 1..=steps {
        let t = convert(k as f64 * dt);
        stepper.advance(&mut system, &mut state, t, k).ok()?;
    }
    Some(state.q.iter().map(|&x| x.into()).collect())
}

/// [`integrate_once`] timed: the final positions and the wall time per simulated second, the
/// least of the repetitions in 50 ms (at least two).
fn simulate<T, C, const NQ: usize, const NV: usize>(
    s: &Scenario,
    method: Method,
    dt: f64,
) -> (Option<Vec<f64>>, f64)
where
    T: RealField + Copy + Into<f64>,
    C: ForwardDynamics<T, NQ, NV>,
{
    let (result, best) = best_time(|| integrate_once::<T, C, NQ, NV>(s, method, dt));
    (result, best / T_END)
}

/// `once` repeated for 50 ms (at least twice, and not after a run that stopped): its last
/// result and its least wall time in seconds.
fn best_time<R>(mut once: impl FnMut() -> Option<R>) -> (Option<R>, f64) {
    let start = Instant::now();
    let mut repetitions = 0u32;
    let mut result = None;
    let mut best = f64::INFINITY;
    while repetitions < 2 || start.elapsed().as_secs_f64() < 0.05 {
        let t0 = Instant::now();
        result = once();
        best = best.min(t0.elapsed().as_secs_f64());
        repetitions += 1;
        if result.is_none() {
            break;
        }
    }
    (result, best)
}

/// The copies of an ensemble option ([`ENSEMBLE`]).
pub const COPIES: usize = 64;

/// The model column of the ensemble option: [`COPIES`] copies of the full model stepped by
/// [`Ensemble::rk4`], four in lanes (`lanes = 4`), its time per copy. Off the Pareto front,
/// which answers for one simulation.
pub const ENSEMBLE: &str = "full, per copy of 64 in lanes";

/// One second of [`COPIES`] copies of the scenario's start by [`Ensemble::rk4`] at the step
/// `dt`: the first copy's final positions (each copy follows [`Rk4`](articulated::integrate::Rk4)'s trajectory alone, so
/// its error is the scalar option's) and the wall time per simulated second and per copy, the
/// least of the repetitions in 50 ms (at least two).
fn simulate_ensemble<C, const NQ: usize, const NV: usize>(
    s: &Scenario,
    dt: f64,
) -> (Option<Vec<f64>>, f64)
where
    C: ForwardDynamics<f64, NQ, NV>,
{
    let q0 = SVector::<f64, NQ>::from_iterator(s.q0.iter().take(NQ).copied());
    let v0 = SVector::<f64, NV>::from_iterator(s.v0.iter().take(NV).copied());
    let steps = (T_END / dt).round() as usize;
    let dt = T_END / steps as f64;
    let tau = vec![SVector::<f64, NV>::zeros(); COPIES];
    let p = [C::default_params()];
    let mut ensemble = Ensemble::new();
    let once = |ensemble: &mut Ensemble<f64, NQ, NV>| {
        let (mut q, mut v) = (vec![q0; COPIES], vec![v0; COPIES]);
        let mut faults = vec![None; COPIES];
        for _ in 0..steps {
            ensemble
                .rk4::<C>(&mut q, &mut v, &tau, &p, dt, &mut faults)
                .ok()?;
            if faults.iter().any(Option::is_some) {
                return None;
            }
        }
        Some(q[0].iter().copied().collect::<Vec<f64>>())
    };
    let (result, best) = best_time(|| once(&mut ensemble));
    (result, best / T_END / COPIES as f64)
}

/// Every option of one scenario, with the Pareto front marked.
pub fn points(s: &Scenario, truth: &[f64]) -> Vec<Point> {
    let mut out = Vec::new();
    for method in METHODS {
        for dt in STEPS {
            let mut push =
                |scalar, accuracy, model, kept: usize, (q, seconds): (Option<Vec<f64>>, f64)| {
                    let error = q.map(|q: Vec<f64>| {
                        q.iter()
                            .zip(truth)
                            .take(kept)
                            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                    });
                    out.push(Point {
                        scalar,
                        accuracy,
                        model,
                        method,
                        dt,
                        seconds,
                        error: error.filter(|e| e.is_finite()),
                        pareto: false,
                    });
                };
            let n = s.v0.len();
            // One scenario's six generated types: full in each scalar and accuracy choice, the
            // pruned model (its coordinates), the quasi-static one.
            macro_rules! options {
                ($f64:ty, $robust:ty, $f32:ty, $f32_robust:ty, $pruned:ty, $kept:literal,
                 $quasi:ty, $lanes:ty, $n:literal) => {
                    push(
                        "f64",
                        "fastest",
                        "full",
                        n,
                        simulate::<f64, $f64, $n, $n>(s, method, dt),
                    );
                    push(
                        "f64",
                        "robust",
                        "full",
                        n,
                        simulate::<f64, $robust, $n, $n>(s, method, dt),
                    );
                    push(
                        "f32",
                        "fastest",
                        "full",
                        n,
                        simulate::<f32, $f32, $n, $n>(s, method, dt),
                    );
                    push(
                        "f32",
                        "robust",
                        "full",
                        n,
                        simulate::<f32, $f32_robust, $n, $n>(s, method, dt),
                    );
                    push(
                        "f64",
                        "fastest",
                        s.pruned,
                        s.kept,
                        simulate::<f64, $pruned, $kept, $kept>(s, method, dt),
                    );
                    push(
                        "f64",
                        "fastest",
                        "quasi-static",
                        n,
                        simulate::<f64, $quasi, $n, $n>(s, method, dt),
                    );
                    if method == Method::Rk4 {
                        push(
                            "f64",
                            "fastest",
                            ENSEMBLE,
                            n,
                            simulate_ensemble::<$lanes, $n, $n>(s, dt),
                        );
                    }
                };
            }
            if s.name == TWO_LINK.name {
                options!(
                    TwoLinkF64,
                    TwoLinkF64Robust,
                    TwoLinkF32,
                    TwoLinkF32Robust,
                    TwoLinkHipLocked,
                    3,
                    TwoLinkQuasiStatic,
                    TwoLinkF64Lanes,
                    6
                );
            } else {
                options!(
                    Arm7F64,
                    Arm7F64Robust,
                    Arm7F32,
                    Arm7F32Robust,
                    Arm7WristLocked,
                    4,
                    Arm7QuasiStatic,
                    Arm7F64Lanes,
                    7
                );
            }
        }
    }
    mark_pareto(&mut out);
    out
}

/// Marks the points that no other beats on both time and error, for one simulation (the
/// ensemble's points, a time per copy, are left off): from the fastest, each that is
/// at least 5 % more accurate than every faster one (a difference below that is rounding
/// between options that compute the same thing, not a choice).
pub fn mark_pareto(points: &mut [Point]) {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].error.is_some() && points[i].model != ENSEMBLE)
        .collect();
    order.sort_by(|&a, &b| points[a].seconds.total_cmp(&points[b].seconds));
    let mut best = f64::INFINITY;
    for i in order {
        let e = points[i].error.unwrap_or(f64::INFINITY);
        if e < 0.95 * best {
            best = e;
            points[i].pareto = true;
        }
    }
}

/// Forward dynamics of one generated chain: its time per call (ns, the least of several batches
/// of calls at the scenario's start).
fn fd_cost<C, const NQ: usize, const NV: usize>(s: &Scenario) -> f64
where
    C: ForwardDynamics<f64, NQ, NV>,
{
    let q = SVector::<f64, NQ>::from_iterator(s.q0.iter().take(NQ).copied());
    let v = SVector::<f64, NV>::from_iterator(s.v0.iter().take(NV).copied());
    let tau = SVector::<f64, NV>::zeros();
    let batch = 20_000;
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let t0 = Instant::now();
        let mut sink = 0.0;
        for k in 0..batch {
            let mut qk = q;
            qk[0] += k as f64 * 1e-9;
            if let Ok(a) = C::forward_dynamics(std::hint::black_box(&qk), &v, &tau) {
                sink += a[0];
            }
        }
        std::hint::black_box(sink);
        best = best.min(t0.elapsed().as_secs_f64() / batch as f64);
    }
    best * 1e9
}

/// What the scene costs: forward dynamics of the full model, of the pruned one and of the
/// quasi-static one, `(label, operations, ns per call)`.
pub fn scene_costs(s: &Scenario) -> Vec<(&'static str, usize, f64)> {
    macro_rules! costs {
        ($full:ty, $pruned:ty, $kept:literal, $quasi:ty, $n:literal) => {
            vec![
                (
                    "full",
                    <$full>::FORWARD_DYNAMICS_OPS.total(),
                    fd_cost::<$full, $n, $n>(s),
                ),
                (
                    s.pruned,
                    <$pruned>::FORWARD_DYNAMICS_OPS.total(),
                    fd_cost::<$pruned, $kept, $kept>(s),
                ),
                (
                    "quasi-static",
                    <$quasi>::FORWARD_DYNAMICS_OPS.total(),
                    fd_cost::<$quasi, $n, $n>(s),
                ),
            ]
        };
    }
    if s.name == TWO_LINK.name {
        costs!(TwoLinkF64, TwoLinkHipLocked, 3, TwoLinkQuasiStatic, 6)
    } else {
        costs!(Arm7F64, Arm7WristLocked, 4, Arm7QuasiStatic, 7)
    }
}
