//! `articulated expand`: the formatted Rust the macros would emit for a model file
//! (`docs/guide/generated-code.md`, "Reading the generated code"), so users can read generated
//! code without `cargo expand` or a nightly toolchain.

use articulated_codegen::generate::generate_file;
use articulated_codegen::load::FloatingBase;
use articulated_codegen::options::{Accuracy, Output, ScalarKind};

use crate::ExpandArgs;

/// Runs `expand`; the Rust source, or the error message for stderr.
pub fn run(args: &ExpandArgs) -> Result<String, String> {
    let mut chain = crate::load_description(&args.model, args.base)?;
    // The header names the command that regenerates the file, so it carries the flags too.
    let mut source = args.model.display().to_string();
    match args.base.floating {
        Some(FloatingBase::Quaternion) => source.push_str(" --floating=quaternion"),
        Some(_) => source.push_str(" --floating"),
        None => {}
    }
    if let Some(name) = &args.scalar {
        chain.options.scalar = ScalarKind::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = ScalarKind::ALL.iter().map(|(_, n)| *n).collect();
            format!("error: --scalar `{name}`: expected {}", names.join(", "))
        })?;
        source.push_str(&format!(" --scalar {name}"));
    }
    if let Some(list) = &args.outputs {
        let outputs = list
            .split(',')
            .map(str::trim)
            .map(|name| {
                Output::named(name).ok_or_else(|| {
                    format!(
                        "error: --outputs: {}",
                        articulated_codegen::options::unknown_output(name)
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        chain.options.set_outputs(outputs.into_iter().flatten());
        source.push_str(&format!(" --outputs {list}"));
    }
    if let Some(name) = &args.accuracy {
        chain.options.accuracy = Accuracy::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = Accuracy::ALL.iter().map(|(_, n)| *n).collect();
            format!("error: --accuracy `{name}`: expected {}", names.join(", "))
        })?;
        source.push_str(&format!(" --accuracy {name}"));
    }
    for lock in &args.locks {
        let (joint, values) = lock
            .split_once('=')
            .ok_or_else(|| format!("error: --lock `{lock}`: expected JOINT=Q[,Q…]"))?;
        let q = values
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|e| format!("error: --lock `{lock}`: {e}"))?;
        chain.options.locks.push((joint.trim().to_string(), q));
        source.push_str(&format!(" --lock {lock}"));
    }
    if let Some(keep) = &args.keep {
        chain.options.keep = Some(keep.split(',').map(|b| b.trim().to_string()).collect());
        source.push_str(&format!(" --keep {keep}"));
    }
    if let Some(frames) = &args.frames {
        chain.options.frames = frames.split(',').map(|f| f.trim().to_string()).collect();
        source.push_str(&format!(" --frames {frames}"));
    }
    if args.quasi_static {
        chain.options.quasi_static = true;
        source.push_str(" --quasi-static");
    }
    generate_file(&chain.model, &chain.options, &source).map_err(|e| {
        // Every problem the check stage found with the options given, one per line.
        e.into_iter()
            .map(|e| format!("{}: error: {e}", args.model.display()))
            .collect::<Vec<_>>()
            .join("\n")
    })
}
