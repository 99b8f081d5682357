//! Operation counts of the generated code against the number of joints, beside Featherstone's
//! published counts: `docs/size.md`'s op-count table and `docs/figures/op_counts.svg`.
//!
//! For n = 1…50 this writes the `.chain` text of a generic serial chain of n revolute joints
//! (axes cycling z, y, x, y; joint frames tilted by small roll-pitch-yaw angles; full inertia
//! tensors; links 0.1 m; seeded, so every run writes the same text), parses it with
//! [`parse_chain_str`] and traces `inverse_dynamics`, `mass_matrix` and `forward_dynamics` with
//! the generator ([`trace`]): the counts are those of the code the macros would emit, and nothing
//! is compiled.
//!
//! ```text
//! cargo run --release -p articulated-bench --bin op_counts              # SVG + CSV, table on stdout
//! cargo run --release -p articulated-bench --bin op_counts -- --max 10  # n = 1…10 only (a quick look)
//! ```
//!
//! Writes `docs/figures/op_counts.svg` and `bench/size/op_counts.csv` (each whole or not at all)
//! and prints the Markdown section for `docs/size.md` on stdout; progress goes to stderr.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use articulated::files::write_atomically;
use articulated::OpCounts;
use articulated_codegen::load::{load, parse_chain_str};
use articulated_codegen::model::Model;
use articulated_codegen::options::Output;
use articulated_codegen::trace::{trace, FdMethod, Traced};
use articulated_dynamics::random::Rng;
use plotters::prelude::*;

/// The chain lengths of the table (the figure has every n up to [`MAX_N`]).
const TABLE_N: [usize; 8] = [1, 2, 5, 7, 10, 20, 30, 50];
/// The longest chain traced.
const MAX_N: usize = 50;

/// The repository's root (this crate is `bench/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap_or_else(|| Path::new("."))
        .to_path_buf()
}

/// Uniform in `[lo, hi)` from `rng`, rounded to `digits` decimals (so the text stays short).
fn uniform(rng: &mut Rng, lo: f64, hi: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    (rng.range(lo, hi) * scale).round() / scale
}

/// `R = Rz(yaw)·Ry(pitch)·Rx(roll)`, URDF's convention.
fn rotation([r, p, y]: [f64; 3]) -> [[f64; 3]; 3] {
    let (sr, cr) = r.sin_cos();
    let (sp, cp) = p.sin_cos();
    let (sy, cy) = y.sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// `R·diag(principal)·Rᵀ`, exactly symmetric: a full inertia tensor.
fn tilted(principal: [f64; 3], rpy: [f64; 3]) -> [[f64; 3]; 3] {
    let r = rotation(rpy);
    let mut i = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in a..3 {
            let x: f64 = (0..3).map(|k| r[a][k] * principal[k] * r[b][k]).sum();
            i[a][b] = x;
            i[b][a] = x;
        }
    }
    i
}

/// `[a, b, c]` with every number in its shortest round-trip form.
fn vec3(v: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// The `.chain` text of the generic serial chain of `n` revolute joints (see the module docs);
/// the same approach as `models/make_scale_models.py`'s `chain50`, every link 0.1 m long.
pub fn chain_text(n: usize) -> String {
    /// The joint axes, cycled.
    const AXES: [char; 4] = ['z', 'y', 'x', 'y'];
    /// Every link's length (m).
    const LENGTH: f64 = 0.1;
    let mut rng = Rng::new(0x5eed_0000 + n as u64);
    let mut text = format!(
        "/// A generic serial chain of {n} revolute joints (bench/src/bin/op_counts.rs).\n\
         pub chain Serial{n} {{\n    gravity: [0.0, 0.0, -9.81];\n"
    );
    for i in 1..=n {
        let mass = uniform(&mut rng, 0.25, 2.0, 3);
        let com = [
            uniform(&mut rng, -0.01, 0.01, 4),
            uniform(&mut rng, -0.01, 0.01, 4),
            LENGTH / 2.0,
        ];
        // A solid cylinder of radius 3 cm along z, tilted by up to 0.3 rad.
        let (radius, along) = (0.03_f64, 0.5 * mass * 0.03 * 0.03);
        let across = mass * (3.0 * radius * radius + LENGTH * LENGTH) / 12.0;
        let tilt = [0; 3].map(|_| uniform(&mut rng, -0.3, 0.3, 3));
        let inertia = tilted([across, across, along], tilt);
        let _ = writeln!(
            text,
            "    body link{i} {{ mass: {mass:?}, com: {}, inertia: [{}, {}, {}] }}",
            vec3(com),
            vec3(inertia[0]),
            vec3(inertia[1]),
            vec3(inertia[2]),
        );
    }
    for i in 1..=n {
        let parent = if i == 1 {
            "world".to_string()
        } else {
            format!("link{}", i - 1)
        };
        let rpy = [0; 3].map(|_| uniform(&mut rng, -0.1, 0.1, 3));
        let _ = writeln!(
            text,
            "    joint j{i}: revolute({}) {{ parent: {parent}, child: link{i}, xyz: [0.0, 0.0, {LENGTH:?}], rpy: {} }}",
            AXES[(i - 1) % 4],
            vec3(rpy),
        );
    }
    text.push_str("}\n");
    text
}

/// The counts of one chain length.
#[derive(Clone, Debug)]
struct Row {
    /// The number of joints.
    n: usize,
    /// `inverse_dynamics` (Newton–Euler, the variant the generator keeps).
    rnea: OpCounts,
    /// `mass_matrix` (CRBA, the variant kept).
    crba: OpCounts,
    /// `forward_dynamics` (the variant kept: ABA or CRBA + `LᵀDL`).
    fd: OpCounts,
    /// The method of the kept forward-dynamics variant.
    fd_method: FdMethod,
    /// The fewest operations among the ABA variants traced for forward dynamics.
    fd_aba: OpCounts,
    /// The fewest among the CRBA + `LᵀDL` variants.
    fd_ltdl: OpCounts,
}

/// The cheapest candidate of `traced` computed by `method`.
fn cheapest(traced: &Traced, method: FdMethod) -> OpCounts {
    traced
        .candidates
        .iter()
        .filter(|(v, _)| v.method == Some(method))
        .map(|(_, ops)| *ops)
        .min_by_key(OpCounts::total)
        .unwrap_or_default()
}

/// Traces the three outputs of the chain of `n` joints.
fn measure(n: usize) -> Result<Row, String> {
    let text = chain_text(n);
    let path = PathBuf::from(format!("serial{n}.chain"));
    let description = parse_chain_str(&text, &path).map_err(|e| e.to_string())?;
    Ok(row(n, &description.model))
}

/// Traces the three outputs of `model`, a chain of `n` joints.
fn row(n: usize, model: &Model) -> Row {
    let fd = trace(model, Output::ForwardDynamics);
    Row {
        n,
        rnea: trace(model, Output::InverseDynamics).ops(),
        crba: trace(model, Output::MassMatrix).ops(),
        fd_method: fd.variant.method.unwrap_or(FdMethod::Aba),
        fd_aba: cheapest(&fd, FdMethod::Aba),
        fd_ltdl: cheapest(&fd, FdMethod::CrbaLtdl),
        fd: fd.ops(),
    }
}

/// A published operation count: `muls(n)` multiplications and `adds(n)` additions for a chain of
/// `n` revolute joints, and where it was read.
struct Published {
    /// The algorithm, as the table names it.
    name: &'static str,
    /// The formula as printed (multiplications; additions).
    formula: &'static str,
    /// Multiplications for `n` joints.
    muls: fn(f64) -> f64,
    /// Additions for `n` joints.
    adds: fn(f64) -> f64,
}

/// Evaluation.
impl Published {
    /// Multiplications and additions together for `n` joints.
    fn total(&self, n: usize) -> f64 {
        (self.muls)(n as f64) + (self.adds)(n as f64)
    }
}

/// Featherstone's published counts that this report could confirm from a source it can cite;
/// see [`SOURCE`]. Empty: none could be confirmed here (see `docs/size.md`), so the figure and
/// the table show our counts alone rather than formulas quoted from memory.
const FEATHERSTONE: [Published; 0] = [];

/// Where [`FEATHERSTONE`]'s formulas come from.
const SOURCE: &str = "R. Featherstone, *Rigid Body Dynamics Algorithms*, Springer 2008, ch. 10 \
(cost tables of the RNEA, the CRBA with its sparse factorization, and the ABA); R. Featherstone \
and D. Orin, \"Dynamics\", *Springer Handbook of Robotics*, Springer 2008, §2.5–2.6";

/// The figure: total operations against n, log–log, ours solid and the published counts dashed.
fn figure(rows: &[Row]) -> Result<String, String> {
    let text = |e: &dyn std::fmt::Display| e.to_string();
    let n_max = rows.last().map_or(1, |r| r.n) as f64;
    /// One of our curves: its label, the count it reads from a row, its colour.
    type Curve = (&'static str, fn(&Row) -> OpCounts, RGBColor);
    let curves: [Curve; 5] = [
        (
            "inverse_dynamics (our RNEA)",
            |r| r.rnea,
            RGBColor(31, 119, 180),
        ),
        ("mass_matrix (our CRBA)", |r| r.crba, RGBColor(214, 39, 40)),
        (
            "forward_dynamics (kept variant)",
            |r| r.fd,
            RGBColor(44, 160, 44),
        ),
        (
            "forward_dynamics, best ABA variant",
            |r| r.fd_aba,
            RGBColor(148, 103, 189),
        ),
        (
            "forward_dynamics, best CRBA + LᵀDL variant",
            |r| r.fd_ltdl,
            RGBColor(255, 127, 14),
        ),
    ];
    let ours: Vec<_> = curves
        .iter()
        .map(|&(label, count, colour)| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .map(|r| (r.n as f64, count(r).total() as f64))
                .collect();
            (label, points, colour)
        })
        .collect();
    let published: Vec<(String, Vec<(f64, f64)>)> = FEATHERSTONE
        .iter()
        .map(|p| {
            (
                format!("Featherstone: {}", p.name),
                rows.iter().map(|r| (r.n as f64, p.total(r.n))).collect(),
            )
        })
        .collect();
    let y_max = ours
        .iter()
        .flat_map(|(_, pts, _)| pts.iter())
        .chain(published.iter().flat_map(|(_, pts)| pts.iter()))
        .map(|p| p.1)
        .fold(1.0, f64::max);
    let y_min = ours
        .iter()
        .flat_map(|(_, pts, _)| pts.iter())
        .map(|p| p.1)
        .filter(|y| *y > 0.0)
        .fold(f64::INFINITY, f64::min);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 620)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| text(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Operations of the generated code, serial chains of n revolute joints",
                ("sans-serif", 20),
            )
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(72)
            .build_cartesian_2d(
                (0.9..n_max * 1.1)
                    .log_scale()
                    .with_key_points(vec![1.0, 2.0, 5.0, 7.0, 10.0, 20.0, 30.0, 50.0]),
                (y_min * 0.7..y_max * 1.5)
                    .log_scale()
                    .with_key_points(vec![10.0, 100.0, 1e3, 1e4, 1e5, 1e6]),
            )
            .map_err(|e| text(&e))?;
        chart
            .configure_mesh()
            .light_line_style(TRANSPARENT)
            .x_desc("n (joints)")
            .y_desc("operations (add/sub + mul + div + neg + sin/cos + sqrt)")
            .y_label_formatter(&|y| format!("{y:.0}"))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .draw()
            .map_err(|e| text(&e))?;
        for (k, (label, points, colour)) in ours.into_iter().enumerate() {
            // A log axis has no zero: a function with no operations (M of one joint is
            // constant) starts where it has some. The kept variant is drawn wide and pale, under
            // the two candidates it is the cheaper of.
            let points = points.into_iter().filter(|p| p.1 > 0.0);
            let style = if k == 2 {
                colour.mix(0.35).stroke_width(9)
            } else {
                colour.stroke_width(2)
            };
            chart
                .draw_series(LineSeries::new(points, style))
                .map_err(|e| text(&e))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style));
        }
        for (k, (label, points)) in published.into_iter().enumerate() {
            let colour = [
                RGBColor(31, 119, 180),
                RGBColor(214, 39, 40),
                RGBColor(148, 103, 189),
            ][k % 3];
            chart
                .draw_series(DashedLineSeries::new(points, 6, 4, colour.stroke_width(2)))
                .map_err(|e| text(&e))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| text(&e))?;
        root.present().map_err(|e| text(&e))?;
    }
    Ok(out)
}

/// One line per (n, output), every count.
fn csv(rows: &[Row]) -> String {
    let mut out = String::from("n,output,adds,muls,divs,negs,sin_cos,sqrts,total\n");
    for r in rows {
        for (name, ops) in [
            ("inverse_dynamics", r.rnea),
            ("mass_matrix", r.crba),
            ("forward_dynamics", r.fd),
            ("forward_dynamics_best_aba", r.fd_aba),
            ("forward_dynamics_best_crba_ltdl", r.fd_ltdl),
        ] {
            let _ = writeln!(
                out,
                "{},{name},{},{},{},{},{},{},{}",
                r.n,
                ops.adds,
                ops.muls,
                ops.divs,
                ops.negs,
                ops.sin_cos,
                ops.sqrts,
                ops.total()
            );
        }
    }
    out
}

/// `1234 (567 mul, 600 add)`: the total with its main split.
fn cell(ops: &OpCounts) -> String {
    format!("{} ({} mul, {} add)", ops.total(), ops.muls, ops.adds)
}

/// The Markdown section for `docs/size.md`.
fn markdown(rows: &[Row], shipped: &Row) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Generic serial chains of n revolute joints, written by `op_counts` (axes cycling z, y, x, y; \
         joint frames tilted by up to 0.1 rad in roll, pitch and yaw; full inertia tensors; links \
         0.1 m; seeded). Every count is the generator's own (`articulated_codegen::trace`, the \
         figure in each generated function's doc and in the `…_OPS` constants): the operations of \
         the emitted straight-line code, after constant folding, common-subexpression sharing and \
         the choice of the cheapest variant. A total counts add/sub, mul, div, neg, sin/cos (one \
         per angle) and sqrt alike.\n"
    );
    let _ = writeln!(
        s,
        "| n | inverse_dynamics | /n | mass_matrix | /n | forward_dynamics (method kept) | /n | best ABA variant | best CRBA + LᵀDL variant |"
    );
    let _ = writeln!(s, "|---:|---|---:|---|---:|---|---:|---:|---:|");
    for r in rows.iter().filter(|r| TABLE_N.contains(&r.n)) {
        let per = |ops: &OpCounts| format!("{:.0}", ops.total() as f64 / r.n as f64);
        let method = match r.fd_method {
            FdMethod::Aba => "ABA",
            FdMethod::CrbaLtdl => "CRBA + LᵀDL",
            // Serial chains have no branching body to condense at.
            FdMethod::CrbaCondensed => "CRBA + condensed LᵀDL",
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} — {method} | {} | {} | {} |",
            r.n,
            cell(&r.rnea),
            per(&r.rnea),
            cell(&r.crba),
            per(&r.crba),
            cell(&r.fd),
            per(&r.fd),
            r.fd_aba.total(),
            r.fd_ltdl.total(),
        );
    }
    let _ = writeln!(
        s,
        "\nThe shipped `models/chain50.chain` has the same structure with its own numbers (links \
         0.08 to 0.12 m, masses from 2 down to 0.25 kg): inverse_dynamics {}, mass_matrix {}, \
         forward_dynamics {} operations, against {}, {} and {} for n = 50 here, so the curves \
         are not an artefact of this generator's random numbers.",
        shipped.rnea.total(),
        shipped.crba.total(),
        shipped.fd.total(),
        rows.last().map_or(0, |r| r.rnea.total()),
        rows.last().map_or(0, |r| r.crba.total()),
        rows.last().map_or(0, |r| r.fd.total()),
    );
    if FEATHERSTONE.is_empty() {
        let _ = writeln!(
            s,
            "\n**Featherstone's published counts are not shown.** The brief asks for them beside \
             ours ({SOURCE}); this report could not read those tables in any source it can cite \
             (the book and the handbook chapter are not available to it, and the copies it could \
             search held only abstracts), and it will not quote formulas from memory. The \
             comparison column and the dashed curves are left out until someone with the book \
             fills in `FEATHERSTONE` in `bench/src/bin/op_counts.rs` (formula and page); the \
             program then plots them and adds the ratio column."
        );
    } else {
        let _ = writeln!(s, "\nFeatherstone's counts ({SOURCE}):\n");
        for p in &FEATHERSTONE {
            let _ = writeln!(s, "- {}: {}", p.name, p.formula);
        }
    }
    s
}

/// Operation counts of the generated code against the number of joints: writes
/// `docs/figures/op_counts.svg` and `bench/size/op_counts.csv`, prints the section of
/// `docs/size.md`.
#[derive(clap::Parser)]
#[command(name = "op_counts")]
struct Cli {
    /// Trace the chains of 1 to N joints only (a quick look); N in 1..=50.
    #[arg(long, value_name = "N", default_value_t = MAX_N, value_parser = chain_length)]
    max: usize,
}

/// A chain length in `1..=MAX_N` (`--max`).
fn chain_length(text: &str) -> Result<usize, String> {
    text.parse()
        .ok()
        .filter(|n| (1..=MAX_N).contains(n))
        .ok_or_else(|| format!("want a number in 1..={MAX_N}"))
}

/// Traces every chain, writes the figure and the CSV, prints the section.
fn main() -> ExitCode {
    let max = <Cli as clap::Parser>::parse().max;
    let mut rows = Vec::new();
    for n in 1..=max {
        eprint!("\rop_counts: tracing n = {n:2}/{max}");
        match measure(n) {
            Ok(row) => rows.push(row),
            Err(e) => {
                eprintln!("\nop_counts: the chain of {n} joints: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    eprintln!();
    let root = root();
    let svg = match figure(&rows) {
        Ok(svg) => svg,
        Err(e) => {
            eprintln!("op_counts: cannot draw the figure: {e}");
            return ExitCode::FAILURE;
        }
    };
    for (path, contents) in [
        (root.join("docs/figures/op_counts.svg"), svg),
        (root.join("bench/size/op_counts.csv"), csv(&rows)),
    ] {
        if let Err(e) = write_atomically(&path, contents.as_bytes()) {
            eprintln!("op_counts: cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        eprintln!("op_counts: wrote {}", path.display());
    }
    let chain50 = root.join("models/chain50.chain");
    let shipped = match load(&chain50, false).map(|d| row(50, &d.model)) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("op_counts: {}: {e}", chain50.display());
            return ExitCode::FAILURE;
        }
    };
    print!("{}", markdown(&rows, &shipped));
    ExitCode::SUCCESS
}
