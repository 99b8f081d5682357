//! `docs/throughput.md` and its plot: how the states per second grow with threads, ours against
//! Pinocchio's parallel algorithms, from the figures of a run on a machine with many cores.
//!
//! ```text
//! throughput --threads 1,2,4,8,16 --json ours.json
//! pinocchio_timing --urdf models/arm7.urdf --states … --throughput 1,2,4,8,16 arm7 > arm7.json
//! pinocchio_timing --urdf models/humanoid.urdf --floating … humanoid > humanoid.json
//! cargo run --release -p articulated-bench --bin scaling -- --ours ours.json \
//!     --pinocchio arm7=arm7.json --pinocchio humanoid=humanoid.json --machine "…" --out docs
//! ```
//!
//! `bench/peers/run.sh` measures at one thread and at this machine's threads and writes
//! `BENCHMARKS.md`; this page is for a machine with more cores (a session's lent device), where
//! the scaling shows. Written whole: the page and the plot go to temporary files first.

use std::collections::BTreeMap;
use std::path::PathBuf;

use articulated::plot::{svg, Panel};
use clap::Parser;
use serde::Deserialize;

#[derive(Parser)]
#[command(about = "docs/throughput.md from a many-core run of `throughput` and Pinocchio's")]
struct Args {
    /// The JSON `throughput --json` wrote.
    #[arg(long)]
    ours: PathBuf,
    /// `MODEL=FILE`: what `pinocchio_timing --throughput` printed for that model (repeatable).
    #[arg(long)]
    pinocchio: Vec<String>,
    /// The machine, in words (CPU, cores, clock), for the page.
    #[arg(long)]
    machine: String,
    /// The command that gave the figures, for the page.
    #[arg(long, default_value = "")]
    command: String,
    /// The folder of the page (`throughput.md`) and of `figures/throughput_scaling.svg`.
    #[arg(long, default_value = "target/docs")]
    out: PathBuf,
}

#[derive(Deserialize)]
struct Ours {
    model: String,
    output: String,
    scalar: String,
    mode: String,
    threads: usize,
    states_per_second: f64,
}

#[derive(Deserialize)]
struct Theirs {
    output: String,
    threads: usize,
    states_per_second: f64,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn read<T: for<'de> Deserialize<'de>>(path: &std::path::Path) -> Result<T, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes `text` to `path` whole: a temporary file beside it, renamed into place.
fn write_whole(path: &std::path::Path, text: &str) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

fn run() -> Result<(), String> {
    let args = Args::parse();
    let ours: Vec<Ours> = read(&args.ours)?;
    let mut theirs: BTreeMap<String, Vec<Theirs>> = BTreeMap::new();
    for p in &args.pinocchio {
        let (model, file) = p
            .split_once('=')
            .ok_or_else(|| format!("--pinocchio `{p}`: expected MODEL=FILE"))?;
        theirs.insert(model.to_string(), read(std::path::Path::new(file))?);
    }
    let find = |model: &str, output: &str, prec: &str, mode: &str, t: usize| {
        ours.iter()
            .find(|f| {
                (
                    f.model.as_str(),
                    f.output.as_str(),
                    f.scalar.as_str(),
                    f.mode.as_str(),
                    f.threads,
                ) == (model, output, prec, mode, t)
            })
            .map(|f| f.states_per_second)
    };
    let pin = |model: &str, output: &str, t: usize| {
        theirs.get(model).and_then(|v| {
            v.iter()
                .find(|f| f.output == output && f.threads == t)
                .map(|f| f.states_per_second)
        })
    };
    let mut threads: Vec<usize> = ours.iter().map(|f| f.threads).collect();
    threads.sort_unstable();
    threads.dedup();
    let top = threads.last().copied().unwrap_or(1);
    let m = |x: Option<f64>| x.map_or("–".to_string(), |x| format!("{:.2}", x / 1e6));

    let mut page = String::new();
    let mut w = |line: &str| {
        page.push_str(line);
        page.push('\n');
    };
    // How this page was written, to write it again.
    let invocation: Vec<String> = std::env::args()
        .skip(1)
        .map(|a| {
            if a.contains(' ') || a.contains('`') {
                format!("'{}'", a.replace('`', ""))
            } else {
                a
            }
        })
        .collect();
    w("# Many states per call: scaling with threads");
    w("");
    w("Written by `bench/src/bin/scaling.rs` from a run of `bench/src/bin/throughput.rs` and of");
    w("Pinocchio's `pinocchio_timing --throughput` on one machine with many cores; do not edit by");
    w("hand. The figures at one thread and at the threads of the benchmark machine, side by side");
    w("with the rest: [BENCHMARKS.md](../BENCHMARKS.md) (\"Many states per call\"). What each mode");
    w("is: the same section. Written with:");
    w("");
    w("```sh");
    w(&format!(
        "cargo run --release -p articulated-bench --bin scaling -- {}",
        invocation.join(" ")
    ));
    w("```");
    w("");
    w(&format!("- Machine: {}", args.machine));
    if !args.command.is_empty() {
        w(&format!("- Command: `{}`", args.command));
    }
    w("");
    w("![States per second against threads](figures/throughput_scaling.svg)");
    let mut panels = Vec::new();
    for (model, outputs) in [
        (
            "arm7",
            ["inverse_dynamics", "forward_dynamics", "mass_matrix"],
        ),
        (
            "humanoid",
            ["inverse_dynamics", "forward_dynamics", "mass_matrix"],
        ),
    ] {
        w("");
        w(&format!("## {model}"));
        w("");
        w("Millions of states per second; efficiency: the rate at T threads over T times the rate at one.");
        w("");
        let mut head = "| output | mode |".to_string();
        let mut rule = "|---|---|".to_string();
        for t in &threads {
            head += &format!(" {t} |");
            rule += "---:|";
        }
        head += &format!(" efficiency at {top} |");
        rule += "---:|";
        w(&head);
        w(&rule);
        for output in outputs {
            for (label, prec, mode) in [
                ("ours, lanes", "f64", "lanes_threads"),
                ("ours, lanes, f32", "f32", "lanes_threads"),
                ("ours, scalar loop", "f64", "scalar_threads"),
                ("Pinocchio", "f64", "pinocchio"),
            ] {
                let at = |t: usize| match mode {
                    "pinocchio" => pin(model, output, t),
                    _ => find(model, output, prec, mode, t),
                };
                let mut row = format!("| `{output}` | {label} |");
                for &t in &threads {
                    row += &format!(" {} |", m(at(t)));
                }
                let eff = match (at(1), at(top)) {
                    (Some(a), Some(b)) => format!("{:.2}", b / (a * top as f64)),
                    _ => "–".to_string(),
                };
                row += &format!(" {eff} |");
                w(&row);
            }
        }
        for output in ["forward_dynamics"] {
            let mut panel = Panel::new(
                &format!("{model}: {output}"),
                "threads",
                "million states per second",
            );
            for (label, prec, mode) in [
                ("ours, lanes (f64)", "f64", "lanes_threads"),
                ("ours, lanes (f32)", "f32", "lanes_threads"),
                ("ours, scalar loop (f64)", "f64", "scalar_threads"),
                ("Pinocchio abaInParallel (f64)", "f64", "pinocchio"),
            ] {
                let points: Vec<(f64, f64)> = threads
                    .iter()
                    .filter_map(|&t| {
                        let v = match mode {
                            "pinocchio" => pin(model, output, t),
                            _ => find(model, output, prec, mode, t),
                        };
                        v.map(|v| (t as f64, v / 1e6))
                    })
                    .collect();
                if !points.is_empty() {
                    panel = panel.with(label, points);
                }
            }
            panels.push(panel);
        }
    }
    let plot = svg(&panels, 900, 360).map_err(|e| e.to_string())?;
    write_whole(
        &args.out.join("figures").join("throughput_scaling.svg"),
        &plot,
    )?;
    write_whole(&args.out.join("throughput.md"), &page)?;
    eprintln!(
        "[scaling] wrote {}",
        args.out.join("throughput.md").display()
    );
    Ok(())
}
