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

mod decimal;
mod fold;
mod graph;

use std::cell::RefCell;
use std::collections::HashSet;
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
    /// Component `i` of the wrench the world exerts on the root body (`[n; f]`), for joint
    /// wrenches bottom-up.
    Base(usize),
    /// Constraint force `f[i]` (one per constraint row), an input of the parts of the composed
    /// constrained derivatives.
    Force(usize),
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
            Var::Base(i) => write!(f, "base{i}"),
            Var::Force(i) => write!(f, "force{i}"),
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

    /// The same operation made again in the graph being traced, on the operands `m` gives in
    /// place of this node's (a constant and an input as they are): the step of a
    /// [`Graph::rebuild`] that changes nothing but the operands.
    pub fn remade(self, m: impl Fn(Sym) -> Sym) -> Sym {
        match self {
            Node::Const(x) => Sym::from_f64(x),
            Node::Input(v) => Sym::input(v),
            Node::Add(a, b) => m(a) + m(b),
            Node::Sub(a, b) => m(a) - m(b),
            Node::Mul(a, b) => m(a) * m(b),
            Node::Div(a, b) => m(a) / m(b),
            Node::Neg(a) => -m(a),
            Node::Sin(a) => unary(m(a), Graph::sin),
            Node::Cos(a) => unary(m(a), Graph::cos),
            Node::Sqrt(a) => unary(m(a), Graph::sqrt),
        }
    }
}

/// Operation counts of the part of a graph that some outputs need (see [`Graph::op_counts`]);
/// the same type the runtime exposes on generated chains.
pub use articulated_dynamics::OpCounts;

pub use graph::Graph;
use graph::Key;

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
            // A misuse of this crate's internals, not of a description: every `Sym` the
            // generator makes is made inside `trace`.
            #[allow(clippy::panic)]
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

/// Applies a binary graph operation to two `Sym`s of the current trace.
fn binary(a: Sym, b: Sym, op: fn(&mut Graph, u32, u32) -> u32) -> Sym {
    with_graph(|g| {
        let (a, b) = (g.idx(a), g.idx(b));
        let r = op(g, a, b);
        g.sym(r)
    })
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
            let i = g.literal(x);
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

    /// Records the name for the emitter (see [`Sym::named`]; the first name a node gets wins).
    fn label(self, name: fmt::Arguments<'_>) -> Sym {
        self.named(&name.to_string())
    }
}
