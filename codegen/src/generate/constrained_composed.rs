//! `constrained_forward_dynamics_derivatives` of a large chain, composed of smaller generated
//! functions and products at run time rather than traced whole (as
//! [`composed`](super::composed) does for `forward_dynamics_derivatives`, for the same reason:
//! traced whole, the humanoid's on two feet is a few hundred thousand operations of
//! straight-line code, bound by fetching it).
//!
//! At the solution `(q̈, f)` the residuals `r₁ = ID(q, v, q̈) − Jᵀ·f − τ` and `r₂ = J·q̈ + γ`
//! vanish for every state, so along any direction (Pinocchio's
//! `computeConstraintDynamicsDerivatives` takes the same path)
//!
//! ```text
//! (∂q̈, ∂f) = −N·(∂r₁, ∂r₂),   N = [M −Jᵀ; J 0]⁻¹ with its second block column negated
//! ```
//!
//! whose first `nv` columns are `∂(q̈, f)/∂τ` (`∂r₁/∂τ = −1`). The parts:
//!
//! ```text
//! (q̈, f)            = constrained_forward_dynamics(q, v, τ)?
//! M⁻¹               = mass_matrix_inverse(q)?
//! ∂ID/∂q, ∂ID/∂v    = inverse_dynamics_derivatives(q, v, q̈)
//! ∂c/∂q, ∂c/∂v, J   = the constraints' terms c = (−Jᵀ·f, J·q̈ + γ) at (q, v, q̈, f), by
//!                     forward mode on massless bodies (a few thousand operations)
//! N                 = from M⁻¹ and J: G = J·M⁻¹·Jᵀ factored, dense products
//! (∂q̈, ∂f)/∂x       = −N·((∂ID/∂x, 0) + ∂c/∂x)   for x = q, v
//! ```
//!
//! the last products visiting only the entries of `∂r` the traced parts can make non-zero, all
//! in the runtime's axes (a six-dimensional constraint's rows and wrench in its frame), at run
//! time (`articulated::constraint::derivatives::composed`). Inverse dynamics' derivatives and
//! `M⁻¹` are the composed `forward_dynamics_derivatives`' own parts where it is composed too.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use super::composed::{rows_const, COMPOSE_OPS};
use super::constraints::vector_type;
use super::function::{self, Used};
use super::{docs, Context};
use crate::emit;
use crate::options::Output;
use crate::sym::{Graph, Node, OpCounts, Sym};
use crate::trace::constrained::{self, Constraint};

/// Whether a traced `constrained_forward_dynamics_derivatives` of `ops` is emitted composed:
/// past the threshold of the composed `forward_dynamics_derivatives`, for the same reason. Below
/// it the traced function is faster (arm7 with its flange welded, measured side by side: the
/// figures are in the commit that set it).
pub(super) fn composes(ops: &OpCounts) -> bool {
    ops.total() > COMPOSE_OPS
}

/// The composed function (`traced_ops`: what the traced function would have taken, `solve_ops`:
/// `constrained_forward_dynamics`'), preceded by the parts the chain does not have already, as
/// private functions; and its operation count. `fdd_composed`: the composed
/// `forward_dynamics_derivatives` has its `M⁻¹` part.
pub(super) fn item(
    cx: &Context,
    constraints: &[Constraint],
    (traced_ops, solve_ops): (&OpCounts, &OpCounts),
    fdd_composed: bool,
) -> syn::Result<(TokenStream, OpCounts)> {
    let (nv, rows) = (cx.nv, cx.options.constraint_rows());
    let n = nv + rows;
    let (graph, values) = constrained::trace_constraint_terms(cx.model, &cx.frames(), constraints);
    let terms_ops = graph.op_counts(&values);
    let mut privates = vec![terms_function(cx, &graph, &values)?];
    let (minv_call, _, minv_ops) =
        part(cx, Output::MassMatrixInverse, fdd_composed, &mut privates)?;
    let (idd_call, idd, idd_ops) = part(
        cx,
        Output::InverseDynamicsDerivatives,
        fdd_composed,
        &mut privates,
    )?;
    // The rows of `∂r` that can be non-zero: inverse dynamics' (the first `nv`) and the
    // constraints' terms'.
    let (id_q, id_v) = super::composed::nonzero_rows(&idd, nv);
    let union = |id: Vec<Vec<u16>>, start: usize| -> Vec<Vec<u16>> {
        id.into_iter()
            .zip(nonzero_rows(&graph, &values[start..start + n * nv], n, nv))
            .map(|(mut a, b)| {
                a.extend(b);
                a.sort_unstable();
                a.dedup();
                a
            })
            .collect()
    };
    let (dq_rows, dv_rows) = (union(id_q, 0), union(id_v, n * nv));
    let visited = dq_rows.iter().chain(&dv_rows).map(Vec::len).sum::<usize>();
    // The dense products of `N` (`J·M⁻¹`, `G`, `G⁻¹·J·M⁻¹`, `P`: about `rows·nv²` each and
    // `G`'s factorization), then the two sparse ones: a multiply and an add per visited entry
    // of `∂r` and row of `N`, and the entry's negation.
    let mut ops = *solve_ops + minv_ops + idd_ops + terms_ops;
    let dense = 3 * rows * nv * nv + rows * rows * nv + rows * rows * rows;
    ops.muls += dense + visited * n;
    ops.adds += dense + visited * n;
    ops.divs += rows * rows;
    ops.negs += visited;

    let consts = consts((&dq_rows, &dv_rows), constraints);
    let paragraphs = doc(
        cx,
        (traced_ops, &ops),
        [solve_ops, &minv_ops, &idd_ops, &terms_ops],
        visited,
    );
    let docs = docs::lines(&paragraphs)
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    let (q_ty, v_ty) = (vector_type(cx, cx.nq), vector_type(cx, nv));
    let params_ty = &cx.params_ty;
    let params = if cx.param_idents.is_empty() {
        quote!(&())
    } else {
        quote!(&<#params_ty>::defaults())
    };
    let (nv, r, n) = (
        Literal::usize_unsuffixed(nv),
        Literal::usize_unsuffixed(rows),
        Literal::usize_unsuffixed(n),
    );
    let private = quote!(::articulated::__private);
    let error = quote!(::articulated::constraint::ConstraintError);
    let tokens = quote! {
        #(#privates)*
        #(#docs)*
        pub fn constrained_forward_dynamics_derivatives(
            q: &#q_ty,
            v: &#v_ty,
            tau: &#v_ty,
        ) -> ::core::result::Result<
            ::articulated::constraint::derivatives::Derivatives<#nv, #r>,
            #error,
        > {
            #consts
            let (qdd, forces) = Self::constrained_forward_dynamics(q, v, tau)?;
            // Each part borrowed where it lies, not moved: moving these matrices is copying them.
            let minv = #minv_call(q, #params);
            let minv = match &minv {
                Ok(minv) => minv,
                Err(e) => return Err(#error::MassMatrix { velocity: e.velocity }),
            };
            let dtau = #idd_call(q, v, &qdd, #params);
            let terms =
                Self::constrained_forward_dynamics_derivatives_part_constraints(q, v, &qdd, &forces);
            let solution = ::articulated::constraint::Solution {
                acceleration: qdd,
                forces,
                rows: #r,
                residual: terms.2,
                iterations: 1,
            };
            #private::constrained_derivatives::<#nv, #r, #n>(
                solution,
                minv,
                (&dtau.0, &dtau.1),
                (&terms.0, &terms.1),
                (&DQ, &DV),
                &terms.3,
                ::articulated::constraint::PIVOT_TOLERANCE,
                &OWNERS,
            )
        }
    };
    Ok((tokens, ops))
}

/// The composed function's constants: the rows of each column of `∂r/∂q` (`DQ`) and `∂r/∂v`
/// (`DV`) that can be non-zero, and for each row of `G` its constraint and its row there
/// (`OWNERS`, for `ConstraintError::Redundant`).
fn consts(
    (dq_rows, dv_rows): (&[Vec<u16>], &[Vec<u16>]),
    constraints: &[Constraint],
) -> TokenStream {
    let (dq, dv) = (rows_const("DQ", dq_rows), rows_const("DV", dv_rows));
    let owners = constraints.iter().enumerate().flat_map(|(c, constraint)| {
        (0..constraint.rows()).map(move |row| {
            let (c, row) = (Literal::usize_unsuffixed(c), Literal::usize_unsuffixed(row));
            quote!((#c, #row))
        })
    });
    let rows = Literal::usize_unsuffixed(constraints.iter().map(|c| c.rows()).sum());
    quote! {
        #dq
        #dv
        const OWNERS: [(usize, usize); #rows] = [#(#owners),*];
    }
}

/// How the composed function calls `output` (`mass_matrix_inverse` or
/// `inverse_dynamics_derivatives`, each `(…, p)`): through its trait where the description
/// asks for it, as the composed `forward_dynamics_derivatives`' part where that is there
/// (`fdd_composed`), else as a private part of its own pushed on `privates`; with its trace and
/// its operations.
fn part(
    cx: &Context,
    output: Output,
    fdd_composed: bool,
    privates: &mut Vec<TokenStream>,
) -> syn::Result<(TokenStream, crate::trace::Traced, OpCounts)> {
    let traced = cx.trace(output);
    let ops = traced.graph.op_counts(&function::outputs(cx, &traced));
    cx.checked(&traced, &ops)?;
    let call = if cx.options.outputs.contains(&output) {
        let trait_ = function::trait_path(cx, output);
        let with = output.spec().with_name();
        quote!(<Self as #trait_>::#with)
    } else {
        let owner = if fdd_composed {
            "forward_dynamics_derivatives"
        } else {
            "constrained_forward_dynamics_derivatives"
        };
        let name = format_ident!("{owner}_part_{}", output.name());
        if !fdd_composed {
            let doc = format!(
                " Part of [`constrained_forward_dynamics_derivatives`]\
                 (Self::constrained_forward_dynamics_derivatives): as `{}`.",
                output.name()
            );
            privates.push(function::part(cx, &traced, &name, &doc)?);
        }
        quote!(Self::#name)
    };
    Ok((call, traced, ops))
}

/// The constraints' part: `∂c/∂q`, `∂c/∂v` and the rows `J` (stored entry by entry where they
/// are computed) and `max |r₂|`, from `(q, v)` and the solution `(q̈, f)`
/// ([`constrained::trace_constraint_terms`]).
fn terms_function(cx: &Context, graph: &Graph, values: &[Sym]) -> syn::Result<TokenStream> {
    let (nv, rows) = (cx.nv, cx.options.constraint_rows());
    let n = nv + rows;
    let (sink, declare) = sink(
        cx,
        &[("dc_dq", n, nv), ("dc_dv", n, nv), ("rows", rows, nv)],
    );
    let emitted = emit::straight_line_into(
        graph,
        values,
        cx.options.scalar,
        &|var| cx.input(var),
        Some(&sink),
        None,
    )?;
    let mut used = Used::in_graph(graph, values, cx.nq, nv, 0);
    used.forces.resize(rows, false);
    let [bind_q, bind_v, bind_a, bind_f] = [
        ("q", &used.q),
        ("v", &used.v),
        ("a", &used.a),
        ("force", &used.forces),
    ]
    .map(|(name, used)| function::destructure(name, used));
    let params_ty = &cx.params_ty;
    let bind_params = used
        .params
        .then(|| quote!(let p = &<#params_ty>::defaults();));
    let residuals = &emitted.outputs[(2 * n + rows) * nv..];
    let (uses, statements) = (&emitted.uses, &emitted.statements);
    let (q_ty, v_ty, r_ty) = (
        vector_type(cx, cx.nq),
        vector_type(cx, nv),
        vector_type(cx, rows),
    );
    let (n, nv, r) = (
        Literal::usize_unsuffixed(n),
        Literal::usize_unsuffixed(nv),
        Literal::usize_unsuffixed(rows),
    );
    Ok(quote! {
        /// Part of [`constrained_forward_dynamics_derivatives`](Self::constrained_forward_dynamics_derivatives):
        /// the constraints' share `c = (−Jᵀ·f, J·q̈ + γ)` of the residuals' derivatives,
        /// `∂c/∂q` and `∂c/∂v` at `(q, v)` with the solution `(q̈, f)` held fixed, `max |J·q̈ +
        /// γ|` over the rows and the rows `J` (a six-dimensional constraint's in its frame).
        #[inline(never)]
        #[allow(clippy::type_complexity)]
        fn constrained_forward_dynamics_derivatives_part_constraints(
            q: &#q_ty,
            v: &#v_ty,
            a: &#v_ty,
            force: &#r_ty,
        ) -> (
            ::articulated::nalgebra::SMatrix<f64, #n, #nv>,
            ::articulated::nalgebra::SMatrix<f64, #n, #nv>,
            f64,
            ::articulated::nalgebra::SMatrix<f64, #r, #nv>,
        ) {
            #declare
            #uses
            #bind_q
            #bind_v
            #bind_a
            #bind_f
            #bind_params
            #statements
            let residual = [#(#residuals),*].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            (dc_dq, dc_dv, residual, rows)
        }
    })
}

/// A sink that stores the first values into the `matrices` (name, rows, columns), one after
/// the other, each row-major; and the matrices' declarations (zero).
fn sink(cx: &Context, matrices: &[(&str, usize, usize)]) -> (emit::Sink, TokenStream) {
    let mut places = Vec::new();
    let mut declare = TokenStream::new();
    let zero = emit::zero(cx.options.scalar);
    for &(name, rows, cols) in matrices {
        let name = format_ident!("{name}");
        places.extend((0..rows * cols).map(|i| {
            let (r, c) = (
                Literal::usize_unsuffixed(i / cols),
                Literal::usize_unsuffixed(i % cols),
            );
            vec![quote!(#name.data.0[#c][#r])]
        }));
        let (r, c) = (
            Literal::usize_unsuffixed(rows),
            Literal::usize_unsuffixed(cols),
        );
        declare.extend(quote! {
            let mut #name = ::articulated::nalgebra::SMatrix::<f64, #r, #c>::from_array_storage(
                ::articulated::nalgebra::ArrayStorage([[#zero; #r]; #c])
            );
        });
    }
    let sink = emit::Sink {
        places,
        boundaries: false,
    };
    (sink, declare)
}

/// The rows of each column of a row-major `rows × cols` matrix of `values` that are not the
/// constant zero.
fn nonzero_rows(graph: &Graph, values: &[Sym], rows: usize, cols: usize) -> Vec<Vec<u16>> {
    (0..cols)
        .map(|c| {
            (0..rows)
                .filter(
                    |&r| !matches!(graph.node(values[r * cols + c]), Node::Const(x) if x == 0.0),
                )
                .map(|r| u16::try_from(r).unwrap_or(u16::MAX))
                .collect()
        })
        .collect()
}

/// The composed function's docs: what it returns, how, and its operations (`ops`: the traced
/// function's and the composed one's; `parts`: the solve's, `M⁻¹`'s, inverse dynamics'
/// derivatives' and the constraints' terms').
fn doc(
    cx: &Context,
    (traced, ops): (&OpCounts, &OpCounts),
    parts: [&OpCounts; 4],
    visited: usize,
) -> Vec<String> {
    let (nv, rows) = (cx.nv, cx.options.constraint_rows());
    let [solve, minv, idd, terms] = parts.map(OpCounts::total);
    let mut paragraphs = super::constraints::derivatives_doc_head();
    paragraphs.push(format!(
        "Composed: `q̈` and the forces by `constrained_forward_dynamics` ({solve} operations), \
         `M⁻¹` as `mass_matrix_inverse` ({minv}), the derivatives of the residuals `r₁ = ID(q, \
         v, q̈) − Jᵀ·f − τ` and `r₂ = J·q̈ + γ` at fixed `(q̈, f)`: inverse dynamics' as \
         `inverse_dynamics_derivatives` at `(q, v, q̈)` ({idd}), the constraints' by forward \
         mode with the rows `J` ({terms}); then the solve's linear map `N = [M −Jᵀ; J 0]⁻¹` \
         (its last {rows} columns negated) from `M⁻¹` and `J` by dense products, and `(∂q̈, ∂f) \
         = −N·∂r` for `q` and `v`, visiting the {visited} of {} entries of `∂r/∂q` and `∂r/∂v` \
         that can be non-zero (Pinocchio's `computeConstraintDynamicsDerivatives` takes the \
         same path); `∂(q̈, f)/∂τ` are `N`'s first {nv} columns. Traced whole, this function \
         would be {} operations of straight-line code, more than the generator emits as one \
         function ({COMPOSE_OPS} at most): composed, it fetches far less code per call, which \
         is what bounds a function that large. `solution.residual` is in the rows' axes here (a \
         six-dimensional constraint's in its frame).",
        2 * (nv + rows) * nv,
        traced.total(),
    ));
    paragraphs.push(format!(
        "Operations, the parts and the products: {}.",
        docs::operations(ops)
    ));
    paragraphs.extend(super::constraints::derivatives_doc_errors());
    paragraphs
}
