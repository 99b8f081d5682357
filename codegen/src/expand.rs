//! The macros' expansions, on `proc_macro2` so they can be tested and reused: `chain!{…}` and
//! `#[derive(Chain)]` (the `articulated-macros` crate is a shim that calls these).
//!
//! On an error the expansion is a `compile_error!` at the offending token, plus a stand-in for
//! what the macro would have declared ([`fallback`]): the struct (for `chain!`), its `NQ`/`NV`
//! constants and every trait impl, with bodies that are never run. So the user sees the real
//! error and not a cascade of "cannot find type" or "no function named" errors after it (as
//! `thiserror`'s `fallback.rs`). The ui tests in `macros/tests/ui` lock this.

use std::path::{Path, PathBuf};

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::parse::{ParseStream, Parser};
use syn::{Attribute, Data, DeriveInput, Fields, Ident, LitStr, Visibility};

use crate::generate::{generate, generate_impls};
use crate::load::{load_model, LoadError};
use crate::lower::lower;
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
    let result = lower(&def).and_then(|model| generate(&model));
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

/// What stands in for the generated items after an error (the error itself is reported
/// beside it): `NQ` and `NV` (zero) and the runtime traits, generic in the scalar and in one size
/// `N` for both `q` and `v`, so that uses of them type-check and the sizes are inferred from `q`
/// (a size left free would be a "type annotations needed" error of its own). The bodies are
/// never run: the crate does not compile.
fn fallback(name: &Ident) -> TokenStream {
    let sizes = quote!(<T, const N: usize>);
    let v = quote!(::articulated::nalgebra::SVector<T, N>);
    let m = quote!(::articulated::nalgebra::SMatrix<T, N, N>);
    let fd = quote!(::core::result::Result<#v, ::articulated::SingularMassMatrix>);
    let never = quote!({ ::core::unreachable!() });
    let name_str = name.to_string();
    quote! {
        impl #name {
            /// Stand-in after an error in the description.
            pub const NQ: usize = 0;
            /// Stand-in after an error in the description.
            pub const NV: usize = 0;
        }
        impl<T> ::articulated::Chain<T> for #name {
            const NAME: &'static str = #name_str;
            const COORDINATES: &'static [::articulated::Coordinates] = &[];
            type Params = ();
            fn default_params() {}
        }
        impl #sizes ::articulated::MassMatrix<T, N, N> for #name {
            fn mass_matrix_with(_: &#v, _: &()) -> #m #never
        }
        impl #sizes ::articulated::Bias<T, N, N> for #name {
            fn bias_with(_: &#v, _: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::Gravity<T, N, N> for #name {
            fn gravity_with(_: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::InverseDynamics<T, N, N> for #name {
            fn inverse_dynamics_with(_: &#v, _: &#v, _: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::ForwardDynamics<T, N, N> for #name {
            fn forward_dynamics_with(_: &#v, _: &#v, _: &#v, _: &()) -> #fd #never
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

/// A file that does not load, as errors at the path in the attribute. Messages name the file as
/// the attribute does (relative to the crate), not by the absolute path it resolved to: that is
/// the text under the caret, and the same on every machine. Each problem of a `.chain` file is
/// its own error, `file:line:column: message` (rustc adds the `error: `).
fn load_error(e: LoadError, path: &Path, lit: &LitStr) -> syn::Error {
    let shown = lit.value();
    let error = |m: String| syn::Error::new(lit.span(), m);
    match e {
        LoadError::Chain(file) => file
            .diagnostics
            .iter()
            .map(|d| match d.line {
                0 if Path::new(&shown).is_relative() => error(format!(
                    "{shown}: {}; paths in #[chain(…)] are relative to the crate's directory \
                     (CARGO_MANIFEST_DIR)",
                    d.message
                )),
                0 => error(format!("{shown}: {}", d.message)),
                _ => error(format!("{shown}:{}:{}: {}", d.line, d.column, d.message)),
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
/// `#[chain(urdf = "models/x.urdf")]` (optionally `floating`): the impls for the described
/// chain, named after the struct. The crate rebuilds when the file changes.
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
    let mut model = load_model(&path, floating).map_err(|e| load_error(e, &path, lit))?;
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
