//! The error context of lowering: [`Ctxt`] collects every problem found, each spanned at the
//! offending token, and combines them into one `syn::Error` in source order (as serde_derive's
//! `internals::Ctxt` does).

use std::fmt;

use quote::ToTokens;

/// Collects errors; [`Ctxt::check`] combines them (serde_derive's `internals::Ctxt`).
#[derive(Default)]
pub(super) struct Ctxt {
    errors: Vec<syn::Error>,
}

impl Ctxt {
    /// Records the error `msg`, spanned at the tokens of `at`.
    pub(super) fn error(&mut self, at: impl ToTokens, msg: impl fmt::Display) {
        self.errors.push(syn::Error::new_spanned(at, msg));
    }
    /// Records errors already made.
    pub(super) fn errors(&mut self, errors: impl IntoIterator<Item = syn::Error>) {
        self.errors.extend(errors);
    }
    /// Whether any error was recorded.
    pub(super) fn has_errors(&self) -> bool {
        !self.errors.is_empty()
    }
    /// All errors combined in one, in source order where spans know their position.
    pub(super) fn check(mut self) -> syn::Result<()> {
        self.errors.sort_by_key(|e| {
            let start = e.span().start();
            (start.line, start.column)
        });
        let mut errors = self.errors.into_iter();
        let Some(mut first) = errors.next() else {
            return Ok(());
        };
        for e in errors {
            first.combine(e);
        }
        Err(first)
    }
}
