//! What generated forward dynamics refuses, in `f64` and `f32` (issue 30, item 6):
//!
//! - the floating humanoid (`models/humanoid.chain`, 37 velocity coordinates, a 75 kg body
//!   whose wrists are a few grams of inertia) solves every one of 64 random regular states in
//!   `f32`, with the default `LᵀDL`: `‖M·q̈ − (τ − h)‖∞ / ‖τ − h‖∞ ≤ 1e-4` against the `f64`
//!   reference's `M` and `h = bias + gravity` at the same (rounded) inputs, and `q̈` within 1e-3
//!   of the acceleration `τ` was made from. An `f32` pivot used to be held to 1e-5 of the trace
//!   of `M`, which the base's mass dominates: every state was refused;
//! - every model whose `M` is singular at every configuration is refused in every state, in both
//!   scalars: Pinocchio's `arm6_mixed` and the two-link `two_link_xyz` on a free base over their
//!   massless roots (the base's rotation about the first joint's axis moves nothing the joint
//!   does not), with an Euler and a quaternion base. Their pivots are rounding noise that passed
//!   the comparisons in some states (`arm6_mixed` on an Euler base: 8e-12 of its unreduced value
//!   and 1.07e-12 of the trace in `f64`, 6e-4 and 7e-5 in `f32`); the generator now finds the
//!   singularity itself (`articulated_codegen::trace::singular_everywhere`).
//!
//! `cargo test -p articulated-tests --test generated_pivots -- --nocapture` prints the worst
//! `f32` errors.

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_codegen::urdf::FloatingBase;
use articulated_dynamics::random::random_state;

/// Random states per model.
const STATES: u64 = 64;

#[derive(Chain)]
#[chain(file = "../models/humanoid.chain", scalar = f32, outputs = [forward_dynamics])]
struct HumanoidF32;

#[derive(Chain)]
#[chain(urdf = "data/pinocchio/arm6_mixed.urdf", floating, outputs = [forward_dynamics])]
struct Arm6Floating;
#[derive(Chain)]
#[chain(
    urdf = "data/pinocchio/arm6_mixed.urdf",
    floating,
    scalar = f32,
    outputs = [forward_dynamics]
)]
struct Arm6FloatingF32;
#[derive(Chain)]
#[chain(
    urdf = "data/pinocchio/arm6_mixed.urdf",
    floating = quaternion,
    outputs = [forward_dynamics, mass_matrix_inverse, forward_dynamics_derivatives]
)]
struct Arm6Quaternion;
#[derive(Chain)]
#[chain(
    urdf = "data/pinocchio/arm6_mixed.urdf",
    floating = quaternion,
    scalar = f32,
    outputs = [forward_dynamics]
)]
struct Arm6QuaternionF32;
#[derive(Chain)]
#[chain(urdf = "data/pinocchio/two_link_xyz.urdf", floating, outputs = [forward_dynamics])]
struct TwoLinkFloating;
#[derive(Chain)]
#[chain(
    urdf = "data/pinocchio/two_link_xyz.urdf",
    floating,
    scalar = f32,
    outputs = [forward_dynamics]
)]
struct TwoLinkFloatingF32;

fn f32s<const N: usize>(x: &[f64]) -> SVector<f32, N> {
    SVector::<f32, N>::from_iterator(x.iter().map(|&v| v as f32))
}

fn norm_inf(x: impl IntoIterator<Item = f64>) -> f64 {
    x.into_iter().fold(0.0, |a, x| a.max(x.abs()))
}

#[test]
fn f32_humanoid_solves_regular_states() {
    let model = load_model(Path::new(articulated_models::HUMANOID.chain), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let (mut worst_residual, mut worst_error) = (0.0f64, 0.0f64);
    let mut refused = Vec::new();
    for seed in 0..STATES {
        let (q, v, a) = random_state(&model, seed);
        // The inputs rounded to f32 first, so that both sides see the same state.
        let round = |x: &[f64]| x.iter().map(|&x| f64::from(x as f32)).collect::<Vec<_>>();
        let (q, v, a) = (round(&q), round(&v), round(&a));
        let tau = round(r.inverse_dynamics(&q, &v, &a).unwrap().as_slice());
        let (qf, vf, tauf) = (f32s::<38>(&q), f32s::<37>(&v), f32s::<37>(&tau));
        let Ok(qdd) = HumanoidF32::forward_dynamics(&qf, &vf, &tauf) else {
            refused.push(seed);
            continue;
        };
        let qdd: Vec<f64> = qdd.iter().map(|&x| f64::from(x)).collect();
        let m = r.mass_matrix(&q).unwrap();
        let h = r.bias(&q, &v).unwrap() + r.gravity(&q).unwrap();
        let rhs: Vec<f64> = (0..37).map(|i| tau[i] - h[i]).collect();
        let residual = norm_inf((0..37).map(|i| {
            let mq: f64 = (0..37).map(|j| m[(i, j)] * qdd[j]).sum();
            mq - rhs[i]
        })) / norm_inf(rhs.iter().copied());
        // `a` solves M·a = τ − h with τ rounded: the f64 reference's q̈ to ~1e-7.
        let error = norm_inf(qdd.iter().zip(&a).map(|(x, y)| x - y)) / norm_inf(a.iter().copied());
        worst_residual = worst_residual.max(residual);
        worst_error = worst_error.max(error);
    }
    println!(
        "humanoid f32 forward dynamics, {STATES} states: worst residual {worst_residual:.1e}, \
         worst error against f64 {worst_error:.1e}"
    );
    assert!(
        refused.is_empty(),
        "f32 refused the states of seeds {refused:?}"
    );
    assert!(worst_residual <= 1e-4, "residual {worst_residual:.1e}");
    assert!(worst_error <= 5e-3, "error against f64 {worst_error:.1e}");
}

/// Every state of `C` is refused.
fn refuses_all<C, T, const NQ: usize, const NV: usize>(path: &str, floating: FloatingBase)
where
    C: ForwardDynamics<T, NQ, NV>,
    T: articulated::nalgebra::Scalar + Copy + From<f32>,
{
    let model = load_model(Path::new(path), floating).unwrap();
    for seed in 0..STATES {
        let (q, v, a) = random_state(&model, seed);
        let lift = |x: &[f64]| x.iter().map(|&x| T::from(x as f32)).collect::<Vec<T>>();
        let q = SVector::<T, NQ>::from_column_slice(&lift(&q));
        let v = SVector::<T, NV>::from_column_slice(&lift(&v));
        let tau = SVector::<T, NV>::from_column_slice(&lift(&a));
        assert!(
            C::forward_dynamics(&q, &v, &tau).is_err(),
            "{path} ({floating:?}, {}): state {seed} was solved; M is singular everywhere",
            core::any::type_name::<T>()
        );
    }
}

#[test]
fn models_singular_everywhere_are_refused_in_both_scalars() {
    let arm6 = "data/pinocchio/arm6_mixed.urdf";
    let two_link = "data/pinocchio/two_link_xyz.urdf";
    let (euler, quaternion) = (FloatingBase::Euler, FloatingBase::Quaternion);
    refuses_all::<Arm6Floating, f64, 12, 12>(arm6, euler);
    refuses_all::<Arm6FloatingF32, f32, 12, 12>(arm6, euler);
    refuses_all::<Arm6Quaternion, f64, 13, 12>(arm6, quaternion);
    refuses_all::<Arm6QuaternionF32, f32, 13, 12>(arm6, quaternion);
    refuses_all::<TwoLinkFloating, f64, 12, 12>(two_link, euler);
    refuses_all::<TwoLinkFloatingF32, f32, 12, 12>(two_link, euler);
}

#[test]
fn the_other_pivoted_outputs_refuse_them_too() {
    let model = load_model(
        Path::new("data/pinocchio/arm6_mixed.urdf"),
        FloatingBase::Quaternion,
    )
    .unwrap();
    for seed in 0..8 {
        let (q, v, a) = random_state(&model, seed);
        let q = SVector::<f64, 13>::from_column_slice(&q);
        let v = SVector::<f64, 12>::from_column_slice(&v);
        let tau = SVector::<f64, 12>::from_column_slice(&a);
        assert!(Arm6Quaternion::mass_matrix_inverse(&q).is_err());
        assert!(Arm6Quaternion::forward_dynamics_derivatives(&q, &v, &tau).is_err());
    }
}
