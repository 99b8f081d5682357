//! The `articulated` command: evaluate a chain description's dynamics from the shell.
//!
//! ```text
//! articulated eval models/two_link.chain --q 0.1,0.2,0,0,0.3,0
//! articulated eval models/two_link.chain --engine symbolic
//! articulated expand models/two_link.chain > two_link.rs
//! ```

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

mod eval;
mod expand;

/// Rigid-body dynamics from a chain description (`.chain` or `.urdf`).
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
    /// The model: a `.chain` or `.urdf` file.
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
    /// Put a free base (translation, then Euler angles zyx) under a URDF root: q and v gain 6
    /// leading entries.
    #[arg(long)]
    pub floating: bool,
    /// Which implementation evaluates the model: `reference` (the interpreted recursions) or
    /// `symbolic` (the generator's expression graphs; checks the generator without compiling).
    #[arg(long, value_enum, default_value_t = Engine::Reference)]
    pub engine: Engine,
}

/// Arguments of `articulated expand`.
#[derive(clap::Args, Debug)]
pub struct ExpandArgs {
    /// The model: a `.chain` or `.urdf` file.
    pub model: PathBuf,
    /// Put a free base (translation, then Euler angles zyx) under a URDF root.
    #[arg(long)]
    pub floating: bool,
    /// The scalar of the generated code, in place of the description's: `f64`, `f32` or
    /// `generic`.
    #[arg(long)]
    pub scalar: Option<String>,
    /// The outputs to generate, comma-separated, in place of the description's (e.g.
    /// `mass_matrix,inverse_dynamics`).
    #[arg(long)]
    pub outputs: Option<String>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Eval(args) => eval::run(args),
        Command::Expand(args) => expand::run(args),
    };
    match result {
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
