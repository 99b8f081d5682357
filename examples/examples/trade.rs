//! The speed–accuracy trade of issue 12 on the two-link and the 7-DOF arm: every option of
//! `articulated_examples::trade` timed and compared with the double-double ground truth.
//! Writes `trade.md` (the table, Pareto front marked) and `figures/trade.svg` (time per
//! simulated second against error, log–log, the front drawn), each whole or not at all, into
//! the folder given as its argument (default `target/docs/`; `scripts/figures.sh` passes
//! `docs/`). Timings are wall-clock on this machine: run it with nothing else running.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example trade [-- OUT]
//! ```

use articulated_examples::output::Output;
use articulated_examples::trade::{
    points, scene_costs, truth, Point, Scenario, ARM7, ENSEMBLE, TWO_LINK,
};
use plotters::prelude::*;

const COLOURS: [RGBColor; 3] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
];

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    s: &Scenario,
    pts: &[Point],
) -> Result<(), String> {
    let text = |e: &dyn std::fmt::Display| e.to_string();
    let ok: Vec<&Point> = pts.iter().filter(|p| p.error.is_some()).collect();
    let err = |p: &Point| p.error.unwrap_or(1.0).max(1e-16);
    let (x0, x1) = ok.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.seconds), b.max(p.seconds))
    });
    let (y0, y1) = ok.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(err(p)), b.max(err(p)))
    });
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{}: one simulated second, every option", s.name),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 3.0..y1 * 3.0).log_scale(),
        )
        .map_err(|e| text(&e))?;
    chart
        .configure_mesh()
        .x_desc("wall time per simulated second (s)")
        .y_desc("largest position error at 1 s (rad)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(|e| text(&e))?;
    for (k, method) in articulated_examples::trade::METHODS.iter().enumerate() {
        let c = COLOURS[k];
        let of = |scalar: &'static str, model: &'static str| {
            ok.iter()
                .filter(move |p| {
                    p.method == *method
                        && p.scalar == scalar
                        && (model.is_empty() || p.model == model)
                })
                .map(|p| (p.seconds, err(p)))
                .collect::<Vec<_>>()
        };
        chart
            .draw_series(
                of("f64", "full")
                    .into_iter()
                    .map(|xy| Circle::new(xy, 4, c.filled())),
            )
            .map_err(|e| text(&e))?
            .label(format!("{}, f64", method.name()))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
        chart
            .draw_series(
                of("f32", "")
                    .into_iter()
                    .map(|xy| TriangleMarker::new(xy, 5, c.stroke_width(1))),
            )
            .map_err(|e| text(&e))?
            .label(format!("{}, f32", method.name()))
            .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 5, c.stroke_width(1)));
        let pruned: Vec<(f64, f64)> = ok
            .iter()
            .filter(|p| {
                p.method == *method && p.scalar == "f64" && p.model != "full" && p.model != ENSEMBLE
            })
            .map(|p| (p.seconds, err(p)))
            .collect();
        chart
            .draw_series(
                pruned
                    .into_iter()
                    .map(|xy| Cross::new(xy, 5, c.stroke_width(2))),
            )
            .map_err(|e| text(&e))?
            .label(format!("{}, pruned or quasi-static", method.name()))
            .legend(move |(x, y)| Cross::new((x + 8, y), 5, c.stroke_width(2)));
        let copies = of("f64", ENSEMBLE);
        if !copies.is_empty() {
            chart
                .draw_series(
                    copies
                        .into_iter()
                        .map(|xy| Circle::new(xy, 6, c.stroke_width(2))),
                )
                .map_err(|e| text(&e))?
                .label(format!("{}, f64, per copy of 64 in lanes", method.name()))
                .legend(move |(x, y)| Circle::new((x + 8, y), 6, c.stroke_width(2)));
        }
    }
    let mut front: Vec<(f64, f64)> = ok
        .iter()
        .filter(|p| p.pareto)
        .map(|p| (p.seconds, err(p)))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front, BLACK.stroke_width(1)))
        .map_err(|e| text(&e))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(|e| text(&e))?;
    Ok(())
}

fn main() {
    let out = match Output::from_args() {
        Ok(out) => out,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mut md = String::from(
        "# The speed–accuracy trade\n\n\
         Written by `scripts/figures.sh trade` \
         (`examples/src/trade.rs`). Each option simulates one second of the chain left to itself \
         from the same start (generated code, `τ = 0`); the error is the largest difference of \
         the final positions it keeps from the ground truth's (classic Runge–Kutta at 1e-4 s, the arm 2.5e-5 s, in \
         double-double arithmetic on the full model; its own error is given per model); the time \
         is wall-clock per simulated second on this machine, the least of several repetitions. \
         *Pareto*: no other option is both faster and more accurate. A pruned model keeps fewer \
         coordinates (the locked joints held at their start, where the full model lets them \
         swing); quasi-static drops the velocity-product terms. *Per copy of 64 in lanes*: 64 copies \
         stepped together by `integrate::Ensemble` (classic Runge–Kutta, the model generated \
         with `lanes = 4`), the time divided by 64: what each simulation costs when many run \
         at once (a Monte Carlo, a sweep); each copy follows the scalar Runge–Kutta's \
         trajectory, so its error is that option's, and it is left off the Pareto front, \
         which is for one simulation. `—`: the run stopped (an error \
         value, not a NaN).\n\n![The trade](figures/trade.svg)\n",
    );
    let mut all = Vec::new();
    for s in [TWO_LINK, ARM7] {
        eprintln!("{}: ground truth…", s.name);
        let (q_truth, own) = truth(&s);
        eprintln!("{}: options…", s.name);
        let pts = points(&s, &q_truth);
        md.push_str(&format!(
            "\n## {}\n\nGround truth's own error (its step doubled, against it): {own:.1e} rad.\n\n",
            s.name
        ));
        md.push_str("Generated for the scene: forward dynamics of each model (operations, and ns per \
                     call, the least of ten batches of 20,000 calls):\n\n| model | operations | ns per call |\n|---|---:|---:|\n");
        for (label, ops, ns) in scene_costs(&s) {
            md.push_str(&format!("| {label} | {ops} | {ns:.0} |\n"));
        }
        md.push_str(
            "\n| scalar | accuracy | model | integrator | step (s) | error (rad) | time per simulated s (µs) | Pareto |\n\
             |---|---|---|---|---:|---:|---:|:---:|\n",
        );
        let mut sorted = pts.clone();
        sorted.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
        for p in &sorted {
            md.push_str(&format!(
                "| {} | {} | {} | {} | {:.0e} | {} | {:.0} | {} |\n",
                p.scalar,
                p.accuracy,
                p.model,
                p.method.name(),
                p.dt,
                p.error.map_or("—".into(), |e| format!("{e:.1e}")),
                p.seconds * 1e6,
                if p.pareto { "●" } else { "" }
            ));
        }
        println!("{}:", s.name);
        for p in sorted.iter().filter(|p| p.pareto) {
            println!(
                "  {:<48} {:>10.1e} rad {:>10.0} µs/s",
                p.label(),
                p.error.unwrap_or(f64::NAN),
                p.seconds * 1e6
            );
        }
        all.push((s, pts));
    }
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (900, 1100)).into_drawing_area();
        let drawn = area.fill(&WHITE).map_err(|e| e.to_string()).and_then(|()| {
            let halves = area.split_evenly((2, 1));
            for ((s, pts), half) in all.iter().zip(&halves) {
                panel(half, s, pts)?;
            }
            area.present().map_err(|e| e.to_string())
        });
        if let Err(e) = drawn {
            eprintln!("error: cannot draw the figure: {e}");
            std::process::exit(1);
        }
    }
    for (path, contents) in [
        (out.page("trade.md"), md.as_bytes()),
        (out.figure("trade.svg"), svg.as_bytes()),
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
