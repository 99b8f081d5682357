//! The macros' expansions, on `proc_macro2` so they can be tested and reused: `chain!{…}` and
//! `#[derive(Chain)]` (the `articulated-macros` crate is a shim that calls these).
//!
//! On an error the expansion is a `compile_error!` at the offending token, plus a stand-in for
//! what the macro would have declared (`fallback.rs`), so the user sees one error and not a
//! cascade.

mod attr;
mod fallback;
mod path;

use std::path::{Path, PathBuf};

use proc_macro2::TokenStream;
use quote::quote;
use syn::parse::{ParseStream, Parser};
use syn::{Attribute, Data, DeriveInput, Fields, Ident, LitStr, Visibility};

use attr::{parse_attr, Source};
use fallback::fallback;
use path::{resolve, unreadable, wrong_extension, Key};

use crate::check::{self, About};
use crate::generate::{generate, generate_impls};
use crate::load::{load_with, FloatingBase, LoadError, LoadOptions};
use crate::lower::lower;
use crate::options::{Contact, Loop};
use crate::parse::ChainDef;

/// `chain!{ … }`: the grammar of [`crate::parse`], expanded to the type and its impls.
pub fn chain(input: TokenStream) -> TokenStream {
    let def: ChainDef = match syn::parse2(input.clone()) {
        Ok(def) => def,
        Err(e) => {
            // A syntax error stops the parse; the header (`[vis] chain Name`) usually still
            // reads, and then the stand-in keeps uses of `Name` quiet.
            let errors = e.to_compile_error();
            return match header.parse2(input) {
                Ok((vis, name)) => {
                    let stub = fallback(&name);
                    quote! { #errors #vis struct #name; #stub }
                }
                Err(_) => errors,
            };
        }
    };
    let (vis, name) = (&def.vis, &def.name);
    let result = lower(&def).and_then(|chain| generate(&chain.model, &chain.options));
    match result {
        Ok(g) => g.tokens,
        Err(e) => {
            let errors = e.to_compile_error();
            let stub = fallback(name);
            quote! { #errors #vis struct #name; #stub }
        }
    }
}

/// Reads the header of a chain whose body does not parse: `[attrs] [vis] chain Name …`.
fn header(input: ParseStream) -> syn::Result<(Visibility, Ident)> {
    input.call(Attribute::parse_outer)?;
    let vis: Visibility = input.parse()?;
    let kw: Ident = input.parse()?;
    if kw != "chain" {
        return Err(syn::Error::new(kw.span(), "expected `chain`"));
    }
    let name: Ident = input.parse()?;
    input.parse::<TokenStream>()?;
    Ok((vis, name))
}

/// A file that does not load, as errors at the path in the attribute. Messages name the file as
/// the attribute does (relative to the crate), not by the absolute path it resolved to: that is
/// the text under the caret, and the same on every machine (a file that cannot be read says
/// where it was looked for: `path.rs`). Each problem of a `.chain` file is its own error,
/// `file:line:column: message` (rustc adds the `error: `).
fn load_error(
    e: LoadError,
    key: Key,
    path: &Path,
    manifest_dir: Option<&Path>,
    lit: &LitStr,
) -> syn::Error {
    let shown = lit.value();
    let error = |m: String| syn::Error::new(lit.span(), m);
    match e {
        LoadError::Read { error: io, .. } => {
            error(unreadable(key, &shown, path, manifest_dir, &io))
        }
        LoadError::Chain(file) => file
            .diagnostics
            .iter()
            .map(|d| error(format!("{shown}:{}:{}: {}", d.line, d.column, d.message)))
            .reduce(|mut all, e| {
                all.combine(e);
                all
            })
            .unwrap_or_else(|| error(format!("{shown}: cannot be loaded"))),
        LoadError::Strict { warnings, .. } => warnings
            .iter()
            .map(|w| {
                let at = w.line.map_or(String::new(), |l| format!(":{l}"));
                error(format!("{shown}{at}: {} (refused: `strict`)", w.message))
            })
            .reduce(|mut all, e| {
                all.combine(e);
                all
            })
            .unwrap_or_else(|| error(format!("{shown}: cannot be loaded"))),
        other => error(
            other
                .to_string()
                .replace(&path.display().to_string(), &shown),
        ),
    }
}

/// `#[derive(Chain)]` on a unit struct with `#[chain(file = "models/x.chain")]` or
/// `#[chain(urdf = "models/x.urdf")]` (optionally `floating`, `scalar = …`, `outputs = […]`,
/// `contacts = […]`, …):
/// the impls for the described chain, named after the struct. The crate rebuilds when the file
/// changes.
pub fn derive(input: TokenStream) -> TokenStream {
    match derive_inner(input.clone()) {
        Ok(tokens) => tokens,
        Err(e) => {
            let errors = e.to_compile_error();
            // The stand-in, on a type it can be written for (no generic parameters).
            match syn::parse2::<DeriveInput>(input) {
                Ok(input) if input.generics.params.is_empty() => {
                    let stub = fallback(&input.ident);
                    quote! { #errors #stub }
                }
                _ => errors,
            }
        }
    }
}

fn derive_inner(input: TokenStream) -> syn::Result<TokenStream> {
    let input: DeriveInput = syn::parse2(input)?;
    match &input.data {
        Data::Struct(s) if matches!(s.fields, Fields::Unit) => {}
        _ => {
            return Err(syn::Error::new(
                input.ident.span(),
                "#[derive(Chain)] goes on a unit struct: `struct Arm;`",
            ))
        }
    }
    if !input.generics.params.is_empty() {
        return Err(syn::Error::new(
            input.ident.span(),
            "#[derive(Chain)] goes on a struct without generic parameters",
        ));
    }
    let attr = parse_attr(&input)?;
    let lit = attr.source.lit();
    let (key, floating) = match attr.source {
        Source::Chain(_) => (Key::File, FloatingBase::Fixed),
        Source::Urdf(_, floating) => (Key::Urdf, floating),
        Source::Mjcf(_) => (Key::Mjcf, FloatingBase::Fixed),
    };
    let manifest_dir = std::env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from);
    let path = resolve(&lit.value(), manifest_dir.as_deref());
    if let Some(m) = wrong_extension(key, &lit.value(), &path, floating.is_floating()) {
        return Err(syn::Error::new(lit.span(), m));
    }
    let options = LoadOptions {
        floating,
        balance_inertia: attr.balance_inertia,
        strict: attr.strict,
        mimic_equalities: attr.mimic_equalities,
    };
    let mut chain = load_with(&path, options)
        .map_err(|e| load_error(e, key, &path, manifest_dir.as_deref(), lit))?;
    let warnings = warning_items(&chain.warnings, &lit.value(), lit.span());
    chain.model.name = input.ident.to_string();
    // The struct is the user's: its visibility goes on what is generated beside it.
    chain.options.visibility = crate::lower::visibility(&input.vis);
    if let Some(scalar) = attr.scalar {
        chain.options.scalar = scalar;
    }
    if let Some(outputs) = &attr.outputs {
        chain.options.outputs = outputs.iter().map(|(o, _)| *o).collect();
    }
    if let Some((accuracy, _)) = attr.accuracy {
        chain.options.accuracy = accuracy;
    }
    chain.options.quasi_static |= attr.quasi_static;
    if let Some((n, _)) = attr.lanes {
        chain.options.lanes = Some(n);
    }
    for (name, q) in &attr.locks {
        chain.options.locks.push((name.to_string(), q.clone()));
    }
    if let Some(keep) = &attr.keep {
        chain.options.keep = Some(keep.iter().map(Ident::to_string).collect());
    }
    if let Some(frames) = &attr.frames {
        chain.options.frames = frames.iter().map(Ident::to_string).collect();
    }
    if let Some(contacts) = &attr.contacts {
        chain.options.contacts = contacts
            .iter()
            .map(|(frame, kind)| Contact {
                frame: frame.to_string(),
                kind: *kind,
            })
            .collect();
    }
    if let Some(loops) = &attr.loops {
        chain.options.loops = loops
            .iter()
            .map(|(name, kind, [a, b])| Loop {
                name: name.to_string(),
                kind: *kind,
                a: a.to_string(),
                b: b.to_string(),
            })
            .collect();
    }
    // The check stage on the options the attribute gives the file's model, every problem at the
    // key that asked for it (at the file's path where the file asked).
    let problems = check::options(&chain.model, &chain.options);
    if let Some(e) = check::combined(problems, |about| {
        attr_span(&attr, about).unwrap_or(lit.span())
    }) {
        return Err(e);
    }
    let g = generate_impls(&chain.model, &chain.options, &lit.value())
        .map_err(|e| syn::Error::new(lit.span(), e.to_string()))?;
    let tokens = g.tokens;
    let abs = path.display().to_string();
    Ok(quote! {
        // Makes cargo rebuild the crate when the description changes.
        const _: &[u8] = include_bytes!(#abs);
        #warnings
        #tokens
    })
}

/// Where in `#[chain(…)]` the problem about `about` was asked for: the name of an output, the
/// accuracy, a joint locked, a body kept, a frame, a constraint; `None` for what the file says.
fn attr_span(attr: &attr::Attr, about: &About) -> Option<proc_macro2::Span> {
    let named = |name: &str| -> Option<&Ident> {
        let locked = attr.locks.iter().map(|(n, _)| n);
        locked
            .chain(attr.keep.iter().flatten())
            .chain(attr.frames.iter().flatten())
            .find(|n| *n == name)
    };
    if *about == About::Lanes {
        return attr.lanes.map(|(_, span)| span);
    }
    match about {
        About::Output(o) => attr
            .outputs
            .iter()
            .flatten()
            .find(|(x, _)| x == o)
            .map(|(_, n)| n),
        About::Accuracy => attr.accuracy.as_ref().map(|(_, n)| n),
        About::Scene(name) => named(name),
        About::Contact(k) => attr
            .contacts
            .as_ref()
            .and_then(|c| c.get(*k))
            .map(|(f, _)| f),
        About::Loop(k) => attr
            .loops
            .as_ref()
            .and_then(|l| l.get(*k))
            .map(|(n, _, _)| n),
        About::LoopFrame(k, side) => attr
            .loops
            .as_ref()
            .and_then(|l| l.get(*k))
            .and_then(|(_, _, frames)| frames.get(*side)),
        _ => None,
    }
    .map(Ident::span)
}

/// The loader's warnings as compiler warnings at the file's path in the attribute. Stable Rust
/// has no way for a macro to warn, so each is a deprecated item used right away: rustc prints
/// `use of deprecated unit struct …: robot.urdf:193: link …`, and `#[deny(warnings)]` or
/// `strict` in the attribute turns them into errors.
fn warning_items(
    warnings: &[crate::options::Warning],
    shown: &str,
    span: proc_macro2::Span,
) -> TokenStream {
    let items = warnings.iter().map(|w| {
        let note = match w.line {
            Some(l) => format!("{shown}:{l}: {}", w.message),
            None => format!("{shown}: {}", w.message),
        };
        let name = syn::Ident::new("articulated_warning", span);
        quote::quote_spanned! {span=>
            const _: () = {
                #[deprecated(note = #note)]
                #[allow(non_camel_case_types)]
                struct #name;
                let _ = #name;
            };
        }
    });
    quote!(#(#items)*)
}
