//! Explicit Euler and semi-implicit (symplectic) Euler, on the manifold (Lie–Euler: `q ⊕ h·v`).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, RealField};

use super::{scaled, Fault, Integrator, SecondOrder, State, Step};

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

/// One step of either method: `v_{n+1} = v_n + h·a(t_n, q_n, v_n)` and `q_{n+1} = q_n ⊕ h·v`
/// with `v = v_n` ([`Euler`]) or `v = v_{n+1}` ([`SymplecticEuler`], `symplectic`).
#[inline(always)]
fn euler<T, Q, V, S>(
    symplectic: bool,
    system: &mut S,
    state: &mut State<T, Q, V>,
    t_to: T,
    step: usize,
) -> Result<(), Fault<T>>
where
    T: RealField + Copy,
    Q: Dim,
    V: Dim,
    S: SecondOrder<T, Q, V> + ?Sized,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    let (mut s, h) = Step::begin(system, state, t_to, step, false)?;
    let a = s.evaluate(state.t, &state.q, &state.v)?;
    let v = &state.v + a * h;
    let q = s.retract(&state.q, &scaled(if symplectic { &v } else { &state.v }, h));
    s.commit(state, t_to, q, v)
}

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
        euler(false, system, state, t_to, step)
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
        euler(true, system, state, t_to, step)
    }
}
