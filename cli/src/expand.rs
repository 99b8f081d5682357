//! `articulated expand`: the formatted Rust the macros would emit for a model file
//! (`docs/guide/generated-code.md`, "Reading the generated code"), so users can read generated
//! code without `cargo expand` or a nightly toolchain.

use articulated_codegen::generate::generate_file;
use articulated_codegen::load::FloatingBase;
use articulated_codegen::options::{
    unknown_contact_kind, unknown_loop_kind, Accuracy, Contact, ContactKind, Loop, Output,
    ScalarKind,
};

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
    if let Some(n) = args.lanes {
        if !articulated_codegen::options::LANES.contains(&n) {
            return Err(format!(
                "error: --lanes {n}: {}",
                articulated_codegen::options::unknown_lanes(&n.to_string())
            ));
        }
        chain.options.lanes = Some(n);
        source.push_str(&format!(" --lanes {n}"));
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
    if let Some(contacts) = &args.contacts {
        chain.options.contacts = parse_contacts(contacts)?;
        source.push_str(&format!(" --contacts {contacts}"));
    }
    if let Some(loops) = &args.loops {
        chain.options.loops = parse_loops(loops)?;
        // Quoted: the shell would read the parentheses.
        source.push_str(&format!(" --loops '{loops}'"));
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

/// `--contacts a:six_d,b:point`: each frame and its kind, in order (as `contacts: […]`).
fn parse_contacts(list: &str) -> Result<Vec<Contact>, String> {
    list.split(',')
        .map(str::trim)
        .map(|item| {
            let (frame, kind) = item
                .split_once(':')
                .map(|(f, k)| (f.trim(), k.trim()))
                .filter(|(f, _)| !f.is_empty())
                .ok_or_else(|| {
                    format!(
                        "error: --contacts: `{item}`: expected FRAME:KIND with KIND `six_d` or \
                         `point`, e.g. `left_sole:six_d`"
                    )
                })?;
            let kind = ContactKind::from_name(kind)
                .ok_or_else(|| format!("error: --contacts: {}", unknown_contact_kind(kind)))?;
            Ok(Contact {
                frame: frame.to_string(),
                kind,
            })
        })
        .collect()
}

/// `--loops rod:point(a,b),grip:six_d(c,d),…`: each loop's name and two frames, in order (as `loops: […]`);
/// the commas inside the parentheses are the frames'.
fn parse_loops(list: &str) -> Result<Vec<Loop>, String> {
    let mut items = Vec::new();
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in list.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&list[start..]);
    items
        .into_iter()
        .map(str::trim)
        .map(|item| {
            let bad = || {
                format!(
                    "error: --loops: `{item}`: expected NAME:point(A,B), frame A's origin held \
                     on frame B's, or NAME:six_d(A,B), frame A held on frame B, e.g. \
                     `rod:point(tip,ground)`"
                )
            };
            let (name, value) = item.split_once(':').ok_or_else(bad)?;
            let (kind, frames) = match value.trim().split_once('(') {
                Some((kind, rest)) => (kind.trim(), rest.strip_suffix(')').ok_or_else(bad)?),
                None => (value.trim(), ""),
            };
            let Some(kind) = ContactKind::from_name(kind) else {
                return Err(format!("error: --loops: {}", unknown_loop_kind(kind)));
            };
            let frames: Vec<&str> = frames.split(',').map(str::trim).collect();
            match (name.trim(), &frames[..]) {
                (name, [a, b]) if !name.is_empty() && !a.is_empty() && !b.is_empty() => Ok(Loop {
                    name: name.to_string(),
                    kind,
                    a: a.to_string(),
                    b: b.to_string(),
                }),
                _ => Err(bad()),
            }
        })
        .collect()
}
