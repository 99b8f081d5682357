//! What stands in for the generated items after an error, so the user sees the real error and
//! not a cascade of "cannot find type" or "no function named" errors after it (as `thiserror`'s
//! `fallback.rs`). The ui tests in `macros/tests/ui` lock this.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::outputs::{Types, SPECS};

/// `NQ` and `NV` (zero), the declared constraints' items (none, and a
/// `constrained_forward_dynamics` generic in the sizes), every output's operation count (`MASS_MATRIX_OPS`, zero) and trait ([`SPECS`]), generic in the scalar and in one
/// size `N` for `q`, `v` and the joints, so that uses of them type-check and the sizes are
/// inferred from `q` (a size left free would be a "type annotations needed" error of its own).
/// The bodies are never run: the crate does not compile.
pub(crate) fn fallback(name: &Ident) -> TokenStream {
    let t = Types {
        scalar: quote!(T),
        nq: quote!(N),
        nv: quote!(N),
        nb: quote!(N),
        nf: quote!(N),
        krate: quote!(::articulated),
    };
    let name_str = name.to_string();
    let impls = SPECS.iter().map(|s| {
        let trait_ = s.trait_path(&t);
        let with = s.with_name();
        let args = s.args.iter().map(|&a| {
            let ty = s.arg_type(a, &t);
            quote!(_: &#ty,)
        });
        let kept = s.kept_type(&t).map(|ty| quote!(, _: #ty));
        let ret = s.ret(&t);
        quote! {
            impl<T, const N: usize> #trait_ for #name {
                fn #with(#(#args)* _: &() #kept) #ret { ::core::unreachable!() }
            }
        }
    });
    let ops = SPECS.iter().map(|s| {
        let name = format_ident!("{}_OPS", s.name.to_uppercase());
        quote! {
            /// Stand-in after an error in the description.
            pub const #name: ::articulated::OpCounts = ::articulated::OpCounts {
                adds: 0, muls: 0, divs: 0, negs: 0, sin_cos: 0, sqrts: 0,
            };
        }
    });
    quote! {
        impl #name {
            #(#ops)*
            /// Stand-in after an error in the description.
            pub const NQ: usize = 0;
            /// Stand-in after an error in the description.
            pub const NV: usize = 0;
            /// Stand-in after an error in the description.
            pub const NB: usize = 0;
            /// Stand-in after an error in the description.
            pub const NF: usize = 0;
            /// Stand-in after an error in the description.
            pub const CONTACTS: &'static [::articulated::constraint::Contact] = &[];
            /// Stand-in after an error in the description.
            pub const LOOPS: &'static [::articulated::constraint::Loop] = &[];
            /// Stand-in after an error in the description.
            pub const CONSTRAINT_ROWS: usize = 0;
            /// Stand-in after an error in the description: the forces sized as `v`, so that
            /// uses need no annotation.
            pub fn constrained_forward_dynamics<const NQ: usize, const NV: usize>(
                _: &::articulated::nalgebra::SVector<f64, NQ>,
                _: &::articulated::nalgebra::SVector<f64, NV>,
                _: &::articulated::nalgebra::SVector<f64, NV>,
            ) -> ::core::result::Result<
                (
                    ::articulated::nalgebra::SVector<f64, NV>,
                    ::articulated::nalgebra::SVector<f64, NV>,
                ),
                ::articulated::constraint::ConstraintError,
            > {
                ::core::unreachable!()
            }
        }
        impl<T> ::articulated::Chain<T> for #name {
            const NAME: &'static str = #name_str;
            const COORDINATES: &'static [::articulated::Coordinates] = &[];
            const Q_NAMES: &'static [&'static str] = &[];
            const V_NAMES: &'static [&'static str] = &[];
            const DRIVES: &'static [::articulated::Drive] = &[];
            type Params = ();
            fn default_params() {}
        }
        #(#impls)*
    }
}
