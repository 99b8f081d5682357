//! Straight-line Rust from an expression [`Graph`].
//!
//! [`straight_line`] turns the nodes some outputs need into one `let` per operation, in
//! dependency order, plus one expression per output; the caller wraps them in a function body.
//! [`format()`] pretty-prints a whole item list. The steps, one file each:
//! - `names`: each local named after what it holds (the recursions' labels, `s_q3`/`c_q3`,
//!   the terms of a labelled value after it);
//! - `fusion`: products fused into their sum as `mul_add` (f64 and f32);
//! - `sines`: the math calls per scalar, and the joint angles' sines and cosines in one call;
//! - `literals`: constants as a person writes them and clippy accepts them.
//!
//! The emitted code allocates nothing, has no `unsafe`, cannot panic, and compiles under
//! `#![no_std]` without `alloc`, in each [`ScalarKind`]: `f64` and `f32` (literals suffixed
//! `_f64`/`_f32`; in `f32` the constants are rounded to `f32` and the graph folded again first,
//! so that a constant that becomes `0` or `±1` there disappears too), or generic (a type
//! parameter `T: nalgebra::RealField + Copy` in scope; constants
//! `::articulated::nalgebra::convert::<f64, T>(1.5)`).
//!
//! It is also meant to be clean under `clippy -D warnings` in the user's crate: the graph never
//! contains `x·1`, `x+0`, `x−x` and the like (see [`crate::sym`]); every `let` is used; operands
//! are names, literals or inputs, so no parentheses are needed.

mod blocks;
mod fusion;
mod literals;
mod names;
mod sines;

use std::collections::{HashMap, HashSet};
use std::fmt;

use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

use crate::options::ScalarKind;
use crate::sym::{Graph, Node, OpCounts, Sym, Var};
use names::Names;
use sines::{MathFn, Trig};

/// Straight-line code for some outputs of a graph (see [`straight_line`]).
#[derive(Clone, Debug)]
pub struct Emitted {
    /// The `use` of the fused multiply-add the statements call (`use …::mul_add;`), if any: the
    /// function states it first, before its statements.
    pub uses: TokenStream,
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
    straight_line_into(graph, outputs, scalar, input, None, None)
}

/// Where outputs of [`straight_line_into`] are stored as soon as they are computed:
/// `places[i]` are the places (such as `m[3][5]`, an array the caller declared) that take
/// output `i`; an output without places (or past the end of `places`) is not sunk. An output that is the constant `0` is not stored (the caller's array starts at
/// zero); the others are stored right after the statement that computes them, constants and
/// inputs first.
///
/// Why: a result built at the end, `ArrayStorage([[a, b, …], …])`, keeps every entry live from
/// where it is computed to the end of the function. On the humanoid's mass matrix (hundreds of
/// entries that are not zero) LLVM kept them on the stack, and stores and loads of spilled
/// values were a large share of its instructions. Stored where they are computed, each entry
/// is dead at once.
#[derive(Clone, Debug, Default)]
pub struct Sink {
    /// The places each output goes to, in the order of the outputs.
    pub places: Vec<Vec<TokenStream>>,
    /// Cut the statements into basic blocks with calls to `articulated::math::block_boundary`
    /// (about every 200 statements, every 80 in functions of fewer than 1,000, none below 300;
    /// `with_boundaries` in the source has the measurements); `false` leaves them one block.
    pub boundaries: bool,
}

/// [`straight_line`], with the outputs that `sink` names stored where they are computed (see
/// [`Sink`]); those are left out of the blocks' exports, so the caller must not read their
/// names after the statements ([`Emitted::outputs`] still lists them).
///
/// # Errors
/// As [`straight_line`].
///
/// # Panics
/// If an output belongs to another graph.
///
/// With `lanes` (a lane type, `articulated::lanes::F64x4`), the same statements for its values
/// (many states at once): the constants stay scalars (the lane type's operators take them on either side),
/// and the fused multiply–add and the sines, cosines and square roots are `articulated::lanes`'
/// functions of the same names.
pub fn straight_line_into(
    graph: &Graph,
    outputs: &[Sym],
    scalar: ScalarKind,
    input: &dyn Fn(Var) -> TokenStream,
    sink: Option<&Sink>,
    lanes: Option<&TokenStream>,
) -> Result<Emitted, EmitError> {
    if scalar == ScalarKind::F32 {
        let (g, outs) = crate::optimize::round_constants_to_f32(graph, outputs);
        let mut w = Writer::new(&g, &outs, scalar, input, sink);
        w.lanes = lanes.cloned();
        if w.lanes.is_some() {
            // In `f32` lanes each angle's sines by a call of its own: the lanes are already
            // eight states wide, and one `sincos_array` of all the angles measured slower there
            // (arm7's batch functions, x86-64-v3: the figures are in the commit that set this).
            w.batched.clear();
        }
        return w.emit(&outs, sink);
    }
    let mut w = Writer::new(graph, outputs, scalar, input, sink);
    w.lanes = lanes.cloned();
    w.emit(outputs, sink)
}

/// The constant `0` in `scalar`, as the emitted code writes it (what a [`Sink`]'s array starts
/// from).
pub fn zero(scalar: ScalarKind) -> TokenStream {
    match literals::constant(0.0, scalar) {
        Ok((zero, _)) => zero,
        Err(_) => unreachable!("0 is finite in every scalar"),
    }
}

/// Up to this many statements a function binds one value per `let`, which reads best. rustc
/// (1.95, with debug info) overflows its stack on a function with about 2,500 `let`s or more,
/// because each `let` opens a lexical scope nested in the previous one (LLVM's
/// `DwarfCompileUnit::createAndAddScopeChildren` recurses through them). Past this many, the
/// statements are cut, in their order, into blocks of about `√n` (at least half this many), each
/// block the value of one array `let` that binds what later blocks and the result read:
/// `let [a, b, …] = { let t = …; …; [a, b, …] };`. The nesting is then about `2·√n` deep
/// (a few hundred for the largest functions generated), and the statements keep the order of the
/// recursion they were traced from: the values a body's computation needs are computed next to
/// it, which keeps few of them live at once. (Binding the values level by level of the graph
/// instead, as this did before, keeps them far fewer `let`s deep but computes every body's
/// first step before any body's second, and measured slower: arm7's forward dynamics
/// derivatives, x86-64-v3.)
///
/// An array, not a tuple: rustc's MIR pass `ScalarReplacementOfAggregates` splits every tuple
/// into one local per field and inserts their statements one at a time into the function's one
/// huge basic block, which costs time quadratic in the function's size (rustc 1.95: most of a
/// release build of the 50-body chain, `models/chain50.chain`, on the default target). It
/// leaves arrays alone; LLVM's own SROA splits them as cheaply.
const MAX_LETS: usize = 1000;

/// One statement: its pattern, its value, the values it binds and the values of other
/// statements it reads, and how it is written.
struct Statement {
    pattern: TokenStream,
    value: TokenStream,
    binds: Vec<Sym>,
    reads: Vec<Sym>,
    kind: Kind,
}

/// How a [`Statement`] is written.
enum Kind {
    /// `let pattern = value;`
    Let,
    /// `pattern = value;`: the value assigned to a place (see [`Sink`]).
    Store,
    /// `value;` with no pattern: a call to [`boundary`].
    Boundary,
}

/// Everything the statements are written from.
struct Writer<'g> {
    graph: &'g Graph,
    scalar: ScalarKind,
    live: Vec<Sym>,
    inputs: HashMap<Sym, TokenStream>,
    trig: Trig,
    /// The product fused into each sum.
    fused: HashMap<Sym, Sym>,
    /// The inputs whose sines and cosines one `sincos_array` call computes.
    batched: Vec<Sym>,
    /// The local each statement binds.
    name: HashMap<Sym, Ident>,
    /// The lane type the statements are for (`articulated::lanes::F64x4`; see
    /// [`straight_line_into`]), `None` for one state.
    lanes: Option<TokenStream>,
}

impl<'g> Writer<'g> {
    fn new(
        graph: &'g Graph,
        outputs: &[Sym],
        scalar: ScalarKind,
        input: &dyn Fn(Var) -> TokenStream,
        sink: Option<&Sink>,
    ) -> Self {
        let live = graph.live(outputs);
        let mut names = Names::default();
        // The fused multiply–add is called by its short name.
        names.reserve_idents(quote!(mul_add mul_addf));
        for place in sink.iter().flat_map(|k| &k.places).flatten() {
            names.reserve_idents(place.clone());
        }
        let mut inputs = HashMap::new();
        for &s in &live {
            if let Node::Input(var) = graph.node(s) {
                let tokens = input(var);
                names.reserve_idents(tokens.clone());
                inputs.insert(s, tokens);
            }
        }
        let trig = Trig::of(graph, &live);
        let fused = match scalar {
            ScalarKind::Generic => HashMap::new(),
            _ => fusion::fused_products(graph, &live, outputs),
        };
        let batched = match scalar {
            ScalarKind::F64 | ScalarKind::F32 => {
                Some(trig.batched_angles(graph, &live)).filter(|a| a.len() >= 2)
            }
            ScalarKind::Generic => None,
        }
        .unwrap_or_default();
        let mut w = Writer {
            graph,
            scalar,
            live,
            inputs,
            trig,
            fused,
            batched,
            name: HashMap::new(),
            lanes: None,
        };
        let statements = w.statement_nodes(outputs);
        w.name = names::assign(graph, &statements, &|s| w.reads(s), &mut names);
        w
    }

    /// The nodes bound by a `let`, in the order they are emitted: the batched angles that are
    /// not inputs (an input plus its turn), the batched sines and cosines, then every other
    /// operation except the products fused into a sum.
    fn statement_nodes(&self, outputs: &[Sym]) -> Vec<Sym> {
        let in_fma: HashSet<Sym> = self.fused.values().copied().collect();
        let angles = self.batched_sums();
        let batch = self.batch_nodes();
        let first: HashSet<Sym> = angles.iter().chain(&batch).copied().collect();
        let rest = self.live.iter().copied().filter(|&s| {
            !matches!(self.graph.node(s), Node::Const(_) | Node::Input(_))
                && !in_fma.contains(&s)
                && !first.contains(&s)
        });
        let order: Vec<Sym> = angles.into_iter().chain(batch).chain(rest).collect();
        self.hoisted(order, outputs)
    }

    /// `order` with each sum or product moved up to just after the last statement it reads,
    /// where it is the last reader of one of its operands: then it frees at least as many
    /// values as it makes, and moving it up shortens live ranges.
    ///
    /// The order of tracing keeps a recursion's values together, but a value built from early
    /// terms is emitted where its graph node was made, which can be far later: the sum of the
    /// humanoid's pelvis composite inertia is regrouped ([`crate::optimize::reassociate()`]) so
    /// that the legs' terms are added first, yet every one of those partial sums was made when
    /// the pelvis was reached, the last body; the legs' thirty terms stayed live through the
    /// arms and the waist and were spilled to the stack.
    fn hoisted(&self, order: Vec<Sym>, outputs: &[Sym]) -> Vec<Sym> {
        let in_order: HashSet<Sym> = order.iter().copied().collect();
        let mut readers: HashMap<Sym, Vec<Sym>> = HashMap::new();
        let mut uses: HashMap<Sym, usize> = HashMap::new();
        for &s in &order {
            for o in self.reads(s) {
                readers.entry(o).or_default().push(s);
                *uses.entry(o).or_insert(0) += 1;
            }
        }
        for &o in outputs {
            *uses.entry(o).or_insert(0) += 1;
        }
        let movable = |s: Sym| {
            matches!(
                self.graph.node(s),
                Node::Add(..) | Node::Sub(..) | Node::Mul(..) | Node::Neg(_)
            ) && self.reads(s).iter().any(|o| uses.get(o) == Some(&1))
        };
        let mut placed: HashSet<Sym> = HashSet::with_capacity(order.len());
        let ready = |s: Sym, placed: &HashSet<Sym>| {
            self.reads(s)
                .iter()
                .all(|o| !in_order.contains(o) || placed.contains(o))
        };
        let mut out = Vec::with_capacity(order.len());
        let mut stack = Vec::new();
        for &first in &order {
            if placed.contains(&first) {
                continue;
            }
            stack.push(first);
            while let Some(s) = stack.pop() {
                if placed.contains(&s) {
                    continue;
                }
                placed.insert(s);
                out.push(s);
                // Readers of `s` that can go now, in their own order (pushed last first).
                let bound = self.bound_by(s);
                let next: Vec<Sym> = bound
                    .iter()
                    .flat_map(|b| readers.get(b).into_iter().flatten())
                    .copied()
                    .filter(|&r| !placed.contains(&r) && movable(r) && ready(r, &placed))
                    .collect();
                stack.extend(next.into_iter().rev());
            }
        }
        out
    }

    /// The batched angles that are sums (an input and a constant), computed before the batch.
    fn batched_sums(&self) -> Vec<Sym> {
        let sums = self.batched.iter().copied();
        sums.filter(|&a| !matches!(self.graph.node(a), Node::Input(_)))
            .collect()
    }

    /// The sines, then the cosines, that the `sincos_array` call computes.
    fn batch_nodes(&self) -> Vec<Sym> {
        let sines = self.batched.iter().filter_map(|a| self.trig.sin_of.get(a));
        let cosines = self.batched.iter().filter_map(|a| self.trig.cos_of.get(a));
        sines.chain(cosines).copied().collect()
    }

    /// The nodes statement `s` reads, through the product fused into it.
    fn reads(&self, s: Sym) -> Vec<Sym> {
        let mut out = Vec::new();
        for o in self.graph.node(s).operands() {
            if self.fused.get(&s) == Some(&o) {
                out.extend(self.graph.node(o).operands());
            } else {
                out.push(o);
            }
        }
        out
    }

    /// The statements and output expressions.
    fn emit(&self, outputs: &[Sym], sink: Option<&Sink>) -> Result<Emitted, EmitError> {
        let mut stmts = Vec::new();
        let mut done: HashSet<Sym> = HashSet::new();
        let batch: HashSet<Sym> = self.batch_nodes().into_iter().collect();
        // The places each sunk value goes to, and the outputs that are not sunk (read by the
        // caller after the statements).
        let no_places = |i: usize| sink.is_none_or(|k| k.places.get(i).is_none_or(Vec::is_empty));
        let kept: Vec<Sym> = (0..outputs.len())
            .filter(|&i| no_places(i))
            .map(|i| outputs[i])
            .collect();
        let mut places: HashMap<Sym, Vec<&TokenStream>> = HashMap::new();
        for (&o, ps) in outputs.iter().zip(sink.iter().flat_map(|k| &k.places)) {
            if !matches!(self.graph.node(o), Node::Const(x) if x == 0.0) {
                places.entry(o).or_default().extend(ps);
            }
        }
        let stores = |s: Sym, stmts: &mut Vec<Statement>| -> Result<(), EmitError> {
            for &place in places.get(&s).into_iter().flatten() {
                stmts.push(Statement {
                    pattern: place.clone(),
                    value: self.stored(s)?,
                    binds: Vec::new(),
                    reads: vec![s],
                    kind: Kind::Store,
                });
            }
            Ok(())
        };
        // Constants and inputs first: no statement computes them.
        let mut first = HashSet::new();
        for &o in outputs {
            if places.contains_key(&o)
                && matches!(self.graph.node(o), Node::Const(_) | Node::Input(_))
                && first.insert(o)
            {
                stores(o, &mut stmts)?;
            }
        }
        for s in self.statement_nodes(outputs) {
            if done.contains(&s) {
                continue;
            }
            if batch.contains(&s) {
                // The first of the batch: the one call that computes all of it.
                if let Some(call) = self.sincos_array()? {
                    done.extend(batch.iter().copied());
                    let binds = call.binds.clone();
                    stmts.push(call);
                    for b in binds {
                        stores(b, &mut stmts)?;
                    }
                }
                continue;
            }
            let (pattern, value, args) = self.statement(s, &mut done)?;
            let binds = self.bound_by(s);
            stmts.push(Statement {
                pattern,
                value,
                binds: binds.clone(),
                reads: args,
                kind: Kind::Let,
            });
            for b in binds {
                stores(b, &mut stmts)?;
            }
        }
        let stmts = match sink.is_some_and(|k| k.boundaries) {
            true => blocks::with_boundaries(stmts, &batch),
            false => stmts,
        };
        let statements = self.bind(stmts, &kept)?;
        let uses = match (self.fused.is_empty(), self.scalar) {
            (true, _) => TokenStream::new(),
            (false, ScalarKind::F32) if self.lanes.is_some() => quote!(
                use ::articulated::lanes::mul_add as mul_addf;
            ),
            (false, _) if self.lanes.is_some() => quote!(
                use ::articulated::lanes::mul_add;
            ),
            (false, ScalarKind::F32) => quote!(
                use ::articulated::math::mul_addf;
            ),
            (false, _) => quote!(
                use ::articulated::math::mul_add;
            ),
        };
        Ok(Emitted {
            uses,
            statements,
            outputs: outputs
                .iter()
                .map(|&s| self.stored(s))
                .collect::<Result<_, _>>()?,
            ops: self.graph.op_counts(outputs),
        })
    }

    /// The statements as `let`s: one each, or (past [`MAX_LETS`]) in blocks, each the value of
    /// an array `let` that binds what is read after it (see [`MAX_LETS`]).
    fn bind(&self, stmts: Vec<Statement>, outputs: &[Sym]) -> Result<TokenStream, EmitError> {
        let one_each = |stmts: &[Statement]| -> TokenStream {
            stmts
                .iter()
                .map(|st| {
                    let (pattern, value) = (&st.pattern, &st.value);
                    match st.kind {
                        Kind::Store => quote!(#pattern = #value;),
                        Kind::Let => quote!(let #pattern = #value;),
                        Kind::Boundary => quote!(#value;),
                    }
                })
                .collect()
        };
        let n = stmts.len();
        if n <= MAX_LETS {
            return Ok(one_each(&stmts));
        }
        let size = (MAX_LETS / 2).max((n as f64).sqrt().ceil() as usize);
        let chunks: Vec<&[Statement]> = stmts.chunks(size).collect();
        // The last block that reads each value (the result counts as one past the last).
        let mut last_read: HashMap<Sym, usize> = HashMap::new();
        for (c, chunk) in chunks.iter().enumerate() {
            for r in chunk.iter().flat_map(|st| &st.reads) {
                last_read.insert(*r, c);
            }
        }
        for &o in outputs {
            last_read.insert(o, chunks.len());
        }
        let mut out = TokenStream::new();
        for (c, chunk) in chunks.iter().enumerate() {
            let exported: Vec<TokenStream> = chunk
                .iter()
                .flat_map(|st| &st.binds)
                .filter(|b| last_read.get(b).is_some_and(|&l| l > c))
                .map(|&b| self.operand(b))
                .collect::<Result<_, _>>()?;
            let body = one_each(chunk);
            out.extend(if exported.is_empty() {
                // Only stores leave it (see [`Sink`]).
                quote!({ #body })
            } else {
                quote! {
                    let [#(#exported),*] = {
                        #body
                        [#(#exported),*]
                    };
                }
            });
        }
        Ok(out)
    }

    /// The nodes the statement of `s` binds: itself, or a sine and its cosine.
    fn bound_by(&self, s: Sym) -> Vec<Sym> {
        match self.graph.node(s) {
            Node::Sin(a) | Node::Cos(a) => {
                match (self.trig.sin_of.get(&a), self.trig.cos_of.get(&a)) {
                    (Some(&sin), Some(&cos)) => vec![sin, cos],
                    _ => vec![s],
                }
            }
            _ => vec![s],
        }
    }

    /// `let ([s_q1, …], [c_q1, …]) = ::articulated::math::sincos_array([q1, …]);`
    fn sincos_array(&self) -> Result<Option<Statement>, EmitError> {
        if self.batched.is_empty() {
            return Ok(None);
        }
        let pattern = |of: &HashMap<Sym, Sym>| {
            let names = self.batched.iter().map(|a| match of.get(a) {
                Some(s) => {
                    let n = &self.name[s];
                    quote!(#n)
                }
                None => quote!(_),
            });
            quote!([#(#names),*])
        };
        let (sines, cosines) = (pattern(&self.trig.sin_of), pattern(&self.trig.cos_of));
        let args = self
            .batched
            .iter()
            .map(|&a| self.operand(a))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Some(Statement {
            pattern: quote!((#sines, #cosines)),
            value: match (self.lanes.is_some(), self.scalar) {
                (true, _) => quote!(::articulated::lanes::sincos_array([#(#args),*])),
                (false, ScalarKind::F32) => {
                    quote!(::articulated::math::sincosf_array([#(#args),*]))
                }
                (false, _) => quote!(::articulated::math::sincos_array([#(#args),*])),
            },
            binds: self.batch_nodes(),
            reads: self.batched.clone(),
            kind: Kind::Let,
        }))
    }

    /// The pattern and value of the statement computing `s`, and the nodes it reads.
    fn statement(
        &self,
        s: Sym,
        done: &mut HashSet<Sym>,
    ) -> Result<(TokenStream, TokenStream, Vec<Sym>), EmitError> {
        let n = &self.name[&s];
        let node = self.graph.node(s);
        let (value, args) = match node {
            Node::Add(..) | Node::Sub(..) if self.fused.contains_key(&s) => self.fma(s)?,
            Node::Add(a, b) => {
                let (ta, tb) = (self.term(a)?, self.term(b)?);
                (quote!(#ta + #tb), vec![a, b])
            }
            Node::Sub(a, b) => {
                let (ta, tb) = (self.term(a)?, self.term(b)?);
                (quote!(#ta - #tb), vec![a, b])
            }
            Node::Mul(a, b) => {
                // A constant factor first: `2.0_f64 * x` reads as the math does.
                let (a, b) = self.constant_first(a, b);
                let (ta, tb) = (self.term(a)?, self.term(b)?);
                (quote!(#ta * #tb), vec![a, b])
            }
            Node::Div(a, b) => {
                let (ta, tb) = (self.term(a)?, self.term(b)?);
                (quote!(#ta / #tb), vec![a, b])
            }
            Node::Neg(a) => {
                let ta = self.operand(a)?;
                (quote!(-#ta), vec![a])
            }
            Node::Sin(a) | Node::Cos(a) => {
                let both = (self.trig.sin_of.get(&a), self.trig.cos_of.get(&a));
                if let (Some(&sin), Some(&cos)) = both {
                    done.extend([sin, cos]);
                    let (ns, nc) = (&self.name[&sin], &self.name[&cos]);
                    let call = sines::call(
                        self.scalar,
                        self.lanes.is_some(),
                        MathFn::SinCos,
                        self.operand(a)?,
                    );
                    return Ok((quote!((#ns, #nc)), call, vec![a]));
                }
                let f = match node {
                    Node::Sin(_) => MathFn::Sin,
                    _ => MathFn::Cos,
                };
                (
                    sines::call(self.scalar, self.lanes.is_some(), f, self.operand(a)?),
                    vec![a],
                )
            }
            Node::Sqrt(a) => (
                sines::call(
                    self.scalar,
                    self.lanes.is_some(),
                    MathFn::Sqrt,
                    self.operand(a)?,
                ),
                vec![a],
            ),
            Node::Const(_) | Node::Input(_) => unreachable!("never bound to a local"),
        };
        Ok((quote!(#n), value, args))
    }

    /// `mul_add(x, y, c)` for the sum `s` and the product fused into it.
    fn fma(&self, s: Sym) -> Result<(TokenStream, Vec<Sym>), EmitError> {
        let p = self.fused[&s];
        let (Node::Mul(x, y), Node::Add(a, b) | Node::Sub(a, b)) =
            (self.graph.node(p), self.graph.node(s))
        else {
            unreachable!("only products are fused, only into sums")
        };
        let (x, y) = self.constant_first(x, y);
        let c = if p == a { b } else { a };
        let subtract = matches!(self.graph.node(s), Node::Sub(..));
        let (tx, ty, tc) = if subtract && p == b {
            // c − x·y = (−x)·y + c
            (self.negated(x)?, self.operand(y)?, self.operand(c)?)
        } else if subtract {
            // x·y − c
            (self.operand(x)?, self.operand(y)?, self.negated(c)?)
        } else {
            (self.operand(x)?, self.operand(y)?, self.operand(c)?)
        };
        let f = match self.scalar {
            ScalarKind::F32 => quote!(mul_addf),
            _ => quote!(mul_add),
        };
        Ok((quote!(#f(#tx, #ty, #tc)), vec![x, y, c]))
    }

    /// The operands of a product, a constant first.
    fn constant_first(&self, a: Sym, b: Sym) -> (Sym, Sym) {
        if matches!(self.graph.node(b), Node::Const(_)) {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// An operand as a function argument or an output: a name, an input, or a constant.
    fn operand(&self, s: Sym) -> Result<TokenStream, EmitError> {
        match self.graph.node(s) {
            Node::Const(x) => Ok(literals::constant(x, self.scalar)?.0),
            Node::Input(_) => Ok(self.inputs[&s].clone()),
            _ => {
                let n = &self.name[&s];
                Ok(quote!(#n))
            }
        }
    }

    /// A value stored or returned: [`Writer::operand`], with a constant made lanes where the
    /// statements are for lanes (`F64x4::splat(c)`: the result holds lanes).
    fn stored(&self, s: Sym) -> Result<TokenStream, EmitError> {
        let value = self.operand(s)?;
        Ok(match (self.graph.node(s), &self.lanes) {
            (Node::Const(_), Some(ty)) => quote!(#ty::splat(#value)),
            _ => value,
        })
    }

    /// An operand of `+ − · /`: the same, with the rare constant that is itself a quotient (see
    /// [`literals::constant`]) in parentheses.
    fn term(&self, s: Sym) -> Result<TokenStream, EmitError> {
        match self.graph.node(s) {
            Node::Const(x) => match literals::constant(x, self.scalar)? {
                (c, true) => Ok(quote!((#c))),
                (c, false) => Ok(c),
            },
            _ => self.operand(s),
        }
    }

    /// `−x` as an argument: a constant negated, anything else with a minus sign.
    fn negated(&self, s: Sym) -> Result<TokenStream, EmitError> {
        match self.graph.node(s) {
            Node::Const(x) => Ok(literals::constant(-x, self.scalar)?.0),
            _ => {
                let t = self.operand(s)?;
                Ok(quote!(-#t))
            }
        }
    }
}

/// Pretty-prints a list of items (a whole file's worth) with `prettyplease`.
///
/// # Errors
/// If `tokens` do not parse as a list of items.
pub fn format(tokens: TokenStream) -> Result<String, syn::Error> {
    let file: syn::File = syn::parse2(tokens)?;
    Ok(prettyplease::unparse(&file))
}
