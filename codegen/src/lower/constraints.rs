//! The constraints as written, for `contacts: […]` and `loops: […]` in a description and the
//! same keys of `#[chain(…)]`: `[left_sole: six_d, toe: point]` and `[rod: point(a, b)]`,
//! every malformed item and unknown kind reported at its token. Whether the frames exist, move
//! and are named once is the check stage's ([`crate::check::options`]).

use proc_macro2::Ident;
use quote::ToTokens;
use syn::punctuated::Punctuated;

use crate::options::{unknown_contact_kind, unknown_loop_kind, ContactKind};
use crate::parse::Expr;

/// The contacts of `[frame: kind, …]`, each with its frame's token, and the errors: a value
/// that is not a list, an item that is not `frame: kind`, an unknown kind.
pub(crate) fn contacts_of(v: &Expr) -> (Vec<(Ident, ContactKind)>, Vec<syn::Error>) {
    let mut contacts = Vec::new();
    let mut errors = Vec::new();
    let mut error = |at: &dyn ToTokens, message: String| {
        errors.push(syn::Error::new_spanned(at.to_token_stream(), message));
    };
    let Expr::List(_, elems) = v else {
        error(
            v,
            format!(
                "expected a list of contacts such as `[left_sole: six_d, toe: point]`, found `{v}`"
            ),
        );
        return (contacts, errors);
    };
    for e in elems {
        let Expr::Labeled(frame, _, kind) = e else {
            error(
                e,
                format!("expected a contact `frame: kind` such as `left_sole: six_d`, found `{e}`"),
            );
            continue;
        };
        match &**kind {
            Expr::Name(k) => match ContactKind::from_name(&k.to_string()) {
                Some(kind) => contacts.push((frame.clone(), kind)),
                None => error(k, unknown_contact_kind(&k.to_string())),
            },
            other => error(
                other,
                format!(
                    "expected the contact's kind, `six_d` or `point`, found `{other}` (a loop \
                     between two frames goes in `loops: [name: point(a, b)]`)"
                ),
            ),
        }
    }
    (contacts, errors)
}

/// A loop's name token, its kind and its frames' tokens.
pub(crate) type LoopTokens = (Ident, ContactKind, [Ident; 2]);

/// The loops of `[name: point(a, b), name: six_d(a, b), …]`, each with its name's token, its
/// kind and its frames' tokens, and the errors: a value that is not a list, an item that is not
/// `name: kind(a, b)`, an unknown kind, other than two frame names.
pub(crate) fn loops_of(v: &Expr) -> (Vec<LoopTokens>, Vec<syn::Error>) {
    let mut loops = Vec::new();
    let mut errors = Vec::new();
    let mut error = |at: &dyn ToTokens, message: String| {
        errors.push(syn::Error::new_spanned(at.to_token_stream(), message));
    };
    let Expr::List(_, elems) = v else {
        error(
            v,
            format!("expected a list of loops such as `[rod: point(tip, ground)]`, found `{v}`"),
        );
        return (loops, errors);
    };
    for e in elems {
        let Expr::Labeled(name, _, value) = e else {
            error(
                e,
                format!(
                    "expected a loop `name: point(a, b)` such as `rod: point(tip, ground)`, \
                     found `{e}`"
                ),
            );
            continue;
        };
        let (kind, args) = match &**value {
            Expr::Call(kind, _, args) => (kind, Some(args)),
            Expr::Name(kind) => (kind, None),
            other => {
                error(
                    other,
                    format!("expected `point(a, b)`, the loop's two frames, found `{other}`"),
                );
                continue;
            }
        };
        let Some(kind_of) = ContactKind::from_name(&kind.to_string()) else {
            error(kind, unknown_loop_kind(&kind.to_string()));
            continue;
        };
        let count = args.map_or(0, Punctuated::len);
        if count != 2 {
            error(
                value,
                format!(
                    "expected the loop's two frames, `{kind}(a, b)` (frame `a`{held} held on \
                     frame `b`{s}), found {count} in `{value}`",
                    held = if kind_of == ContactKind::Point {
                        "'s origin"
                    } else {
                        ""
                    },
                    s = if kind_of == ContactKind::Point {
                        "'s"
                    } else {
                        ""
                    },
                ),
            );
            continue;
        }
        let mut frames = Vec::new();
        for a in args.into_iter().flatten() {
            match a {
                Expr::Name(n) => frames.push(n.clone()),
                other => error(other, format!("expected a frame name, found `{other}`")),
            }
        }
        if let Ok(frames) = <[Ident; 2]>::try_from(frames) {
            loops.push((name.clone(), kind_of, frames));
        }
    }
    (loops, errors)
}
