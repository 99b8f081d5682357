//! Passes over a traced graph that keep its values: [`reassociate`](mod@reassociate) (sums regrouped by arrival
//! time, a shorter critical path for the same operations), [`reciprocals`](mod@reciprocals)
//! (one division per divisor, products by its reciprocal for the rest) and
//! [`round_constants_to_f32`] (what `f32` code needs before it is emitted).

pub mod reassociate;
pub mod reciprocals;

pub use reassociate::reassociate;
pub use reciprocals::reciprocals;

use crate::sym::{Graph, Sym};

/// The part of `graph` that `outputs` need with every constant rounded to `f32`, folded again
/// until nothing changes, so that a constant that becomes `0` or `±1` in `f32` folds away there
/// too (`x·1.0_f32` would be a clippy warning in the user's crate). Folding two rounded
/// constants can make a new one that rounds to 0 or ±1 in turn: the loop repeats until the graph
/// stops shrinking (two passes in practice). A constant that overflows `f32` is kept as it is,
/// for the emitter to report. Arithmetic between constants was done in `f64` while tracing.
pub fn round_constants_to_f32(graph: &Graph, outputs: &[Sym]) -> (Graph, Vec<Sym>) {
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
    (g, outs)
}
