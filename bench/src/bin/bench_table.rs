//! Per shipped model and output, ns/call of the generated code and of the
//! reference, their ratio, and the generator's operation count, measured side by side in one
//! run (what each engine's figure includes: `docs/guide/accuracy-and-speed.md`, "Against our
//! own reference"). Criterion (`cargo bench -p articulated-bench`) stays the authoritative harness; this is
//! a plain loop timing: batches of N calls (N calibrated to about 1 ms), generated and reference
//! batches alternating, the median batch over 201 repeats (`--min`: the fastest batch, which
//! stays reproducible to a few per cent on a loaded machine where the median does not).
//!
//! ```text
//! cargo run --release -p articulated-bench --bin bench_table                  # timing table
//! cargo run --release -p articulated-bench --bin bench_table -- --min          # fastest batch
//! cargo run --release -p articulated-bench --bin bench_table -- --instructions  # callgrind
//! bench_table --calls K MODEL OUTPUT ENGINE   # exactly K calls of one kernel, then exit
//! ```
//!
//! `--instructions` runs this binary under `valgrind --tool=callgrind` twice per kernel, with
//! `--calls 0` and `--calls K`, and reports (Ir(K) − Ir(0)) / K: the instructions of one call
//! (plus the few of the loop and `black_box`), independent of the machine's load.

use std::hint::black_box;
use std::process::ExitCode;
use std::time::Duration;

use articulated::OpCounts;
use articulated_bench::{batch, calibrate, each_model, Engine, Output, Visit, STATES};
use clap::{CommandFactory, Parser};

/// Per shipped model and output, ns/call (or instructions/call) of the generated code and of the
/// reference, side by side.
#[derive(Parser)]
#[command(
    name = "bench_table",
    override_usage = "bench_table [--repeats R] [--batch-ms T] [--min]
       bench_table --instructions [--calls K]
       bench_table --calls K MODEL OUTPUT ENGINE   (ENGINE: generated, reference, reference_aba)"
)]
struct Cli {
    /// Batches per kernel; the median (or, with --min, the fastest) is reported. At least 1.
    #[arg(long, value_name = "R", default_value_t = 201)]
    repeats: usize,
    /// Target duration of one batch in milliseconds.
    #[arg(long, value_name = "T", default_value_t = 1)]
    batch_ms: u64,
    /// Report the fastest batch instead of the median.
    #[arg(long)]
    min: bool,
    /// Instructions per call under callgrind instead of timing.
    #[arg(long)]
    instructions: bool,
    /// With MODEL OUTPUT ENGINE: make exactly K calls of that kernel, then exit. With
    /// --instructions: the calls per callgrind run (default 1024).
    #[arg(long, value_name = "K")]
    calls: Option<usize>,
    /// With --calls: MODEL OUTPUT ENGINE, the kernel to call.
    #[arg(value_names = ["MODEL", "OUTPUT", "ENGINE"])]
    kernel: Vec<String>,
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// One row of the timing table.
struct Row {
    model: &'static str,
    output: Output,
    ops: OpCounts,
    generated_ns: f64,
    reference_ns: f64,
    /// Forward dynamics only: the bare ABA recursion of the reference.
    bare_ns: Option<f64>,
}

/// Times every kernel: `repeats` alternating batches of each engine, each about `batch_time`;
/// keeps the median batch (or the fastest, with `min`).
struct Timer {
    repeats: usize,
    min: bool,
    batch_time: Duration,
    rows: Vec<Row>,
}

impl Timer {
    fn pick(&self, xs: Vec<f64>) -> f64 {
        if self.min {
            xs.into_iter().fold(f64::INFINITY, f64::min)
        } else {
            median(xs)
        }
    }
}

impl Visit for Timer {
    fn visit<G: FnMut(usize), R: FnMut(usize)>(
        &mut self,
        model: &'static str,
        output: Output,
        ops: OpCounts,
        mut generated: G,
        mut reference: R,
        mut bare: Option<&mut dyn FnMut(usize)>,
    ) {
        let ng = calibrate(&mut generated, self.batch_time);
        let nr = calibrate(&mut reference, self.batch_time);
        let nb = bare.as_mut().map(|f| calibrate(f, self.batch_time));
        let (mut tg, mut tr, mut tb) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..self.repeats {
            tg.push(batch(&mut generated, ng).as_secs_f64() * 1e9 / ng as f64);
            tr.push(batch(&mut reference, nr).as_secs_f64() * 1e9 / nr as f64);
            if let (Some(f), Some(n)) = (bare.as_mut(), nb) {
                tb.push(batch(f, n).as_secs_f64() * 1e9 / n as f64);
            }
        }
        let row = Row {
            model,
            output,
            ops,
            generated_ns: self.pick(tg),
            reference_ns: self.pick(tr),
            bare_ns: (!tb.is_empty()).then(|| self.pick(tb)),
        };
        eprintln!(
            "{model}/{}: {:.1} ns vs {:.1} ns",
            output.name(),
            row.generated_ns,
            row.reference_ns
        );
        self.rows.push(row);
    }
}

/// Runs exactly `calls` calls of one kernel (for callgrind).
struct Only {
    model: String,
    output: Output,
    engine: Engine,
    calls: usize,
    found: bool,
}

impl Visit for Only {
    fn visit<G: FnMut(usize), R: FnMut(usize)>(
        &mut self,
        model: &'static str,
        output: Output,
        _ops: OpCounts,
        mut generated: G,
        mut reference: R,
        bare: Option<&mut dyn FnMut(usize)>,
    ) {
        if model != self.model || output != self.output {
            return;
        }
        match (self.engine, bare) {
            (Engine::Generated, _) => black_box(batch(&mut generated, self.calls)),
            (Engine::Reference, _) => black_box(batch(&mut reference, self.calls)),
            (Engine::ReferenceAba, Some(mut f)) => black_box(batch(&mut f, self.calls)),
            (Engine::ReferenceAba, None) => return,
        };
        self.found = true;
    }
}

/// Collects the (model, output, ops) of every kernel without running any.
struct List(Vec<(&'static str, Output, OpCounts)>);

impl Visit for List {
    fn visit<G: FnMut(usize), R: FnMut(usize)>(
        &mut self,
        model: &'static str,
        output: Output,
        ops: OpCounts,
        _: G,
        _: R,
        _: Option<&mut dyn FnMut(usize)>,
    ) {
        self.0.push((model, output, ops));
    }
}

fn print_timing(rows: &[Row], stat: &str) {
    println!("| model | output | ops | sin/cos | generated (ns/call, {stat}) | reference (ns/call, {stat}) | reference / generated | ns/op (generated) |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        println!(
            "| {} | {} | {} | {} | {:.1} | {:.0} | {:.1}× | {:.2} |",
            r.model,
            r.output.name(),
            r.ops.total(),
            r.ops.sin_cos,
            r.generated_ns,
            r.reference_ns,
            r.reference_ns / r.generated_ns,
            r.generated_ns / r.ops.total() as f64
        );
    }
    println!();
    println!("Forward dynamics against the reference's bare ABA recursion (no input, pivot or eigenvalue checks):");
    println!();
    println!("| model | generated (ns/call) | bare `aba()` (ns/call) | `aba()` / generated |");
    println!("|---|---:|---:|---:|");
    for r in rows {
        if let Some(b) = r.bare_ns {
            println!(
                "| {} | {:.1} | {:.0} | {:.1}× |",
                r.model,
                r.generated_ns,
                b,
                b / r.generated_ns
            );
        }
    }
}

/// What a sine/cosine pair costs: per angle of six, as the generated `f64` code computes them
/// (`articulated::math::sincos_array`), and one at a time by `libm::sincos` (no_std) and
/// `f64::sin_cos` (std, the platform's libm): the floor under outputs with few operations but
/// several angles.
fn print_sincos(timer: &Timer) {
    let angles: Vec<f64> = (0..STATES).map(|i| -1.0 + 0.13 * i as f64).collect();
    let six = |i: usize| core::array::from_fn::<f64, 6, _>(|k| angles[(i + k) % STATES]);
    let mut array = |i: usize| {
        black_box(articulated::math::sincos_array(black_box(six(i))));
    };
    let mut libm = |i: usize| {
        black_box(articulated::libm::sincos(black_box(angles[i % STATES])));
    };
    let mut std = |i: usize| {
        black_box(black_box(angles[i % STATES]).sin_cos());
    };
    let na = calibrate(&mut array, timer.batch_time);
    let nl = calibrate(&mut libm, timer.batch_time);
    let ns = calibrate(&mut std, timer.batch_time);
    let (mut ta, mut tl, mut ts) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..timer.repeats {
        ta.push(batch(&mut array, na).as_secs_f64() * 1e9 / na as f64 / 6.0);
        tl.push(batch(&mut libm, nl).as_secs_f64() * 1e9 / nl as f64);
        ts.push(batch(&mut std, ns).as_secs_f64() * 1e9 / ns as f64);
    }
    println!();
    println!(
        "One sine/cosine pair: `math::sincos_array` of six angles (what generated f64 code calls) \
         {:.1} ns per angle, `libm::sincos` {:.1} ns, `f64::sin_cos` (std) {:.1} ns.",
        timer.pick(ta),
        timer.pick(tl),
        timer.pick(ts)
    );
}

/// Instructions callgrind counts for `--calls calls model output engine`.
fn callgrind(model: &str, output: Output, engine: Engine, calls: usize) -> Result<u64, String> {
    let calls = calls.to_string();
    articulated_bench::callgrind(&["--calls", &calls, model, output.name(), engine.name()])
}

fn instructions(calls: usize) -> Result<(), String> {
    let mut list = List(Vec::new());
    each_model(&mut list);
    println!("| model | output | ops | sin/cos | generated (instr/call) | reference (instr/call) | reference / generated | instr/op (generated) |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    let mut bare = Vec::new();
    for (model, output, ops) in list.0 {
        let mut per_call = [0.0; 2];
        for (k, engine) in [Engine::Generated, Engine::Reference]
            .into_iter()
            .enumerate()
        {
            let base = callgrind(model, output, engine, 0)?;
            let full = callgrind(model, output, engine, calls)?;
            per_call[k] = full.saturating_sub(base) as f64 / calls as f64;
        }
        if output == Output::ForwardDynamics {
            let base = callgrind(model, output, Engine::ReferenceAba, 0)?;
            let full = callgrind(model, output, Engine::ReferenceAba, calls)?;
            bare.push((
                model,
                per_call[0],
                full.saturating_sub(base) as f64 / calls as f64,
            ));
        }
        println!(
            "| {model} | {} | {} | {} | {:.0} | {:.0} | {:.1}× | {:.2} |",
            output.name(),
            ops.total(),
            ops.sin_cos,
            per_call[0],
            per_call[1],
            per_call[1] / per_call[0],
            per_call[0] / ops.total() as f64
        );
    }
    println!();
    println!("| model | forward_dynamics generated (instr/call) | bare `aba()` (instr/call) | `aba()` / generated |");
    println!("|---|---:|---:|---:|");
    for (model, g, b) in bare {
        println!("| {model} | {g:.0} | {b:.0} | {:.1}× |", b / g);
    }
    Ok(())
}

fn run(cli: Cli) -> Result<(), String> {
    let usage = || Cli::command().render_usage().to_string();
    if cli.instructions {
        if !cli.kernel.is_empty() {
            return Err(usage());
        }
        return instructions(cli.calls.unwrap_or(STATES * 64).max(1));
    }
    if let Some(calls) = cli.calls {
        let [model, output, engine] = cli.kernel.as_slice() else {
            return Err(usage());
        };
        let output =
            Output::from_name(output).ok_or_else(|| format!("unknown output `{output}`"))?;
        let engine =
            Engine::from_name(engine).ok_or_else(|| format!("unknown engine `{engine}`"))?;
        let mut only = Only {
            model: model.clone(),
            output,
            engine,
            calls,
            found: false,
        };
        each_model(&mut only);
        return if only.found {
            Ok(())
        } else {
            Err(format!("unknown model `{model}`"))
        };
    }
    if !cli.kernel.is_empty() {
        return Err(usage());
    }
    let (repeats, min) = (cli.repeats.max(1), cli.min);
    let mut timer = Timer {
        repeats,
        min,
        batch_time: Duration::from_millis(cli.batch_ms),
        rows: Vec::new(),
    };
    each_model(&mut timer);
    print_timing(&timer.rows, if min { "min" } else { "median" });
    print_sincos(&timer);
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bench_table: {e}");
            ExitCode::FAILURE
        }
    }
}
