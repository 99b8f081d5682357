//! The constraints a description declares (`contacts: […]`, `loops: […]`) on the generated
//! type: the constants `CONTACTS`, `LOOPS` and `CONSTRAINT_ROWS`, and
//! `constrained_forward_dynamics(q, v, τ)`, which hands them to the runtime's solver
//! (`articulated::constraint::forward_dynamics_of`, f64 only: the check stage refused other
//! scalars) with the frame outputs [`Options::resolved`](crate::options::Options::resolved)
//! added.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::{docs, Context};
use crate::options::{ContactKind, Loop};

/// The constants and the function; nothing for a description without constraints.
pub(super) fn items(cx: &Context) -> TokenStream {
    let options = cx.options;
    if !options.constrained() {
        return quote!();
    }
    // The check stage made sure each frame exists; `resolved` put each in `frames`.
    let index = |name: &str| {
        let i = options.frames.iter().position(|f| f == name).unwrap_or(0);
        Literal::usize_unsuffixed(i)
    };
    let contacts = options.contacts.iter().map(|c| {
        let frame = index(&c.frame);
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
        let (a, b) = (index(&l.a), index(&l.b));
        quote!(::articulated::constraint::Loop { a: #a, b: #b })
    });
    let rows = options.constraint_rows();
    let [nq, nv, nf, r] = [cx.nq, cx.nv, options.frames.len(), rows].map(Literal::usize_unsuffixed);
    let vector = |n: &Literal| quote!(::articulated::nalgebra::SVector<f64, #n>);
    let (q_ty, v_ty, r_ty) = (vector(&nq), vector(&nv), vector(&r));
    let doc = |lines: Vec<String>| lines.into_iter().map(|d| quote!(#[doc = #d]));
    let contacts_doc = doc(docs::lines(&contacts_doc(cx)));
    let loops_doc = doc(docs::lines(&loops_doc(cx)));
    let rows_doc = doc(docs::lines(&["The constraints' rows, the forces \
        `constrained_forward_dynamics` returns: 3 per point contact and loop, 6 per \
        six-dimensional contact."
        .to_string()]));
    let function_doc = doc(docs::lines(&function_doc(cx)));
    let name = &cx.name;
    quote! {
        impl #name {
            #(#contacts_doc)*
            pub const CONTACTS: &'static [::articulated::constraint::Contact] = &[#(#contacts),*];
            #(#loops_doc)*
            pub const LOOPS: &'static [::articulated::constraint::Loop] = &[#(#loops),*];
            #(#rows_doc)*
            pub const CONSTRAINT_ROWS: usize = #r;
            #(#function_doc)*
            pub fn constrained_forward_dynamics(
                q: &#q_ty,
                v: &#v_ty,
                tau: &#v_ty,
            ) -> ::core::result::Result<(#v_ty, #r_ty), ::articulated::constraint::ConstraintError> {
                let solution = ::articulated::constraint::forward_dynamics_of::<Self, #nq, #nv, #nf, #r>(
                    q,
                    v,
                    tau,
                    Self::CONTACTS,
                    Self::LOOPS,
                    None,
                    &::articulated::constraint::Settings::default(),
                )?;
                Ok((solution.acceleration, solution.forces))
            }
        }
    }
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
        lines.push(format!(
            "{}: loop `{}` (`{}` on `{}`), the force on `{}`'s origin (its opposite on `{}`'s), \
             world axes;",
            range(Loop::ROWS),
            l.name,
            l.a,
            l.b,
            l.a,
            l.b
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
        .map(|l| format!("`{}` (`{}` on `{}`)", l.name, l.a, l.b))
        .collect();
    let which = if listed.is_empty() {
        "none".to_string()
    } else {
        listed.join(", ")
    };
    vec![format!(
        "The loop closures the description declares, in its order: {which}. Each holds frame \
         `a`'s origin on frame `b`'s, by their indices in `Chain::FRAMES`."
    )]
}

fn function_doc(cx: &Context) -> Vec<String> {
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
    paragraphs.push(
        "The runtime's `articulated::constraint::forward_dynamics_of` computes them from this \
         chain's `mass_matrix_and_nonlinear_effects`, `frame_placements`, \
         `frame_jacobians_local`, `frame_velocities` and `frame_accelerations` (at the \
         parameters' defaults); call it for Baumgarte terms or a proximal solve."
            .to_string(),
    );
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
