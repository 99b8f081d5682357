//! Explicit Euler and semi-implicit (symplectic) Euler, on the manifold (Lie–Euler: `q ⊕ h·v`).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, RealField};

use super::{begin, commit, evaluate, retract, scaled, Fault, Integrator, SecondOrder, State};

/// Explicit Euler: `v̇_n = a(t_n, q_n, v_n)`, `q_{n+1} = q_n ⊕ h·v_n`, `v_{n+1} = v_n + h·v̇_n`.
/// Order 1, one evaluation per step. On quaternion joints this is the Lie–Euler method
/// (Hairer, Lubich & Wanner 2006, §IV.8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Euler;

/// Semi-implicit (symplectic) Euler: `v_{n+1} = v_n + h·a(t_n, q_n, v_n)`, then
/// `q_{n+1} = q_n ⊕ h·v_{n+1}`. Order 1, one evaluation per step; symplectic for separable
/// Hamiltonians with `v = q̇` (Hairer, Lubich & Wanner 2006, §VI.3, Theorem 3.3), so its energy
/// error stays bounded there. A chain's `M(q)` makes it non-separable: then it is only a cheap
/// first-order method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SymplecticEuler;

impl<T: RealField + Copy, Q: Dim, V: Dim> Integrator<T, Q, V> for Euler
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    fn advance<S: SecondOrder<T, Q, V> + ?Sized>(
        &mut self,
        system: &mut S,
        state: &mut State<T, Q, V>,
        t_to: T,
        step: usize,
    ) -> Result<(), Fault<T>> {
        let t = state.t;
        let fault = |cause| Fault { t, step, cause };
        let (h, vs) = begin(system, state, t_to, false).map_err(fault)?;
        let a = evaluate(system, t, &state.q, &state.v).map_err(fault)?;
        let q = retract(system.coordinates(), vs, &state.q, &scaled(&state.v, h));
        let v = &state.v + a * h;
        commit(state, t_to, q, v, step)
    }
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Integrator<T, Q, V> for SymplecticEuler
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    fn advance<S: SecondOrder<T, Q, V> + ?Sized>(
        &mut self,
        system: &mut S,
        state: &mut State<T, Q, V>,
        t_to: T,
        step: usize,
    ) -> Result<(), Fault<T>> {
        let t = state.t;
        let fault = |cause| Fault { t, step, cause };
        let (h, vs) = begin(system, state, t_to, false).map_err(fault)?;
        let a = evaluate(system, t, &state.q, &state.v).map_err(fault)?;
        let v = &state.v + a * h;
        let q = retract(system.coordinates(), vs, &state.q, &scaled(&v, h));
        commit(state, t_to, q, v, step)
    }
}
