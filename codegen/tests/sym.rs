//! The symbolic scalar: hash-consing, folding, sin/cos sharing, f64 interpretation against the
//! same generic code run on `f64`, operation counts, dead-code elimination, nested traces.

use articulated_codegen::sym::{trace, Graph, Node, OpCounts, Sym, Var};
use articulated_dynamics::random::Rng;
use articulated_dynamics::Scalar;

fn q(i: usize) -> Sym {
    Sym::input(Var::Q(i))
}

fn c(x: f64) -> Sym {
    Sym::from_f64(x)
}

#[test]
fn an_expression_built_twice_is_one_node() {
    let (graph, (a, b, c1, c2, d1, d2)) = trace(|| {
        let a = (q(0) * q(1)).sin_cos().0 + q(2) / q(3);
        let b = (q(0) * q(1)).sin_cos().0 + q(2) / q(3);
        // Commutative operands in either order.
        let c1 = q(0) * q(1) + q(2);
        let c2 = q(2) + q(1) * q(0);
        // Non-commutative ones are not swapped.
        let d1 = q(0) - q(1);
        let d2 = q(1) - q(0);
        (a, b, c1, c2, d1, d2)
    });
    assert_eq!(a, b);
    assert_eq!(c1, c2);
    assert_ne!(d1, d2);
    // q0..q3, q0·q1, sin, cos, q2/q3, a, c1, d1, d2: nothing else.
    assert_eq!(graph.len(), 12, "{graph:#?}");
}

#[test]
fn every_folding_rule() {
    let (graph, (inf, nan)) = trace(|| {
        let x = q(0);
        let y = q(1);
        let zero = c(0.0);
        let one = c(1.0);
        let minus_one = c(-1.0);
        let neg_x = -x;
        // constant ⊕ constant
        assert_eq!(c(1.5) + c(2.0), c(3.5));
        assert_eq!(c(1.5) - c(2.0), c(-0.5));
        assert_eq!(c(1.5) * c(2.0), c(3.0));
        assert_eq!(c(1.5) / c(2.0), c(0.75));
        // identities
        assert_eq!(x + zero, x);
        assert_eq!(zero + x, x);
        assert_eq!(x - zero, x);
        assert_eq!(x * one, x);
        assert_eq!(one * x, x);
        assert_eq!(x / one, x);
        // annihilators
        assert_eq!(x * zero, zero);
        assert_eq!(zero * x, zero);
        assert_eq!(zero / x, zero);
        // negation
        assert_eq!(zero - x, neg_x);
        assert_eq!(-neg_x, x);
        assert_eq!(x * minus_one, neg_x);
        assert_eq!(minus_one * x, neg_x);
        assert_eq!(x / minus_one, neg_x);
        assert_eq!(-c(2.5), c(-2.5));
        assert_eq!(-zero, zero);
        assert_eq!(c(-0.0), zero);
        // x − x, x / x
        assert_eq!(x - x, zero);
        assert_eq!(x / x, one);
        // negations absorbed
        assert_eq!(x + -y, x - y);
        assert_eq!(-y + x, x - y);
        assert_eq!(x - -y, x + y);
        assert_eq!(x + c(-2.0), x - c(2.0));
        assert_eq!(x - c(-2.0), x + c(2.0));
        assert_eq!(-x * -y, x * y);
        assert_eq!(c(-2.0) * -y, c(2.0) * y);
        assert_eq!(-x / -y, x / y);
        assert_eq!(-(x - y), y - x);
        // negations moved out of products and differences, where a sum absorbs them
        assert_eq!(x * -y, -(x * y));
        assert_eq!(-x * y, -(x * y));
        assert_eq!(-x - y, -(x + y));
        assert_eq!(c(3.0) + x * -y, c(3.0) - x * y);
        let (s, co) = x.sin_cos();
        let (sn, cn) = neg_x.sin_cos();
        assert_eq!(sn, -s);
        assert_eq!(cn, co);
        // unary functions of constants
        let (s, co) = c(0.5).sin_cos();
        assert_eq!(s, c(<f64 as Scalar>::sin_cos(0.5).0));
        assert_eq!(co, c(<f64 as Scalar>::sin_cos(0.5).1));
        assert_eq!(c(2.25).sqrt(), c(1.5));
        // not folded into a non-finite constant
        (c(1.0) / zero, c(-1.0).sqrt())
    });
    assert!(matches!(graph.node(inf), Node::Div(..)));
    assert!(matches!(graph.node(nan), Node::Sqrt(..)));
    assert_no_foldable_pattern(&graph);
}

/// Fails if any node of `graph` is a pattern the builder must fold away.
fn assert_no_foldable_pattern(graph: &Graph) {
    let value = |s: Sym| match graph.node(s) {
        Node::Const(x) => Some(x),
        _ => None,
    };
    let is_neg =
        |s: Sym| matches!(graph.node(s), Node::Neg(_)) || value(s).is_some_and(|x| x < 0.0);
    let order = order(graph);
    let mut seen = std::collections::HashSet::new();
    for s in graph.syms() {
        let node = graph.node(s);
        // Hash-consing: no two nodes are the same expression.
        let key = match node {
            Node::Const(x) => format!("Const({})", x.to_bits()),
            _ => format!("{node:?}"),
        };
        assert!(seen.insert(key), "duplicate node {node:?}");
        let finite_fold = |r: f64| assert!(!r.is_finite(), "unfolded constant op {node:?}");
        match node {
            Node::Const(x) => assert!(x != 0.0 || x.is_sign_positive(), "−0 constant"),
            Node::Input(_) => {}
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                if let (Some(x), Some(y)) = (value(a), value(b)) {
                    finite_fold(match node {
                        Node::Add(..) => x + y,
                        Node::Sub(..) => x - y,
                        Node::Mul(..) => x * y,
                        _ => x / y,
                    });
                }
                let (va, vb) = (value(a), value(b));
                match node {
                    Node::Add(..) => {
                        assert!(va != Some(0.0) && vb != Some(0.0), "x+0 in {node:?}");
                        assert!(!is_neg(a) && !is_neg(b), "x+(−y) in {node:?}");
                        assert!(order[&a] <= order[&b], "unordered {node:?}");
                    }
                    Node::Sub(..) => {
                        assert!(va != Some(0.0) && vb != Some(0.0), "x−0 or 0−x in {node:?}");
                        assert!(a != b, "x−x in {node:?}");
                        assert!(!is_neg(b), "x−(−y) in {node:?}");
                        assert!(!matches!(graph.node(a), Node::Neg(_)), "(−x)−y in {node:?}");
                    }
                    Node::Mul(..) => {
                        for v in [va, vb] {
                            assert!(
                                !matches!(v, Some(x) if x == 0.0 || x == 1.0 || x == -1.0),
                                "x·0, x·1 or x·(−1) in {node:?}"
                            );
                        }
                        assert!(!(is_neg(a) && is_neg(b)), "(−x)·(−y) in {node:?}");
                        for f in [a, b] {
                            assert!(!matches!(graph.node(f), Node::Neg(_)), "x·(−y) in {node:?}");
                        }
                        assert!(order[&a] <= order[&b], "unordered {node:?}");
                    }
                    _ => {
                        assert!(va != Some(0.0), "0/x in {node:?}");
                        assert!(
                            vb != Some(1.0) && vb != Some(-1.0),
                            "x/1 or x/(−1) in {node:?}"
                        );
                        assert!(a != b, "x/x in {node:?}");
                        assert!(!(is_neg(a) && is_neg(b)), "(−x)/(−y) in {node:?}");
                    }
                }
            }
            Node::Neg(a) => assert!(
                !matches!(graph.node(a), Node::Const(_) | Node::Neg(_) | Node::Sub(..)),
                "−c, −(−x) or −(x−y) in {node:?}"
            ),
            Node::Sin(a) | Node::Cos(a) => assert!(
                !matches!(graph.node(a), Node::Const(_) | Node::Neg(_)),
                "sin/cos of a constant or a negation in {node:?}"
            ),
            Node::Sqrt(a) => {
                if let Some(x) = value(a) {
                    finite_fold(x.sqrt());
                }
            }
        }
    }
}

/// Position of each node in creation order.
fn order(graph: &Graph) -> std::collections::HashMap<Sym, usize> {
    graph.syms().enumerate().map(|(i, s)| (s, i)).collect()
}

#[test]
fn sine_and_cosine_of_one_angle_share_one_evaluation() {
    let (graph, (s1, c1, s2, c2, only_sin)) = trace(|| {
        let (s1, c1) = q(0).sin_cos();
        let (s2, c2) = q(0).sin_cos();
        let (only_sin, _) = (q(1) * q(2)).sin_cos();
        (s1, c1, s2, c2, only_sin)
    });
    assert_eq!((s1, c1), (s2, c2));
    assert_eq!(graph.node(s1), Node::Sin(graph.live(&[s1])[0]));
    let both = graph.op_counts(&[s1, c1]);
    assert_eq!(both.sin_cos, 1);
    assert_eq!(both.total(), 1);
    let three = graph.op_counts(&[s1, c1, only_sin]);
    assert_eq!((three.sin_cos, three.muls, three.total()), (2, 1, 3));
}

/// A small random program: each step combines two earlier values. Written once, over any
/// `Scalar`, and run on `f64` and on `Sym` (the tracer's pattern).
#[derive(Clone, Copy, Debug)]
enum Step {
    Add(usize, usize),
    Sub(usize, usize),
    Mul(usize, usize),
    /// `a / (1.5 + b²)`: never divides by zero.
    Div(usize, usize),
    Neg(usize),
    Sin(usize),
    Cos(usize),
    /// `√(1 + a²)`.
    Sqrt(usize),
}

const CONSTANTS: [f64; 6] = [0.0, 1.0, -1.0, 2.0, 0.5, -3.0];
const N_INPUTS: usize = 4;

fn run<T: Scalar>(steps: &[Step], inputs: &[T]) -> Vec<T> {
    let mut v: Vec<T> = inputs.to_vec();
    v.extend(CONSTANTS.iter().map(|&x| T::from_f64(x)));
    for &step in steps {
        let x = match step {
            Step::Add(a, b) => v[a] + v[b],
            Step::Sub(a, b) => v[a] - v[b],
            Step::Mul(a, b) => v[a] * v[b],
            Step::Div(a, b) => v[a] / (T::from_f64(1.5) + v[b] * v[b]),
            Step::Neg(a) => -v[a],
            Step::Sin(a) => v[a].sin_cos().0,
            Step::Cos(a) => v[a].sin_cos().1,
            Step::Sqrt(a) => (T::one() + v[a] * v[a]).sqrt(),
        };
        v.push(x);
    }
    v
}

fn random_program(rng: &mut Rng, len: usize) -> Vec<Step> {
    let base = N_INPUTS + CONSTANTS.len();
    (0..len)
        .map(|k| {
            let n = base + k;
            // Favour recent values (deep trees) and the constants (folding patterns).
            let pick = |rng: &mut Rng| match rng.below(3) {
                0 => N_INPUTS + rng.below(CONSTANTS.len()),
                1 => n - 1 - rng.below(n.min(4)),
                _ => rng.below(n),
            };
            let (a, b) = (pick(rng), pick(rng));
            match rng.below(8) {
                0 => Step::Add(a, b),
                1 => Step::Sub(a, b),
                2 => Step::Mul(a, b),
                3 => Step::Div(a, b),
                4 => Step::Neg(a),
                5 => Step::Sin(a),
                6 => Step::Cos(a),
                _ => Step::Sqrt(a),
            }
        })
        .collect()
}

#[test]
fn eval_equals_the_same_code_run_on_f64() {
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut compared = 0;
    for _ in 0..200 {
        let steps = random_program(&mut rng, 40);
        let (graph, outputs) = trace(|| {
            let inputs: Vec<Sym> = (0..N_INPUTS).map(q).collect();
            run(&steps, &inputs)
        });
        assert_no_foldable_pattern(&graph);
        for _ in 0..3 {
            let x: Vec<f64> = (0..N_INPUTS).map(|_| rng.range(-2.0, 2.0)).collect();
            let direct = run(&steps, &x);
            let symbolic = graph.eval(&outputs, |v| match v {
                Var::Q(i) => x[i],
                other => panic!("unexpected input {other:?}"),
            });
            for (k, (d, s)) in direct.iter().zip(&symbolic).enumerate() {
                if d.is_finite() {
                    // The rewrites are exact in IEEE arithmetic (x+(−y) = x−y, a·b = b·a,
                    // sin(−x) = −sin x, …), so the values agree to the bit.
                    assert_eq!(d, s, "value {k} of {steps:?} at {x:?}");
                    compared += 1;
                }
            }
        }
    }
    assert!(compared > 10_000, "only {compared} finite values compared");
}

#[test]
fn op_counts_of_a_hand_counted_expression() {
    // y = (q0·q1 + 2·sin q0) / √(q2 − cos q0) − q1, and z = −(q0·q1) dead or alive.
    let (graph, (y, z)) = trace(|| {
        let (s, co) = q(0).sin_cos();
        let p = q(0) * q(1);
        let y = (p + c(2.0) * s) / (q(2) - co).sqrt() - q(1);
        let z = -p;
        (y, z)
    });
    // mul: q0·q1, 2·s; add: p + 2s, q2 − c, … − q1; div 1; sqrt 1; sin/cos 1 pair.
    let expected = OpCounts {
        adds: 3,
        muls: 2,
        divs: 1,
        negs: 0,
        sin_cos: 1,
        sqrts: 1,
    };
    assert_eq!(graph.op_counts(&[y]), expected);
    assert_eq!(expected.total(), 8);
    let with_z = graph.op_counts(&[y, z]);
    assert_eq!(with_z.negs, 1);
    assert_eq!(with_z.total(), 9);
    assert_eq!(
        expected.to_string(),
        "3 add/sub, 2 mul, 1 div, 0 neg, 1 sin/cos, 1 sqrt (8 total)"
    );
}

#[test]
fn dead_nodes_are_dropped() {
    let (graph, (y, dead)) = trace(|| {
        let dead = (q(3) * q(4)).sqrt() + c(7.0);
        let y = q(0) * q(1);
        (y, dead)
    });
    let live = graph.live(&[y]);
    assert_eq!(live.len(), 3, "q0, q1, q0·q1");
    assert!(!live.contains(&dead));
    let order = order(&graph);
    assert!(live.windows(2).all(|w| order[&w[0]] < order[&w[1]]));
    assert_eq!(graph.op_counts(&[y]).total(), 1);
    // Dead inputs are never read.
    let values = graph.eval(&[y], |v| match v {
        Var::Q(0) => 3.0,
        Var::Q(1) => 5.0,
        other => panic!("dead input {other:?} read"),
    });
    assert_eq!(values, vec![15.0]);
    // Nothing live beyond an input.
    assert_eq!(graph.live(&[]).len(), 0);
}

#[test]
fn names_first_one_wins_and_constants_and_inputs_take_none() {
    let (graph, (p, x)) = trace(|| {
        let p = (q(0) * q(1)).named("body1 r_x");
        let again = (q(1) * q(0)).named("other");
        assert_eq!(p, again);
        let x = q(0).named("angle");
        (p, x)
    });
    assert_eq!(graph.hint_of(p), Some("body1 r_x"));
    assert_eq!(graph.hint_of(x), None);
}

#[test]
fn traces_nest_and_each_sym_belongs_to_its_own() {
    let (outer, (y, inner, z)) = trace(|| {
        let a = q(0) + q(1);
        let (inner, w) = trace(|| q(0) * c(3.0));
        // The outer trace resumes where it was.
        let y = a * q(2);
        // A Sym of the outer trace used inside an inner one is caught.
        let caught = std::panic::catch_unwind(|| trace(|| a + c(1.0)));
        assert!(caught.is_err());
        // … and the outer trace is still intact after the inner one unwound.
        let z = a - q(2);
        (y, (inner, w), z)
    });
    let (inner, w) = inner;
    let at = |v: Var| match v {
        Var::Q(i) => [1.0, 2.0, 4.0][i],
        _ => 0.0,
    };
    assert_eq!(outer.eval(&[y, z], at), vec![12.0, -1.0]);
    assert_eq!(inner.eval(&[w], at), vec![3.0]);
    assert_eq!(inner.len(), 3);
    // A Sym used with another graph is caught too.
    assert!(std::panic::catch_unwind(|| outer.eval(&[w], at)).is_err());
}

#[test]
fn a_sym_outside_any_trace_panics_with_a_message() {
    let (_, escaped) = trace(|| q(0));
    let err = std::panic::catch_unwind(|| escaped + escaped).unwrap_err();
    let msg = err
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| err.downcast_ref::<&str>().copied())
        .unwrap_or("");
    assert!(msg.contains("outside `sym::trace`"), "{msg}");
}

#[test]
fn map_constants_refolds_and_keeps_names() {
    let (graph, out) = trace(|| {
        let x = q(0);
        let named = (c(1.0 + 1e-10) * x + c(2.0)).named("shifted");
        vec![named * c(0.5), c(3.0)]
    });
    let (rounded, new) = graph.map_constants(&out, |x| f64::from(x as f32));
    // 1 + 1e-10 became 1 and the product with x folded away: x + 2, (x + 2)·0.5, and 3.
    assert_eq!(rounded.op_counts(&new).total(), 2);
    assert_eq!(rounded.hint_of(rounded.live(&new[..1])[2]), Some("shifted"));
    let at = |_: Var| 0.25;
    assert_eq!(rounded.eval(&new, at), vec![1.125, 3.0]);
    approx::assert_relative_eq!(graph.eval(&out, at)[0], 1.125, max_relative = 1e-9);
}

#[test]
fn numbers_as_written_fold_in_exact_decimal_arithmetic() {
    // Sums, differences and products of numbers as written are exact and rounded once: the
    // regrouped inertia 3.2 − 2.8 is 0.4, not the 0.40000000000000036 of binary arithmetic.
    let (_, folded) = trace(|| {
        [
            c(3.2) - c(2.8),
            c(0.1) + c(0.2),
            (c(50.9) * c(0.32) * c(0.32) + c(2.8)) - (c(50.9) * c(0.1024) + c(3.2)),
            c(1.2) * c(0.6),
        ]
        .map(|s| s.constant())
    });
    assert_eq!(folded, [Some(0.4), Some(0.3), Some(-0.4), Some(0.72)]);
    // A quotient is a binary value: what it takes part in folds in binary, as IEEE computes it.
    let (_, folded) = trace(|| (c(1.0) / c(10.0) + c(0.2)).constant());
    assert_eq!(folded, Some(1.0 / 10.0 + 0.2));
    assert_ne!(folded, Some(0.3));
}
