//! The `articulated` command: evaluate a chain description's dynamics from the shell.
//!
//! ```text
//! articulated eval models/two_link.chain --q 0.1,0.2,0,0,0.3,0
//! articulated eval models/two_link.chain --engine symbolic
//! articulated expand models/two_link.chain > two_link.rs
//! articulated simulate models/two_link.chain --t-end 5 --dt 0.001 --integrator rk4 \
//!     --q0 0.1,0,0,0,0,0 --out swing.csv --plot swing.svg
//! articulated invert models/two_link.chain swing.csv --out couples.csv
//! ```
// No panic reachable from the command line (issue 14), without exception.
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use articulated_codegen::load::FloatingBase;
use clap::{Parser, Subcommand, ValueEnum};

mod contacts;
mod eval;
mod expand;
mod export;
mod ground;
mod invert;
mod pinocchio;
mod simulate;

/// Rigid-body dynamics from a chain description (`.chain`, `.urdf` or MJCF `.xml`).
#[derive(Parser, Debug)]
#[command(name = "articulated", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Evaluate M(q), bias, gravity, inverse and forward dynamics at one state; print JSON.
    Eval(EvalArgs),
    /// Print the formatted Rust that `chain!`/`#[derive(Chain)]` would emit for a model, with
    /// each function's operation counts in a header.
    Expand(ExpandArgs),
    /// Simulate a chain left to itself (τ = 0) from an initial state; write the trajectory as
    /// CSV (`t,q0,…,v0,…`, one row per step, the initial state included) and optionally a plot.
    Simulate(SimulateArgs),
    /// Write a model (`.chain`, URDF, MJCF) as MuJoCo's MJCF (`--mjcf`), on stdout or to
    /// `--out`.
    Export(ExportArgs),
    /// Recover the joint couples behind a sampled motion (the `t` and `q…` columns of a
    /// trajectory CSV): smoothed derivatives, then inverse dynamics; write `t,tau0,…`.
    Invert(InvertArgs),
}

/// Which implementation evaluates the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// The interpreted reference dynamics (Featherstone's recursions, f64).
    Reference,
    /// The generator's own expression graphs, evaluated in f64: what the generated code
    /// computes (forward dynamics by the method it keeps, with its pivot checks), without
    /// compiling it.
    Symbolic,
}

/// Arguments of `articulated eval`.
#[derive(clap::Args, Debug)]
pub struct EvalArgs {
    /// The model: a `.chain`, `.urdf` or MJCF `.xml` file.
    pub model: PathBuf,
    /// Positions, comma-separated (default: the neutral configuration).
    #[arg(long, allow_hyphen_values = true)]
    pub q: Option<String>,
    /// Velocities, comma-separated (default: zero).
    #[arg(long, allow_hyphen_values = true)]
    pub v: Option<String>,
    /// Accelerations for inverse dynamics, comma-separated (default: zero).
    #[arg(long, allow_hyphen_values = true)]
    pub a: Option<String>,
    /// Joint forces for forward dynamics, comma-separated (default: zero).
    #[arg(long, allow_hyphen_values = true)]
    pub tau: Option<String>,
    /// Runtime parameter values in declaration order, comma-separated (default: the file's).
    #[arg(long, allow_hyphen_values = true)]
    pub params: Option<String>,
    /// The base under a URDF root.
    #[command(flatten)]
    pub base: Base,
    /// Frames to evaluate, comma-separated (bodies, `frame` items, URDF links): their
    /// placement, LOCAL velocity, classical acceleration, Jacobians and their time variations
    /// in LOCAL, WORLD and LOCAL_WORLD_ALIGNED, under `"frames"`.
    #[arg(long)]
    pub frames: Option<String>,
    /// Constraints on frames, comma-separated `FRAME:KIND` with KIND `six_d` (the frame's
    /// spatial acceleration held, a wrench `[n; f]` in its axes) or `point` (its origin's
    /// acceleration held, a force in world axes), e.g. `--contacts left_foot:six_d,tip:point`:
    /// the constrained `q̈` at `--tau`, the forces and the residual `max |J·q̈ + γ|`, under
    /// `"constrained"`.
    #[arg(long)]
    pub contacts: Option<String>,
    /// Baumgarte gains `KP,KD` of the constraints: `J·q̈ + γ = −KD·J·v − KP·e`, with the
    /// reference the current placement (`e = 0`: at one state only `KD` acts).
    #[arg(long, allow_hyphen_values = true, requires = "contacts")]
    pub baumgarte: Option<String>,
    /// An impact on the constraints at `--v` with this coefficient of restitution (≥ 0):
    /// `v⁺` and the impulses, under `"impulse"`.
    #[arg(long, allow_hyphen_values = true, requires = "contacts")]
    pub restitution: Option<String>,
    /// The layout of `--q`, `--v`, `--a`, `--tau` and of every vector and matrix printed:
    /// `articulated` (ours) or `pinocchio` (its free flyer `[x, y, z, qx, qy, qz, qw]`,
    /// continuous joints as `(cos θ, sin θ)`, its URDF joint order).
    #[arg(long, value_enum, default_value_t)]
    pub q_order: pinocchio::QOrder,
    /// Which implementation evaluates the model: `reference` (the interpreted recursions) or
    /// `symbolic` (the generator's expression graphs; checks the generator without compiling).
    #[arg(long, value_enum, default_value_t = Engine::Reference)]
    pub engine: Engine,
}

/// Arguments of `articulated export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The model: a `.chain`, `.urdf` or MJCF `.xml` file.
    pub model: PathBuf,
    /// The base under a URDF root.
    #[command(flatten)]
    pub base: Base,
    /// Write MuJoCo's MJCF (the one format exported).
    #[arg(long, required = true)]
    pub mjcf: bool,
    /// The file to write (whole or not at all); stdout without it.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `articulated expand`.
#[derive(clap::Args, Debug)]
pub struct ExpandArgs {
    /// The model: a `.chain`, `.urdf` or MJCF `.xml` file.
    pub model: PathBuf,
    /// The base under a URDF root.
    #[command(flatten)]
    pub base: Base,
    /// The scalar of the generated code, in place of the description's: `f64`, `f32` or
    /// `generic`.
    #[arg(long)]
    pub scalar: Option<String>,
    /// The outputs to generate, comma-separated, in place of the description's (e.g.
    /// `mass_matrix,inverse_dynamics`).
    #[arg(long)]
    pub outputs: Option<String>,
    /// Speed or accuracy where formulations differ, in place of the description's: `fastest`
    /// or `robust` (forward dynamics by ABA).
    #[arg(long)]
    pub accuracy: Option<String>,
    /// States per vector value of the batch functions (`inverse_dynamics_batch`, …), in place
    /// of the description's: 2, 4 or 8 in `f64`, 4, 8 or 16 in `f32`.
    #[arg(long)]
    pub lanes: Option<usize>,
    /// Locks a joint at its position coordinates, e.g. `--lock elbow=0.3` or
    /// `--lock hip=0,0.1,0` (repeatable): it becomes fixed and its body merges into its parent.
    #[arg(long = "lock")]
    pub locks: Vec<String>,
    /// Keeps only these bodies, comma-separated; the other joints are locked at neutral and
    /// their bodies ride as a payload.
    #[arg(long)]
    pub keep: Option<String>,
    /// Quasi-static motion: velocity-product terms dropped.
    #[arg(long)]
    pub quasi_static: bool,
    /// The frames the frame outputs compute, comma-separated, in place of the description's
    /// (bodies, `frame` items, URDF links), e.g. `--frames tool,left_sole`.
    #[arg(long)]
    pub frames: Option<String>,
    /// The contacts, in place of the description's, comma-separated `FRAME:KIND` with KIND
    /// `six_d` or `point` (as `eval --contacts`), e.g. `--contacts left_sole:six_d,toe:point`:
    /// with `--loops`, the type gains `CONTACTS`, `LOOPS`, `CONSTRAINT_ROWS` and
    /// `constrained_forward_dynamics(q, v, tau)`, and the frames and outputs it reads.
    #[arg(long)]
    pub contacts: Option<String>,
    /// The loop closures, in place of the description's, comma-separated `NAME:point(A,B)`
    /// (frame A's origin held on frame B's) or `NAME:six_d(A,B)` (frame A held on frame B),
    /// e.g. `--loops 'rod:point(tip,ground)'`.
    #[arg(long)]
    pub loops: Option<String>,
}

/// Arguments of `articulated simulate`.
#[derive(clap::Args, Debug)]
pub struct SimulateArgs {
    /// The model: a `.chain`, `.urdf` or MJCF `.xml` file.
    pub model: PathBuf,
    /// End time (s); the simulation starts at 0.
    #[arg(long)]
    pub t_end: f64,
    /// Time step (s); for `dopri5`, the first step and the spacing of the recorded states.
    #[arg(long)]
    pub dt: f64,
    /// `euler`, `symplectic-euler`, `rk4` (the default), `dopri5` (adaptive, error-controlled)
    /// or `implicit-midpoint` (long horizons: its energy error stays bounded). Not with
    /// `--ground`, which steps with contacts.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Initial positions, comma-separated (default: the neutral configuration).
    #[arg(long, allow_hyphen_values = true)]
    pub q0: Option<String>,
    /// Initial velocities, comma-separated (default: zero).
    #[arg(long, allow_hyphen_values = true)]
    pub v0: Option<String>,
    /// Runtime parameter values in declaration order, comma-separated (default: the file's).
    #[arg(long, allow_hyphen_values = true)]
    pub params: Option<String>,
    /// The base under a URDF root.
    #[command(flatten)]
    pub base: Base,
    /// The layout of `--q0` and `--v0`: `articulated` (ours) or `pinocchio` (its free flyer
    /// `[x, y, z, qx, qy, qz, qw]`, continuous joints as `(cos θ, sin θ)`, its URDF joint order).
    /// The trajectory is written in ours; its sidecar names every column.
    #[arg(long, value_enum, default_value_t)]
    pub q_order: pinocchio::QOrder,
    /// `dopri5`: relative tolerance per component.
    #[arg(long, default_value_t = 1e-9)]
    pub rtol: f64,
    /// `dopri5`: absolute tolerance per component.
    #[arg(long, default_value_t = 1e-9)]
    pub atol: f64,
    /// Apply the joints' drives (`articulated::drives`): damping, dry friction and the position
    /// stops the description gives (`.chain` joint fields, URDF `<dynamics>` and `<limit>`).
    /// Without it the chain moves freely (the rotor inertia is always in the dynamics).
    #[arg(long)]
    pub drives: bool,
    /// The trajectory CSV to write (whole or not at all), and beside it `OUT.json`: each
    /// column's coordinate and unit, the integrator, how the run ended. A run that stops on a
    /// fault writes both (and the plot) up to its last good state, then fails.
    #[arg(long)]
    pub out: PathBuf,
    /// An SVG plot of the positions and the energies against time (and the contact forces).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// A ground, the half-space `NX,NY,NZ,D` of the points `x` with `n·x ≥ D` (`n` made a unit
    /// vector); repeat for several. With a ground the chain is stepped with contacts
    /// (`articulated::contact`: semi-implicit Euler, unilateral contacts with exact Coulomb
    /// cones) at `--dt`, the spheres of `--contact-points` against every ground.
    #[arg(long, allow_hyphen_values = true)]
    pub ground: Vec<String>,
    /// The contact spheres' centres, comma-separated: `FRAME` (its origin) or `FRAME@X:Y:Z` (a
    /// point in the frame's axes); any body or frame of the model.
    #[arg(long, allow_hyphen_values = true)]
    pub contact_points: Option<String>,
    /// The contact spheres' radius (m); 0 makes them points.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub radius: f64,
    /// The friction coefficient μ of every contact (needed with `--ground`).
    #[arg(long, allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// The restitution e ∈ [0, 1] of every contact.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub restitution: f64,
    /// Gravity `GX,GY,GZ` (m/s², world axes) in place of the description's: a slope is a flat
    /// ground under a tilted gravity.
    #[arg(long, allow_hyphen_values = true)]
    pub gravity: Option<String>,
    /// Add each contact point's force to the CSV, world axes in N (summed over the grounds,
    /// over the step that ends at the row): columns `f.POINT.x`, `.y`, `.z`, `POINT` the
    /// point's entry in `--contact-points`.
    #[arg(long)]
    pub contact_forces: bool,
}

/// Arguments of `articulated invert`.
#[derive(clap::Args, Debug)]
pub struct InvertArgs {
    /// The model: a `.chain`, `.urdf` or MJCF `.xml` file.
    pub model: PathBuf,
    /// The sampled motion: a CSV with a header naming `t` and `q0`, `q1`, … (other columns are
    /// ignored); times strictly increasing, not necessarily uniform.
    pub trajectory: PathBuf,
    /// The couples CSV to write (`t,tau0,…`; whole or not at all).
    #[arg(long)]
    pub out: PathBuf,
    /// Samples on each side of the differentiation window (Savitzky–Golay).
    #[arg(long, default_value_t = 5)]
    pub half_window: usize,
    /// Degree of the polynomial fitted in each window.
    #[arg(long, default_value_t = 4)]
    pub degree: usize,
    /// Runtime parameter values in declaration order, comma-separated (default: the file's).
    #[arg(long, allow_hyphen_values = true)]
    pub params: Option<String>,
    /// The base under a URDF root.
    #[command(flatten)]
    pub base: Base,
}

/// The model in `path` (with a free base under a URDF root if `floating`) and its reference
/// dynamics at the parameter values `params` (comma-separated; the file's defaults if `None`).
pub fn load_reference(
    path: &std::path::Path,
    base: Base,
    params: Option<&str>,
) -> Result<(articulated::model::Model, articulated::reference::Reference), String> {
    load_described(path, base, params).map(|(d, r)| (d.model, r))
}

/// [`load_reference`], with the whole description (what a front end reports beside the model).
pub fn load_described(
    path: &std::path::Path,
    base: Base,
    params: Option<&str>,
) -> Result<
    (
        articulated_codegen::options::Description,
        articulated::reference::Reference,
    ),
    String,
> {
    let description = load_description(path, base)?;
    let model = &description.model;
    let params = match params {
        None => model.param_defaults(),
        Some(p) => parse_vector(p, "params", model.params.len())?,
    };
    let reference = articulated::reference::Reference::with_params(model, &params)
        .map_err(|e| format!("{}: error: {e}", path.display()))?;
    Ok((description, reference))
}

/// Parses a comma-separated vector of `len` finite numbers; `what` names it in errors.
pub fn parse_vector(text: &str, what: &str, len: usize) -> Result<Vec<f64>, String> {
    let text = text.trim();
    let items: Vec<&str> = if text.is_empty() {
        Vec::new()
    } else {
        text.split(',').map(str::trim).collect()
    };
    if items.len() != len {
        return Err(format!(
            "error: --{what} has {} values, but the model needs {len}",
            items.len()
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, s)| match s.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(x) => Err(format!(
                "error: --{what}[{i}] is {x}: values must be finite"
            )),
            Err(_) => Err(format!("error: --{what}[{i}] = `{s}` is not a number")),
        })
        .collect()
}

/// `--floating[=euler|quaternion]`, shared by every command that reads a model.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct Base {
    /// Put a free base under a URDF root: `--floating` or `--floating=euler`, translation then
    /// Euler angles zyx (q and v gain 6 leading entries); `--floating=quaternion`, translation
    /// then a quaternion (q gains 7, v 6).
    #[arg(
        long,
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "euler",
        value_parser = parse_floating
    )]
    pub floating: Option<FloatingBase>,
    /// Refuse a file that loads with warnings (an inertia no rigid body has, a `<mimic>` on a
    /// fixed joint): each warning becomes an error.
    #[arg(long)]
    pub strict: bool,
    /// Give each body whose inertia no rigid body has (the triangle inequality broken, or not
    /// positive semi-definite) the mean of its principal moments about every axis, as
    /// MuJoCo's `balanceinertia`, instead of a warning.
    #[arg(long)]
    pub balance_inertia: bool,
    /// In an MJCF model, make each `<joint>` equality with a linear `polycoef` a mimic joint
    /// (or lock its joint where it names no second joint) instead of keeping every coordinate.
    #[arg(long)]
    pub mimic_equalities: bool,
}

/// Loads `path` as `base` says, its warnings on stderr (with `--strict`, errors that refuse
/// it).
pub fn load_description(
    path: &std::path::Path,
    base: Base,
) -> Result<articulated_codegen::options::Description, String> {
    let options = articulated_codegen::load::LoadOptions {
        floating: base.floating.unwrap_or_default(),
        balance_inertia: base.balance_inertia,
        strict: base.strict,
        mimic_equalities: base.mimic_equalities,
    };
    let chain = articulated_codegen::load::load_with(path, options).map_err(|e| e.to_string())?;
    for w in &chain.warnings {
        eprintln!("{}", w.display_in(path));
    }
    for n in &chain.notes {
        eprintln!(
            "{}",
            n.display_in(path).replacen(": warning: ", ": note: ", 1)
        );
    }
    Ok(chain)
}

/// `euler` or `quaternion`, for `--floating`.
fn parse_floating(name: &str) -> Result<FloatingBase, String> {
    match FloatingBase::from_name(name) {
        Some(b) if b.is_floating() => Ok(b),
        _ => Err(format!("`{name}`: expected `euler` or `quaternion`")),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Eval(args) => match eval::run(args) {
            // Every quantity computed at this state is printed; one that could not be fails
            // the run, with its message on stderr too.
            Ok((json, errors)) if !errors.is_empty() => {
                println!("{json}");
                for e in &errors {
                    eprintln!("{e}");
                }
                return ExitCode::FAILURE;
            }
            other => other.map(|(json, _)| json),
        },
        Command::Expand(args) => expand::run(args),
        Command::Export(args) => export::run(args),
        Command::Simulate(args) => simulate::run(args),
        Command::Invert(args) => invert::run(args),
    };
    match result {
        // Written to a file (`export --out`): nothing for stdout.
        Ok(text) if text.is_empty() => ExitCode::SUCCESS,
        Ok(text) => {
            // A closed pipe (`articulated expand … | head`) is not an error worth a panic.
            let mut out = std::io::stdout().lock();
            match writeln!(out, "{}", text.trim_end_matches('\n')) {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    eprintln!("error: cannot write the output: {e}");
                    ExitCode::FAILURE
                }
                _ => ExitCode::SUCCESS,
            }
        }
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}
