//! Sines, cosines and square roots in each scalar, and the joint angles' sines and cosines
//! computed together at the top of an `f64` function.
//!
//! - `f64`: one `::articulated::math::sincos_array([…])` for the sines and cosines of the inputs
//!   (two angles per SSE2 instruction, four under AVX2, no branches, within 1 ulp of `libm`),
//!   `::articulated::libm::{sin, cos, sincos, sqrt}` otherwise;
//! - `f32`: one `::articulated::math::sincosf_array([…])` for the inputs' (four angles at a time,
//!   `libm::sincosf`'s algorithm in `f64` lanes, the `f32` batch functions' own),
//!   `::articulated::libm::{sinf, cosf, sincosf, sqrtf}` otherwise;
//! - generic: the methods `x.sin()`, `x.cos()`, `x.sin_cos()`, `x.sqrt()` of
//!   `nalgebra::ComplexField` (callable through the `RealField` bound).

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::options::ScalarKind;
use crate::sym::{Graph, Node, Sym};

/// The math functions the emitted code calls.
#[derive(Clone, Copy)]
pub(super) enum MathFn {
    Sin,
    Cos,
    SinCos,
    Sqrt,
}

/// The call of `f` on `x` in `scalar`.
pub(super) fn call(scalar: ScalarKind, lanes: bool, f: MathFn, x: TokenStream) -> TokenStream {
    let (free, method) = match f {
        MathFn::Sin => ("sin", "sin"),
        MathFn::Cos => ("cos", "cos"),
        MathFn::SinCos => ("sincos", "sin_cos"),
        MathFn::Sqrt => ("sqrt", "sqrt"),
    };
    if lanes {
        let f = format_ident!("{}", free);
        return quote!(::articulated::lanes::#f(#x));
    }
    match scalar {
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

/// The live sines and cosines by argument, so that both are computed by one call.
#[derive(Default)]
pub(super) struct Trig {
    /// `sin(a)` by `a`.
    pub sin_of: HashMap<Sym, Sym>,
    /// `cos(a)` by `a`.
    pub cos_of: HashMap<Sym, Sym>,
}

impl Trig {
    pub(super) fn of(graph: &Graph, live: &[Sym]) -> Trig {
        let mut t = Trig::default();
        for &s in live {
            match graph.node(s) {
                Node::Sin(a) => {
                    t.sin_of.insert(a, s);
                }
                Node::Cos(a) => {
                    t.cos_of.insert(a, s);
                }
                _ => {}
            }
        }
        t
    }

    /// The angles whose sine or cosine is live, in order of first use: the inputs, and an input
    /// plus or minus a constant (a joint angle with its placement's turn folded in,
    /// `crate::trace::turns`). In `f64` they are computed by one `sincos_array` call when
    /// there are two or more.
    pub(super) fn batched_angles(&self, graph: &Graph, live: &[Sym]) -> Vec<Sym> {
        let mut angles: Vec<Sym> = Vec::new();
        for &s in live {
            if let Node::Sin(a) | Node::Cos(a) = graph.node(s) {
                if is_angle(graph, a) && !angles.contains(&a) {
                    angles.push(a);
                }
            }
        }
        angles
    }
}

/// An input, or an input plus or minus a constant.
fn is_angle(graph: &Graph, a: Sym) -> bool {
    let input = |x: Sym| matches!(graph.node(x), Node::Input(_));
    let constant = |x: Sym| matches!(graph.node(x), Node::Const(_));
    match graph.node(a) {
        Node::Input(_) => true,
        Node::Add(x, y) | Node::Sub(x, y) => (input(x) && constant(y)) || (constant(x) && input(y)),
        _ => false,
    }
}
