//! The macros' expansions, on `proc_macro2` so they can be tested and reused: `chain!{…}` and
//! `#[derive(Chain)]` (the `articulated-macros` crate is a shim that calls these).
//!
//! On an error the expansion is a `compile_error!` at the offending token, plus the struct
//! itself where the macro would have declared it, so the user sees the real error and not a
//! cascade of "cannot find type" errors after it.

use std::path::{Path, PathBuf};

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::{Data, DeriveInput, Fields, LitStr};

use crate::generate::{generate, generate_impls};
use crate::load::load_model;
use crate::lower::lower;
use crate::parse::ChainDef;

/// `chain!{ … }`: the grammar of [`crate::parse`], expanded to the type and its impls.
pub fn chain(input: TokenStream) -> TokenStream {
    let def: ChainDef = match syn::parse2(input) {
        Ok(def) => def,
        Err(e) => return e.to_compile_error(),
    };
    let model = match lower(&def) {
        Ok(model) => model,
        Err(e) => {
            // The struct alone, so that uses of it elsewhere do not add errors of their own.
            let (vis, name) = (&def.vis, &def.name);
            let errors = e.to_compile_error();
            return quote! { #errors #vis struct #name; };
        }
    };
    match generate(&model) {
        Ok(g) => g.tokens,
        Err(e) => {
            let (vis, name) = (&def.vis, &def.name);
            let errors = e.to_compile_error();
            quote! { #errors #vis struct #name; }
        }
    }
}

/// Where `#[chain(…)]` says the description is.
enum Source {
    Chain(LitStr),
    Urdf(LitStr, bool),
}

fn parse_attr(input: &DeriveInput) -> syn::Result<Source> {
    let mut file: Option<LitStr> = None;
    let mut urdf: Option<LitStr> = None;
    let mut floating = false;
    let mut seen = false;
    for attr in input.attrs.iter().filter(|a| a.path().is_ident("chain")) {
        seen = true;
        attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("file") {
                file = Some(meta.value()?.parse()?);
            } else if meta.path.is_ident("urdf") {
                urdf = Some(meta.value()?.parse()?);
            } else if meta.path.is_ident("floating") {
                floating = true;
            } else {
                return Err(meta.error(
                    "unknown key in #[chain(…)]: expected `file = \"….chain\"`, `urdf = \"….urdf\"` or `floating`",
                ));
            }
            Ok(())
        })?;
    }
    match (file, urdf, seen) {
        (Some(f), None, _) if floating => Err(syn::Error::new(
            f.span(),
            "`floating` applies to `urdf = …`; in a `.chain` file write the free base as a joint",
        )),
        (Some(f), None, _) => Ok(Source::Chain(f)),
        (None, Some(u), _) => Ok(Source::Urdf(u, floating)),
        (Some(_), Some(u), _) => Err(syn::Error::new(
            u.span(),
            "give either `file = \"….chain\"` or `urdf = \"….urdf\"`, not both",
        )),
        (None, None, true) => Err(syn::Error::new(
            Span::call_site(),
            "#[chain(…)] needs `file = \"….chain\"` or `urdf = \"….urdf\"`",
        )),
        (None, None, false) => Err(syn::Error::new(
            input.ident.span(),
            "#[derive(Chain)] needs an attribute naming the description: \
             #[chain(file = \"models/x.chain\")] or #[chain(urdf = \"models/x.urdf\")]",
        )),
    }
}

/// Resolves a path from the attribute against the crate's `CARGO_MANIFEST_DIR`.
fn resolve(rel: &str) -> PathBuf {
    let path = Path::new(rel);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    match std::env::var_os("CARGO_MANIFEST_DIR") {
        Some(dir) => Path::new(&dir).join(path),
        None => path.to_path_buf(),
    }
}

/// `#[derive(Chain)]` on a unit struct with `#[chain(file = "models/x.chain")]` or
/// `#[chain(urdf = "models/x.urdf")]` (optionally `floating`): the impls for the described
/// chain, named after the struct. The crate rebuilds when the file changes.
pub fn derive(input: TokenStream) -> TokenStream {
    match derive_inner(input) {
        Ok(tokens) => tokens,
        Err(e) => e.to_compile_error(),
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
    let source = parse_attr(&input)?;
    let (lit, floating) = match &source {
        Source::Chain(l) => (l, false),
        Source::Urdf(l, f) => (l, *f),
    };
    let path = resolve(&lit.value());
    let is_urdf = matches!(source, Source::Urdf(..));
    let ext_ok = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e == if is_urdf { "urdf" } else { "chain" });
    if !ext_ok {
        return Err(syn::Error::new(
            lit.span(),
            format!(
                "expected a `.{}` file, found `{}`",
                if is_urdf { "urdf" } else { "chain" },
                lit.value()
            ),
        ));
    }
    let mut model =
        load_model(&path, floating).map_err(|e| syn::Error::new(lit.span(), e.to_string()))?;
    model.name = input.ident.to_string();
    let g = generate_impls(&model).map_err(|e| syn::Error::new(lit.span(), e.to_string()))?;
    let tokens = g.tokens;
    let abs = path.display().to_string();
    Ok(quote! {
        // Makes cargo rebuild the crate when the description changes.
        const _: &[u8] = include_bytes!(#abs);
        #tokens
    })
}
