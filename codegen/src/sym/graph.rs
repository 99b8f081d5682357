//! The expression graph: its nodes, hash-consed, and what can be asked of it (the live part,
//! use counts, evaluation, operation counts, names).

use std::collections::{HashMap, HashSet};

use articulated_dynamics::Scalar;

use super::decimal::Decimal;
use super::{trace, Node, OpCounts, Sym, Var, INDEX_BITS, MAX_NODES};

/// The hash-consing key of a node: operands are node indices, constants their bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Key {
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
    pub(super) fn operands(self) -> impl Iterator<Item = u32> {
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
/// [module docs](super).
#[derive(Clone, Debug)]
pub struct Graph {
    pub(super) tag: u8,
    pub(super) nodes: Vec<Key>,
    index: HashMap<Key, u32>,
    hints: HashMap<u32, String>,
    /// The exact decimal value of the constants that are numbers as written, or sums, differences
    /// and products of them ([`super::decimal`]).
    pub(super) decimals: HashMap<u32, Decimal>,
}

impl Graph {
    pub(super) fn new(tag: u8) -> Graph {
        Graph {
            tag,
            nodes: Vec::new(),
            index: HashMap::new(),
            hints: HashMap::new(),
            decimals: HashMap::new(),
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
        self.eval_in::<f64>(outputs, inputs)
    }

    /// Evaluates `outputs` in the scalar `T` (`f32` for what generated `f32` code computes, up
    /// to the order of its fused operations), each constant and input rounded to `T` first.
    ///
    /// # Panics
    /// If an output belongs to another graph.
    pub fn eval_in<T: Scalar>(&self, outputs: &[Sym], inputs: impl Fn(Var) -> f64) -> Vec<T> {
        let mut value = vec![T::zero(); self.nodes.len()];
        for s in self.live(outputs) {
            let i = s.index() as usize;
            let v = |j: u32| value[j as usize];
            let x = match self.nodes[i] {
                Key::Const(bits) => T::from_f64(f64::from_bits(bits)),
                Key::Input(var) => T::from_f64(inputs(var)),
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
        let (graph, new, _) = self.rebuild(outputs, |s, map| {
            Some(match self.node(s) {
                Node::Const(x) => Sym::from_f64(constant(x)),
                node => node.remade(|a| map[&a]),
            })
        });
        (graph, new)
    }

    /// Rebuilds the part of the graph `outputs` need in a new trace, node by node in dependency
    /// order: `node_of(s, map)` makes the new node of live node `s`, `map` holding the new nodes
    /// of those before it ([`Node::remade`] copies one). It may return `None` for a node that only
    /// the nodes built in its place read (the terms inside a regrouped sum). Names are carried
    /// over in dependency order, so that where two old nodes become one, the first name wins as
    /// it did while tracing. Returns the new graph, the outputs in it and the map from old nodes
    /// to new. The passes of [`crate::optimize`] and [`Graph::map_constants`] are each one call.
    ///
    /// # Panics
    /// If an output belongs to another graph, or was left out.
    pub fn rebuild(
        &self,
        outputs: &[Sym],
        mut node_of: impl FnMut(Sym, &HashMap<Sym, Sym>) -> Option<Sym>,
    ) -> (Graph, Vec<Sym>, HashMap<Sym, Sym>) {
        let live = self.live(outputs);
        let (mut graph, (new, map)) = trace(|| {
            let mut map: HashMap<Sym, Sym> = HashMap::with_capacity(live.len());
            for &s in &live {
                if let Some(n) = node_of(s, &map) {
                    map.insert(s, n);
                }
            }
            (outputs.iter().map(|s| map[s]).collect::<Vec<_>>(), map)
        });
        for &s in &live {
            if let (Some(name), Some(&n)) = (self.hint_of(s), map.get(&s)) {
                graph.hint(n, name);
            }
        }
        (graph, new, map)
    }

    /// The node index of `s`, checking that `s` belongs to this graph.
    pub(super) fn idx(&self, s: Sym) -> u32 {
        assert!(
            s.tag() == self.tag && (s.index() as usize) < self.nodes.len(),
            "a symbolic scalar (`Sym`) of one trace was used with the graph of another: \
             each `Sym` belongs to the `sym::trace` that created it"
        );
        s.index()
    }

    pub(super) fn sym(&self, i: u32) -> Sym {
        Sym((u32::from(self.tag) << INDEX_BITS) | i)
    }

    pub(super) fn intern(&mut self, key: Key) -> u32 {
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
}
