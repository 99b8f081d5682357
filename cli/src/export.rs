//! `articulated export --mjcf`: any model (`.chain`, URDF, MJCF) written as MuJoCo's MJCF, so
//! that a comparison with MuJoCo or MJX runs the same bodies and joints
//! (`articulated_codegen::mjcf::export` gives the mapping).

use articulated::files::write_atomically;
use articulated_codegen::load::FloatingBase;

use crate::ExportArgs;

/// Runs `export`: the MJCF text for stdout (empty when written to `--out`), or the error
/// message for stderr. What differs from the model exported is said on stderr as notes.
pub fn run(args: &ExportArgs) -> Result<String, String> {
    let chain = crate::load_description(&args.model, args.base)?;
    let exported = articulated_codegen::mjcf::to_mjcf(&chain.model)
        .map_err(|e| format!("{}: error: {e}", args.model.display()))?;
    for note in &exported.notes {
        eprintln!("{}: note: {note}", args.model.display());
    }
    if !chain.options.loops.is_empty() || !chain.options.contacts.is_empty() {
        eprintln!(
            "{}: note: the description's contacts and loops are not exported (MuJoCo writes \
             them as equality constraints and contact pairs of its own)",
            args.model.display()
        );
    }
    // The comment names the source and the base (an XML comment may not hold `--`).
    let floating = match args.base.floating {
        Some(FloatingBase::Quaternion) => ", with a quaternion free base",
        Some(FloatingBase::Euler) => ", with an Euler free base",
        _ => "",
    };
    let header = format!(
        "<!-- Written by the MJCF export of articulated from {}{floating}. -->\n",
        args.model.display()
    );
    let text = header + &exported.text;
    match &args.out {
        Some(path) => {
            write_atomically(path, text.as_bytes())
                .map_err(|e| format!("error: cannot write {}: {e}", path.display()))?;
            Ok(String::new())
        }
        None => Ok(text),
    }
}
