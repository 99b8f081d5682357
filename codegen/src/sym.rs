//! A symbolic scalar that records an expression graph.
//!
//! The dynamics recursions are written once, generically over [`Scalar`], and never branch on a
//! value. Run on `f64` they compute numbers; run on [`Sym`] inside [`trace`] they record every
//! operation as a node of a [`Graph`], which [`crate::emit`] turns into straight-line Rust and
//! [`Graph::eval`] interprets in `f64`.
//!
//! The graph is simplified while it is built, so that no later pass has to:
//! - **hash-consing**: an expression built twice is one node (the operands of `+` and `·` are put
//!   in a canonical order first), which is common-subexpression elimination for free;
//! - **folding**: constant ⊕ constant → constant (when the result is finite); `x+0`, `0+x`, `x−0`,
//!   `x·1`, `1·x`, `x/1` → `x`; `x·0`, `0·x`, `0/x` → `0`; `0−x` → `−x`; `x·(−1)`, `(−1)·x`,
//!   `x/(−1)` → `−x`; `−(−x)` → `x`; `−c` → the constant `−c`; `x−x` → `0`, `x/x` → `1` (the
//!   algebra of real numbers, as any computer-algebra system takes it: at `x = 0` the emitted
//!   code would otherwise compute `NaN`); `x+(−y)`, `(−y)+x` → `x−y`; `x−(−y)` → `x+y`;
//!   `(−x)·(−y)` → `x·y`, `(−x)/(−y)` → `x/y`; `−(x−y)` → `y−x`; `sin(−x)` → `−sin x`,
//!   `cos(−x)` → `cos x`; `sin`, `cos`, `sqrt` of a constant are computed (with the same `libm`
//!   functions as [`Scalar`] for `f64`). A negative constant counts as a negation of its absolute
//!   value in these rules, so `x + (−2)` becomes `x − 2`.
//!
//! # Threads and nesting
//! The operators of [`Scalar`] take no context, so the graph being recorded lives in a
//! thread-local: a *stack* of graphs, one per active [`trace`]. A trace inside a trace records
//! into its own fresh graph and the outer one resumes when it returns; traces on other threads
//! are independent. Every [`Sym`] carries a tag of the trace that created it. Using a `Sym`
//! outside any trace, or inside a trace other than its own, is a bug in the calling code: it
//! panics with a message saying so (the operators cannot return an error). Tags are 8 bits, so
//! a `Sym` that escaped a finished trace is caught with probability 255/256 when it is used in a
//! later one; a `Sym` from an enclosing (still active) trace is always caught.

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

use articulated_dynamics::Scalar;

/// Bits of a [`Sym`] that index its node; the top 8 bits are the tag of its trace.
const INDEX_BITS: u32 = 24;
const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// The largest number of nodes one graph can hold (2²⁴ ≈ 16.7 million).
pub const MAX_NODES: usize = 1 << INDEX_BITS;

/// A symbolic scalar: a handle to a node of the graph being recorded by [`trace`].
///
/// It is `Copy` and implements [`Scalar`], so the recursions run on it unchanged; every operation
/// adds (or finds) a node in the current graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sym(u32);

/// An input of a traced function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// Position coordinate `q[i]`.
    Q(usize),
    /// Velocity `v[i]`.
    V(usize),
    /// Acceleration `a[i]`.
    A(usize),
    /// Generalized force `τ[i]`.
    Tau(usize),
    /// Runtime parameter `i` of the model.
    Param(usize),
}

impl fmt::Display for Var {
    /// `q3`, `v0`, `a1`, `tau2`, `p0`: the stem of the names the emitter derives from an input.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Var::Q(i) => write!(f, "q{i}"),
            Var::V(i) => write!(f, "v{i}"),
            Var::A(i) => write!(f, "a{i}"),
            Var::Tau(i) => write!(f, "tau{i}"),
            Var::Param(i) => write!(f, "p{i}"),
        }
    }
}

/// One node of a [`Graph`], with its operands as [`Sym`]s of the same graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    /// A finite constant (or, only if [`Scalar::from_f64`] was given one, a non-finite one).
    Const(f64),
    /// An input.
    Input(Var),
    /// `a + b`.
    Add(Sym, Sym),
    /// `a − b`.
    Sub(Sym, Sym),
    /// `a · b`.
    Mul(Sym, Sym),
    /// `a / b`.
    Div(Sym, Sym),
    /// `−a`.
    Neg(Sym),
    /// `sin a`.
    Sin(Sym),
    /// `cos a`.
    Cos(Sym),
    /// `√a`.
    Sqrt(Sym),
}

impl Node {
    /// The operands, in order.
    pub fn operands(self) -> impl Iterator<Item = Sym> {
        let (a, b) = match self {
            Node::Const(_) | Node::Input(_) => (None, None),
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                (Some(a), Some(b))
            }
            Node::Neg(a) | Node::Sin(a) | Node::Cos(a) | Node::Sqrt(a) => (Some(a), None),
        };
        a.into_iter().chain(b)
    }
}

/// The hash-consing key of a node: operands are node indices, constants their bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    Const(u64),
    Input(Var),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sin(u32),
    Cos(u32),
    Sqrt(u32),
}

impl Key {
    /// The operands, in order.
    fn operands(self) -> impl Iterator<Item = u32> {
        let (a, b) = match self {
            Key::Const(_) | Key::Input(_) => (None, None),
            Key::Add(a, b) | Key::Sub(a, b) | Key::Mul(a, b) | Key::Div(a, b) => (Some(a), Some(b)),
            Key::Neg(a) | Key::Sin(a) | Key::Cos(a) | Key::Sqrt(a) => (Some(a), None),
        };
        a.into_iter().chain(b)
    }
}

/// An expression graph recorded by [`trace`]: nodes in creation order, so every node comes after
/// its operands (a topological order), hash-consed and folded as described in the
/// [module docs](self).
#[derive(Clone, Debug)]
pub struct Graph {
    tag: u8,
    nodes: Vec<Key>,
    index: HashMap<Key, u32>,
    hints: HashMap<u32, String>,
}

/// Operation counts of the part of a graph that some outputs need (see [`Graph::op_counts`]);
/// the same type the runtime exposes on generated chains.
pub use articulated_dynamics::OpCounts;

/// The graphs being recorded on this thread (innermost last) and the next tag to hand out.
struct Traces {
    stack: Vec<Graph>,
    next_tag: u8,
}

thread_local! {
    static TRACES: RefCell<Traces> = const { RefCell::new(Traces { stack: Vec::new(), next_tag: 0 }) };
}

/// Records the operations `f` performs on [`Sym`]s into a fresh [`Graph`] and returns it with
/// `f`'s result (typically the output `Sym`s).
///
/// Traces nest: a trace started inside `f` records into its own graph (see the
/// [module docs](self#threads-and-nesting)). If `f` panics, its graph is discarded and the
/// enclosing trace, if any, is left as it was.
///
/// ```
/// use articulated_codegen::sym::{trace, Sym, Var};
/// use articulated_dynamics::Scalar;
///
/// let (graph, y) = trace(|| {
///     let q = Sym::input(Var::Q(0));
///     let (s, c) = q.sin_cos();
///     s * s + c * c
/// });
/// let value = graph.eval(&[y], |_| 0.3);
/// assert!((value[0] - 1.0).abs() < 1e-15);
/// assert_eq!(graph.op_counts(&[y]).sin_cos, 1);
/// ```
///
/// # Panics
/// If 255 traces are already active on this thread.
pub fn trace<R>(f: impl FnOnce() -> R) -> (Graph, R) {
    /// Pops this trace's graph (and anything above it) even if `f` unwinds.
    struct Pop(usize);
    impl Drop for Pop {
        fn drop(&mut self) {
            // `try_with`: nothing to clean up if the thread-local is already being destroyed.
            let _ = TRACES.try_with(|t| t.borrow_mut().stack.truncate(self.0));
        }
    }

    let depth = TRACES.with(|t| {
        let mut t = t.borrow_mut();
        assert!(
            t.stack.len() < 255,
            "sym::trace: 255 traces are already active on this thread"
        );
        let active: HashSet<u8> = t.stack.iter().map(|g| g.tag).collect();
        let mut tag = t.next_tag;
        while active.contains(&tag) {
            tag = tag.wrapping_add(1);
        }
        t.next_tag = tag.wrapping_add(1);
        let depth = t.stack.len();
        t.stack.push(Graph::new(tag));
        depth
    });
    let pop = Pop(depth);
    let result = f();
    let graph = TRACES.with(|t| t.borrow_mut().stack.pop());
    drop(pop);
    match graph {
        Some(graph) => (graph, result),
        // The stack is private to this module and every push is paired with a pop.
        None => unreachable!("sym::trace: the trace stack lost its graph"),
    }
}

/// Runs `f` on the graph of the innermost active trace.
fn with_graph<R>(f: impl FnOnce(&mut Graph) -> R) -> R {
    TRACES.with(|t| {
        let mut t = t.borrow_mut();
        match t.stack.last_mut() {
            Some(g) => f(g),
            None => panic!(
                "a symbolic scalar (`Sym`) was used outside `sym::trace`: \
                 create and combine `Sym`s only inside the closure given to `trace`"
            ),
        }
    })
}

impl Sym {
    /// The input `var`, as a node of the current trace.
    ///
    /// # Panics
    /// Outside [`trace`].
    pub fn input(var: Var) -> Sym {
        with_graph(|g| {
            let i = g.intern(Key::Input(var));
            g.sym(i)
        })
    }

    /// Gives this node a name the emitter will use for it (sanitized to a snake_case
    /// identifier), and returns it. The first name a node is given wins: with hash-consing the
    /// same node can be reached from several places, and the first is the most primitive.
    /// Names of constants and inputs are ignored (they are never bound to a variable).
    ///
    /// # Panics
    /// Outside [`trace`], or with a `Sym` of another trace.
    pub fn named(self, name: &str) -> Sym {
        with_graph(|g| g.hint(self, name));
        self
    }

    /// The value of this node if it is a constant of the current trace.
    ///
    /// # Panics
    /// Outside [`trace`], or with a `Sym` of another trace.
    pub fn constant(self) -> Option<f64> {
        with_graph(|g| match g.nodes[g.idx(self) as usize] {
            Key::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        })
    }

    fn tag(self) -> u8 {
        (self.0 >> INDEX_BITS) as u8
    }

    fn index(self) -> u32 {
        self.0 & INDEX_MASK
    }
}

impl Graph {
    fn new(tag: u8) -> Graph {
        Graph {
            tag,
            nodes: Vec::new(),
            index: HashMap::new(),
            hints: HashMap::new(),
        }
    }

    /// Number of nodes, live or not.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph has no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// All nodes, in creation (= dependency) order.
    pub fn syms(&self) -> impl Iterator<Item = Sym> + '_ {
        (0..self.nodes.len() as u32).map(|i| self.sym(i))
    }

    /// The node `s` stands for.
    ///
    /// # Panics
    /// If `s` belongs to another graph.
    pub fn node(&self, s: Sym) -> Node {
        match self.nodes[self.idx(s) as usize] {
            Key::Const(bits) => Node::Const(f64::from_bits(bits)),
            Key::Input(v) => Node::Input(v),
            Key::Add(a, b) => Node::Add(self.sym(a), self.sym(b)),
            Key::Sub(a, b) => Node::Sub(self.sym(a), self.sym(b)),
            Key::Mul(a, b) => Node::Mul(self.sym(a), self.sym(b)),
            Key::Div(a, b) => Node::Div(self.sym(a), self.sym(b)),
            Key::Neg(a) => Node::Neg(self.sym(a)),
            Key::Sin(a) => Node::Sin(self.sym(a)),
            Key::Cos(a) => Node::Cos(self.sym(a)),
            Key::Sqrt(a) => Node::Sqrt(self.sym(a)),
        }
    }

    /// Names node `s` for the emitter (see [`Sym::named`]; the first name given wins).
    ///
    /// # Panics
    /// If `s` belongs to another graph.
    pub fn hint(&mut self, s: Sym, name: &str) {
        let i = self.idx(s);
        if !matches!(self.nodes[i as usize], Key::Const(_) | Key::Input(_)) {
            self.hints.entry(i).or_insert_with(|| name.to_owned());
        }
    }

    /// The name given to `s` with [`Graph::hint`] or [`Sym::named`], if any.
    ///
    /// # Panics
    /// If `s` belongs to another graph.
    pub fn hint_of(&self, s: Sym) -> Option<&str> {
        self.hints.get(&self.idx(s)).map(String::as_str)
    }

    /// The nodes `outputs` depend on (including themselves), in dependency order; nodes no
    /// output needs are dropped.
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn live(&self, outputs: &[Sym]) -> Vec<Sym> {
        let mut needed = vec![false; self.nodes.len()];
        for &s in outputs {
            needed[self.idx(s) as usize] = true;
        }
        for i in (0..self.nodes.len()).rev() {
            if needed[i] {
                for o in self.nodes[i].operands() {
                    needed[o as usize] = true;
                }
            }
        }
        (0..self.nodes.len() as u32)
            .filter(|&i| needed[i as usize])
            .map(|i| self.sym(i))
            .collect()
    }

    /// How many times each node `outputs` need is read: by the live nodes, once per operand,
    /// and once for each time it is among `outputs`.
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn use_counts(&self, outputs: &[Sym]) -> HashMap<Sym, usize> {
        let mut uses: HashMap<Sym, usize> = HashMap::new();
        for s in self.live(outputs) {
            for o in self.node(s).operands() {
                *uses.entry(o).or_default() += 1;
            }
        }
        for &s in outputs {
            *uses.entry(s).or_default() += 1;
        }
        uses
    }

    /// Evaluates `outputs` in `f64`, reading inputs from `inputs` (called once per live input).
    /// Sine, cosine and square root are `libm`'s, as in [`Scalar`] for `f64`.
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn eval(&self, outputs: &[Sym], inputs: impl Fn(Var) -> f64) -> Vec<f64> {
        let mut value = vec![0.0; self.nodes.len()];
        for s in self.live(outputs) {
            let i = s.index() as usize;
            let v = |j: u32| value[j as usize];
            let x = match self.nodes[i] {
                Key::Const(bits) => f64::from_bits(bits),
                Key::Input(var) => inputs(var),
                Key::Add(a, b) => v(a) + v(b),
                Key::Sub(a, b) => v(a) - v(b),
                Key::Mul(a, b) => v(a) * v(b),
                Key::Div(a, b) => v(a) / v(b),
                Key::Neg(a) => -v(a),
                Key::Sin(a) => Scalar::sin_cos(v(a)).0,
                Key::Cos(a) => Scalar::sin_cos(v(a)).1,
                Key::Sqrt(a) => Scalar::sqrt(v(a)),
            };
            value[i] = x;
        }
        outputs.iter().map(|&s| value[s.index() as usize]).collect()
    }

    /// Counts the operations needed to compute `outputs` (live nodes only; see [`OpCounts`]).
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn op_counts(&self, outputs: &[Sym]) -> OpCounts {
        let mut counts = OpCounts::default();
        let mut trig_args = HashSet::new();
        for s in self.live(outputs) {
            match self.nodes[s.index() as usize] {
                Key::Const(_) | Key::Input(_) => {}
                Key::Add(..) | Key::Sub(..) => counts.adds += 1,
                Key::Mul(..) => counts.muls += 1,
                Key::Div(..) => counts.divs += 1,
                Key::Neg(_) => counts.negs += 1,
                Key::Sin(a) | Key::Cos(a) => {
                    trig_args.insert(a);
                }
                Key::Sqrt(_) => counts.sqrts += 1,
            }
        }
        counts.sin_cos = trig_args.len();
        counts
    }

    /// Rebuilds the part of the graph `outputs` need with every constant `c` replaced by
    /// `constant(c)`, folding again on the way (names carried over); returns the new graph and
    /// the outputs in it.
    ///
    /// The emitter uses it to round constants to `f32` before printing them: a constant that
    /// becomes exactly `0` or `1` in `f32` must fold away there too (`x·1.0_f32` would be a clippy
    /// warning in the user's crate).
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn map_constants(
        &self,
        outputs: &[Sym],
        constant: impl Fn(f64) -> f64,
    ) -> (Graph, Vec<Sym>) {
        let live = self.live(outputs);
        let (mut graph, (new, map)) = trace(|| {
            let mut map: HashMap<Sym, Sym> = HashMap::with_capacity(live.len());
            for &s in &live {
                let m = |a: Sym| map[&a];
                let n = match self.node(s) {
                    Node::Const(x) => Sym::from_f64(constant(x)),
                    Node::Input(v) => Sym::input(v),
                    Node::Add(a, b) => m(a) + m(b),
                    Node::Sub(a, b) => m(a) - m(b),
                    Node::Mul(a, b) => m(a) * m(b),
                    Node::Div(a, b) => m(a) / m(b),
                    Node::Neg(a) => -m(a),
                    Node::Sin(a) => unary(m(a), Graph::sin),
                    Node::Cos(a) => unary(m(a), Graph::cos),
                    Node::Sqrt(a) => m(a).sqrt(),
                };
                map.insert(s, n);
            }
            (outputs.iter().map(|s| map[s]).collect::<Vec<_>>(), map)
        });
        for &s in &live {
            if let Some(name) = self.hint_of(s) {
                graph.hint(map[&s], name);
            }
        }
        (graph, new)
    }

    /// The node index of `s`, checking that `s` belongs to this graph.
    fn idx(&self, s: Sym) -> u32 {
        assert!(
            s.tag() == self.tag && (s.index() as usize) < self.nodes.len(),
            "a symbolic scalar (`Sym`) of one trace was used with the graph of another: \
             each `Sym` belongs to the `sym::trace` that created it"
        );
        s.index()
    }

    fn sym(&self, i: u32) -> Sym {
        Sym((u32::from(self.tag) << INDEX_BITS) | i)
    }

    fn intern(&mut self, key: Key) -> u32 {
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        assert!(
            self.nodes.len() < MAX_NODES,
            "sym: an expression graph cannot hold more than {MAX_NODES} nodes"
        );
        let i = self.nodes.len() as u32;
        self.nodes.push(key);
        self.index.insert(key, i);
        i
    }

    fn constant(&mut self, x: f64) -> u32 {
        // One zero: −0 and +0 are the same number to the algebra (and to every rule above).
        let x = if x == 0.0 { 0.0 } else { x };
        self.intern(Key::Const(x.to_bits()))
    }

    fn value(&self, i: u32) -> Option<f64> {
        match self.nodes[i as usize] {
            Key::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    fn is(&self, i: u32, x: f64) -> bool {
        self.value(i) == Some(x)
    }

    /// Whether `i` is a negation: a `Neg` node or a negative constant.
    fn is_negation(&self, i: u32) -> bool {
        match self.nodes[i as usize] {
            Key::Neg(_) => true,
            Key::Const(bits) => f64::from_bits(bits) < 0.0,
            _ => false,
        }
    }

    /// `−i` for a negation `i` (see [`Graph::is_negation`]): its operand, or the positive constant.
    fn strip_negation(&mut self, i: u32) -> u32 {
        match self.nodes[i as usize] {
            Key::Neg(a) => a,
            Key::Const(bits) => self.constant(-f64::from_bits(bits)),
            _ => unreachable!("strip_negation of a node that is not a negation"),
        }
    }

    /// Folds two constants if both are and the result is finite.
    fn fold2(&mut self, a: u32, b: u32, op: fn(f64, f64) -> f64) -> Option<u32> {
        let r = op(self.value(a)?, self.value(b)?);
        r.is_finite().then(|| self.constant(r))
    }

    fn fold1(&mut self, a: u32, op: fn(f64) -> f64) -> Option<u32> {
        let r = op(self.value(a)?);
        r.is_finite().then(|| self.constant(r))
    }

    fn add(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x + y) {
            return r;
        }
        if self.is(a, 0.0) {
            return b;
        }
        if self.is(b, 0.0) {
            return a;
        }
        if self.is_negation(b) {
            let y = self.strip_negation(b);
            return self.sub(a, y);
        }
        if self.is_negation(a) {
            let x = self.strip_negation(a);
            return self.sub(b, x);
        }
        self.intern(Key::Add(a.min(b), a.max(b)))
    }

    fn sub(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x - y) {
            return r;
        }
        if self.is(b, 0.0) {
            return a;
        }
        if self.is(a, 0.0) {
            return self.neg(b);
        }
        if a == b {
            return self.constant(0.0);
        }
        if self.is_negation(b) {
            let y = self.strip_negation(b);
            return self.add(a, y);
        }
        // `(−x) − y = −(x + y)`: one negation, which an enclosing sum can absorb.
        if let Key::Neg(x) = self.nodes[a as usize] {
            let t = self.add(x, b);
            return self.neg(t);
        }
        self.intern(Key::Sub(a, b))
    }

    fn mul(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x * y) {
            return r;
        }
        if self.is(a, 0.0) || self.is(b, 0.0) {
            return self.constant(0.0);
        }
        if self.is(a, 1.0) {
            return b;
        }
        if self.is(b, 1.0) {
            return a;
        }
        if self.is(a, -1.0) {
            return self.neg(b);
        }
        if self.is(b, -1.0) {
            return self.neg(a);
        }
        if self.is_negation(a) && self.is_negation(b) {
            let (x, y) = (self.strip_negation(a), self.strip_negation(b));
            return self.mul(x, y);
        }
        // The sign of a negated (non-constant) factor moves out, where a sum or difference
        // absorbs it: `x·(−y) = −(x·y)`.
        if let Key::Neg(y) = self.nodes[b as usize] {
            let p = self.mul(a, y);
            return self.neg(p);
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            let p = self.mul(x, b);
            return self.neg(p);
        }
        self.intern(Key::Mul(a.min(b), a.max(b)))
    }

    fn div(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x / y) {
            return r;
        }
        if self.is(a, 0.0) {
            return self.constant(0.0);
        }
        if self.is(b, 1.0) {
            return a;
        }
        if self.is(b, -1.0) {
            return self.neg(a);
        }
        if a == b {
            return self.constant(1.0);
        }
        if self.is_negation(a) && self.is_negation(b) {
            let (x, y) = (self.strip_negation(a), self.strip_negation(b));
            return self.div(x, y);
        }
        self.intern(Key::Div(a, b))
    }

    fn neg(&mut self, a: u32) -> u32 {
        match self.nodes[a as usize] {
            Key::Const(bits) => self.constant(-f64::from_bits(bits)),
            Key::Neg(x) => x,
            Key::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Key::Neg(a)),
        }
    }

    fn sin(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, |x| snap_unit(Scalar::sin_cos(x).0)) {
            return r;
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            let s = self.sin(x);
            return self.neg(s);
        }
        self.intern(Key::Sin(a))
    }

    fn cos(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, |x| snap_unit(Scalar::sin_cos(x).1)) {
            return r;
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            return self.cos(x);
        }
        self.intern(Key::Cos(a))
    }

    fn sqrt(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, <f64 as Scalar>::sqrt) {
            return r;
        }
        self.intern(Key::Sqrt(a))
    }
}

/// Applies a binary graph operation to two `Sym`s of the current trace.
fn binary(a: Sym, b: Sym, op: fn(&mut Graph, u32, u32) -> u32) -> Sym {
    with_graph(|g| {
        let (a, b) = (g.idx(a), g.idx(b));
        let r = op(g, a, b);
        g.sym(r)
    })
}

/// The sine or cosine of a constant angle, with values within 1e-15 of 0 or ±1 made exact.
/// Constant angles come from placements written in decimal (`rpy="1.5707963267948966 0 0"`),
/// where a quarter turn is meant: `cos(fl(π/2)) = 6.1e-17` kept as it is makes every rotation
/// through such a frame dense, while an exact 0 lets the products with it fold away. The change
/// (≤ 1e-15) is far below every tolerance the outputs are held to.
fn snap_unit(x: f64) -> f64 {
    const EPS: f64 = 1e-15;
    if x.abs() < EPS {
        0.0
    } else if (x - 1.0).abs() < EPS {
        1.0
    } else if (x + 1.0).abs() < EPS {
        -1.0
    } else {
        x
    }
}

fn unary(a: Sym, op: fn(&mut Graph, u32) -> u32) -> Sym {
    with_graph(|g| {
        let a = g.idx(a);
        let r = op(g, a);
        g.sym(r)
    })
}

macro_rules! binary_op {
    ($Trait:ident, $method:ident) => {
        impl $Trait for Sym {
            type Output = Sym;
            /// Records the operation in the current trace (folded and hash-consed).
            ///
            /// # Panics
            /// Outside [`trace`], or with a `Sym` of another trace.
            fn $method(self, rhs: Sym) -> Sym {
                binary(self, rhs, Graph::$method)
            }
        }
    };
}

binary_op!(Add, add);
binary_op!(Sub, sub);
binary_op!(Mul, mul);
binary_op!(Div, div);

impl Neg for Sym {
    type Output = Sym;
    /// Records `−self` in the current trace (folded and hash-consed).
    ///
    /// # Panics
    /// Outside [`trace`], or with a `Sym` of another trace.
    fn neg(self) -> Sym {
        unary(self, Graph::neg)
    }
}

impl Scalar for Sym {
    /// The constant `x` in the current trace.
    ///
    /// # Panics
    /// Outside [`trace`].
    fn from_f64(x: f64) -> Sym {
        with_graph(|g| {
            let i = g.constant(x);
            g.sym(i)
        })
    }

    /// The sine and cosine nodes of the same argument (emitted as one call when both are used).
    fn sin_cos(self) -> (Sym, Sym) {
        (unary(self, Graph::sin), unary(self, Graph::cos))
    }

    fn sqrt(self) -> Sym {
        unary(self, Graph::sqrt)
    }
}
