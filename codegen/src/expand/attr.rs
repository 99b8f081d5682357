//! The keys of `#[chain(…)]` on `#[derive(Chain)]`: where the description is (`file = "….chain"`
//! or `urdf = "….urdf"`, with `floating` for a free base under the URDF root) and the options
//! every front end can state (`scalar = f32`, `outputs = [mass_matrix, bias]`, `contacts =
//! [left_sole: six_d]`), each error spanned at its key or value.

use std::path::Path;

use proc_macro2::Span;
use syn::meta::ParseNestedMeta;
use syn::punctuated::Punctuated;
use syn::{DeriveInput, Ident, LitStr, Token};

use super::path::Key;
use crate::load::FloatingBase;
use crate::lower::constraints::{contacts_of, loops_of, LoopTokens};
use crate::options::{
    unknown_accuracy, unknown_output, unknown_scalar, Accuracy, ContactKind, Output, ScalarKind,
};
use crate::parse::Expr;

/// Where `#[chain(…)]` says the description is.
pub(crate) enum Source {
    /// A `.chain` file.
    Chain(LitStr),
    /// A URDF file, with its base (`floating`, `floating = quaternion`).
    Urdf(LitStr, FloatingBase),
    /// A MuJoCo MJCF file (`.xml`), whose free joints are its own.
    Mjcf(LitStr),
}

impl Source {
    /// The path as written.
    pub(crate) fn lit(&self) -> &LitStr {
        match self {
            Source::Chain(l) | Source::Urdf(l, _) | Source::Mjcf(l) => l,
        }
    }
}

/// Everything `#[chain(…)]` says.
pub(crate) struct Attr {
    /// The description's file.
    pub source: Source,
    /// `scalar = …`, if given.
    pub scalar: Option<ScalarKind>,
    /// `outputs = […]`, if given, sorted, without duplicates, each with its name's token.
    pub outputs: Option<Vec<(Output, Ident)>>,
    /// `accuracy = fastest | robust`, if given, with its token.
    pub accuracy: Option<(Accuracy, Ident)>,
    /// `lock = [joint(q…), …]`: the joints locked, each with its name's token.
    pub locks: Vec<(Ident, Vec<f64>)>,
    /// `keep = [body, …]`, if given.
    pub keep: Option<Vec<Ident>>,
    /// `frames = [frame, …]`, if given.
    pub frames: Option<Vec<Ident>>,
    /// `contacts = [frame: kind, …]`, if given: each frame's token and the kind.
    pub contacts: Option<Vec<(Ident, ContactKind)>>,
    /// `loops = [name: point(a, b) | six_d(a, b), …]`, if given: each loop's name and frames.
    pub loops: Option<Vec<LoopTokens>>,
    /// `quasi_static`.
    pub quasi_static: bool,
    /// `lanes = N`, if given, with its token's span.
    pub lanes: Option<(usize, Span)>,
    /// `strict`: a warning of the loader refuses the file.
    pub strict: bool,
    /// `balance_inertia`: inertias no rigid body has are balanced, not warned about.
    pub balance_inertia: bool,
    /// `mimic_equalities`: an MJCF model's `<joint>` equalities become mimic joints.
    pub mimic_equalities: bool,
}

const KEYS: &str = "expected `file = \"….chain\"`, `urdf = \"….urdf\"`, `mjcf = \"….xml\"`, \
                    `floating [= euler | quaternion]`, \
                    `scalar = f64 | f32 | generic`, `outputs = [mass_matrix, …]`, \
                    `accuracy = fastest | robust`, `lock = [joint(q, …), …]`, \
                    `keep = [body, …]`, `frames = [frame, …]`, \
                    `contacts = [frame: six_d | point, …]`, `loops = [name: point(a, b) | six_d(a, b), …]`, \
                    `lanes = 2 | 4 | 8 | 16`, `quasi_static`, `strict`, `balance_inertia` \
                    or `mimic_equalities`";

/// Reads every `#[chain(…)]` on `input`.
pub(crate) fn parse_attr(input: &DeriveInput) -> syn::Result<Attr> {
    let mut file: Option<LitStr> = None;
    let mut urdf: Option<LitStr> = None;
    let mut mjcf: Option<LitStr> = None;
    let mut floating: Option<(Ident, FloatingBase)> = None;
    let mut scalar = None;
    let mut outputs = None;
    let mut accuracy = None;
    let mut locks = Vec::new();
    let mut keep = None;
    let mut frames = None;
    let mut contacts = None;
    let mut loops = None;
    let mut quasi_static = false;
    let mut lanes = None;
    let mut strict = false;
    let mut balance_inertia = false;
    let mut mimic_equalities = false;
    let mut seen = false;
    for attr in input.attrs.iter().filter(|a| a.path().is_ident("chain")) {
        seen = true;
        attr.parse_nested_meta(|meta| {
            let key = meta.path.get_ident().map(Ident::to_string);
            match key.as_deref() {
                Some("file") => file = Some(meta.value()?.parse()?),
                Some("urdf") => urdf = Some(meta.value()?.parse()?),
                Some("mjcf") => mjcf = Some(meta.value()?.parse()?),
                Some("floating") => floating = parse_floating(&meta)?,
                Some("scalar") => scalar = Some(parse_scalar(&meta)?),
                Some("outputs") => outputs = Some(parse_outputs(&meta)?),
                Some("accuracy") => accuracy = Some(parse_accuracy(&meta)?),
                Some("lock") => locks.extend(parse_locks(&meta)?),
                Some("keep") => keep = Some(parse_names(&meta)?),
                Some("frames") => frames = Some(parse_names(&meta)?),
                Some("contacts") => {
                    let (list, errors) = contacts_of(&meta.value()?.parse::<Expr>()?);
                    contacts = Some(list);
                    combined(errors)?;
                }
                Some("loops") => {
                    let (list, errors) = loops_of(&meta.value()?.parse::<Expr>()?);
                    loops = Some(list);
                    combined(errors)?;
                }
                Some("lanes") => lanes = Some(parse_lanes(&meta)?),
                Some("quasi_static") => quasi_static = true,
                Some("strict") => strict = true,
                Some("balance_inertia") => balance_inertia = true,
                Some("mimic_equalities") => mimic_equalities = true,
                _ => return Err(unknown_key(&meta)),
            }
            Ok(())
        })?;
    }
    let source = source(
        Given {
            file,
            urdf,
            mjcf,
            floating,
        },
        seen,
        input,
    )?;
    Ok(Attr {
        source,
        scalar,
        outputs,
        accuracy,
        locks,
        keep,
        frames,
        contacts,
        loops,
        quasi_static,
        lanes,
        strict,
        balance_inertia,
        mimic_equalities,
    })
}

/// The description's file keys as the attribute gives them.
struct Given {
    file: Option<LitStr>,
    urdf: Option<LitStr>,
    mjcf: Option<LitStr>,
    floating: Option<(Ident, FloatingBase)>,
}

/// Where the description is: one file key, `floating` with a URDF only; `seen` whether any
/// `#[chain(…)]` was written (the error differs), `input` the struct (for where to put it).
fn source(given: Given, seen: bool, input: &DeriveInput) -> syn::Result<Source> {
    let Given {
        file,
        urdf,
        mjcf,
        floating,
    } = given;
    let given: Vec<&LitStr> = [&file, &urdf, &mjcf].into_iter().flatten().collect();
    if let Some(second) = given.get(1) {
        return Err(syn::Error::new(
            second.span(),
            "give one of `file = \"….chain\"`, `urdf = \"….urdf\"` and `mjcf = \"….xml\"`",
        ));
    }
    if let (None, Some((f, _))) = (&urdf, &floating) {
        if file.is_some() || mjcf.is_some() {
            return Err(syn::Error::new(
                f.span(),
                "`floating` applies to `urdf = …`; in a `.chain` file write the free base as a \
                 joint, and in MJCF as `<freejoint/>` in the body",
            ));
        }
    }
    match (file, urdf, mjcf) {
        (Some(f), _, _) => Ok(Source::Chain(f)),
        (_, Some(u), _) => Ok(Source::Urdf(
            u,
            floating.map_or(FloatingBase::Fixed, |(_, base)| base),
        )),
        (_, _, Some(m)) => Ok(Source::Mjcf(m)),
        (None, None, None) if seen => Err(syn::Error::new(
            Span::call_site(),
            "#[chain(…)] needs `file = \"….chain\"`, `urdf = \"….urdf\"` or `mjcf = \"….xml\"`",
        )),
        (None, None, None) => Err(syn::Error::new(
            input.ident.span(),
            "#[derive(Chain)] needs an attribute naming the description: \
                 #[chain(file = \"models/x.chain\")], #[chain(urdf = \"models/x.urdf\")] or \
                 #[chain(mjcf = \"models/x.xml\")]",
        )),
    }
}

/// `errors` as one, or `Ok` for none.
fn combined(errors: Vec<syn::Error>) -> syn::Result<()> {
    match errors.into_iter().reduce(|mut all, e| {
        all.combine(e);
        all
    }) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// An unknown key, with the likely slip where its value is the path of a description under
/// another key's name (`path = "x.chain"`, `model = "x.urdf"`): the key that reads it.
fn unknown_key(meta: &ParseNestedMeta) -> syn::Error {
    let value = meta.input.fork();
    let path = value
        .parse::<Token![=]>()
        .and_then(|_| value.parse::<LitStr>())
        .ok();
    let read_by = path.as_ref().and_then(|lit| {
        let shown = lit.value();
        let key = Key::for_extension(Path::new(&shown).extension().and_then(|e| e.to_str()))?;
        Some((key, shown))
    });
    match (read_by, meta.path.get_ident()) {
        (Some((key, shown)), Some(name)) => meta.error(format!(
            "unknown key `{name}` in #[chain(…)]: for `{shown}` write `{} = \"{shown}\"`",
            key.name()
        )),
        _ => meta.error(format!("unknown key in #[chain(…)]: {KEYS}")),
    }
}

/// `lock = [joint(q, …), …]`, each coordinate a number literal, negative or not.
fn parse_locks(meta: &ParseNestedMeta) -> syn::Result<Vec<(Ident, Vec<f64>)>> {
    let value = meta.value()?;
    let content;
    syn::bracketed!(content in value);
    let items = Punctuated::<syn::ExprCall, Token![,]>::parse_terminated(&content)?;
    items
        .iter()
        .map(|call| {
            let syn::Expr::Path(path) = &*call.func else {
                return Err(syn::Error::new_spanned(&call.func, "expected a joint name"));
            };
            let name = path
                .path
                .get_ident()
                .cloned()
                .ok_or_else(|| syn::Error::new_spanned(path, "expected a joint name"))?;
            let values = call
                .args
                .iter()
                .map(number)
                .collect::<syn::Result<Vec<f64>>>()?;
            Ok((name, values))
        })
        .collect()
}

/// A number literal, or its negation.
fn number(e: &syn::Expr) -> syn::Result<f64> {
    let bad = || syn::Error::new_spanned(e, "expected a number such as `0.3` or `-1.2`");
    match e {
        syn::Expr::Lit(syn::ExprLit { lit, .. }) => match lit {
            syn::Lit::Float(f) => f.base10_parse().map_err(|_| bad()),
            syn::Lit::Int(i) => i.base10_parse::<i64>().map(|x| x as f64).map_err(|_| bad()),
            _ => Err(bad()),
        },
        syn::Expr::Unary(syn::ExprUnary {
            op: syn::UnOp::Neg(_),
            expr,
            ..
        }) => number(expr).map(|x| -x),
        _ => Err(bad()),
    }
}

/// `accuracy = fastest | robust`, with its token.
fn parse_accuracy(meta: &ParseNestedMeta) -> syn::Result<(Accuracy, Ident)> {
    let name: Ident = meta.value()?.parse()?;
    Accuracy::from_name(&name.to_string())
        .map(|a| (a, name.clone()))
        .ok_or_else(|| syn::Error::new(name.span(), unknown_accuracy(&name.to_string())))
}

/// `floating` alone (the Euler base) or `floating = euler | quaternion`, with the key's token.
fn parse_floating(meta: &ParseNestedMeta) -> syn::Result<Option<(Ident, FloatingBase)>> {
    let key = meta.path.get_ident().cloned();
    let base = if meta.input.peek(Token![=]) {
        let name: Ident = meta.value()?.parse()?;
        match FloatingBase::from_name(&name.to_string()) {
            Some(b) if b.is_floating() => b,
            _ => {
                return Err(syn::Error::new(
                    name.span(),
                    format!("unknown floating base `{name}`: expected `euler` or `quaternion`"),
                ))
            }
        }
    } else {
        FloatingBase::Euler
    };
    Ok(key.map(|k| (k, base)))
}

/// `[name, …]` (`keep`, `frames`).
fn parse_names(meta: &ParseNestedMeta) -> syn::Result<Vec<Ident>> {
    let value = meta.value()?;
    let content;
    syn::bracketed!(content in value);
    let names = Punctuated::<Ident, Token![,]>::parse_terminated(&content)?;
    Ok(names.into_iter().collect())
}

/// `lanes = N`, one of the lane counts, with its token's span.
fn parse_lanes(meta: &ParseNestedMeta) -> syn::Result<(usize, Span)> {
    let n: syn::LitInt = meta.value()?.parse()?;
    match n.base10_parse::<usize>() {
        Ok(k) if crate::options::LANES.contains(&k) => Ok((k, n.span())),
        _ => Err(syn::Error::new(
            n.span(),
            crate::options::unknown_lanes(&n.to_string()),
        )),
    }
}

/// `scalar = f64 | f32 | generic`.
fn parse_scalar(meta: &ParseNestedMeta) -> syn::Result<ScalarKind> {
    let name: Ident = meta.value()?.parse()?;
    ScalarKind::from_name(&name.to_string())
        .ok_or_else(|| syn::Error::new(name.span(), unknown_scalar(&name.to_string())))
}

/// `outputs = [name, …]`, sorted, without duplicates, each with its token (the first).
fn parse_outputs(meta: &ParseNestedMeta) -> syn::Result<Vec<(Output, Ident)>> {
    let value = meta.value()?;
    let content;
    syn::bracketed!(content in value);
    let names = Punctuated::<Ident, Token![,]>::parse_terminated(&content)?;
    let mut outputs = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for name in &names {
        match Output::named(&name.to_string()) {
            Some(named) => outputs.extend(named.into_iter().map(|o| (o, name.clone()))),
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
    outputs.sort_by_key(|(o, _)| *o);
    outputs.dedup_by_key(|(o, _)| *o);
    Ok(outputs)
}
