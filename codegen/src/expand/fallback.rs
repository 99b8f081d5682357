//! What stands in for the generated items after an error, so the user sees the real error and
//! not a cascade of "cannot find type" or "no function named" errors after it (as `thiserror`'s
//! `fallback.rs`). The ui tests in `macros/tests/ui` lock this.

use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// `NQ` and `NV` (zero) and the runtime traits, generic in the scalar and in one size `N` for
/// both `q` and `v`, so that uses of them type-check and the sizes are inferred from `q` (a size
/// left free would be a "type annotations needed" error of its own). The bodies are never run:
/// the crate does not compile.
pub(crate) fn fallback(name: &Ident) -> TokenStream {
    let sizes = quote!(<T, const N: usize>);
    let v = quote!(::articulated::nalgebra::SVector<T, N>);
    let m = quote!(::articulated::nalgebra::SMatrix<T, N, N>);
    let fd = quote!(::core::result::Result<#v, ::articulated::SingularMassMatrix>);
    let fdd = quote!(::core::result::Result<(#m, #m, #m), ::articulated::SingularMassMatrix>);
    let minv = quote!(::core::result::Result<#m, ::articulated::SingularMassMatrix>);
    let w = quote!(::articulated::nalgebra::SMatrix<T, 6, N>);
    let v6 = quote!(::articulated::nalgebra::SVector<T, 6>);
    let v3 = quote!(::articulated::nalgebra::SVector<T, 3>);
    let j3 = quote!(::articulated::nalgebra::SMatrix<T, 3, N>);
    let never = quote!({ ::core::unreachable!() });
    let name_str = name.to_string();
    quote! {
        impl #name {
            /// Stand-in after an error in the description.
            pub const NQ: usize = 0;
            /// Stand-in after an error in the description.
            pub const NV: usize = 0;
            /// Stand-in after an error in the description.
            pub const NB: usize = 0;
        }
        impl<T> ::articulated::Chain<T> for #name {
            const NAME: &'static str = #name_str;
            const COORDINATES: &'static [::articulated::Coordinates] = &[];
            const DRIVES: &'static [::articulated::Drive] = &[];
            type Params = ();
            fn default_params() {}
        }
        impl #sizes ::articulated::MassMatrix<T, N, N> for #name {
            fn mass_matrix_with(_: &#v, _: &()) -> #m #never
        }
        impl #sizes ::articulated::MassMatrixUpdate<T, N, N> for #name {
            fn mass_matrix_update_with(
                _: &#v,
                _: &(),
                _: &mut ::articulated::KeptMassMatrix<Self, T, N>,
            ) #never
        }
        impl #sizes ::articulated::MassMatrixLower<T, N, N> for #name {
            fn mass_matrix_lower_with(
                _: &#v,
                _: &(),
                _: &mut ::articulated::KeptMassMatrixLower<Self, T, N>,
            ) #never
        }
        impl #sizes ::articulated::Bias<T, N, N> for #name {
            fn bias_with(_: &#v, _: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::Gravity<T, N, N> for #name {
            fn gravity_with(_: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::InverseDynamics<T, N, N> for #name {
            fn inverse_dynamics_with(_: &#v, _: &#v, _: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::ForwardDynamics<T, N, N> for #name {
            fn forward_dynamics_with(_: &#v, _: &#v, _: &#v, _: &()) -> #fd #never
        }
        impl #sizes ::articulated::NonlinearEffects<T, N, N> for #name {
            fn nonlinear_effects_with(_: &#v, _: &#v, _: &()) -> #v #never
        }
        impl #sizes ::articulated::MassMatrixAndNonlinearEffects<T, N, N> for #name {
            fn mass_matrix_and_nonlinear_effects_with(_: &#v, _: &#v, _: &()) -> (#m, #v) #never
        }
        impl #sizes ::articulated::JointWrenches<T, N, N, N> for #name {
            fn joint_wrenches_with(_: &#v, _: &#v, _: &#v, _: &()) -> #w #never
        }
        impl #sizes ::articulated::JointWrenchesBottomUp<T, N, N, N> for #name {
            fn joint_wrenches_bottom_up_with(_: &#v, _: &#v, _: &#v, _: &#v6, _: &()) -> #w #never
        }
        impl #sizes ::articulated::CenterOfMass<T, N, N> for #name {
            fn center_of_mass_with(_: &#v, _: &()) -> #v3 #never
        }
        impl #sizes ::articulated::CenterOfMassVelocity<T, N, N> for #name {
            fn center_of_mass_velocity_with(_: &#v, _: &#v, _: &()) -> #v3 #never
        }
        impl #sizes ::articulated::CenterOfMassJacobian<T, N, N> for #name {
            fn center_of_mass_jacobian_with(_: &#v, _: &()) -> #j3 #never
        }
        impl #sizes ::articulated::CentroidalMomentum<T, N, N> for #name {
            fn centroidal_momentum_with(_: &#v, _: &#v, _: &()) -> #v6 #never
        }
        impl #sizes ::articulated::CentroidalMomentumMatrix<T, N, N> for #name {
            fn centroidal_momentum_matrix_with(_: &#v, _: &()) -> #w #never
        }
        impl #sizes ::articulated::KineticEnergy<T, N, N> for #name {
            fn kinetic_energy_with(_: &#v, _: &#v, _: &()) -> T #never
        }
        impl #sizes ::articulated::PotentialEnergy<T, N, N> for #name {
            fn potential_energy_with(_: &#v, _: &()) -> T #never
        }
        impl #sizes ::articulated::CoriolisMatrix<T, N, N> for #name {
            fn coriolis_matrix_with(_: &#v, _: &#v, _: &()) -> #m #never
        }
        impl #sizes ::articulated::InverseDynamicsDerivatives<T, N, N> for #name {
            fn inverse_dynamics_derivatives_with(_: &#v, _: &#v, _: &#v, _: &()) -> (#m, #m) #never
        }
        impl #sizes ::articulated::ForwardDynamicsDerivatives<T, N, N> for #name {
            fn forward_dynamics_derivatives_with(_: &#v, _: &#v, _: &#v, _: &()) -> #fdd #never
        }
        impl #sizes ::articulated::MassMatrixInverse<T, N, N> for #name {
            fn mass_matrix_inverse_with(_: &#v, _: &()) -> #minv #never
        }
    }
}
