//! One generated function per output: its trait impl, its arguments (only the inputs it reads
//! are bound), its straight-line body and its result.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote, ToTokens};

use super::{docs, Context};
use crate::emit::{self, Emitted};
use crate::options::{Output, ScalarKind};
use crate::outputs::{Arg, Dim, Each, Order, Part};
use crate::sym::{Graph, Node, Sym, Var};
use crate::trace::{
    lower_triangle, Pivots, Traced, PIVOT_TOL_F32, PIVOT_TOL_F64, PIVOT_TOL_GLOBAL_ABA_F32,
    PIVOT_TOL_GLOBAL_ABA_F64, PIVOT_TOL_GLOBAL_F64,
};

/// The trait impl of one traced output: its function, and where the chain asks for lanes
/// (`lanes: N`), its batch twin over lanes ([`batch`]).
pub(super) fn item(cx: &Context, traced: &Traced) -> syn::Result<TokenStream> {
    let Signature {
        trait_,
        after_params,
        ret,
        ..
    } = signature(cx, traced.output);
    let (args, p_arg, body) = function(cx, traced)?;
    let function = format_ident!("{}_with", traced.output.name());
    let (name, generics, params_ty) = (&cx.name, &cx.impl_generics, &cx.params_ty);
    let doc = docs::function_doc(cx, traced)
        .into_iter()
        .map(|d| quote!(#[doc = #d]));
    // A scalar result is the last `let`, named after what it is (`kinetic_energy`): returning
    // the name reads better than inlining its expression, which is what clippy would have.
    let allow = if matches!(
        traced.output,
        Output::KineticEnergy | Output::PotentialEnergy
    ) {
        quote!(#[allow(clippy::let_and_return)])
    } else {
        quote!()
    };
    let batch = match (cx.options.lanes, cx.options.scalar) {
        (Some(n), ScalarKind::F64 | ScalarKind::F32) if !traced.output.is_kept() => {
            batch(cx, traced, n)?
        }
        _ => TokenStream::new(),
    };
    Ok(quote! {
        impl #generics #trait_ for #name {
            #(#doc)*
            #allow
            fn #function(#(#args)* #p_arg: &#params_ty, #after_params) #ret {
                #body
            }
            #batch
        }
    })
}

/// `traced`'s function as an associated function `name` of the chain's own impl, with the
/// output's signature but no trait, batch twin or docs beyond `doc`: a part that a composed
/// output calls ([`super::composed`]). Never inlined: a part is large, and LLVM inlines a
/// private function with one caller whatever its size, which would make the composed function
/// the one large function composing avoids.
pub(super) fn part(
    cx: &Context,
    traced: &Traced,
    name: &proc_macro2::Ident,
    doc: &str,
) -> syn::Result<TokenStream> {
    let Signature {
        after_params, ret, ..
    } = signature(cx, traced.output);
    let (args, p_arg, body) = function(cx, traced)?;
    // Generic over the scalar on the function, not on the impl, which would not constrain it.
    let (params_ty, generics) = (&cx.params_ty, &cx.impl_generics);
    Ok(quote! {
        #[doc = #doc]
        #[inline(never)]
        fn #name #generics(#(#args)* #p_arg: &#params_ty, #after_params) #ret {
            #body
        }
    })
}

/// The trait of an output, as `<Self as Trait<…>>`'s path (`::articulated::ForwardDynamics<f64,
/// 7, 7>`).
pub(super) fn trait_path(cx: &Context, output: Output) -> TokenStream {
    signature(cx, output).trait_
}

/// A function's arguments before the parameters (`q: &SVector<f64, 7>,` …), the parameters'
/// name (`_p` where unread) and its body, in `cx`'s scalar (lanes for [`batch`]).
fn function(
    cx: &Context,
    traced: &Traced,
) -> syn::Result<(Vec<TokenStream>, TokenStream, TokenStream)> {
    let sunk = sink(cx, traced);
    let emitted = emit::straight_line_into(
        &traced.graph,
        &outputs(cx, traced),
        cx.options.scalar,
        &|var| cx.input(var),
        sunk.as_ref().map(|k| &k.sink),
        cx.lanes.map(|_| &cx.scalar),
    )?;
    let used = Used::of(traced, &outputs(cx, traced), cx.nq, cx.nv);
    // A staged matrix ([`staged`]) is the caller's: neither declared nor returned here.
    let (declare, result) = if staged(cx, traced).is_some() {
        (TokenStream::new(), TokenStream::new())
    } else {
        (
            sunk.as_ref().map(|k| k.declare.clone()).unwrap_or_default(),
            result(cx, traced, &emitted, sunk.as_ref().map(|k| &k.names[..])),
        )
    };
    // Each argument, and the `let` that binds the entries the function reads.
    let types = cx.types();
    let (args, inputs): (Vec<TokenStream>, Vec<TokenStream>) = traced
        .output
        .spec()
        .args
        .iter()
        .map(|&arg| {
            let used = match arg {
                Arg::Q => &used.q,
                Arg::Base => &used.base,
                Arg::V => &used.v,
                Arg::A => &used.a,
                Arg::Tau => &used.tau,
            };
            let ty = traced.output.spec().arg_type(arg, &types);
            let id = format_ident!("{}", arg.name());
            (quote!(#id: &#ty,), destructure(arg.name(), used))
        })
        .unzip();
    let p_arg = if used.params { quote!(p) } else { quote!(_p) };
    let (uses, statements) = (&emitted.uses, &emitted.statements);
    Ok((
        args,
        p_arg,
        quote! {
            #uses
            #(#inputs)*
            #declare
            #statements
            #result
        },
    ))
}

/// The fewest operations of an output whose batch twin takes the lanes that fit one of the
/// target's registers (`articulated::lanes::fit`) rather than the lanes asked for. Carried in
/// two halves (four `f64` lanes without AVX, eight with AVX and no AVX-512), the statements need
/// twice the registers: a large function then spills, while a small one gains from the halves'
/// extra instruction-level parallelism. Measured on the default target, four lanes against
/// two: arm7's mass matrix (356 operations) faster in four, its nonlinear effects and inverse
/// dynamics (543, 564) the same either way, its forward dynamics (1,132), its inverse dynamics'
/// derivatives and the humanoid's mass matrix (about 4,000 each) faster in two (the figures
/// are in the commit that set this).
const FIT_OPS: usize = 1000;

/// The batch twin of an output (`inverse_dynamics_batch_with_each`) over lanes of `n` states:
/// the output's statements in `F64x4` (`articulated::lanes`) as an inner function, run on each
/// group of `n` states gathered from the slices, with their runtime parameters in lanes, its
/// results scattered into `out`.
fn batch(cx: &Context, traced: &Traced, n: usize) -> syn::Result<TokenStream> {
    let spec = traced.output.spec();
    let fit = traced.ops().total() >= FIT_OPS;
    let lanes = cx.with_lanes(n, fit);
    let (args, p_arg, body) = function(&lanes, traced)?;
    let lane = &lanes.scalar;
    let n_lit = group_size(n, fit);
    let staged = staged(&lanes, traced);
    let ret = if staged.is_some() && !spec.fallible {
        TokenStream::new()
    } else {
        lane_ret(traced.output, &lanes, &n_lit)
    };
    let names = arg_names(traced.output);
    let (stage, stage_param, stage_arg) = stage_tokens(staged.as_ref(), lane);
    let call = quote!(lanes(#(&::articulated::lanes::gather(#names),)* &lanes_p, #stage_arg));
    let (call, scatter) = if spec.fallible {
        (
            quote!(let values = #call;),
            quote!(::articulated::lanes::scatter_results(&values.0, &values.1, out);),
        )
    } else if let Some((name, ..)) = &staged {
        (
            quote!(#call;),
            quote!(::articulated::lanes::Split::scatter(&#name, out);),
        )
    } else {
        (
            quote!(let values = #call;),
            quote!(::articulated::lanes::Split::scatter(&values, out);),
        )
    };
    let np_lit = Literal::usize_unsuffixed(cx.param_idents.len());
    let allow = match traced.output {
        Output::KineticEnergy | Output::PotentialEnergy => {
            quote!(#[allow(clippy::let_and_return)])
        }
        _ => TokenStream::new(),
    };
    let doc = lanes_doc(spec.name, n, fit);
    let inner = quote! {
        #[doc = #doc]
        #allow
        #[allow(clippy::type_complexity)]
        #[inline(always)]
        fn lanes(#(#args)* #p_arg: &[#lane; #np_lit], #stage_param) #ret {
            #body
        }
    };
    Ok(batch_shell(
        cx,
        traced.output,
        (&lanes, &n_lit, fit),
        inner,
        stage,
        quote!(#call #scatter),
    ))
}

/// `-> value` of an output's function in lanes (`lanes`), and where it can fail each lane's
/// first failure beside it (groups of `n_lit` states).
fn lane_ret(output: Output, lanes: &Context, n_lit: &TokenStream) -> TokenStream {
    let value = output.spec().value_type(&lanes.types());
    if output.spec().fallible {
        quote!(-> (#value, [::core::option::Option<::articulated::SingularMassMatrix>; #n_lit]))
    } else {
        quote!(-> #value)
    }
}

/// The lanes a group of a batch holds, as the batch function writes it: the count asked for,
/// or where the lanes `fit`, the fitting lane type's (`LANES`, a constant of the batch
/// function, [`batch_shell`]).
pub(super) fn group_size(n: usize, fit: bool) -> TokenStream {
    if fit {
        quote!(LANES)
    } else {
        Literal::usize_unsuffixed(n).into_token_stream()
    }
}

/// The names of an output's arguments (`q`, `v`, `tau`), as its functions bind them.
pub(super) fn arg_names(output: Output) -> Vec<proc_macro2::Ident> {
    output
        .spec()
        .args
        .iter()
        .map(|a| format_ident!("{}", a.name()))
        .collect()
}

/// A batch twin (`_batch_with_each`) around its lane functions `inner`: the lengths checked, a
/// batch of one state sent to the scalar function, `prepare` run once, then for each group of
/// states (`out` and each argument's slice of the group, named as the arguments, and the
/// group's parameters in lanes, `lanes_p`) the statements `group`. `lanes`: the chain in
/// lanes, the group's size ([`group_size`]) and whether the lanes fit a register.
pub(super) fn batch_shell(
    cx: &Context,
    output: Output,
    (lanes, n_lit, fit): (&Context, &TokenStream, bool),
    inner: TokenStream,
    prepare: TokenStream,
    group: TokenStream,
) -> TokenStream {
    let spec = output.spec();
    let t = cx.types();
    let each = spec.batch_each_name();
    let out_ty = spec.batch_out_type(&t);
    let lane = &lanes.scalar;
    let lanes_const = if fit {
        quote!(const LANES: usize = <#lane as ::articulated::lanes::Simd>::LANES;)
    } else {
        quote!()
    };
    let names = arg_names(output);
    let strs: Vec<&str> = spec.args.iter().map(|a| a.name()).collect();
    let types: Vec<TokenStream> = spec.args.iter().map(|&a| spec.arg_type(a, &t)).collect();
    let np = cx.param_idents.len();
    // The group's number, read only to gather its parameters.
    let k = if np == 0 { quote!(_) } else { quote!(k) };
    let (zipped, pattern) = names.iter().fold(
        (
            quote!(out.chunks_mut(#n_lit).enumerate()),
            quote!((#k, out)),
        ),
        |(z, p), a| (quote!(#z.zip(#a.chunks(#n_lit))), quote!((#p, #a))),
    );
    // A batch of one state goes to the scalar function, which computes what its lane would, bit
    // for bit, without computing three padding lanes (what a call from Python with one state
    // is). Outside the loop: a branch in it slowed the humanoid's forward dynamics in lanes.
    let with = spec.with_name();
    let single = quote! {
        if let ([o], #([#names]),*) = (&mut *out, #(#names),*) {
            *o = Self::#with(#(#names,)* ::articulated::lanes::params_of(p, 0));
            return Ok(());
        }
    };
    let params_ty = &cx.params_ty;
    let (params, group_params) = lane_params(cx, lane, n_lit);
    // Not inlined into the caller: one call runs a whole batch, and inlined into a large caller
    // the lane statements were left partly unvectorized (arm7's inverse dynamics in four lanes
    // ran no faster than the scalar loop).
    quote! {
        #[allow(clippy::type_complexity)]
        #[inline(never)]
        fn #each(
            #(#names: &[#types],)*
            p: &[#params_ty],
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), ::articulated::lanes::BatchLengths> {
            #lanes_const
            #inner
            ::articulated::lanes::check_batch(out.len(), &[#((#strs, #names.len())),*], p.len())?;
            #single
            #params
            #prepare
            for #pattern in #zipped {
                #group_params
                #group
            }
            Ok(())
        }
    }
}

/// A part of a composed output as a function in lanes inside its batch twin (`name`, never
/// inlined: each part is large): `traced`'s statements in `lanes`, returning its value in lanes
/// and, where the output can fail, each lane's first failure (groups of `n_lit` states).
pub(super) fn lane_part(
    lanes: &Context,
    traced: &Traced,
    name: &proc_macro2::Ident,
    n_lit: &TokenStream,
) -> syn::Result<TokenStream> {
    let spec = traced.output.spec();
    // The parts (forward dynamics, its derivatives' parts) have no staged matrix: each result
    // is returned.
    debug_assert!(staged(lanes, traced).is_none());
    let (args, p_arg, body) = function(lanes, traced)?;
    let (lane, ret) = (&lanes.scalar, lane_ret(traced.output, lanes, n_lit));
    let np_lit = Literal::usize_unsuffixed(lanes.param_idents.len());
    let doc = format!(
        " `{}` on a group of states: the same statements in lanes (`articulated::lanes::fit`).",
        spec.name
    );
    Ok(quote! {
        #[doc = #doc]
        #[allow(clippy::type_complexity)]
        #[inline(never)]
        fn #name(#(#args)* #p_arg: &[#lane; #np_lit]) #ret {
            #body
        }
    })
}

/// The documentation of a batch twin's inner function: `name` on `n` states at once, or on as
/// many as a register holds where the lanes `fit`.
fn lanes_doc(name: &str, n: usize, fit: bool) -> String {
    if fit {
        format!(
            " `{name}` on {n} states at once where one of the target's vector registers holds \
             {n} (`articulated::lanes::fit`), else on as many as it holds: the same statements \
             in lanes."
        )
    } else {
        format!(
            " `{name}` on {n} states at once: the same statements in lanes (`articulated::lanes`)."
        )
    }
}

/// The staged matrix of a batch (see [`staged`]): its declaration, once per call and zero where
/// the function never stores, the lane function's parameter and the argument each group passes
/// it by `&mut`; nothing where the output has none.
fn stage_tokens(
    staged: Option<&(proc_macro2::Ident, usize, usize)>,
    lane: &TokenStream,
) -> (TokenStream, TokenStream, TokenStream) {
    let Some((name, r, c)) = staged else {
        return (quote!(), quote!(), quote!());
    };
    let zero = quote!(<#lane as ::articulated::lanes::Simd>::ZERO);
    let (r, c) = (Literal::usize_unsuffixed(*r), Literal::usize_unsuffixed(*c));
    let ty = quote!(::articulated::nalgebra::SMatrix::<#lane, #r, #c>);
    (
        quote! {
            let mut #name = #ty::from_array_storage(
                ::articulated::nalgebra::ArrayStorage([[#zero; #r]; #c])
            );
        },
        quote!(#name: &mut #ty,),
        quote!(&mut #name,),
    )
}

/// The runtime parameters in lanes of a batch over groups of `n` states: what the call
/// prepares once, and what each group `k` binds as `lanes_p`. Each group's own where `p` holds
/// one set per state, the same set in every lane (gathered once) where it holds one for all;
/// an empty array where the chain has none.
fn lane_params(cx: &Context, lane: &TokenStream, n: &TokenStream) -> (TokenStream, TokenStream) {
    let np = cx.param_idents.len();
    if np == 0 {
        return (quote!(let lanes_p: [#lane; 0] = [];), quote!());
    }
    let (params_ty, element, fields) = (&cx.params_ty, &cx.element, &cx.param_idents);
    let np = Literal::usize_unsuffixed(np);
    (
        quote! {
            let fields = |p: &#params_ty| -> [#element; #np] { [#(p.#fields),*] };
            let once = (p.len() == 1)
                .then(|| ::articulated::lanes::gather_params::<#lane, _, #np>(p, fields));
        },
        quote! {
            let lanes_p = match once {
                Some(p) => p,
                None => ::articulated::lanes::gather_params(&p[k * #n..], fields),
            };
        },
    )
}

/// The fewest entries of a [`staged`] matrix.
const STAGED_ENTRIES: usize = 256;

/// In lanes, the one matrix of a sunk output that solves nothing (`M`, its lower triangle,
/// the Coriolis and centroidal momentum matrices) as (name, rows, columns), where it has at
/// least [`STAGED_ENTRIES`] entries: the batch function declares it once and the lane function
/// stores into it through `&mut`, rather than zeroing and copying a new one (43 KB for the
/// humanoid's `M` in `F64x4`) for every group of states. A small matrix is returned by value:
/// the optimizer keeps it in registers, which a matrix that lives across groups cannot be
/// (staged, arm7's 7×7 `M` in `f32` lanes was slower on the default target). The figures
/// are in commits e12e0ab and c635335.
fn staged(cx: &Context, traced: &Traced) -> Option<(proc_macro2::Ident, usize, usize)> {
    cx.lanes?;
    if traced.output.is_kept() || traced.output.spec().fallible {
        return None;
    }
    match sunk_layout(cx, traced)?.0[..] {
        [(name, rows, cols)] if rows * cols >= STAGED_ENTRIES => {
            Some((format_ident!("{name}"), rows, cols))
        }
        _ => None,
    }
}

/// The matrices of an output's result, each stored into as soon as its entries are computed
/// ([`emit::Sink`]): the sink, the `let`s that declare them, and their names.
struct Sunk {
    sink: emit::Sink,
    declare: TokenStream,
    names: Vec<proc_macro2::Ident>,
}

/// The matrices [`result`] returns, as (name, rows, columns) and where value `i` goes
/// (`None` for a value not returned, else the matrix and its row and column), for the outputs
/// where storing as computed measured faster; `None` for the others, whose results are built
/// from their values at the end.
///
/// Measured side by side (x86-64-v3), stored as computed against built at the end: faster for
/// the humanoid's `M`, centroidal momentum matrix and Coriolis matrix and for arm7's
/// `inverse_dynamics_derivatives` and `mass_matrix_inverse`, no different for
/// `forward_dynamics_derivatives`. Left at the end: `mass_matrix_and_nonlinear_effects` (slower
/// on the humanoid with `M` stored as computed, whether or not its `nle` was too), the
/// centre-of-mass Jacobian (slower), and the vectors and scalars, whose few values cost little
/// to keep. The figures are in this comment's history (commit 4b955c8).
#[allow(clippy::type_complexity)]
fn sunk_layout(
    cx: &Context,
    traced: &Traced,
) -> Option<(
    Vec<(&'static str, usize, usize)>,
    Box<dyn Fn(usize) -> Option<(usize, usize, usize)>>,
)> {
    let nv = cx.nv;
    let nn = nv * nv;
    // Row-major `rows × cols` values from `start`, in matrix `k`.
    let row_major = move |k: usize, cols: usize, start: usize| {
        move |i: usize| {
            let j = i.checked_sub(start)?;
            Some((k, j / cols, j % cols))
        }
    };
    Some(match traced.output {
        Output::MassMatrix | Output::MassMatrixUpdate => {
            (vec![("mass_matrix", nv, nv)], Box::new(row_major(0, nv, 0)))
        }
        // The lower triangle row by row (`Traced::values`).
        Output::MassMatrixLower => {
            let lower: Vec<(usize, usize)> = lower_triangle(nv).collect();
            (
                vec![("mass_matrix", nv, nv)],
                Box::new(move |i| lower.get(i).map(|&(r, c)| (0, r, c))),
            )
        }
        Output::CoriolisMatrix => (
            vec![("coriolis_matrix", nv, nv)],
            Box::new(row_major(0, nv, 0)),
        ),
        Output::CentroidalMomentumMatrix => (
            vec![("centroidal_momentum_matrix", 6, nv)],
            Box::new(row_major(0, nv, 0)),
        ),
        Output::InverseDynamicsDerivatives => (
            vec![("dtau_dq", nv, nv), ("dtau_dv", nv, nv)],
            Box::new(move |i| Some((i / nn, (i % nn) / nv, i % nv))),
        ),
        // q̈ first, not returned (its finiteness is checked).
        Output::ForwardDynamicsDerivatives => (
            vec![
                ("dqdd_dq", nv, nv),
                ("dqdd_dv", nv, nv),
                ("mass_matrix_inverse", nv, nv),
            ],
            Box::new(move |i| {
                let j = i.checked_sub(nv)?;
                Some((j / nn, (j % nn) / nv, j % nv))
            }),
        ),
        Output::MassMatrixInverse => (
            vec![("mass_matrix_inverse", nv, nv)],
            Box::new(row_major(0, nv, 0)),
        ),
        _ => return None,
    })
}

/// The [`Sunk`] matrices of `traced`'s result, if it is made of matrices (see [`sunk_layout`]).
fn sink(cx: &Context, traced: &Traced) -> Option<Sunk> {
    let (matrices, place) = sunk_layout(cx, traced)?;
    let scalar = &cx.scalar;
    let names: Vec<_> = matrices.iter().map(|m| format_ident!("{}", m.0)).collect();
    // nalgebra's storage is column by column: entry (r, c) is `data.0[c][r]`.
    let places = (0..traced.values.len())
        .map(|i| match place(i) {
            Some((k, r, c)) => {
                let (name, r, c) = (
                    &names[k],
                    Literal::usize_unsuffixed(r),
                    Literal::usize_unsuffixed(c),
                );
                vec![quote!(#name.data.0[#c][#r])]
            }
            None => Vec::new(),
        })
        .collect();
    let zero = match cx.lanes {
        Some(_) => quote!(<#scalar as ::articulated::lanes::Simd>::ZERO),
        None => emit::zero(cx.options.scalar),
    };
    // Each matrix a new zero one; the update's is the one its caller keeps, not zeroed (only the
    // entries that can be non-zero are stored).
    let zeroed = |(&(_, rows, cols), name): (&(&str, usize, usize), &proc_macro2::Ident)| {
        let (r, c) = (
            Literal::usize_unsuffixed(rows),
            Literal::usize_unsuffixed(cols),
        );
        let ty = quote!(::articulated::nalgebra::SMatrix::<#scalar, #r, #c>);
        quote! {
            let mut #name = #ty::from_array_storage(
                ::articulated::nalgebra::ArrayStorage([[#zero; #r]; #c])
            );
        }
    };
    let declare = if traced.output.is_kept() {
        quote!(let mass_matrix = ::articulated::__private::kept_entries(kept);)
    } else {
        matrices.iter().zip(&names).map(zeroed).collect()
    };
    // The mass matrix cut into basic blocks (`emit::Sink::boundaries`, measured there). Not the
    // other outputs, which it made slower or larger (x86-64-v3, five layouts each): the
    // humanoid's forward dynamics slower at every spacing from 80 to 500 statements, its
    // inverse dynamics and nonlinear effects larger, arm7's derivatives and `mass_matrix_inverse`
    // slower (the figures: this comment's history, commit 4b955c8).
    let boundaries = traced.output == Output::MassMatrix || traced.output.is_kept();
    Some(Sunk {
        sink: emit::Sink { places, boundaries },
        declare,
        names,
    })
}

/// What an output's function looks like, from its description ([`crate::outputs::Spec`]): its
/// trait, the `kept` argument after the parameters, and its return type (`-> …`, or nothing).
struct Signature {
    trait_: TokenStream,
    after_params: TokenStream,
    ret: TokenStream,
}

fn signature(cx: &Context, output: Output) -> Signature {
    let spec = output.spec();
    let t = cx.types();
    Signature {
        trait_: spec.trait_path(&t),
        after_params: spec.kept_arg(&t).map(|k| quote!(#k,)).unwrap_or_default(),
        ret: spec.ret(&t),
    }
}

/// The expression a function returns after its statements: the result built from the values
/// (or, for an output whose matrices were [`sink`]ed, those matrices by name), behind the checks
/// of the outputs that solve with `M`.
fn result(
    cx: &Context,
    traced: &Traced,
    emitted: &Emitted,
    sunk: Option<&[proc_macro2::Ident]>,
) -> TokenStream {
    let values = &emitted.outputs[..traced.values.len()];
    let nv = cx.nv;
    if traced.output.is_kept() {
        return TokenStream::new();
    }
    let built = match sunk {
        Some([one]) => quote!(#one),
        Some(names) => quote!((#(#names),*)),
        None => built(cx, traced.output, values),
    };
    let ok = |finite: &[TokenStream]| {
        let checks = pivot_checks(cx, traced, emitted);
        let finite = finite_checks(cx, finite);
        match cx.lanes {
            // Every check of every lane, the first failure per lane kept (`lanes::refuse`).
            Some(_) => {
                let lane = &cx.scalar;
                quote! {
                    let mut status = [None; <#lane as ::articulated::lanes::Simd>::LANES];
                    #(#checks)* #(#finite)*
                    (#built, status)
                }
            }
            None => quote!(#(#checks)* #(#finite)* Ok(#built)),
        }
    };
    let spec = traced.output.spec();
    if !spec.fallible {
        return built;
    }
    // The accelerations, returned or not (forward dynamics' derivatives compute q̈ first): a
    // non-finite q̈ (a NaN in `v` or `tau`) is refused like a singular `M`.
    match spec.parts.first() {
        Some(Part::Hidden | Part::Vector(Dim::Nv)) => ok(&values[..nv]),
        _ => ok(&[]),
    }
}

/// An output's result from its values (see [`crate::trace`] for their order), part by part as
/// its description says ([`crate::outputs::Part`]).
fn built(cx: &Context, output: Output, values: &[TokenStream]) -> TokenStream {
    let size = |d: Dim| match d {
        Dim::Nv => cx.nv,
        Dim::Nb => cx.model.nb(),
        Dim::Nf => cx.options.frames.len(),
        Dim::N(n) => n,
    };
    let each_size = |e: Each| match e {
        Each::Placement => 12,
        Each::Vector(n) => n,
        Each::Matrix(r, c, _) => r * size(c),
        Each::Matrices(n, r, c, _) => n * r * size(c),
    };
    let mut rest = values;
    let mut parts = Vec::new();
    for &part in output.spec().parts {
        let n = match part {
            Part::Scalar => 1,
            Part::Vector(d) => size(d),
            Part::Matrix(r, c, _) => size(r) * size(c),
            Part::Hidden => cx.nv,
            Part::Kept { .. } => 0,
            Part::Frames(e) => cx.options.frames.len() * each_size(e),
        };
        let (these, after) = rest.split_at(n);
        rest = after;
        parts.push(match part {
            Part::Scalar => these[0].clone(),
            Part::Vector(_) => vector(cx, these),
            // nalgebra stores columns.
            Part::Matrix(r, _, Order::Columns) => columns(cx, these, size(r)),
            Part::Matrix(r, _, Order::Rows) => columns(cx, &transposed(these, size(r)), size(r)),
            Part::Hidden | Part::Kept { .. } => continue,
            Part::Frames(e) => {
                let each = these.chunks(each_size(e).max(1)).map(|v| match e {
                    Each::Placement => {
                        let rotation = columns(cx, &transposed(&v[..9], 3), 3);
                        let translation = vector(cx, &v[9..]);
                        quote! {
                            ::articulated::FramePlacement {
                                rotation: #rotation,
                                translation: #translation,
                            }
                        }
                    }
                    Each::Vector(_) => vector(cx, v),
                    Each::Matrix(r, _, Order::Columns) => columns(cx, v, r),
                    Each::Matrix(r, _, Order::Rows) => columns(cx, &transposed(v, r), r),
                    Each::Matrices(n, r, _, order) => {
                        let each = v.chunks((v.len() / n.max(1)).max(1)).map(|m| match order {
                            Order::Columns => columns(cx, m, r),
                            Order::Rows => columns(cx, &transposed(m, r), r),
                        });
                        quote!((#(#each),*))
                    }
                });
                quote!([#(#each),*])
            }
        });
    }
    match &parts[..] {
        [] => TokenStream::new(),
        [one] => one.clone(),
        many => quote!((#(#many),*)),
    }
}

/// One `if` per acceleration: an error where it is not finite (in lanes, the lanes where it
/// is not).
fn finite_checks(cx: &Context, qdd: &[TokenStream]) -> Vec<TokenStream> {
    qdd.iter()
        .enumerate()
        .map(|(k, x)| {
            let k = Literal::usize_unsuffixed(k);
            let ok = match cx.lanes {
                Some(_) => quote!(::articulated::lanes::is_finite(#x)),
                None => quote!(#x.is_finite()),
            };
            refusal(cx, ok, &k, true)
        })
        .collect()
}

/// `if !(ok) { return Err(SingularMassMatrix { velocity }) }`; in lanes, `ok` is a mask and the
/// lanes where it is false are refused (`lanes::refuse`) instead of returning.
/// `ok` is negated as written (`!x.is_finite()`) where `simple`, in parentheses otherwise.
fn refusal(cx: &Context, ok: TokenStream, velocity: &Literal, simple: bool) -> TokenStream {
    let not_ok = if simple { quote!(!#ok) } else { quote!(!(#ok)) };
    match cx.lanes {
        Some(_) => quote!(::articulated::lanes::refuse(&mut status, #ok, #velocity);),
        None => quote! {
            if #not_ok {
                return Err(::articulated::SingularMassMatrix { velocity: #velocity });
            }
        },
    }
}

/// A row-major matrix of `rows` rows as its entries column by column.
pub(super) fn transposed(values: &[TokenStream], rows: usize) -> Vec<TokenStream> {
    let cols = values.len() / rows;
    (0..cols)
        .flat_map(|c| (0..rows).map(move |r| values[r * cols + c].clone()))
        .collect()
}

/// `SVector::from_array_storage(ArrayStorage([[v0, v1, …]]))`.
pub(super) fn vector(cx: &Context, values: &[TokenStream]) -> TokenStream {
    let (scalar, nv) = (&cx.scalar, Literal::usize_unsuffixed(values.len()));
    quote! {
        ::articulated::nalgebra::SVector::<#scalar, #nv>::from_array_storage(
            ::articulated::nalgebra::ArrayStorage([[#(#values),*]])
        )
    }
}

/// A matrix of `rows` rows from its entries column by column.
pub(super) fn columns(cx: &Context, values: &[TokenStream], rows: usize) -> TokenStream {
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

/// The pivots' tolerances in this scalar: against each unreduced value, and against their sum
/// (the trace), which an `f32` `LᵀDL` has none of (see `PIVOT_TOL_GLOBAL_F64`).
fn tolerances(cx: &Context, pivots: &Pivots) -> (f64, Option<f64>) {
    let f32 = cx.options.scalar == ScalarKind::F32;
    match (f32, pivots.aba) {
        (true, false) => (PIVOT_TOL_F32, None),
        (true, true) => (PIVOT_TOL_F32, Some(PIVOT_TOL_GLOBAL_ABA_F32)),
        (false, false) => (PIVOT_TOL_F64, Some(PIVOT_TOL_GLOBAL_F64)),
        (false, true) => (PIVOT_TOL_F64, Some(PIVOT_TOL_GLOBAL_ABA_F64)),
    }
}

/// What the function computes: the values, each pivot and its unreduced value, and the sum of
/// those where a check reads it (its operation counts are those of these).
pub(super) fn outputs(cx: &Context, traced: &Traced) -> Vec<Sym> {
    let mut all = traced.all_outputs();
    if traced
        .pivots
        .as_ref()
        .is_some_and(|p| tolerances(cx, p).1.is_none())
    {
        all.pop();
    }
    all
}

/// One `if` per pivot that can fail: positive relative to its unreduced value and to the sum of
/// them all. A check whose outcome the constants already settle is decided here: a pivot that is
/// a constant passing against a constant needs no local test, and one that is its own unreduced
/// value (the first pivot of a factorization, a leaf's) only needs to be positive.
fn pivot_checks(cx: &Context, traced: &Traced, emitted: &Emitted) -> Vec<TokenStream> {
    let Some(pivots) = &traced.pivots else {
        return Vec::new();
    };
    let (tol, tol_global) = tolerances(cx, pivots);
    let constant = |s| match traced.graph.node(s) {
        Node::Const(x) => Some(x),
        _ => None,
    };
    let n = traced.values.len();
    let exprs = &emitted.outputs[n..];
    // Emitted only where a check reads it (`outputs`).
    let scale_expr = exprs
        .get(2 * pivots.pairs.len())
        .cloned()
        .unwrap_or_default();
    let scale_const = constant(pivots.scale);
    let positive_pivot = match cx.lanes {
        Some(_) => quote!(::articulated::lanes::positive_pivot),
        None => quote!(::articulated::__private::positive_pivot),
    };
    let mut checks = Vec::new();
    let (mut uses_local, mut uses_global) = (false, false);
    if let Some(k) = pivots.singular {
        // Decided by the generator (`trace::singular_everywhere`); the function's docs say so.
        let k = Literal::usize_unsuffixed(k);
        checks.push(match cx.lanes {
            Some(_) => quote!(::articulated::lanes::refuse(
                &mut status,
                ::articulated::lanes::Mask::NONE,
                #k
            );),
            None => quote! {
                if ::articulated::__private::singular_at_every_configuration() {
                    return Err(::articulated::SingularMassMatrix { velocity: #k });
                }
            },
        });
    }
    for (k, &(p, d)) in pivots.pairs.iter().enumerate() {
        let (pe, de) = (&exprs[2 * k], &exprs[2 * k + 1]);
        let (p_const, d_const) = (constant(p), constant(d));
        let local = match (p_const, d_const) {
            (Some(pv), Some(dv)) if pv > tol * dv => None,
            _ if p == d => Some(match cx.lanes {
                Some(_) => quote!(::articulated::lanes::positive(#pe)),
                None => {
                    let zero = cx.lit(0.0);
                    quote!(#pe > #zero)
                }
            }),
            _ => {
                uses_local = true;
                Some(quote!(#positive_pivot(#pe, #de, PIVOT_TOL)))
            }
        };
        let global = match (p_const, scale_const, tol_global) {
            (_, _, None) => None,
            // Nothing was eliminated from an exact pivot (`Pivots::exact`): it carries no
            // rounding noise from the rest of the tree for the trace to expose, so a light or
            // slender leaf 1e12 below the rest passes.
            _ if pivots.exact[k] => None,
            (Some(pv), Some(sv), Some(tol_global)) if pv > tol_global * sv => None,
            (_, _, Some(_)) => {
                uses_global = true;
                Some(quote!(#positive_pivot(#pe, #scale_expr, PIVOT_TOL_TRACE)))
            }
        };
        let condition = match (local, global) {
            (None, None) => continue,
            (Some(c), None) | (None, Some(c)) => c,
            (Some(l), Some(g)) if cx.lanes.is_some() => quote!(#l & #g),
            (Some(l), Some(g)) => quote!(#l && #g),
        };
        let k = Literal::usize_unsuffixed(k);
        checks.push(refusal(cx, condition, &k, false));
    }
    // The tolerances by name where a check reads them (`M` is singular where a pivot is not
    // above `PIVOT_TOL` of its unreduced value, or `PIVOT_TOL_TRACE` of the trace): constants,
    // or in a generic scalar the values converted once.
    let scalar = &cx.element;
    let declare = |name: TokenStream, tol: f64| {
        let value = cx.lit(tol);
        match cx.options.scalar {
            ScalarKind::Generic => quote!(#[allow(non_snake_case)] let #name: #scalar = #value;),
            _ => quote!(const #name: #scalar = #value;),
        }
    };
    let mut declared = Vec::new();
    if uses_local {
        declared.push(declare(quote!(PIVOT_TOL), tol));
    }
    if let (true, Some(tol_global)) = (uses_global, tol_global) {
        declared.push(declare(quote!(PIVOT_TOL_TRACE), tol_global));
    }
    declared.extend(checks);
    declared
}

/// `let [[q0, _, q2]] = q.data.0;` binding the inputs a function uses (`_` for the others, so
/// the user's crate sees no unused variable).
pub(super) fn destructure(vector: &str, used: &[bool]) -> TokenStream {
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
pub(super) struct Used {
    pub(super) q: Vec<bool>,
    pub(super) v: Vec<bool>,
    pub(super) a: Vec<bool>,
    pub(super) tau: Vec<bool>,
    pub(super) base: Vec<bool>,
    pub(super) forces: Vec<bool>,
    pub(super) params: bool,
}

impl Used {
    fn of(t: &Traced, outputs: &[Sym], nq: usize, nv: usize) -> Used {
        let base = if t.output == Output::JointWrenchesBottomUp {
            6
        } else {
            0
        };
        Used::in_graph(&t.graph, outputs, nq, nv, base)
    }

    /// The inputs `graph` reads to compute `outputs` (`base` the length of the base wrench).
    pub(super) fn in_graph(
        graph: &Graph,
        outputs: &[Sym],
        nq: usize,
        nv: usize,
        base: usize,
    ) -> Used {
        let mut u = Used {
            q: vec![false; nq],
            v: vec![false; nv],
            a: vec![false; nv],
            tau: vec![false; nv],
            base: vec![false; base],
            forces: Vec::new(),
            params: false,
        };
        for s in graph.live(outputs) {
            if let Node::Input(var) = graph.node(s) {
                match var {
                    Var::Q(i) => u.q[i] = true,
                    Var::V(i) => u.v[i] = true,
                    Var::A(i) => u.a[i] = true,
                    Var::Tau(i) => u.tau[i] = true,
                    Var::Base(i) => u.base[i] = true,
                    Var::Force(i) => {
                        if u.forces.len() <= i {
                            u.forces.resize(i + 1, false);
                        }
                        u.forces[i] = true;
                    }
                    Var::Param(_) => u.params = true,
                }
            }
        }
        u
    }
}
