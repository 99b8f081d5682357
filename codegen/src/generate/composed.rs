//! `forward_dynamics_derivatives` of a large chain, composed of three smaller generated
//! functions rather than traced whole.
//!
//! Traced whole, the derivatives of forward dynamics are one straight-line function of the most
//! operations the generator knows, and for a large chain that is the wrong measure of speed: the
//! humanoid's is hundreds of kilobytes of machine code run once per call, many times what a
//! core's instruction caches hold, so it runs at about one instruction per cycle, bound by
//! fetching its code rather than by its arithmetic (`BENCHMARKS.md`'s derivative tables have
//! its time and instructions). Composed, the same values come from
//! three functions of a few tens of thousands of operations each and two products that are
//! loops (Carpentier & Mansard 2018, §III: the derivatives of forward dynamics from those of
//! inverse dynamics):
//!
//! ```text
//! q̈ = forward_dynamics(q, v, τ)
//! (∂τ/∂q, ∂τ/∂v) = inverse_dynamics_derivatives(q, v, q̈)
//! ∂q̈/∂q = −M⁻¹·∂τ/∂q,  ∂q̈/∂v = −M⁻¹·∂τ/∂v,  with M⁻¹ = mass_matrix_inverse(q)
//! ```
//!
//! the products visiting only the entries of `∂τ` the traced inverse-dynamics derivatives can
//! make non-zero (`articulated::__private::minus_product`). More operations in all,
//! fewer instructions fetched: faster past [`COMPOSE_OPS`], slower below it.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use super::{docs, function, Context};
use crate::options::{Output, ScalarKind};
use crate::outputs::Arg;
use crate::sym::{Node, OpCounts};

/// The most operations of a traced `forward_dynamics_derivatives` that the generator emits as
/// one function; past it, the composition. Set between the chains measured side by side
/// (x86-64-v3, the traced and the composed function in one binary): arm7 (6,320 operations
/// traced) ran faster traced, the humanoid's legs on its free base (`keep`, 33,647) and every
/// larger chain faster composed. The figures are in the message of the commit that set it.
pub(super) const COMPOSE_OPS: usize = 20_000;

/// The parts, each with what it returns (for its private function's docs).
const PARTS: [(Output, &str); 3] = [
    (Output::ForwardDynamics, "q̈, as `forward_dynamics`"),
    (
        Output::InverseDynamicsDerivatives,
        "`(∂τ/∂q, ∂τ/∂v)`, as `inverse_dynamics_derivatives`",
    ),
    (Output::MassMatrixInverse, "`M⁻¹`, as `mass_matrix_inverse`"),
];

/// The trait impl of the composed `forward_dynamics_derivatives` (`traced_ops`: what the traced
/// function would have taken), preceded by the parts the description does not ask for as
/// outputs of their own, as private functions of the chain; and the composed operation count.
pub(super) fn item(cx: &Context, traced_ops: OpCounts) -> syn::Result<(TokenStream, OpCounts)> {
    let mut privates = Vec::new();
    let mut calls = Vec::new();
    let mut ops = OpCounts::default();
    let mut rows = None;
    let mut traces = Vec::new();
    for (output, what) in PARTS {
        let traced = cx.trace(output);
        let part_ops = traced.graph.op_counts(&function::outputs(cx, &traced));
        cx.checked(&traced, &part_ops)?;
        ops = ops + part_ops;
        if output == Output::InverseDynamicsDerivatives {
            rows = Some(nonzero_rows(&traced, cx.nv));
        }
        let with = output.spec().with_name();
        if cx.options.outputs.contains(&output) {
            let trait_ = function::trait_path(cx, output);
            calls.push(quote!(<Self as #trait_>::#with));
        } else {
            let name = format_ident!("forward_dynamics_derivatives_part_{}", output.name());
            let doc = format!(
                " Part of [`forward_dynamics_derivatives`](Self::forward_dynamics_derivatives): \
                 {what}."
            );
            privates.push(function::part(cx, &traced, &name, &doc)?);
            calls.push(quote!(Self::#name));
        }
        traces.push(traced);
    }
    let (dq_rows, dv_rows) = rows.unwrap_or_default();
    // Each product: a multiply and an add per visited entry of `∂τ` and row of `M⁻¹`, and the
    // negation of the visited entry.
    let visited = dq_rows.iter().chain(&dv_rows).map(Vec::len).sum::<usize>();
    ops.muls += visited * cx.nv;
    ops.adds += visited * cx.nv;
    ops.negs += visited;
    let [fd, idd, minv] = &calls[..] else {
        unreachable!("three parts")
    };
    let fma = match cx.options.scalar {
        ScalarKind::F64 => quote!(::articulated::math::mul_add),
        ScalarKind::F32 => quote!(::articulated::math::mul_addf),
        ScalarKind::Generic => quote!(|a: T, b: T, c: T| a * b + c),
    };
    let (dq_const, dv_const) = (rows_const("DQ", &dq_rows), rows_const("DV", &dv_rows));
    let docs = doc(cx, &traced_ops, &ops, &dq_rows, &dv_rows)
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    let output = Output::ForwardDynamicsDerivatives;
    let trait_ = function::trait_path(cx, output);
    let ret = output.spec().ret(&cx.types());
    let with = output.spec().with_name();
    let (name, generics, params_ty) = (&cx.name, &cx.impl_generics, &cx.params_ty);
    let privates = (!privates.is_empty()).then(|| quote!(impl #name { #(#privates)* }));
    let types = cx.types();
    let [q_ty, v_ty, tau_ty] =
        [Arg::Q, Arg::V, Arg::Tau].map(|arg| output.spec().arg_type(arg, &types));
    let private = quote!(::articulated::__private);
    let batch = match (cx.options.lanes, cx.options.scalar) {
        (Some(n), ScalarKind::F64 | ScalarKind::F32) => {
            batch(cx, n, &traces, quote!(#dq_const #dv_const))?
        }
        _ => TokenStream::new(),
    };
    let tokens = quote! {
        #privates
        impl #generics #trait_ for #name {
            #(#docs)*
            fn #with(q: &#q_ty, v: &#v_ty, tau: &#tau_ty, p: &#params_ty) #ret {
                // The rows of each column of `∂τ/∂q` and `∂τ/∂v` that can be non-zero.
                #dq_const
                #dv_const
                let qdd = #fd(q, v, tau, p)?;
                // The parts borrowed where they lie: moving these matrices is copying them.
                let dtau = #idd(q, v, &qdd, p);
                match #minv(q, p) {
                    Ok(minv) => Ok((
                        #private::minus_product(&minv, &dtau.0, &DQ, #fma),
                        #private::minus_product(&minv, &dtau.1, &DV, #fma),
                        minv,
                    )),
                    Err(e) => Err(e),
                }
            }
            #batch
        }
    };
    Ok((tokens, ops))
}

/// The composed function's batch twin in lanes: each group of states through the three parts
/// in lanes (`articulated::lanes::fit`: each part has thousands of operations, past
/// `function::FIT_OPS`) and the two products in lanes
/// (`articulated::__private::lanes_minus_product`), so that each state's result is the scalar
/// function's bit for bit; a lane whose forward dynamics or `M⁻¹` fails has that error, its
/// neighbours their values. `parts`: the traces of [`PARTS`], in order; `rows`: the constants
/// `DQ` and `DV` of the scalar function, which the products read here too.
fn batch(
    cx: &Context,
    n: usize,
    parts: &[crate::trace::Traced],
    rows: TokenStream,
) -> syn::Result<TokenStream> {
    let lanes = cx.with_lanes(n, true);
    let n_lit = function::group_size(n, true);
    let names = [
        format_ident!("forward_dynamics_lanes"),
        format_ident!("inverse_dynamics_derivatives_lanes"),
        format_ident!("mass_matrix_inverse_lanes"),
    ];
    let inner = parts
        .iter()
        .zip(&names)
        .map(|(traced, name)| function::lane_part(&lanes, traced, name, &n_lit))
        .collect::<syn::Result<Vec<_>>>()?;
    let [fd, idd, minv] = &names;
    let gather = quote!(::articulated::lanes::gather);
    let private = quote!(::articulated::__private);
    let group = quote! {
        let (q, v, tau) = (#gather(q), #gather(v), #gather(tau));
        let (qdd, fd_status) = #fd(&q, &v, &tau, &lanes_p);
        let dtau = #idd(&q, &v, &qdd, &lanes_p);
        let (minv, minv_status) = #minv(&q, &lanes_p);
        // The scalar function's error: forward dynamics' first, then `M⁻¹`'s.
        let status: [_; #n_lit] = ::core::array::from_fn(|l| fd_status[l].or(minv_status[l]));
        let values = (
            #private::lanes_minus_product(&minv, &dtau.0, &DQ),
            #private::lanes_minus_product(&minv, &dtau.1, &DV),
            minv,
        );
        ::articulated::lanes::scatter_results(&values, &status, out);
    };
    Ok(function::batch_shell(
        cx,
        Output::ForwardDynamicsDerivatives,
        (&lanes, &n_lit, true),
        quote!(#(#inner)* #rows),
        TokenStream::new(),
        group,
    ))
}

/// `const NAME: [&[u16]; C] = […];`: the rows of each of the `C` columns that can be non-zero,
/// which `articulated::__private::minus_product` (and the composed constrained derivatives)
/// visit.
pub(super) fn rows_const(name: &str, rows: &[Vec<u16>]) -> TokenStream {
    let name = Ident::new(name, Span::call_site());
    let c = Literal::usize_unsuffixed(rows.len());
    let columns = rows.iter().map(|r| {
        let r = r.iter().map(|&k| Literal::u16_unsuffixed(k));
        quote!(&[#(#r),*])
    });
    quote!(const #name: [&[u16]; #c] = [#(#columns),*];)
}

/// The rows of each column of `∂τ/∂q` and of `∂τ/∂v` (in `traced`, the inverse-dynamics
/// derivatives: both row-major) that are not the constant zero.
pub(super) fn nonzero_rows(
    traced: &crate::trace::Traced,
    nv: usize,
) -> (Vec<Vec<u16>>, Vec<Vec<u16>>) {
    let rows = |start: usize| -> Vec<Vec<u16>> {
        (0..nv)
            .map(|c| {
                (0..nv)
                    .filter(|&r| {
                        let s = traced.values[start + r * nv + c];
                        !matches!(traced.graph.node(s), Node::Const(x) if x == 0.0)
                    })
                    .map(|r| u16::try_from(r).unwrap_or(u16::MAX))
                    .collect()
            })
            .collect()
    };
    (rows(0), rows(nv * nv))
}

/// The composed function's docs: what it returns, how, and its operations.
fn doc(
    cx: &Context,
    traced: &OpCounts,
    ops: &OpCounts,
    dq_rows: &[Vec<u16>],
    dv_rows: &[Vec<u16>],
) -> Vec<String> {
    let nn = cx.nv * cx.nv;
    let count = |rows: &[Vec<u16>]| rows.iter().map(Vec::len).sum::<usize>();
    let mut paragraphs = vec![
        Output::ForwardDynamicsDerivatives
            .spec()
            .equation
            .to_string(),
        format!(
            "Composed: `q̈` by forward dynamics, `(∂τ/∂q, ∂τ/∂v)` by the derivatives of inverse \
             dynamics at `(q, v, q̈)`, `M⁻¹`, then `∂q̈/∂q = −M⁻¹·∂τ/∂q` and `∂q̈/∂v = \
             −M⁻¹·∂τ/∂v` (Carpentier & Mansard 2018), visiting the {} of {nn} entries of \
             `∂τ/∂q` and the {} of `∂τ/∂v` that can be non-zero. Traced whole, this function \
             would be {} operations of straight-line code, more than the generator emits as one \
             function ({} at most): composed, it fetches far less code per call, which is what \
             bounds a function that large.",
            count(dq_rows),
            count(dv_rows),
            traced.total(),
            COMPOSE_OPS
        ),
        format!(
            "Operations, the three parts and the products: {}.",
            docs::operations(ops)
        ),
    ];
    if let Some(source) = cx.source {
        paragraphs.push(format!("`articulated expand {source}` prints this code."));
    }
    docs::lines(&paragraphs)
}
