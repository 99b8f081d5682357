//! `articulated expand`: the formatted Rust the macros would emit for a model file (DESIGN.md
//! §6), so users can read generated code without `cargo expand` or a nightly toolchain.

use articulated_codegen::generate::generate_file;
use articulated_codegen::load::load_model;

use crate::ExpandArgs;

/// Runs `expand`; the Rust source, or the error message for stderr.
pub fn run(args: &ExpandArgs) -> Result<String, String> {
    let model = load_model(&args.model, args.floating).map_err(|e| e.to_string())?;
    // The header names the command that regenerates the file, so it carries the flag too.
    let mut source = args.model.display().to_string();
    if args.floating {
        source.push_str(" --floating");
    }
    generate_file(&model, &source).map_err(|e| format!("{}: error: {e}", args.model.display()))
}
