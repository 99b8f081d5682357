//! One generated function per output: its trait impl, its arguments (only the inputs it reads
//! are bound), its straight-line body and its result.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use super::{docs, Context};
use crate::emit::{self, Emitted};
use crate::options::{Output, ScalarKind};
use crate::sym::{Node, Var};
use crate::trace::{
    Traced, PIVOT_TOL_F32, PIVOT_TOL_F64, PIVOT_TOL_GLOBAL_F32, PIVOT_TOL_GLOBAL_F64,
};

/// The trait impl of one traced output.
pub(super) fn item(cx: &Context, traced: &Traced) -> syn::Result<TokenStream> {
    let emitted = emit::straight_line(
        &traced.graph,
        &traced.all_outputs(),
        cx.options.scalar,
        &|var| cx.input(var),
    )?;
    let used = Used::of(traced, cx.nq, cx.nv);
    let (name, scalar, generics) = (&cx.name, &cx.scalar, &cx.impl_generics);
    let (nq, nv) = (
        Literal::usize_unsuffixed(cx.nq),
        Literal::usize_unsuffixed(cx.nv),
    );
    let doc = docs::function_doc(cx, traced)
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    let p_arg = if used.params { quote!(p) } else { quote!(_p) };
    let params_ty = &cx.params_ty;
    let (sq, sv) = (cx.vector_type(cx.nq), cx.vector_type(cx.nv));
    let statements = &emitted.statements;
    let dq = destructure("q", &used.q);
    let (dv, da, dtau, dbase) = (
        destructure("v", &used.v),
        destructure("a", &used.a),
        destructure("tau", &used.tau),
        destructure("base", &used.base),
    );
    let nb = Literal::usize_unsuffixed(cx.model.nb());
    let values = &emitted.outputs[..traced.values.len()];
    Ok(match traced.output {
        Output::MassMatrix => {
            // nalgebra stores columns; M is symmetric, so its row-major entries are its columns.
            let m = columns(cx, values, cx.nv);
            quote! {
                impl #generics ::articulated::MassMatrix<#scalar, #nq, #nv> for #name {
                    #(#doc)*
                    fn mass_matrix_with(q: &#sq, #p_arg: &#params_ty)
                        -> ::articulated::nalgebra::SMatrix<#scalar, #nv, #nv> {
                        #dq
                        #statements
                        #m
                    }
                }
            }
        }
        Output::Bias => {
            let out = vector(cx, values);
            quote! {
                impl #generics ::articulated::Bias<#scalar, #nq, #nv> for #name {
                    #(#doc)*
                    fn bias_with(q: &#sq, v: &#sv, #p_arg: &#params_ty) -> #sv {
                        #dq #dv
                        #statements
                        #out
                    }
                }
            }
        }
        Output::Gravity => {
            let out = vector(cx, values);
            quote! {
                impl #generics ::articulated::Gravity<#scalar, #nq, #nv> for #name {
                    #(#doc)*
                    fn gravity_with(q: &#sq, #p_arg: &#params_ty) -> #sv {
                        #dq
                        #statements
                        #out
                    }
                }
            }
        }
        Output::InverseDynamics => {
            let out = vector(cx, values);
            quote! {
                impl #generics ::articulated::InverseDynamics<#scalar, #nq, #nv> for #name {
                    #(#doc)*
                    fn inverse_dynamics_with(q: &#sq, v: &#sv, a: &#sv, #p_arg: &#params_ty)
                        -> #sv {
                        #dq #dv #da
                        #statements
                        #out
                    }
                }
            }
        }
        Output::JointWrenches => {
            let w = columns(cx, values, 6);
            quote! {
                impl #generics ::articulated::JointWrenches<#scalar, #nq, #nv, #nb> for #name {
                    #(#doc)*
                    fn joint_wrenches_with(q: &#sq, v: &#sv, a: &#sv, #p_arg: &#params_ty)
                        -> ::articulated::nalgebra::SMatrix<#scalar, 6, #nb> {
                        #dq #dv #da
                        #statements
                        #w
                    }
                }
            }
        }
        Output::JointWrenchesBottomUp => {
            let w = columns(cx, values, 6);
            let s6 = cx.vector_type(6);
            quote! {
                impl #generics ::articulated::JointWrenchesBottomUp<#scalar, #nq, #nv, #nb>
                    for #name
                {
                    #(#doc)*
                    fn joint_wrenches_bottom_up_with(
                        q: &#sq, v: &#sv, a: &#sv, base: &#s6, #p_arg: &#params_ty,
                    ) -> ::articulated::nalgebra::SMatrix<#scalar, 6, #nb> {
                        #dq #dv #da #dbase
                        #statements
                        #w
                    }
                }
            }
        }
        Output::ForwardDynamics => {
            let checks = pivot_checks(cx, traced, &emitted);
            let finite = values.iter().enumerate().map(|(k, x)| {
                let k = Literal::usize_unsuffixed(k);
                quote! {
                    if !#x.is_finite() {
                        return Err(::articulated::SingularMassMatrix { velocity: #k });
                    }
                }
            });
            let out = vector(cx, values);
            quote! {
                impl #generics ::articulated::ForwardDynamics<#scalar, #nq, #nv> for #name {
                    #(#doc)*
                    fn forward_dynamics_with(q: &#sq, v: &#sv, tau: &#sv, #p_arg: &#params_ty)
                        -> ::core::result::Result<#sv, ::articulated::SingularMassMatrix> {
                        #dq #dv #dtau
                        #statements
                        #(#checks)*
                        #(#finite)*
                        Ok(#out)
                    }
                }
            }
        }
    })
}

/// `SVector::from_array_storage(ArrayStorage([[v0, v1, …]]))`.
fn vector(cx: &Context, values: &[TokenStream]) -> TokenStream {
    let (scalar, nv) = (&cx.scalar, Literal::usize_unsuffixed(cx.nv));
    quote! {
        ::articulated::nalgebra::SVector::<#scalar, #nv>::from_array_storage(
            ::articulated::nalgebra::ArrayStorage([[#(#values),*]])
        )
    }
}

/// A matrix of `rows` rows from its entries column by column.
fn columns(cx: &Context, values: &[TokenStream], rows: usize) -> TokenStream {
    let scalar = &cx.scalar;
    let (r, c) = (
        Literal::usize_unsuffixed(rows),
        Literal::usize_unsuffixed(values.len() / rows),
    );
    let cols = values.chunks(rows).map(|col| quote!([#(#col),*]));
    quote! {
        ::articulated::nalgebra::SMatrix::<#scalar, #r, #c>::from_array_storage(
            ::articulated::nalgebra::ArrayStorage([#(#cols),*])
        )
    }
}

/// One `if` per pivot that can fail: positive relative to its unreduced value and to the sum of
/// them all. A check whose outcome the constants already settle is decided here: a pivot that is
/// a constant passing against a constant needs no local test, and one that is its own unreduced
/// value (the first pivot of a factorization) only needs to be positive.
fn pivot_checks(cx: &Context, traced: &Traced, emitted: &Emitted) -> Vec<TokenStream> {
    let Some(pivots) = &traced.pivots else {
        return Vec::new();
    };
    let f32 = cx.options.scalar == ScalarKind::F32;
    let (tol, tol_global) = if f32 {
        (PIVOT_TOL_F32, PIVOT_TOL_GLOBAL_F32)
    } else {
        (PIVOT_TOL_F64, PIVOT_TOL_GLOBAL_F64)
    };
    let constant = |s| match traced.graph.node(s) {
        Node::Const(x) => Some(x),
        _ => None,
    };
    let n = traced.values.len();
    let exprs = &emitted.outputs[n..];
    let scale_expr = &exprs[2 * pivots.pairs.len()];
    let scale_const = constant(pivots.scale);
    let mut checks = Vec::new();
    for (k, &(p, d)) in pivots.pairs.iter().enumerate() {
        let (pe, de) = (&exprs[2 * k], &exprs[2 * k + 1]);
        let (p_const, d_const) = (constant(p), constant(d));
        let local = match (p_const, d_const) {
            (Some(pv), Some(dv)) if pv > tol * dv => None,
            _ if p == d => {
                let zero = cx.lit(0.0);
                Some(quote!(#pe > #zero))
            }
            _ => {
                let t = cx.lit(tol);
                Some(quote!(::articulated::__private::positive_pivot(#pe, #de, #t)))
            }
        };
        let global = match (p_const, scale_const) {
            (Some(pv), Some(sv)) if pv > tol_global * sv => None,
            _ => {
                let t = cx.lit(tol_global);
                Some(quote!(::articulated::__private::positive_pivot(#pe, #scale_expr, #t)))
            }
        };
        let condition = match (local, global) {
            (None, None) => continue,
            (Some(c), None) | (None, Some(c)) => c,
            (Some(l), Some(g)) => quote!(#l && #g),
        };
        let k = Literal::usize_unsuffixed(k);
        checks.push(quote! {
            if !(#condition) {
                return Err(::articulated::SingularMassMatrix { velocity: #k });
            }
        });
    }
    checks
}

/// `let [[q0, _, q2]] = q.data.0;` binding the inputs a function uses (`_` for the others, so
/// the user's crate sees no unused variable).
fn destructure(vector: &str, used: &[bool]) -> TokenStream {
    let vector_id = format_ident!("{}", vector);
    let names = used.iter().enumerate().map(|(i, &u)| {
        if u {
            let id = format_ident!("{}{}", vector, i);
            quote!(#id)
        } else {
            quote!(_)
        }
    });
    quote! { let [[#(#names),*]] = #vector_id.data.0; }
}

/// Which inputs the live part of a graph reads, per kind.
struct Used {
    q: Vec<bool>,
    v: Vec<bool>,
    a: Vec<bool>,
    tau: Vec<bool>,
    base: Vec<bool>,
    params: bool,
}

impl Used {
    fn of(t: &Traced, nq: usize, nv: usize) -> Used {
        let mut u = Used {
            q: vec![false; nq],
            v: vec![false; nv],
            a: vec![false; nv],
            tau: vec![false; nv],
            base: vec![
                false;
                if t.output == Output::JointWrenchesBottomUp {
                    6
                } else {
                    0
                }
            ],
            params: false,
        };
        for s in t.graph.live(&t.all_outputs()) {
            if let Node::Input(var) = t.graph.node(s) {
                match var {
                    Var::Q(i) => u.q[i] = true,
                    Var::V(i) => u.v[i] = true,
                    Var::A(i) => u.a[i] = true,
                    Var::Tau(i) => u.tau[i] = true,
                    Var::Base(i) => u.base[i] = true,
                    Var::Param(_) => u.params = true,
                }
            }
        }
        u
    }
}
