//! The long-horizon study of issue 12: every integrator on the two-link and the floating cat,
//! 100 s at steps of 1e-3 s (1e5 steps) and 1e-4 s (1e6 steps), generated `f64` code. Writes
//! `drift.md` (the table) and `figures/drift.svg` (the energy error against time at 1e-3 s),
//! each whole or not at all, into the folder given as its argument (default `target/docs/`;
//! `scripts/figures.sh` passes `docs/`), and prints the table.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example drift [-- OUT]
//! ```

use articulated::plot::{svg, Panel};
use articulated_examples::drift::{run, Model, Run, METHODS};
use articulated_examples::output::Output;

const HORIZON: f64 = 100.0;
const RECORD_EVERY_S: f64 = 0.1;

/// `log₁₀` of an error, floored at 1e-17 (an exact zero would have none).
fn log10(x: f64) -> f64 {
    x.max(1e-17).log10()
}

fn cell(x: f64) -> String {
    format!("{x:.1e}")
}

fn main() {
    let out = match Output::from_args() {
        Ok(out) => out,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mut table = String::from(
        "| model | method | step (s) | steps | max energy error | first half | second half | \
         max k_G error | max p error | wall time (s) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut panels = Vec::new();
    for model in [Model::TwoLink, Model::Cat] {
        let mut panel = Panel::new(
            &format!("{}: energy error over 100 s, step 1e-3 s", model.name()),
            "t (s)",
            "log₁₀ |E − E₀| / |E₀|",
        );
        for &dt in &[1e-3, 1e-4] {
            let steps = (HORIZON / dt).round() as usize;
            let every = (RECORD_EVERY_S / dt).round() as usize;
            for method in METHODS {
                eprintln!(
                    "{} {} dt = {dt:e} ({steps} steps)…",
                    model.name(),
                    method.name()
                );
                let r: Run = run(model, method, dt, steps, every);
                let (first, second) = r.halves();
                let momentum = |v: &[(f64, f64)]| match v.is_empty() {
                    true => "—".to_string(),
                    false => cell(v.iter().fold(0.0f64, |m, &(_, e)| m.max(e))),
                };
                table.push_str(&format!(
                    "| {} | {} | {dt:.0e} | {steps} | {} | {} | {} | {} | {} | {:.2} |{}\n",
                    model.name(),
                    method.name(),
                    cell(r.max_energy()),
                    cell(first),
                    cell(second),
                    momentum(&r.angular_momentum),
                    momentum(&r.linear_momentum),
                    r.seconds,
                    r.fault
                        .map(|f| format!(" stopped: {f}"))
                        .unwrap_or_default(),
                ));
                if dt == 1e-3 {
                    let points = r.energy.iter().map(|&(t, e)| (t, log10(e))).collect();
                    panel = panel.with(method.name(), points);
                }
            }
        }
        panels.push(panel);
    }
    let text = format!(
        "# Long horizons: energy and momentum drift\n\n\
         Written by `scripts/figures.sh drift` \
         (`examples/src/drift.rs`; the bounds asserted on shorter runs: `examples/tests/drift.rs`). \
         Each model is left to itself (`τ = 0`) for {HORIZON} s with generated `f64` code; the \
         errors are relative to the initial values (the energy `T + V`; on the floating cat, the \
         falling cat of `models/falling_cat.chain` without gravity, the angular momentum about \
         the centre of mass `k_G` and the linear momentum `p`), the largest over the run and \
         over each half \
         (a drift grows from the first half to the second; a bounded error does not). Dopri5's \
         step is its output interval (tolerances 1e-10 relative, 1e-12 absolute).\n\n\
         ![Energy error against time](figures/drift.svg)\n\n{table}"
    );
    print!("{table}");
    let figure = match svg(&panels, 900, 380) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    for (path, contents) in [
        (out.page("drift.md"), text.as_bytes()),
        (out.figure("drift.svg"), figure.as_bytes()),
    ] {
        match out.write(&path, contents) {
            Ok(file) => eprintln!("wrote {file}"),
            Err(e) => {
                eprintln!("error: cannot write {e}");
                std::process::exit(1);
            }
        }
    }
}
