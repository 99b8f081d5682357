//! Products fused into the one sum that uses them, emitted as `mul_add(x, y, c)`: one FMA
//! instruction where the target has it (`-C target-cpu=x86-64-v3` or newer), `x * y + c`
//! otherwise (`articulated::math::mul_add`).

use std::collections::HashMap;

use crate::sym::{Graph, Node, Sym};

/// For each sum (`a + b`, `a − b`) with an operand that is a product read by nothing else, that
/// product. When both operands qualify, the deeper product is fused: the other one is ready
/// earlier and waits as the addend.
pub(super) fn fused_products(graph: &Graph, live: &[Sym], outputs: &[Sym]) -> HashMap<Sym, Sym> {
    let uses = graph.use_counts(outputs);
    let mut depth: HashMap<Sym, usize> = HashMap::new();
    for &s in live {
        let d = graph.node(s).operands().map(|a| depth[&a] + 1).max();
        depth.insert(s, d.unwrap_or(0));
    }
    let mut fused = HashMap::new();
    for &s in live {
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
            }
        }
    }
    fused
}
