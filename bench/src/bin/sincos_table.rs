//! `libm::sincos`, std's `f64::sin_cos` (glibc) and `articulated::math::sincos` side by side,
//! on 1024 seeded angles in [−π, π]: ns per angle (plain loop timing) and instructions per
//! angle (callgrind, independent of the machine's load).
//!
//! ```text
//! cargo run --release -p articulated-bench --bin sincos_table                 # ns per angle
//! cargo run --release -p articulated-bench --bin sincos_table -- --instructions  # callgrind
//! sincos_table --calls K IMPL CASE   # exactly K iterations, then exit
//! ```
//!
//! Cases: `one`, one angle per iteration (independent iterations: the processor overlaps
//! them); `chained`, the next angle is `sin + cos` of the previous one (the latency of one
//! call); `seven`, seven angles per iteration, summed (the joints of an arm). IMPL is `libm`,
//! `std`, `articulated` (`articulated::math::sincos` inlined into the loop, as in generated
//! code), `articulated-call` (through the `#[inline(never)]` [`one_sincos`]),
//! or `articulated-array` (`seven` only: one `sincos_array` call for the seven angles).
//!
//! Timing: batches of about 0.2 ms, the implementations alternating, 101 batches each; the
//! fastest batch is reported, which stays reproducible on a loaded machine. Instructions:
//! (Ir(K) − Ir(0)) / K / angles per iteration, so both include the loop and the table load
//! (a few instructions per angle). `objdump -d target/release/sincos_table` shows
//! `articulated::math::sincos` on its own (what `one_sincos` calls).

use std::hint::black_box;
use std::process::ExitCode;
use std::time::Instant;

use clap::builder::PossibleValuesParser;
use clap::Parser;

/// `libm::sincos`, std's `f64::sin_cos` and `articulated::math::sincos` side by side: ns per
/// angle, or instructions per angle under callgrind.
#[derive(Parser)]
#[command(
    name = "sincos_table",
    override_usage = "sincos_table [--instructions]
       sincos_table --calls K IMPL CASE"
)]
struct Cli {
    /// Instructions per angle under callgrind instead of ns per angle.
    #[arg(long, conflicts_with = "calls")]
    instructions: bool,
    /// Make exactly K iterations of IMPL on CASE, then exit (what --instructions runs).
    #[arg(long, value_name = "K", requires_all = ["imp", "case"])]
    calls: Option<usize>,
    /// With --calls: the implementation (`articulated-array`: `seven` only).
    #[arg(value_name = "IMPL", requires = "calls", value_parser = PossibleValuesParser::new(IMPLS))]
    imp: Option<String>,
    /// With --calls: one angle per iteration, the next angle from the previous result, or seven.
    #[arg(value_parser = PossibleValuesParser::new(CASES.map(|c| c.0)))]
    case: Option<String>,
}

const ANGLES: usize = 1024;
const IMPLS: [&str; 5] = [
    "libm",
    "std",
    "articulated",
    "articulated-call",
    "articulated-array",
];
const CASES: [(&str, f64); 3] = [("one", 1.0), ("chained", 1.0), ("seven", 7.0)];

fn angles() -> Vec<f64> {
    articulated_bench::angles(ANGLES)
}

/// `articulated::math::sincos`, out of line.
#[inline(never)]
pub fn one_sincos(x: f64) -> (f64, f64) {
    articulated::math::sincos(x)
}

fn run<F: Fn(f64) -> (f64, f64)>(f: F, case: &str, calls: usize, table: &[f64]) -> f64 {
    let mut sum = 0.0;
    let mut i = 0;
    match case {
        "one" => {
            for _ in 0..calls {
                i = (i + 1) % ANGLES;
                let (s, c) = f(black_box(table[i]));
                sum += s + c;
            }
        }
        "chained" => {
            let mut x = 0.5;
            for _ in 0..calls {
                let (s, c) = f(x);
                // Stays in [−π, π], but each angle depends on the previous result.
                x = black_box(s * 2.0 + c);
            }
            sum = x;
        }
        _ => {
            for _ in 0..calls {
                i = (i + 7) % (ANGLES - 7);
                let q: &[f64; 7] = black_box(table[i..i + 7].try_into().unwrap());
                for &x in q {
                    let (s, c) = f(x);
                    sum += s + c;
                }
            }
        }
    }
    sum
}

/// `f` (`articulated::math::sincos_array`): the seven angles
/// of an iteration in one call (`seven` only).
fn run_array<F: Fn([f64; 7]) -> ([f64; 7], [f64; 7])>(
    f: F,
    case: &str,
    calls: usize,
    table: &[f64],
) -> Option<f64> {
    if case != "seven" {
        return None;
    }
    let mut sum = 0.0;
    let mut i = 0;
    for _ in 0..calls {
        i = (i + 7) % (ANGLES - 7);
        let q: &[f64; 7] = black_box(table[i..i + 7].try_into().unwrap());
        let (s, c) = f(*q);
        for k in 0..7 {
            sum += s[k] + c[k];
        }
    }
    Some(sum)
}

fn run_impl(imp: &str, case: &str, calls: usize, table: &[f64]) -> Option<f64> {
    Some(match imp {
        "libm" => run(articulated::libm::sincos, case, calls, table),
        "std" => run(f64::sin_cos, case, calls, table),
        "articulated" => run(articulated::math::sincos, case, calls, table),
        "articulated-call" => run(one_sincos, case, calls, table),
        "articulated-array" => run_array(articulated::math::sincos_array, case, calls, table)?,
        _ => return None,
    })
}

fn callgrind(calls: usize, imp: &str, case: &str) -> Result<u64, String> {
    articulated_bench::callgrind(&["--calls", &calls.to_string(), imp, case])
}

fn instructions() -> Result<(), String> {
    let calls = 100_000;
    println!("instructions per angle (loop included)");
    println!("| impl | one | chained | seven |");
    println!("|---|---:|---:|---:|");
    for imp in IMPLS {
        let mut row = format!("| {imp} |");
        for (case, per) in CASES {
            if imp.ends_with("-array") && case != "seven" {
                row.push_str(" – |");
                continue;
            }
            let base = callgrind(0, imp, case)?;
            let full = callgrind(calls, imp, case)?;
            let per_angle = full.saturating_sub(base) as f64 / calls as f64 / per;
            row.push_str(&format!(" {per_angle:.1} |"));
        }
        println!("{row}");
    }
    Ok(())
}

fn timing(table: &[f64]) {
    println!("ns per angle (fastest of 101 batches)");
    println!("| impl | one | chained | seven |");
    println!("|---|---:|---:|---:|");
    let mut best = [[f64::INFINITY; 3]; IMPLS.len()];
    for (k, (case, per)) in CASES.into_iter().enumerate() {
        // About 0.2 ms per batch.
        let calls = (20_000.0 / per) as usize;
        for _ in 0..101 {
            for (j, imp) in IMPLS.into_iter().enumerate() {
                if imp.ends_with("-array") && case != "seven" {
                    continue;
                }
                let start = Instant::now();
                black_box(run_impl(imp, case, calls, table));
                let ns = start.elapsed().as_nanos() as f64 / calls as f64 / per;
                best[j][k] = best[j][k].min(ns);
            }
        }
    }
    let cell = |ns: f64| {
        if ns.is_finite() {
            format!("{ns:.2}")
        } else {
            "–".to_string()
        }
    };
    for (j, imp) in IMPLS.into_iter().enumerate() {
        println!(
            "| {imp} | {} | {} | {} |",
            cell(best[j][0]),
            cell(best[j][1]),
            cell(best[j][2])
        );
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let table = angles();
    if let (Some(calls), Some(imp), Some(case)) = (cli.calls, &cli.imp, &cli.case) {
        return match run_impl(imp, case, calls, &table) {
            Some(sum) => {
                black_box(sum);
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("sincos_table: {imp} has no case {case}");
                ExitCode::FAILURE
            }
        };
    }
    if cli.instructions {
        return match instructions() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        };
    }
    timing(&table);
    ExitCode::SUCCESS
}
