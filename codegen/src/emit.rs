//! Straight-line Rust from an expression [`Graph`].
//!
//! [`straight_line`] turns the nodes some outputs need into one `let` per operation, in
//! dependency order, plus one expression per output; the caller wraps them in a function body
//! (the trait impls of DESIGN §4). [`format()`] pretty-prints a whole item list.
//!
//! The emitted code allocates nothing, has no `unsafe`, cannot panic, and compiles under
//! `#![no_std]` without `alloc`:
//! - [`ScalarKind::F64`]: `1.5_f64` literals; the sines and cosines of the inputs (joint angles)
//!   from one `::articulated::math::sincos_array([…])` at the top (two angles per SSE2
//!   instruction, no branches: 61 instructions per angle against 105 for one `libm::sincos`
//!   call each, the same values to 1 ulp; arm7's inverse dynamics 109 → 101 ns),
//!   `::articulated::libm::{sin, cos, sincos, sqrt}` otherwise;
//! - [`ScalarKind::F32`]: `1.5_f32` literals, `sinf`, `cosf`, `sincosf`, `sqrtf` (constants are
//!   rounded to `f32` and the graph folded again, so that a constant that becomes `0` or `±1`
//!   in `f32` disappears there too; arithmetic between constants was done in `f64` while
//!   tracing);
//! - [`ScalarKind::Generic`]: a type parameter `T: nalgebra::RealField + Copy` in scope; methods
//!   `x.sin()`, `x.cos()`, `x.sin_cos()`, `x.sqrt()` of `nalgebra::ComplexField` (callable
//!   through the bound) and constants `::articulated::nalgebra::convert::<f64, T>(1.5)`.
//!
//! It is also meant to be clean under `clippy -D warnings` in the user's crate: the graph never
//! contains `x·1`, `x+0`, `x−x` and the like (see [`crate::sym`]); every `let` is used; operands
//! are names, literals or inputs, so no parentheses are needed; literals are printed with the
//! shortest digits that round-trip (`{:?}`), a constant equal to one of `core::f64::consts` is
//! written by its name, and a literal that clippy's `approx_constant` would mistake for one (say
//! `3.14`) is written as an exact quotient (`314.0_f64 / 100.0_f64`), which is the same number.
//!
//! Names: `s_q3`/`c_q3` for the sine/cosine of input `q3` (`s_x`/`c_x` for a node named `x`),
//! the names given with [`Sym::named`](crate::sym::Sym::named) (sanitized, made unique), and
//! otherwise `t0, t1, …`. No name collides with an identifier of the input expressions, a
//! keyword, `T`, or another name.

use std::collections::{HashMap, HashSet};
use std::fmt;
use std::str::FromStr;

use crate::options::ScalarKind;
use proc_macro2::{Ident, Literal, Span, TokenStream, TokenTree};
use quote::{format_ident, quote, ToTokens};

use crate::sym::{Graph, Node, OpCounts, Sym, Var};

/// Straight-line code for some outputs of a graph (see [`straight_line`]).
#[derive(Clone, Debug)]
pub struct Emitted {
    /// One `let` per live operation (constants and inputs are used in place), in dependency
    /// order; a sine and a cosine of the same argument share one `let (s, c) = …;`.
    pub statements: TokenStream,
    /// One expression per output, in order: a name bound in `statements`, a literal (a constant
    /// call for `Generic`) or an input expression.
    pub outputs: Vec<TokenStream>,
    /// The operations `statements` perform.
    pub ops: OpCounts,
}

/// Why [`straight_line`] could not emit a graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EmitError {
    /// A constant is not finite in the requested scalar (the graph never folds to one, so it came
    /// from `Scalar::from_f64`, or an `f64` constant overflows `f32`).
    NonFiniteConstant {
        /// The constant in the graph.
        value: f64,
        /// The scalar it was to be printed in.
        scalar: ScalarKind,
    },
}

impl fmt::Display for EmitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EmitError::NonFiniteConstant { value, scalar } => write!(
                f,
                "the constant {value:?} is not a finite {} and cannot be emitted",
                match scalar {
                    ScalarKind::F64 => "f64",
                    ScalarKind::F32 => "f32",
                    ScalarKind::Generic => "f64 (converted to T)",
                }
            ),
        }
    }
}

impl std::error::Error for EmitError {}

impl From<EmitError> for syn::Error {
    /// At the call site: the macro reports it with `to_compile_error`.
    fn from(e: EmitError) -> syn::Error {
        syn::Error::new(Span::call_site(), e)
    }
}

/// Emits straight-line code computing `outputs` of `graph` in `scalar`; `input` gives the
/// expression that reads an input, such as `q[3]` (it must be a path, field access, index or
/// call, so that it can be used as an operand and a method receiver without parentheses).
///
/// # Errors
/// [`EmitError::NonFiniteConstant`] if a live constant is NaN or infinite in `scalar`.
///
/// # Panics
/// If an output belongs to another graph.
pub fn straight_line(
    graph: &Graph,
    outputs: &[Sym],
    scalar: ScalarKind,
    input: &dyn Fn(Var) -> TokenStream,
) -> Result<Emitted, EmitError> {
    if scalar != ScalarKind::F32 {
        return emit(graph, outputs, scalar, input);
    }
    // Round the constants to f32 first, so that one that becomes 0 or ±1 folds away. Folding
    // two rounded constants can make a new one that rounds to 0 or ±1 in turn: repeat until
    // nothing changes (two passes in practice). A constant that overflows f32 is kept as it is,
    // for `constant` to report.
    let to_f32 = |x: f64| {
        let r = x as f32;
        if r.is_finite() {
            f64::from(r)
        } else {
            x
        }
    };
    let (mut g, mut outs) = graph.map_constants(outputs, to_f32);
    for _ in 0..4 {
        let (next, next_outs) = g.map_constants(&outs, to_f32);
        let settled = next.len() == g.len();
        (g, outs) = (next, next_outs);
        if settled {
            break;
        }
    }
    emit(&g, &outs, scalar, input)
}

/// [`straight_line`] with the constants as they are.
fn emit(
    graph: &Graph,
    outputs: &[Sym],
    scalar: ScalarKind,
    input: &dyn Fn(Var) -> TokenStream,
) -> Result<Emitted, EmitError> {
    let live = graph.live(outputs);

    let mut inputs = HashMap::new();
    let mut names = Names::default();
    // The fused multiply–add is called by its short name (see `fused` below).
    names.reserve_idents(quote!(mul_add mul_addf));
    for &s in &live {
        if let Node::Input(var) = graph.node(s) {
            let tokens = input(var);
            names.reserve_idents(tokens.clone());
            inputs.insert(s, tokens);
        }
    }

    // Sines and cosines by argument, to compute both with one call when both are live.
    let mut sin_of = HashMap::new();
    let mut cos_of = HashMap::new();
    for &s in &live {
        match graph.node(s) {
            Node::Sin(a) => {
                sin_of.insert(a, s);
            }
            Node::Cos(a) => {
                cos_of.insert(a, s);
            }
            _ => {}
        }
    }

    // Names, in dependency order.
    let mut name: HashMap<Sym, Ident> = HashMap::new();
    let mut from_hint: HashSet<Sym> = HashSet::new();
    for &s in &live {
        let node = graph.node(s);
        if matches!(node, Node::Const(_) | Node::Input(_)) {
            continue;
        }
        let stem = if let Some(hint) = graph.hint_of(s).and_then(sanitize) {
            from_hint.insert(s);
            Some(hint)
        } else {
            match node {
                Node::Sin(a) | Node::Cos(a) => {
                    let prefix = if matches!(node, Node::Sin(_)) {
                        "s"
                    } else {
                        "c"
                    };
                    match graph.node(a) {
                        Node::Input(var) => Some(format!("{prefix}_{var}")),
                        _ if from_hint.contains(&a) => Some(format!("{prefix}_{}", name[&a])),
                        _ => None,
                    }
                }
                _ => None,
            }
        };
        let ident = match stem {
            Some(stem) => names.unique(&stem),
            None => names.temporary(),
        };
        name.insert(s, ident);
    }

    // Products fused into the one sum that uses them, as `math::mul_add(x, y, c)` (f64 and f32:
    // one FMA instruction where the target has it, `x * y + c` otherwise). When both operands
    // of a sum qualify, the deeper product is fused: the other one is ready earlier and waits
    // as the addend.
    let mut fused: HashMap<Sym, Sym> = HashMap::new();
    let mut in_fma: HashSet<Sym> = HashSet::new();
    if scalar != ScalarKind::Generic {
        let uses = graph.use_counts(outputs);
        let mut depth: HashMap<Sym, usize> = HashMap::new();
        for &s in &live {
            let d = graph.node(s).operands().map(|a| depth[&a] + 1).max();
            depth.insert(s, d.unwrap_or(0));
        }
        for &s in &live {
            if let Node::Add(a, b) | Node::Sub(a, b) = graph.node(s) {
                let product = |x: Sym| matches!(graph.node(x), Node::Mul(..)) && uses[&x] == 1;
                let pick = match (product(a), product(b)) {
                    (true, true) if depth[&b] > depth[&a] => Some(b),
                    (true, _) => Some(a),
                    (false, true) => Some(b),
                    (false, false) => None,
                };
                if let Some(p) = pick {
                    fused.insert(s, p);
                    in_fma.insert(p);
                }
            }
        }
    }
    let (fma_fn, fma_path) = match scalar {
        ScalarKind::F32 => (quote!(mul_addf), quote!(::articulated::math::mul_addf)),
        _ => (quote!(mul_add), quote!(::articulated::math::mul_add)),
    };

    let fns = Math::new(scalar);
    // An operand as a function argument or an output: a name, an input, or a constant.
    let operand = |s: Sym| -> Result<TokenStream, EmitError> {
        match graph.node(s) {
            Node::Const(x) => Ok(constant(x, scalar)?.0),
            Node::Input(_) => Ok(inputs[&s].clone()),
            _ => {
                let n = &name[&s];
                Ok(quote!(#n))
            }
        }
    };
    // An operand of `+ − · /`: the same, with the rare constant that is itself a quotient (see
    // `constant`) in parentheses.
    let term = |s: Sym| -> Result<TokenStream, EmitError> {
        match graph.node(s) {
            Node::Const(x) => match constant(x, scalar)? {
                (c, true) => Ok(quote!((#c))),
                (c, false) => Ok(c),
            },
            _ => operand(s),
        }
    };

    // Each statement: its pattern, its value, and its level in the DAG (1 + the highest level of
    // the statements it reads; inputs and constants are level 0).
    let mut stmts: Vec<(TokenStream, TokenStream, usize)> = Vec::new();
    let mut level: HashMap<Sym, usize> = HashMap::new();
    let level_of = |level: &HashMap<Sym, usize>, args: &[Sym]| -> usize {
        1 + args
            .iter()
            .map(|a| level.get(a).copied().unwrap_or(0))
            .max()
            .unwrap_or(0)
    };
    let mut done = HashSet::new();
    // In f64, the sines and cosines of inputs (the joint angles) in one call at the top:
    // `math::sincos_array` computes them two by two in SSE2 lanes without branches, in fewer
    // instructions than one `libm::sincos` call each (see `articulated::math`).
    if scalar == ScalarKind::F64 {
        let mut angles: Vec<Sym> = Vec::new();
        for &s in &live {
            if let Node::Sin(a) | Node::Cos(a) = graph.node(s) {
                if matches!(graph.node(a), Node::Input(_)) && !angles.contains(&a) {
                    angles.push(a);
                }
            }
        }
        if angles.len() >= 2 {
            let pattern = |of: &HashMap<Sym, Sym>, done: &mut HashSet<Sym>| {
                let names = angles.iter().map(|a| match of.get(a) {
                    Some(s) => {
                        done.insert(*s);
                        let n = &name[s];
                        quote!(#n)
                    }
                    None => quote!(_),
                });
                quote!([#(#names),*])
            };
            let sines = pattern(&sin_of, &mut done);
            let cosines = pattern(&cos_of, &mut done);
            let args = angles
                .iter()
                .map(|&a| operand(a))
                .collect::<Result<Vec<_>, _>>()?;
            for s in &done {
                level.insert(*s, 1);
            }
            stmts.push((
                quote!((#sines, #cosines)),
                quote!(::articulated::math::sincos_array([#(#args),*])),
                1,
            ));
        }
    }
    // `−x` as an argument: a constant negated, anything else with a minus sign.
    let negated = |s: Sym| -> Result<TokenStream, EmitError> {
        match graph.node(s) {
            Node::Const(x) => Ok(constant(-x, scalar)?.0),
            _ => {
                let t = operand(s)?;
                Ok(quote!(-#t))
            }
        }
    };
    for &s in &live {
        let node = graph.node(s);
        if matches!(node, Node::Const(_) | Node::Input(_))
            || done.contains(&s)
            || in_fma.contains(&s)
        {
            continue;
        }
        let n = &name[&s];
        let (value, args) = match node {
            Node::Const(_) | Node::Input(_) => continue,
            Node::Add(a, b) | Node::Sub(a, b) if fused.contains_key(&s) => {
                let p = fused[&s];
                let Node::Mul(x, y) = graph.node(p) else {
                    unreachable!("only products are fused")
                };
                // The constant factor first, as in a product.
                let (x, y) = if matches!(graph.node(y), Node::Const(_)) {
                    (y, x)
                } else {
                    (x, y)
                };
                let c = if p == a { b } else { a };
                let subtract = matches!(node, Node::Sub(..));
                let (tx, ty, tc) = if subtract && p == b {
                    // c − x·y = (−x)·y + c
                    (negated(x)?, operand(y)?, operand(c)?)
                } else if subtract {
                    // x·y − c
                    (operand(x)?, operand(y)?, negated(c)?)
                } else {
                    (operand(x)?, operand(y)?, operand(c)?)
                };
                (quote!(#fma_fn(#tx, #ty, #tc)), vec![x, y, c])
            }
            Node::Add(a, b) => {
                let (ta, tb) = (term(a)?, term(b)?);
                (quote!(#ta + #tb), vec![a, b])
            }
            Node::Sub(a, b) => {
                let (ta, tb) = (term(a)?, term(b)?);
                (quote!(#ta - #tb), vec![a, b])
            }
            Node::Mul(a, b) => {
                // A constant factor first: `2.0_f64 * x` reads as the math does.
                let (a, b) = if matches!(graph.node(b), Node::Const(_)) {
                    (b, a)
                } else {
                    (a, b)
                };
                let (ta, tb) = (term(a)?, term(b)?);
                (quote!(#ta * #tb), vec![a, b])
            }
            Node::Div(a, b) => {
                let (ta, tb) = (term(a)?, term(b)?);
                (quote!(#ta / #tb), vec![a, b])
            }
            Node::Neg(a) => {
                let ta = operand(a)?;
                (quote!(-#ta), vec![a])
            }
            Node::Sin(a) | Node::Cos(a) => {
                if let (Some(&sin), Some(&cos)) = (sin_of.get(&a), cos_of.get(&a)) {
                    done.insert(sin);
                    done.insert(cos);
                    let (ns, nc) = (&name[&sin], &name[&cos]);
                    let call = fns.call(MathFn::SinCos, operand(a)?);
                    let l = level_of(&level, &[a]);
                    level.insert(sin, l);
                    level.insert(cos, l);
                    stmts.push((quote!((#ns, #nc)), call, l));
                    continue;
                }
                let f = if matches!(node, Node::Sin(_)) {
                    MathFn::Sin
                } else {
                    MathFn::Cos
                };
                (fns.call(f, operand(a)?), vec![a])
            }
            Node::Sqrt(a) => (fns.call(MathFn::Sqrt, operand(a)?), vec![a]),
        };
        let l = level_of(&level, &args);
        level.insert(s, l);
        stmts.push((quote!(#n), value, l));
    }
    let mut statements = bind(stmts);
    if !fused.is_empty() {
        statements = quote!(use #fma_path; #statements);
    }

    Ok(Emitted {
        statements,
        outputs: outputs
            .iter()
            .map(|&s| operand(s))
            .collect::<Result<_, _>>()?,
        ops: graph.op_counts(outputs),
    })
}

/// Up to this many statements a function binds one value per `let`, which reads best. rustc
/// (1.95, with debug info) overflows its stack on a function with about 2,500 `let`s or more,
/// because each `let` opens a lexical scope nested in the previous one (LLVM's
/// `DwarfCompileUnit::createAndAddScopeChildren` recurses through them). Past this many, the
/// values of each level of the graph are bound together in one tuple `let`, so the nesting is
/// the graph's depth instead of its size.
const MAX_LETS: usize = 1000;

/// The statements as `let`s: one each, or (past [`MAX_LETS`]) one per level of the graph.
fn bind(stmts: Vec<(TokenStream, TokenStream, usize)>) -> TokenStream {
    if stmts.len() <= MAX_LETS {
        return stmts
            .into_iter()
            .map(|(pattern, value, _)| quote!(let #pattern = #value;))
            .collect();
    }
    let depth = stmts.iter().map(|s| s.2).max().unwrap_or(0);
    let mut by_level: Vec<Vec<(TokenStream, TokenStream)>> = vec![Vec::new(); depth + 1];
    for (pattern, value, l) in stmts {
        by_level[l].push((pattern, value));
    }
    by_level
        .into_iter()
        .filter(|level| !level.is_empty())
        .map(|level| {
            if level.len() == 1 {
                let (pattern, value) = &level[0];
                quote!(let #pattern = #value;)
            } else {
                let (patterns, values): (Vec<_>, Vec<_>) = level.into_iter().unzip();
                quote!(let (#(#patterns),*) = (#(#values),*);)
            }
        })
        .collect()
}

/// Pretty-prints a list of items (a whole file's worth) with `prettyplease`.
///
/// # Errors
/// If `tokens` do not parse as a list of items.
pub fn format(tokens: TokenStream) -> Result<String, syn::Error> {
    let file: syn::File = syn::parse2(tokens)?;
    Ok(prettyplease::unparse(&file))
}

/// The names in use, and the counter for `t0, t1, …`.
#[derive(Default)]
struct Names {
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
    fn reserve_idents(&mut self, tokens: TokenStream) {
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
    fn unique(&mut self, stem: &str) -> Ident {
        let mut name = stem.to_owned();
        let mut k = 2;
        while !self.free(&name) {
            name = format!("{stem}_{k}");
            k += 1;
        }
        self.used.insert(name.clone());
        Ident::new(&name, Span::call_site())
    }

    /// The next free `tN`.
    fn temporary(&mut self) -> Ident {
        loop {
            let name = format!("t{}", self.next_temporary);
            self.next_temporary += 1;
            if self.free(&name) {
                self.used.insert(name.clone());
                return format_ident!("{}", name);
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

/// The math functions the emitted code calls.
#[derive(Clone, Copy)]
enum MathFn {
    Sin,
    Cos,
    SinCos,
    Sqrt,
}

struct Math {
    scalar: ScalarKind,
}

impl Math {
    fn new(scalar: ScalarKind) -> Math {
        Math { scalar }
    }

    fn call(&self, f: MathFn, x: TokenStream) -> TokenStream {
        let (free, method) = match f {
            MathFn::Sin => ("sin", "sin"),
            MathFn::Cos => ("cos", "cos"),
            MathFn::SinCos => ("sincos", "sin_cos"),
            MathFn::Sqrt => ("sqrt", "sqrt"),
        };
        match self.scalar {
            ScalarKind::F64 => {
                let f = format_ident!("{}", free);
                quote!(::articulated::libm::#f(#x))
            }
            ScalarKind::F32 => {
                let f = format_ident!("{}f", free);
                quote!(::articulated::libm::#f(#x))
            }
            ScalarKind::Generic => {
                let m = format_ident!("{}", method);
                quote!(#x.#m())
            }
        }
    }
}

/// `core::f64::consts` (and `f32`) written by name when a constant equals one exactly, and
/// clippy's `approx_constant` table: (value, name, fewest significant characters it checks).
const KNOWN: &[(f64, f32, &str, usize)] = {
    use std::f32::consts as s;
    use std::f64::consts as d;
    &[
        (d::E, s::E, "E", 4),
        (d::FRAC_1_PI, s::FRAC_1_PI, "FRAC_1_PI", 4),
        (d::FRAC_1_SQRT_2, s::FRAC_1_SQRT_2, "FRAC_1_SQRT_2", 5),
        (d::FRAC_2_PI, s::FRAC_2_PI, "FRAC_2_PI", 5),
        (d::FRAC_2_SQRT_PI, s::FRAC_2_SQRT_PI, "FRAC_2_SQRT_PI", 5),
        (d::FRAC_PI_2, s::FRAC_PI_2, "FRAC_PI_2", 5),
        (d::FRAC_PI_3, s::FRAC_PI_3, "FRAC_PI_3", 5),
        (d::FRAC_PI_4, s::FRAC_PI_4, "FRAC_PI_4", 5),
        (d::FRAC_PI_6, s::FRAC_PI_6, "FRAC_PI_6", 5),
        (d::FRAC_PI_8, s::FRAC_PI_8, "FRAC_PI_8", 5),
        (d::LN_2, s::LN_2, "LN_2", 5),
        (d::LN_10, s::LN_10, "LN_10", 5),
        (d::LOG2_10, s::LOG2_10, "LOG2_10", 5),
        (d::LOG2_E, s::LOG2_E, "LOG2_E", 5),
        (d::LOG10_2, s::LOG10_2, "LOG10_2", 5),
        (d::LOG10_E, s::LOG10_E, "LOG10_E", 5),
        (d::PI, s::PI, "PI", 3),
        (d::SQRT_2, s::SQRT_2, "SQRT_2", 5),
        (d::TAU, s::TAU, "TAU", 3),
    ]
};

/// Whether clippy's `approx_constant` would flag a float literal written `text` (its
/// `is_approx_const`, as of clippy 1.95 and as before, applied to the table above).
fn looks_like_known_constant(text: &str) -> bool {
    let Ok(value) = text.parse::<f64>() else {
        return false;
    };
    let shortest = value.to_string();
    let after_dot = text.split_once('.').map_or(0, |(_, frac)| frac.len());
    KNOWN.iter().any(|&(known, _, _, min_digits)| {
        let known_text = known.to_string();
        text.len() > min_digits
            && (known_text.starts_with(text)
                || (shortest.len() > min_digits && known_text.starts_with(&shortest))
                || format!("{known:.*}", text.len() - 2) == text
                || format!("{known:0width$.after_dot$}", width = text.len()) == text)
    })
}

/// A positive constant in `scalar` that is not exactly one of [`KNOWN`], and whether it is a
/// quotient (which needs parentheses as an operand of `+ − · /`).
///
/// Normally the shortest literal that reads back as the same number (`{:?}`). If clippy's
/// `approx_constant` would take that literal for a known constant (a model with a length of
/// `3.14` m), the same number is written as a quotient of two exactly representable integers,
/// `314.0_f64 / 100.0_f64`, which IEEE division rounds to exactly the number `3.14` reads as; if
/// the integers are not exact, as `f64::from_bits(…)`.
fn positive_constant(a: f64, scalar: ScalarKind) -> (TokenStream, bool) {
    let (text, suffix) = match scalar {
        ScalarKind::F32 => (format!("{:?}", a as f32), "_f32"),
        ScalarKind::F64 => (format!("{a:?}"), "_f64"),
        ScalarKind::Generic => (format!("{a:?}"), ""),
    };
    if !looks_like_known_constant(&text) {
        return (
            literal(&format!("{text}{suffix}")).into_token_stream(),
            false,
        );
    }
    if let Some((int, frac)) = text.split_once('.').filter(|_| !text.contains('e')) {
        let numerator = format!("{int}{frac}").trim_start_matches('0').to_owned();
        let denominator = format!("1{}", "0".repeat(frac.len()));
        let exact = match (numerator.parse::<u64>(), denominator.parse::<u64>()) {
            (Ok(n), Ok(d)) => match scalar {
                ScalarKind::F32 => {
                    n < 1 << 24 && d < 1 << 24 && (n as f32) / (d as f32) == a as f32
                }
                _ => n < 1 << 53 && d < 1 << 53 && (n as f64) / (d as f64) == a,
            },
            _ => false,
        };
        let (n, d) = (
            format!("{numerator}.0{suffix}"),
            format!("{denominator}.0{suffix}"),
        );
        if exact && !looks_like_known_constant(&n) && !looks_like_known_constant(&d) {
            let (n, d) = (literal(&n), literal(&d));
            return (quote!(#n / #d), true);
        }
    }
    let tokens = match scalar {
        ScalarKind::F32 => {
            let bits = Literal::u32_unsuffixed((a as f32).to_bits());
            quote!(::core::primitive::f32::from_bits(#bits))
        }
        _ => {
            let bits = Literal::u64_unsuffixed(a.to_bits());
            quote!(::core::primitive::f64::from_bits(#bits))
        }
    };
    (tokens, false)
}

/// A constant as an operand in `scalar`, and whether it is a quotient (see
/// [`positive_constant`]).
fn constant(x: f64, scalar: ScalarKind) -> Result<(TokenStream, bool), EmitError> {
    let error = EmitError::NonFiniteConstant { value: x, scalar };
    let in_scalar_finite = match scalar {
        ScalarKind::F32 => (x as f32).is_finite(),
        _ => x.is_finite(),
    };
    if !in_scalar_finite {
        return Err(error);
    }
    let minus = if x < 0.0 { quote!(-) } else { quote!() };
    let a = x.abs();
    let known = KNOWN.iter().find(|k| match scalar {
        ScalarKind::F32 => a as f32 == k.1,
        _ => a == k.0,
    });
    let module = match scalar {
        ScalarKind::F32 => quote!(f32),
        _ => quote!(f64),
    };
    let (value, compound) = match known {
        Some(k) => {
            let name = format_ident!("{}", k.2);
            (quote!(#minus ::core::#module::consts::#name), false)
        }
        None => {
            let (c, compound) = positive_constant(a, scalar);
            (quote!(#minus #c), compound)
        }
    };
    Ok(match scalar {
        ScalarKind::Generic => (
            quote!(::articulated::nalgebra::convert::<f64, T>(#value)),
            false,
        ),
        _ => (value, compound),
    })
}

/// A float literal token from its text.
fn literal(text: &str) -> Literal {
    match Literal::from_str(text) {
        Ok(lit) => lit,
        // `digits` only produces `{:?}` output of a finite float or its exponent form, plus a
        // suffix: always a valid literal.
        Err(_) => unreachable!("not a float literal: {text}"),
    }
}
