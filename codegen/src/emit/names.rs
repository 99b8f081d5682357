//! The names of the emitted locals, so the code reads like a hand-unrolled recursion:
//! - a value the recursions labelled ([`Scalar::label`](articulated_dynamics::Scalar::label))
//!   gets its label: `trunk_w_x` (the angular velocity of `trunk` about x), `tau_3`;
//! - the sine and cosine of an input get `s_q3` and `c_q3`;
//! - a value without a label is a term of the first labelled value that uses it, and is named
//!   after it: `trunk_w_x_t1`, `trunk_w_x_t2`, numbered in the order they are computed;
//! - what is left (nothing a labelled value uses) is `t1, t2, …`.
//!
//! Names are sanitized to snake_case identifiers and made unique; none collides with an
//! identifier of the input expressions, a keyword, `T`, or another name.

use std::collections::{HashMap, HashSet};

use proc_macro2::{Ident, Span, TokenStream, TokenTree};

use crate::sym::{Graph, Node, Sym};

/// Names every node in `statements` (in dependency order), where `operands(s)` are the
/// statements `s` reads (through the products fused into it).
pub(super) fn assign(
    graph: &Graph,
    statements: &[Sym],
    operands: &dyn Fn(Sym) -> Vec<Sym>,
    names: &mut Names,
) -> HashMap<Sym, Ident> {
    let is_statement: HashSet<Sym> = statements.iter().copied().collect();
    // Own names: labels, and the sines and cosines of inputs and of named values.
    let mut stem: HashMap<Sym, String> = HashMap::new();
    for &s in statements {
        let own = match graph.node(s) {
            Node::Sin(a) | Node::Cos(a) => {
                let prefix = if matches!(graph.node(s), Node::Sin(_)) {
                    "s"
                } else {
                    "c"
                };
                match graph.node(a) {
                    Node::Input(var) => Some(format!("{prefix}_{var}")),
                    _ => match stem.get(&a) {
                        Some(name) => Some(format!("{prefix}_{name}")),
                        None => graph.hint_of(s).and_then(sanitize),
                    },
                }
            }
            _ => graph.hint_of(s).and_then(sanitize),
        };
        if let Some(own) = own {
            stem.insert(s, own);
        }
    }
    // The first statement that reads each one.
    let mut first_reader: HashMap<Sym, Sym> = HashMap::new();
    for &s in statements {
        for o in operands(s) {
            if is_statement.contains(&o) {
                first_reader.entry(o).or_insert(s);
            }
        }
    }
    // Each unnamed statement takes the name of the first statement reading it, through other
    // unnamed ones: readers come later, so a reverse pass sees them first.
    let mut owner: HashMap<Sym, Sym> = HashMap::new();
    for &s in statements.iter().rev() {
        if stem.contains_key(&s) {
            owner.insert(s, s);
        } else if let Some(o) = first_reader.get(&s).and_then(|r| owner.get(r)) {
            owner.insert(s, *o);
        }
    }
    let mut terms: HashMap<Sym, usize> = HashMap::new();
    let mut out = HashMap::with_capacity(statements.len());
    for &s in statements {
        let ident = match (stem.get(&s), owner.get(&s)) {
            (Some(own), _) => names.unique(own),
            (None, Some(o)) => {
                let k = terms.entry(*o).or_insert(0);
                *k += 1;
                names.unique(&format!("{}_t{k}", stem[o]))
            }
            (None, None) => names.temporary(),
        };
        out.insert(s, ident);
    }
    out
}

/// The names in use, and the counter for `t1, t2, …`.
#[derive(Default)]
pub(super) struct Names {
    used: HashSet<String>,
    next_temporary: usize,
}

/// Names the emitted code must not bind: keywords (strict, reserved, weak), and the names the
/// emitted code itself refers to.
const RESERVED: &[&str] = &[
    "as",
    "break",
    "const",
    "continue",
    "crate",
    "else",
    "enum",
    "extern",
    "false",
    "fn",
    "for",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "return",
    "self",
    "Self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "type",
    "unsafe",
    "use",
    "where",
    "while",
    "async",
    "await",
    "dyn",
    "abstract",
    "become",
    "box",
    "do",
    "final",
    "macro",
    "override",
    "priv",
    "typeof",
    "unsized",
    "virtual",
    "yield",
    "try",
    "gen",
    "union",
    "raw",
    "safe",
    "T",
    "articulated",
    "core",
    "std",
    "libm",
    "nalgebra",
];

impl Names {
    /// Reserves every identifier in `tokens` (an input expression reads them).
    pub(super) fn reserve_idents(&mut self, tokens: TokenStream) {
        for t in tokens {
            match t {
                TokenTree::Ident(i) => {
                    self.used.insert(i.to_string());
                }
                TokenTree::Group(g) => self.reserve_idents(g.stream()),
                _ => {}
            }
        }
    }

    fn free(&self, name: &str) -> bool {
        !self.used.contains(name) && !RESERVED.contains(&name)
    }

    /// `stem`, or `stem_2`, `stem_3`, … if taken.
    pub(super) fn unique(&mut self, stem: &str) -> Ident {
        let mut name = stem.to_owned();
        let mut k = 2;
        while !self.free(&name) {
            name = format!("{stem}_{k}");
            k += 1;
        }
        self.used.insert(name.clone());
        Ident::new(&name, Span::call_site())
    }

    /// The next free `tN`, from `t1`.
    pub(super) fn temporary(&mut self) -> Ident {
        loop {
            self.next_temporary += 1;
            let name = format!("t{}", self.next_temporary);
            if self.free(&name) {
                self.used.insert(name.clone());
                return Ident::new(&name, Span::call_site());
            }
        }
    }
}

/// A snake_case identifier from a free-form name: ASCII letters and digits kept (lower-cased, an
/// underscore at each lower→upper step of camelCase), everything else becomes one underscore;
/// `n_` in front of a leading digit. `None` if nothing is left.
fn sanitize(hint: &str) -> Option<String> {
    let mut out = String::new();
    let mut prev_lower = false;
    for ch in hint.chars() {
        if ch.is_ascii_alphanumeric() {
            if ch.is_ascii_uppercase() && prev_lower {
                out.push('_');
            }
            out.push(ch.to_ascii_lowercase());
            prev_lower = ch.is_ascii_lowercase() || ch.is_ascii_digit();
        } else {
            if !out.ends_with('_') {
                out.push('_');
            }
            prev_lower = false;
        }
    }
    let out = out.trim_matches('_');
    if out.is_empty() {
        return None;
    }
    Some(if out.starts_with(|c: char| c.is_ascii_digit()) {
        format!("n_{out}")
    } else {
        out.to_owned()
    })
}
