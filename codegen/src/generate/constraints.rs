//! The constraints a description declares (`contacts: […]`, `loops: […]`) on the generated
//! type: the constants `CONTACTS`, `LOOPS`, `CONSTRAINT_ROWS` and
//! `CONSTRAINED_FORWARD_DYNAMICS_OPS`, and `constrained_forward_dynamics(q, v, τ)`, traced for
//! these constraints ([`crate::trace::constrained`]), in the chain's scalar.
//! [`Options::resolved`](crate::options::Options::resolved) adds the frame outputs the runtime's
//! `articulated::constraint::forward_dynamics_of` reads, which solves any subset of the same
//! constraints (in `f64`) and is checked against this function.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::function::{self, Used};
use super::{constrained_composed, docs, Context};
use crate::emit;
use crate::options::{ContactKind, ScalarKind};
use crate::outputs::Output;
use crate::sym::{Node, OpCounts, Sym};
use crate::trace::constrained::{self, ConstrainedTraced, Constraint};

/// The runtime's `articulated::constraint::PIVOT_TOLERANCE`, for the checks the generator
/// decides itself (a pivot that is a constant).
const PIVOT_TOLERANCE: f64 = 1e-10;
/// The same in `f32`: a pivot below this fraction of its unreduced value is rounding noise
/// (forward dynamics' `PIVOT_TOL_F32`, 84 of `f32`'s epsilons).
const PIVOT_TOLERANCE_F32: f64 = crate::trace::PIVOT_TOL_F32;

/// The constants and the function, with the function's operations; nothing for a description
/// without constraints. `fdd_composed`: `forward_dynamics_derivatives` was composed (its
/// private parts are there to share).
///
/// # Errors
/// A constant that cannot be emitted (as every function's).
pub(super) fn items(
    cx: &Context,
    fdd_composed: bool,
) -> syn::Result<(TokenStream, Vec<(&'static str, OpCounts)>)> {
    let options = cx.options;
    if !options.constrained() {
        return Ok((quote!(), Vec::new()));
    }
    // The check stage made sure each frame exists; `resolved` put each in `frames`.
    let index = |name: &str| options.frames.iter().position(|f| f == name).unwrap_or(0);
    let lit = Literal::usize_unsuffixed;
    let contacts = options.contacts.iter().map(|c| {
        let frame = lit(index(&c.frame));
        let kind = match c.kind {
            ContactKind::Point => quote!(Point),
            ContactKind::SixD => quote!(SixD),
        };
        quote! {
            ::articulated::constraint::Contact {
                frame: #frame,
                kind: ::articulated::constraint::Kind::#kind,
            }
        }
    });
    let loops = options.loops.iter().map(|l| {
        let (a, b) = (lit(index(&l.a)), lit(index(&l.b)));
        let kind = match l.kind {
            ContactKind::Point => quote!(Point),
            ContactKind::SixD => quote!(SixD),
        };
        quote! {
            ::articulated::constraint::Loop {
                a: #a,
                b: #b,
                kind: ::articulated::constraint::Kind::#kind,
            }
        }
    });
    let constraints: Vec<Constraint> = options
        .contacts
        .iter()
        .map(|c| match c.kind {
            ContactKind::Point => Constraint::Point(index(&c.frame)),
            ContactKind::SixD => Constraint::SixD(index(&c.frame)),
        })
        .chain(options.loops.iter().map(|l| match l.kind {
            ContactKind::Point => Constraint::Loop(index(&l.a), index(&l.b)),
            ContactKind::SixD => Constraint::LoopSixD(index(&l.a), index(&l.b)),
        }))
        .collect();
    let traced = constrained::trace(cx.model, &cx.frames(), &constraints);
    let ops = traced.ops();
    let function = function(cx, &traced, &constraints)?;
    let mut all_ops = vec![(super::CONSTRAINED, ops)];
    // With forward dynamics' derivatives asked for, the constrained ones (`f64` only: they
    // return the runtime's `Derivatives`). Not with the other derivative outputs, which the
    // runtime's `forward_dynamics_derivatives_of` reads: on a large chain this function is
    // minutes of release build, which a user of the runtime's derivatives should not pay.
    let derivatives = if options
        .outputs
        .contains(&Output::ForwardDynamicsDerivatives)
        && options.scalar == ScalarKind::F64
    {
        let traced = constrained::trace_derivatives(cx.model, &cx.frames(), &constraints);
        let ops = traced.ops();
        let (function, ops) = if constrained_composed::composes(&ops) {
            let solve_ops = all_ops[0].1;
            constrained_composed::item(cx, &constraints, (&ops, &solve_ops), fdd_composed)?
        } else {
            (derivatives_function(cx, &traced, &constraints)?, ops)
        };
        all_ops.push((super::CONSTRAINED_DERIVATIVES, ops));
        let ops_const = super::ops_const(super::CONSTRAINED_DERIVATIVES, &ops);
        let nv = Literal::usize_unsuffixed(cx.nv);
        let rows = Literal::usize_unsuffixed(options.constraint_rows());
        let batch = batch(
            cx,
            "constrained_forward_dynamics_derivatives",
            quote!(::articulated::constraint::derivatives::Derivatives<#nv, #rows>),
        );
        quote!(#ops_const #function #batch)
    } else {
        quote!()
    };
    let rows = options.constraint_rows();
    let r = lit(rows);
    let doc = |lines: Vec<String>| lines.into_iter().map(|d| quote!(#[doc = #d]));
    let contacts_doc = doc(docs::lines(&contacts_doc(cx)));
    let loops_doc = doc(docs::lines(&loops_doc(cx)));
    let rows_doc = doc(docs::lines(&["The constraints' rows, the forces \
        `constrained_forward_dynamics` returns: 3 per point contact and loop, 6 per \
        six-dimensional contact."
        .to_string()]));
    let ops_const = super::ops_const(super::CONSTRAINED, &ops);
    let (v_ty, r_ty) = (vector_type(cx, cx.nv), vector_type(cx, rows));
    let batch = batch(cx, super::CONSTRAINED, quote!((#v_ty, #r_ty)));
    let name = &cx.name;
    let tokens = quote! {
        impl #name {
            #(#contacts_doc)*
            pub const CONTACTS: &'static [::articulated::constraint::Contact] = &[#(#contacts),*];
            #(#loops_doc)*
            pub const LOOPS: &'static [::articulated::constraint::Loop] = &[#(#loops),*];
            #(#rows_doc)*
            pub const CONSTRAINT_ROWS: usize = #r;
            #ops_const
            #function
            #batch
            #derivatives
        }
    };
    Ok((tokens, all_ops))
}

/// The contact simulation's scene a description declares (`grounds`, `spheres`, `friction`,
/// `restitution`) as the type's `GROUNDS` and `SPHERES`, what `articulated::contact::
/// TimeStepper::new` takes; nothing without spheres.
pub(super) fn scene(cx: &Context) -> TokenStream {
    let options = cx.options;
    if options.spheres.is_empty() {
        return quote!();
    }
    let float = |x: f64| Literal::f64_unsuffixed(x);
    let grounds = options.grounds.iter().map(|g| {
        let [x, y, z] = g.normal.map(float);
        let d = float(g.offset);
        quote!(::articulated::contact::Ground::unit([#x, #y, #z], #d))
    });
    // `resolved` put each sphere's frame in `frames`.
    let index = |name: &str| options.frames.iter().position(|f| f == name).unwrap_or(0);
    let friction = float(options.friction.unwrap_or(0.0));
    let restitution = float(options.restitution);
    let spheres = options.spheres.iter().map(|s| {
        let frame = Literal::usize_unsuffixed(index(&s.frame));
        let [x, y, z] = s.offset.map(float);
        let r = float(s.radius);
        quote! {
            ::articulated::contact::Sphere {
                frame: #frame,
                offset: [#x, #y, #z],
                radius: #r,
                friction: #friction,
                restitution: #restitution,
            }
        }
    });
    let named = |names: Vec<String>| names.join(", ");
    let grounds_doc = format!(
        "The grounds the description declares ({}), each the half-space `n·x ≥ d`, for \
         `articulated::contact`.",
        named(
            options
                .grounds
                .iter()
                .map(|g| format!("`{}`", g.name))
                .collect()
        )
    );
    let spheres_doc = format!(
        "The contact spheres the description declares ({}), each on its frame          (`Chain::FRAMES`), for `articulated::contact`.",
        named(options.spheres.iter().map(|s| format!("`{}` on `{}`", s.name, s.frame)).collect())
    );
    let name = &cx.name;
    quote! {
        impl #name {
            #[doc = #grounds_doc]
            pub const GROUNDS: &'static [::articulated::contact::Ground] = &[#(#grounds),*];
            #[doc = #spheres_doc]
            pub const SPHERES: &'static [::articulated::contact::Sphere] = &[#(#spheres),*];
        }
    }
}

/// The batch twin of the constrained function `name` (`constrained_forward_dynamics_batch`),
/// whose `Ok` value is `value`: state by state (the solve has no lane code: its checks would
/// need a lane's first error among the constraints' rows).
fn batch(cx: &Context, name: &str, value: TokenStream) -> TokenStream {
    let function = quote::format_ident!("{name}");
    let batch = quote::format_ident!("{name}_batch");
    let (q_ty, v_ty) = (vector_type(cx, cx.nq), vector_type(cx, cx.nv));
    let generics = &cx.impl_generics;
    let doc = format!(
        " [`{name}`](Self::{name}) at every state: `out[i]` for `(q[i], v[i], tau[i])`, state \
         by state (no lane code for the constrained solve)."
    );
    quote! {
        #[doc = #doc]
        #[doc = ""]
        #[doc = " # Errors"]
        #[doc = " [`BatchLengths`](::articulated::lanes::BatchLengths) where an argument's length is not `out`'s (nothing is computed). A state whose solve fails has its `Err` in `out`, its neighbours their values."]
        #[allow(clippy::type_complexity)]
        pub fn #batch #generics(
            q: &[#q_ty],
            v: &[#v_ty],
            tau: &[#v_ty],
            out: &mut [::core::result::Result<#value, ::articulated::constraint::ConstraintError>],
        ) -> ::core::result::Result<(), ::articulated::lanes::BatchLengths> {
            ::articulated::lanes::check_lengths(
                out.len(),
                &[("q", q.len()), ("v", v.len()), ("tau", tau.len())],
            )?;
            for (((out, q), v), tau) in out.iter_mut().zip(q).zip(v).zip(tau) {
                *out = Self::#function(q, v, tau);
            }
            Ok(())
        }
    }
}

/// The statements shared by the constrained functions: the inputs checked finite, bound, the
/// traced graph, each pivot of `M` and of `G` checked against its unreduced value
/// ([`pivot_checks`]); and the emitted values (`traced.values`), in order.
fn body(
    cx: &Context,
    traced: &ConstrainedTraced,
    constraints: &[Constraint],
) -> syn::Result<(TokenStream, Vec<TokenStream>)> {
    let outputs = traced.all_outputs();
    let emitted = emit::straight_line_into(
        &traced.graph,
        &outputs,
        cx.options.scalar,
        &|var| cx.input(var),
        None,
        None,
    )?;
    let (nq, nv) = (cx.nq, cx.nv);
    let values = traced.values.len();
    let used = Used::in_graph(&traced.graph, &outputs, nq, nv, 0);
    let [bind_q, bind_v, bind_tau] = [("q", &used.q), ("v", &used.v), ("tau", &used.tau)]
        .map(|(name, used)| function::destructure(name, used));
    let params_ty = &cx.params_ty;
    let bind_params = if used.params {
        quote!(let p = &<#params_ty>::defaults();)
    } else {
        quote!()
    };
    let checks = pivot_checks(cx, traced, constraints, &emitted.outputs[values..]);
    let declare_tolerance = declare_tolerance(cx);
    let (uses, statements) = (&emitted.uses, &emitted.statements);
    let body = quote! {
        #declare_tolerance
        if ![q.as_slice(), v.as_slice(), tau.as_slice()]
            .iter()
            .all(|s| s.iter().all(|x| x.is_finite()))
        {
            return Err(::articulated::constraint::ConstraintError::NonFinite);
        }
        #uses
        #bind_q
        #bind_v
        #bind_tau
        #bind_params
        #statements
        #(#checks)*
    };
    Ok((body, emitted.outputs[..values].to_vec()))
}

/// `constrained_forward_dynamics(q, v, τ)`: the traced solve as straight-line code ([`body`]),
/// the results checked finite last.
fn function(
    cx: &Context,
    traced: &ConstrainedTraced,
    constraints: &[Constraint],
) -> syn::Result<TokenStream> {
    let (body, values) = body(cx, traced, constraints)?;
    let nv = cx.nv;
    let rows = traced.values.len() - nv;
    let qdd = function::vector(cx, &values[..nv]);
    let forces = function::vector(cx, &values[nv..]);
    let (q_ty, v_ty, r_ty) = (
        vector_type(cx, cx.nq),
        vector_type(cx, nv),
        vector_type(cx, rows),
    );
    let generics = &cx.impl_generics;
    let function_doc = docs::lines(&function_doc(cx, traced))
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    Ok(quote! {
        #(#function_doc)*
        pub fn constrained_forward_dynamics #generics(
            q: &#q_ty,
            v: &#v_ty,
            tau: &#v_ty,
        ) -> ::core::result::Result<(#v_ty, #r_ty), ::articulated::constraint::ConstraintError> {
            #body
            let qdd = #qdd;
            let forces = #forces;
            if ![qdd.as_slice(), forces.as_slice()]
                .iter()
                .all(|s| s.iter().all(|x| x.is_finite()))
            {
                return Err(::articulated::constraint::ConstraintError::NonFinite);
            }
            Ok((qdd, forces))
        }
    })
}

/// `constrained_forward_dynamics_derivatives(q, v, τ)`: the traced solve and its derivatives
/// ([`constrained::trace_derivatives`]) as straight-line code ([`body`]), returned as the
/// runtime's `constraint::derivatives::Derivatives` (`f64` chains only), every value checked
/// finite last.
fn derivatives_function(
    cx: &Context,
    traced: &ConstrainedTraced,
    constraints: &[Constraint],
) -> syn::Result<TokenStream> {
    let (body, values) = body(cx, traced, constraints)?;
    let (nv, rows) = (cx.nv, cx.options.constraint_rows());
    let (qdd, rest) = values.split_at(nv);
    let (forces, rest) = rest.split_at(rows);
    let (residual, rest) = rest.split_at(rows);
    let (dqdd, dforces) = rest.split_at(3 * nv * nv);
    let matrix = |values: &[TokenStream], rows: usize| {
        function::columns(cx, &function::transposed(values, rows), rows)
    };
    let [dqdd_dq, dqdd_dv, dqdd_dtau] =
        [0, 1, 2].map(|k| matrix(&dqdd[k * nv * nv..][..nv * nv], nv));
    let [dforces_dq, dforces_dv, dforces_dtau] =
        [0, 1, 2].map(|k| matrix(&dforces[k * rows * nv..][..rows * nv], rows));
    let (qdd, forces) = (function::vector(cx, qdd), function::vector(cx, forces));
    let (q_ty, v_ty) = (vector_type(cx, cx.nq), vector_type(cx, nv));
    let (nv_lit, r_lit) = (
        Literal::usize_unsuffixed(nv),
        Literal::usize_unsuffixed(rows),
    );
    let function_doc = docs::lines(&derivatives_doc(traced))
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    Ok(quote! {
        #(#function_doc)*
        pub fn constrained_forward_dynamics_derivatives(
            q: &#q_ty,
            v: &#v_ty,
            tau: &#v_ty,
        ) -> ::core::result::Result<
            ::articulated::constraint::derivatives::Derivatives<#nv_lit, #r_lit>,
            ::articulated::constraint::ConstraintError,
        > {
            #body
            let residual = [#(#residual),*].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let derivatives = ::articulated::constraint::derivatives::Derivatives {
                solution: ::articulated::constraint::Solution {
                    acceleration: #qdd,
                    forces: #forces,
                    rows: #r_lit,
                    residual,
                    iterations: 1,
                },
                dqdd_dq: #dqdd_dq,
                dqdd_dv: #dqdd_dv,
                dqdd_dtau: #dqdd_dtau,
                dforces_dq: #dforces_dq,
                dforces_dv: #dforces_dv,
                dforces_dtau: #dforces_dtau,
            };
            if !derivatives.all_finite() {
                return Err(::articulated::constraint::ConstraintError::NonFinite);
            }
            Ok(derivatives)
        }
    })
}

/// The relative pivot tolerance in the chain's scalar.
fn tolerance(cx: &Context) -> f64 {
    match cx.options.scalar {
        ScalarKind::F32 => PIVOT_TOLERANCE_F32,
        ScalarKind::F64 | ScalarKind::Generic => PIVOT_TOLERANCE,
    }
}

/// The tolerance by name: the runtime's in `f64`, a constant in `f32`, converted once in a
/// generic scalar.
fn declare_tolerance(cx: &Context) -> TokenStream {
    let scalar = &cx.scalar;
    match cx.options.scalar {
        ScalarKind::F64 => {
            quote!(
                const PIVOT_TOLERANCE: f64 = ::articulated::constraint::PIVOT_TOLERANCE;
            )
        }
        ScalarKind::F32 => {
            let t = cx.lit(PIVOT_TOLERANCE_F32);
            quote!(const PIVOT_TOLERANCE: f32 = #t;)
        }
        ScalarKind::Generic => {
            let t = cx.lit(PIVOT_TOLERANCE);
            quote!(#[allow(non_snake_case)] let PIVOT_TOLERANCE: #scalar = #t;)
        }
    }
}

/// One `if` per pivot that can fail, in the order of elimination: `M`'s from the last velocity
/// to the first (`ConstraintError::MassMatrix`), then `G`'s from the first row to the last
/// (`ConstraintError::Redundant`, naming the constraint and its row). A pivot is decided here
/// where it and its unreduced value are constants, held `> 0` where nothing was eliminated from
/// it, else against its unreduced value. `exprs`: the emitted pivots and unreduced values, in
/// pairs, `M`'s then `G`'s.
fn pivot_checks(
    cx: &Context,
    traced: &ConstrainedTraced,
    constraints: &[Constraint],
    exprs: &[TokenStream],
) -> Vec<TokenStream> {
    let nv = cx.nv;
    let constant = |s| match traced.graph.node(s) {
        Node::Const(x) => Some(x),
        _ => None,
    };
    let (zero, tolerance) = (cx.lit(0.0), tolerance(cx));
    let check = |k: usize, (p, d): (Sym, Sym), error: TokenStream| {
        let (pe, de) = (&exprs[2 * k], &exprs[2 * k + 1]);
        let condition = match (constant(p), constant(d)) {
            (Some(pv), Some(dv)) if pv > tolerance * dv => return None,
            (Some(_), Some(_)) => {
                quote!(!::articulated::__private::singular_at_every_configuration())
            }
            _ if p == d => quote!(#pe > #zero),
            _ => quote!(::articulated::__private::positive_pivot(#pe, #de, PIVOT_TOLERANCE)),
        };
        Some(quote! {
            if !(#condition) {
                return Err(#error);
            }
        })
    };
    let mass = (0..nv).rev().filter_map(|k| {
        let velocity = Literal::usize_unsuffixed(k);
        check(
            k,
            traced.mass[k],
            quote!(::articulated::constraint::ConstraintError::MassMatrix { velocity: #velocity }),
        )
    });
    let owners = constraints
        .iter()
        .enumerate()
        .flat_map(|(c, constraint)| (0..constraint.rows()).map(move |row| (c, row)));
    let delassus = owners.enumerate().filter_map(|(i, (contact, row))| {
        let (contact, row) = (
            Literal::usize_unsuffixed(contact),
            Literal::usize_unsuffixed(row),
        );
        check(
            nv + i,
            traced.delassus[i],
            quote!(::articulated::constraint::ConstraintError::Redundant {
                contact: #contact,
                row: #row,
            }),
        )
    });
    mass.chain(delassus).collect()
}

pub(super) fn vector_type(cx: &Context, n: usize) -> TokenStream {
    let (scalar, n) = (&cx.scalar, Literal::usize_unsuffixed(n));
    quote!(::articulated::nalgebra::SVector<#scalar, #n>)
}

/// Each constraint's rows and what its force is, in declaration order.
fn rows_of(cx: &Context) -> Vec<String> {
    let mut start = 0;
    let mut lines = Vec::new();
    let mut range = |n: usize| {
        let r = format!("rows {}–{}", start, start + n - 1);
        start += n;
        r
    };
    for c in &cx.options.contacts {
        let what = match c.kind {
            ContactKind::SixD => "the wrench `[n; f]` on it, in its axes",
            ContactKind::Point => "the force on its origin, world axes",
        };
        lines.push(format!(
            "{}: contact `{}` (`{}`), {what};",
            range(c.kind.rows()),
            c.frame,
            c.kind.name()
        ));
    }
    for l in &cx.options.loops {
        let what = match l.kind {
            ContactKind::Point => format!(
                "the force on `{}`'s origin (its opposite on `{}`'s), world axes",
                l.a, l.b
            ),
            ContactKind::SixD => format!(
                "the wrench `[n; f]` on `{}` about its origin, in its axes (its opposite on `{}`)",
                l.a, l.b
            ),
        };
        lines.push(format!(
            "{}: loop `{}` (`{}`: `{}` on `{}`), {what};",
            range(l.rows()),
            l.name,
            l.kind.name(),
            l.a,
            l.b,
        ));
    }
    if let Some(last) = lines.last_mut() {
        last.pop();
        last.push('.');
    }
    lines
}

fn contacts_doc(cx: &Context) -> Vec<String> {
    let listed: Vec<String> = cx
        .options
        .contacts
        .iter()
        .map(|c| format!("`{}` (`{}`)", c.frame, c.kind.name()))
        .collect();
    let which = if listed.is_empty() {
        "none".to_string()
    } else {
        listed.join(", ")
    };
    vec![format!(
        "The contacts the description declares, in its order: {which}. Each frame is its index in \
         `Chain::FRAMES`."
    )]
}

fn loops_doc(cx: &Context) -> Vec<String> {
    let listed: Vec<String> = cx
        .options
        .loops
        .iter()
        .map(|l| format!("`{}` (`{}`: `{}` on `{}`)", l.name, l.kind.name(), l.a, l.b))
        .collect();
    let which = if listed.is_empty() {
        "none".to_string()
    } else {
        listed.join(", ")
    };
    vec![format!(
        "The loop closures the description declares, in its order: {which}. Each holds frame \
         `a`'s origin (`point`) or frame `a` (`six_d`) on frame `b`, by their indices in \
         `Chain::FRAMES`."
    )]
}

fn derivatives_doc(traced: &ConstrainedTraced) -> Vec<String> {
    let mut paragraphs = derivatives_doc_head();
    paragraphs.push(format!(
        "Generated for these constraints: the solve of `constrained_forward_dynamics`, then the \
         residuals `r₁ = ID(q, v, q̈) − Jᵀ·f − τ` and `r₂ = J·q̈ + γ` differentiated at fixed \
         `(q̈, f)` by forward mode along each tangent direction (a body's motion does not \
         depend on the joints below it: those terms fold away), and `[M −Jᵀ; J 0]` solved for \
         each column with the factorizations of the solve: {} ({}). The runtime's \
         `articulated::constraint::derivatives::forward_dynamics_derivatives_of` computes the \
         same for any subset of the constraints.",
        traced.ops(),
        traced.variant
    ));
    paragraphs.extend(derivatives_doc_errors());
    paragraphs
}

/// What `constrained_forward_dynamics_derivatives` returns, traced or composed.
pub(super) fn derivatives_doc_head() -> Vec<String> {
    vec![
        "`constrained_forward_dynamics` and its derivatives with respect to `q`, `v` and `τ`, \
         for the constraints the description declares (`Self::CONTACTS`, then `Self::LOOPS`): \
         Pinocchio's `computeConstraintDynamicsDerivatives`, what model-predictive control of a \
         robot on its feet linearizes. `∂/∂q` is along the configuration's tangent, as in \
         `forward_dynamics_derivatives`; the forces and their derivatives are in the axes \
         `constrained_forward_dynamics` documents (a six-dimensional constraint's wrench in its \
         frame). `solution.residual` is `max |J·q̈ + γ|` over the rows, in world axes."
            .to_string(),
    ]
}

/// The errors of `constrained_forward_dynamics_derivatives`, traced or composed.
pub(super) fn derivatives_doc_errors() -> Vec<String> {
    vec![
        "# Errors".to_string(),
        "As `constrained_forward_dynamics`; `ConstraintError::NonFinite` where a derivative is \
         not finite."
            .to_string(),
    ]
}

fn function_doc(cx: &Context, traced: &ConstrainedTraced) -> Vec<String> {
    let mut paragraphs = vec![
        "Constrained forward dynamics with the constraints the description declares \
         (`Self::CONTACTS`, then `Self::LOOPS`): the accelerations `q̈` and the constraint \
         forces `f` that solve `M·q̈ + nle = τ + Jᵀ·f` and `J·q̈ + γ = 0`, with `J` the \
         constraints' stacked Jacobian and `γ` their drift (their acceleration at `q̈ = 0`): \
         the constraints hold, without Baumgarte terms, by the exact solve (the default \
         `articulated::constraint::Settings`)."
            .to_string(),
        format!(
            "The forces, `Self::CONSTRAINT_ROWS` = {} rows, are what the constraints exert on \
             the bodies:",
            cx.options.constraint_rows()
        ),
    ];
    paragraphs.extend(rows_of(cx).into_iter().map(|r| format!("- {r}")));
    paragraphs.push(format!(
        "Generated for these constraints: `M`, `N·q̇ + g`, the rows and their drifts in one \
         pass; `M = LᵀDL` factored with the tree's sparsity, the operational-space matrix \
         `G = J·M⁻¹·Jᵀ` formed through `L⁻ᵀ·Jᵀ` (which keeps each row's sparsity) and factored, \
         `q̈` from one more sparse solve: {} ({}). The runtime's \
         `articulated::constraint::forward_dynamics_of` computes the same from this chain's \
         `mass_matrix_and_nonlinear_effects`, `frame_placements`, `frame_jacobians_local`, \
         `frame_velocities` and `frame_accelerations`: call it for a subset of the \
         constraints, Baumgarte terms or a proximal solve.",
        traced.ops(),
        traced.variant
    ));
    paragraphs.push("# Errors".to_string());
    paragraphs.push(
        "`ConstraintError::Redundant` where the constraints' rows depend on each other at this \
         state (it names the constraint, in the order above, and its row: a proximal \
         `Settings::mu > 0` solves them), `ConstraintError::MassMatrix` where `M` is not \
         positive definite, `ConstraintError::NonFinite` for inputs that are not finite."
            .to_string(),
    );
    paragraphs
}
