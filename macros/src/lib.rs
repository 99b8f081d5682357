//! The `chain!` and `#[derive(Chain)]` macros of `articulated`: a shim over
//! `articulated-codegen`, where all the logic lives (`articulated_codegen::expand`). Use them
//! through the `articulated` crate, which re-exports them with the traits they implement.

use proc_macro::TokenStream;

/// Generates a chain's dynamics from a description written inline (the grammar of
/// `articulated_codegen::parse`):
///
/// ```ignore
/// articulated::chain! {
///     pub chain Pendulum {
///         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// ```
#[proc_macro]
pub fn chain(input: TokenStream) -> TokenStream {
    articulated_codegen::expand::chain(input.into()).into()
}

/// Generates a chain's dynamics on a unit struct from a file, relative to the crate's
/// `CARGO_MANIFEST_DIR`: `#[chain(file = "models/x.chain")]` or
/// `#[chain(urdf = "models/x.urdf")]` (add `floating` for a free base under the URDF root).
#[proc_macro_derive(Chain, attributes(chain))]
pub fn derive_chain(input: TokenStream) -> TokenStream {
    articulated_codegen::expand::derive(input.into()).into()
}

/// The runtime's output traits, from the generator's table of outputs
/// (`articulated_codegen::outputs`): expanded once, inside the `articulated` crate, so that each
/// output is described in one place.
#[doc(hidden)]
#[proc_macro]
pub fn __output_traits(_input: TokenStream) -> TokenStream {
    articulated_codegen::outputs::runtime_traits().into()
}
