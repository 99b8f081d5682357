//! The keys of `#[chain(…)]` on `#[derive(Chain)]`: where the description is (`file = "….chain"`
//! or `urdf = "….urdf"`, with `floating` for a free base under the URDF root) and the options
//! every front end can state (`scalar = f32`, `outputs = [mass_matrix, bias]`), each error
//! spanned at its key or value.

use proc_macro2::Span;
use syn::meta::ParseNestedMeta;
use syn::punctuated::Punctuated;
use syn::{DeriveInput, Ident, LitStr, Token};

use crate::options::{
    unknown_accuracy, unknown_output, unknown_scalar, Accuracy, Output, ScalarKind,
};

/// Where `#[chain(…)]` says the description is.
pub(crate) enum Source {
    /// A `.chain` file.
    Chain(LitStr),
    /// A URDF file, with `floating`.
    Urdf(LitStr, bool),
}

impl Source {
    /// The path as written.
    pub(crate) fn lit(&self) -> &LitStr {
        match self {
            Source::Chain(l) | Source::Urdf(l, _) => l,
        }
    }
}

/// Everything `#[chain(…)]` says.
pub(crate) struct Attr {
    /// The description's file.
    pub source: Source,
    /// `scalar = …`, if given.
    pub scalar: Option<ScalarKind>,
    /// `outputs = […]`, if given.
    pub outputs: Option<Vec<Output>>,
    /// `accuracy = fastest | robust`, if given.
    pub accuracy: Option<Accuracy>,
}

const KEYS: &str = "expected `file = \"….chain\"`, `urdf = \"….urdf\"`, `floating`, \
                    `scalar = f64 | f32 | generic`, `outputs = [mass_matrix, …]` or \
                    `accuracy = fastest | robust`";

/// Reads every `#[chain(…)]` on `input`.
pub(crate) fn parse_attr(input: &DeriveInput) -> syn::Result<Attr> {
    let mut file: Option<LitStr> = None;
    let mut urdf: Option<LitStr> = None;
    let mut floating: Option<Ident> = None;
    let mut scalar = None;
    let mut outputs = None;
    let mut accuracy = None;
    let mut seen = false;
    for attr in input.attrs.iter().filter(|a| a.path().is_ident("chain")) {
        seen = true;
        attr.parse_nested_meta(|meta| {
            let key = meta.path.get_ident().map(Ident::to_string);
            match key.as_deref() {
                Some("file") => file = Some(meta.value()?.parse()?),
                Some("urdf") => urdf = Some(meta.value()?.parse()?),
                Some("floating") => floating = meta.path.get_ident().cloned(),
                Some("scalar") => scalar = Some(parse_scalar(&meta)?),
                Some("outputs") => outputs = Some(parse_outputs(&meta)?),
                Some("accuracy") => accuracy = Some(parse_accuracy(&meta)?),
                _ => return Err(meta.error(format!("unknown key in #[chain(…)]: {KEYS}"))),
            }
            Ok(())
        })?;
    }
    let source =
        match (file, urdf, seen) {
            (Some(_), None, _) if floating.is_some() => return Err(syn::Error::new(
                floating.map_or_else(Span::call_site, |f| f.span()),
                "`floating` applies to `urdf = …`; in a `.chain` file write the free base as a \
                 joint",
            )),
            (Some(f), None, _) => Source::Chain(f),
            (None, Some(u), _) => Source::Urdf(u, floating.is_some()),
            (Some(_), Some(u), _) => {
                return Err(syn::Error::new(
                    u.span(),
                    "give either `file = \"….chain\"` or `urdf = \"….urdf\"`, not both",
                ))
            }
            (None, None, true) => {
                return Err(syn::Error::new(
                    Span::call_site(),
                    "#[chain(…)] needs `file = \"….chain\"` or `urdf = \"….urdf\"`",
                ))
            }
            (None, None, false) => {
                return Err(syn::Error::new(
                    input.ident.span(),
                    "#[derive(Chain)] needs an attribute naming the description: \
                 #[chain(file = \"models/x.chain\")] or #[chain(urdf = \"models/x.urdf\")]",
                ))
            }
        };
    Ok(Attr {
        source,
        scalar,
        outputs,
        accuracy,
    })
}

/// `accuracy = fastest | robust`.
fn parse_accuracy(meta: &ParseNestedMeta) -> syn::Result<Accuracy> {
    let name: Ident = meta.value()?.parse()?;
    Accuracy::from_name(&name.to_string())
        .ok_or_else(|| syn::Error::new(name.span(), unknown_accuracy(&name.to_string())))
}

/// `scalar = f64 | f32 | generic`.
fn parse_scalar(meta: &ParseNestedMeta) -> syn::Result<ScalarKind> {
    let name: Ident = meta.value()?.parse()?;
    ScalarKind::from_name(&name.to_string())
        .ok_or_else(|| syn::Error::new(name.span(), unknown_scalar(&name.to_string())))
}

/// `outputs = [name, …]`, sorted, without duplicates.
fn parse_outputs(meta: &ParseNestedMeta) -> syn::Result<Vec<Output>> {
    let value = meta.value()?;
    let content;
    syn::bracketed!(content in value);
    let names = Punctuated::<Ident, Token![,]>::parse_terminated(&content)?;
    let mut outputs = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for name in &names {
        match Output::from_name(&name.to_string()) {
            Some(o) => outputs.push(o),
            None => {
                let e = syn::Error::new(name.span(), unknown_output(&name.to_string()));
                match &mut errors {
                    Some(all) => all.combine(e),
                    None => errors = Some(e),
                }
            }
        }
    }
    if let Some(e) = errors {
        return Err(e);
    }
    outputs.sort();
    outputs.dedup();
    Ok(outputs)
}
