//! States per second: each output's scalar function called state by state, its batch function
//! in lanes (`lanes: 4` in `f64`, `lanes: 8` in `f32`; `articulated::lanes`), and the batch
//! function on every thread (`_par_batch`, rayon), for the 7-DOF arm and the 37-DOF humanoid
//! (its derivatives with the feature `humanoid-derivatives`, as `bench/peers/run.sh` builds it).
//!
//! ```text
//! cargo run --release -p articulated-bench --bin throughput -- [--threads 1,2] [--json FILE]
//! ```
//!
//! `bench/peers/run.sh` runs it beside Pinocchio's parallel algorithms and writes the figures to
//! `BENCHMARKS.md` ("Many states per call"); run alone it prints them. Each figure is the best
//! of `--rounds` timings of `--batches` batch calls on the same `--states` states (the scalar
//! loop on the same states), after the batch's values were checked against the scalar
//! function's. The states are what a user holds (`&[SVector<f64, NQ>]`): gathering them into
//! lanes and scattering the results back is part of every batch timing.

use std::hint::black_box;
use std::time::Instant;

use articulated::lanes::BatchLengths;
use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use clap::Parser;
use serde::Serialize;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/arm7.chain",
    outputs = [mass_matrix, nonlinear_effects, inverse_dynamics, forward_dynamics,
               inverse_dynamics_derivatives, forward_dynamics_derivatives],
    lanes = 4
)]
struct Arm7;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/arm7.chain",
    outputs = [mass_matrix, nonlinear_effects, inverse_dynamics, forward_dynamics],
    scalar = f32,
    lanes = 8
)]
struct Arm7F32;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [mass_matrix, nonlinear_effects, inverse_dynamics, forward_dynamics],
    lanes = 4
)]
struct Humanoid;

#[derive(articulated::Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [mass_matrix, nonlinear_effects, inverse_dynamics, forward_dynamics],
    scalar = f32,
    lanes = 8
)]
struct HumanoidF32;

/// The humanoid's derivatives (in lanes the largest functions this binary builds): behind the
/// feature `humanoid-derivatives`, which `bench/peers/run.sh` turns on, as `peers` has them.
#[cfg(feature = "humanoid-derivatives")]
#[derive(articulated::Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [inverse_dynamics_derivatives, forward_dynamics_derivatives],
    lanes = 4
)]
struct HumanoidDerivatives;

#[derive(Parser)]
#[command(about = "States per second: scalar loop, lanes, lanes on every thread")]
struct Args {
    /// Thread counts for the batch on every thread, comma-separated (default: 1 and all).
    #[arg(long)]
    threads: Option<String>,
    /// States per batch call.
    #[arg(long, default_value_t = 256)]
    states: usize,
    /// Batch calls per timing.
    #[arg(long, default_value_t = 20)]
    batches: usize,
    /// Timings per figure (the best is kept).
    #[arg(long, default_value_t = 7)]
    rounds: usize,
    /// Writes the figures as JSON here too.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
}

/// One figure.
#[derive(Serialize)]
struct Figure {
    model: &'static str,
    output: &'static str,
    scalar: &'static str,
    /// `scalar` (the function state by state), `lanes`, `lanes_threads`, `scalar_threads`.
    mode: &'static str,
    threads: usize,
    states_per_second: f64,
}

/// The bytes of inputs and results of one thread's share of a batch on many threads: a core's
/// L2 on this machine (Zen 5: 1 MiB).
const SHARE_BYTES: usize = 1 << 20;

/// The best states per second of `rounds` timings of `batches` calls of `f` over `n` states.
fn rate(args: &Args, n: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut best = f64::INFINITY;
    for _ in 0..args.rounds {
        let t = Instant::now();
        for _ in 0..args.batches {
            f();
        }
        best = best.min(t.elapsed().as_secs_f64());
    }
    (n * args.batches) as f64 / best
}

/// `n` states of `K` entries in `[-2, 2]`, a unit quaternion where `quat` says (its first
/// index).
fn states<T: articulated::nalgebra::RealField + Copy, const K: usize>(
    n: usize,
    seed: u64,
    quat: Option<usize>,
) -> Vec<SVector<T, K>> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            let mut s = SVector::<f64, K>::from_fn(|_, _| {
                x = x
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((x >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
            });
            if let Some(k) = quat {
                let r = s.fixed_rows::<4>(k).normalize();
                s.fixed_rows_mut::<4>(k).copy_from(&r);
            }
            s.map(|v| articulated::nalgebra::convert(v))
        })
        .collect()
}

/// The largest difference between two results of one output, relative to the largest entry
/// (at least 1); infinite where one is an error and the other not.
trait Difference {
    fn entries(&self) -> Vec<f64>;
    fn difference(&self, other: &Self) -> f64 {
        let (a, b) = (self.entries(), other.entries());
        if a.len() != b.len() {
            return f64::INFINITY;
        }
        let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        a.iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs() / scale)
            .fold(0.0, f64::max)
    }
}

impl<T: Copy + Into<f64> + articulated::nalgebra::Scalar, const R: usize, const C: usize> Difference
    for SMatrix<T, R, C>
{
    fn entries(&self) -> Vec<f64> {
        self.iter().map(|&x| x.into()).collect()
    }
}

impl<A: Difference, B: Difference> Difference for (A, B) {
    fn entries(&self) -> Vec<f64> {
        let mut v = self.0.entries();
        v.extend(self.1.entries());
        v
    }
}

impl<A: Difference, B: Difference, C: Difference> Difference for (A, B, C) {
    fn entries(&self) -> Vec<f64> {
        let mut v = self.0.entries();
        v.extend(self.1.entries());
        v.extend(self.2.entries());
        v
    }
}

impl<A: Difference> Difference for Result<A, articulated::SingularMassMatrix> {
    fn entries(&self) -> Vec<f64> {
        match self {
            Ok(a) => a.entries(),
            Err(_) => vec![f64::INFINITY],
        }
    }
}

/// Times one output: the scalar loop, the batch, and the batch on each thread count (rayon
/// pools of that size), after checking the batch against the scalar loop.
macro_rules! time_output {
    ($figures:ident, $args:ident, $pools:ident, $model:literal, $prec:literal, $c:ty,
     $output:ident, $batch:ident, $par:ident, $init:expr, $($arg:ident),+) => {{
        let n = $args.states;
        let mut out = vec![$init; n];
        let mut want = out.clone();
        <$c>::$batch($(&$arg),+, &mut out).map_err(|e: BatchLengths| e.to_string())?;
        for (i, w) in want.iter_mut().enumerate() {
            *w = <$c>::$output($(&$arg[i]),+);
        }
        let worst = out.iter().zip(&want).map(|(o, w)| o.difference(w)).fold(0.0, f64::max);
        // The lanes are the scalar function bit for bit in `f64`; in `f32` their sines and
        // cosines are `libm::sincosf`'s algorithm, identical but for a rare argument, which
        // would move a result by an ulp or so.
        if worst > if $prec == "f64" { 0.0 } else { 1e-6 } {
            return Err(format!("{} {}: the batch differs from the scalar function by {worst:e}", $model, stringify!($output)));
        }
        let output = stringify!($output);
        let scalar = rate(&$args, n, || {
            for (i, o) in out.iter_mut().enumerate() {
                *o = <$c>::$output($(&$arg[i]),+);
            }
            black_box(&out);
        });
        let lanes = rate(&$args, n, || {
            let _ = <$c>::$batch($(&$arg),+, &mut out);
            black_box(&out);
        });
        let mut line = format!("{:<9} {:<4} {:<30} scalar {:>9.3} M/s  lanes {:>9.3} M/s ({:.1}×)",
            $model, $prec, output, scalar / 1e6, lanes / 1e6, lanes / scalar);
        $figures.push(Figure { model: $model, output, scalar: $prec, mode: "scalar", threads: 1, states_per_second: scalar });
        $figures.push(Figure { model: $model, output, scalar: $prec, mode: "lanes", threads: 1, states_per_second: lanes });
        for (threads, pool) in &$pools {
            // Each thread's share of the batch: enough states to outweigh the fork and join
            // (up to 4096), as long as their inputs and results fit a core's L2, and never fewer
            // than the one-thread batch. Without the bound the humanoid's mass matrices (11 KB a
            // state) made 45 MB a thread, and the figure timed the memory's bandwidth, not the
            // code: fewer states per second on two threads than on one.
            let bytes = $(std::mem::size_of_val(&$arg[0]) +)+ std::mem::size_of_val(&out[0]);
            let per = threads * (SHARE_BYTES / bytes).min(4096).max(n);
            let reps = per.div_ceil(n);
            $(let $arg: Vec<_> = $arg.iter().cycle().take(reps * n).copied().collect();)+
            let mut out = vec![$init; reps * n];
            let par = pool.install(|| rate(&$args, reps * n, || {
                let _ = <$c>::$par($(&$arg),+, &mut out);
                black_box(&out);
            }));
            let scalar_par = pool.install(|| {
                use rayon::prelude::*;
                rate(&$args, reps * n, || {
                    let chunk = articulated::lanes::par_chunk(out.len());
                    out.par_chunks_mut(chunk).enumerate().for_each(|(k, o)| {
                        for (j, o) in o.iter_mut().enumerate() {
                            let i = k * chunk + j;
                            *o = <$c>::$output($(&$arg[i]),+);
                        }
                    });
                    black_box(&out);
                })
            });
            line += &format!("  {threads} threads: lanes {:>9.3} M/s, scalar {:>9.3} M/s", par / 1e6, scalar_par / 1e6);
            $figures.push(Figure { model: $model, output, scalar: $prec, mode: "lanes_threads", threads: *threads, states_per_second: par });
            $figures.push(Figure { model: $model, output, scalar: $prec, mode: "scalar_threads", threads: *threads, states_per_second: scalar_par });
        }
        println!("{line}");
    }};
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse();
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads: Vec<usize> = match &args.threads {
        Some(list) => list
            .split(',')
            .map(|t| {
                t.trim()
                    .parse::<usize>()
                    .map_err(|e| format!("--threads `{t}`: {e}"))
            })
            .collect::<Result<_, _>>()?,
        None => {
            let mut t = vec![1, all];
            t.dedup();
            t
        }
    };
    let pools: Vec<(usize, rayon::ThreadPool)> = threads
        .iter()
        .map(|&t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .map(|p| (t, p))
                .map_err(|e| e.to_string())
        })
        .collect::<Result<_, _>>()?;
    let n = args.states;
    let mut figures = Vec::new();
    eprintln!(
        "[throughput] {n} states per call, best of {} × {} calls; threads {threads:?}",
        args.rounds, args.batches
    );

    // The four dynamics outputs of one chain at the states `(q, v, a)`, `NV` velocities.
    macro_rules! dynamics {
        ($model:literal, $prec:literal, $c:ty, $t:ty, $nv:literal, $q:ident, $v:ident, $a:ident) => {{
            let (vz, mz) = (
                SVector::<$t, $nv>::zeros(),
                SMatrix::<$t, $nv, $nv>::zeros(),
            );
            time_output!(
                figures,
                args,
                pools,
                $model,
                $prec,
                $c,
                mass_matrix,
                mass_matrix_batch,
                mass_matrix_par_batch,
                mz,
                $q
            );
            time_output!(
                figures,
                args,
                pools,
                $model,
                $prec,
                $c,
                nonlinear_effects,
                nonlinear_effects_batch,
                nonlinear_effects_par_batch,
                vz,
                $q,
                $v
            );
            time_output!(
                figures,
                args,
                pools,
                $model,
                $prec,
                $c,
                inverse_dynamics,
                inverse_dynamics_batch,
                inverse_dynamics_par_batch,
                vz,
                $q,
                $v,
                $a
            );
            time_output!(
                figures,
                args,
                pools,
                $model,
                $prec,
                $c,
                forward_dynamics,
                forward_dynamics_batch,
                forward_dynamics_par_batch,
                Ok(vz),
                $q,
                $v,
                $a
            );
        }};
    }

    let (q, v, a) = (
        states::<f64, 7>(n, 1, None),
        states(n, 2, None),
        states(n, 3, None),
    );
    dynamics!("arm7", "f64", Arm7, f64, 7, q, v, a);
    let m7 = SMatrix::<f64, 7, 7>::zeros();
    time_output!(
        figures,
        args,
        pools,
        "arm7",
        "f64",
        Arm7,
        inverse_dynamics_derivatives,
        inverse_dynamics_derivatives_batch,
        inverse_dynamics_derivatives_par_batch,
        (m7, m7),
        q,
        v,
        a
    );
    time_output!(
        figures,
        args,
        pools,
        "arm7",
        "f64",
        Arm7,
        forward_dynamics_derivatives,
        forward_dynamics_derivatives_batch,
        forward_dynamics_derivatives_par_batch,
        Ok((m7, m7, m7)),
        q,
        v,
        a
    );
    let (q, v, a) = (
        states::<f32, 7>(n, 1, None),
        states(n, 2, None),
        states(n, 3, None),
    );
    dynamics!("arm7", "f32", Arm7F32, f32, 7, q, v, a);
    // The humanoid's base is a quaternion at q[3..7].
    let (q, v, a) = (
        states::<f64, 38>(n, 4, Some(3)),
        states(n, 5, None),
        states(n, 6, None),
    );
    dynamics!("humanoid", "f64", Humanoid, f64, 37, q, v, a);
    #[cfg(feature = "humanoid-derivatives")]
    {
        let m37 = SMatrix::<f64, 37, 37>::zeros();
        time_output!(
            figures,
            args,
            pools,
            "humanoid",
            "f64",
            HumanoidDerivatives,
            inverse_dynamics_derivatives,
            inverse_dynamics_derivatives_batch,
            inverse_dynamics_derivatives_par_batch,
            (m37, m37),
            q,
            v,
            a
        );
        time_output!(
            figures,
            args,
            pools,
            "humanoid",
            "f64",
            HumanoidDerivatives,
            forward_dynamics_derivatives,
            forward_dynamics_derivatives_batch,
            forward_dynamics_derivatives_par_batch,
            Ok((m37, m37, m37)),
            q,
            v,
            a
        );
    }
    let (q, v, a) = (
        states::<f32, 38>(n, 4, Some(3)),
        states(n, 5, None),
        states(n, 6, None),
    );
    dynamics!("humanoid", "f32", HumanoidF32, f32, 37, q, v, a);

    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&figures).map_err(|e| e.to_string())?;
        // Written whole: to a temporary file first, renamed into place.
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
        std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
