//! The classic fourth-order Runge–Kutta method, as a Runge–Kutta–Munthe-Kaas method.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, RealField};

use super::{k, scaled, Fault, Integrator, SecondOrder, State, Step};

/// Classic Runge–Kutta (Kutta 1901; Hairer, Nørsett & Wanner 1993, *Solving Ordinary
/// Differential Equations I*, 2nd ed., §II.1, Table 1.2, left): order 4, four evaluations per
/// step. Stages are taken in local coordinates `q = q_n ⊕ θ` with `θ̇ = dexp⁻¹_θ(v)`
/// (Munthe-Kaas 1998; [`crate::configuration`]), so it keeps order 4 on quaternion joints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rk4;

impl<T: RealField + Copy, Q: Dim, V: Dim> Integrator<T, Q, V> for Rk4
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
        let (mut s, h) = Step::begin(system, state, t_to, step, false)?;
        let t = state.t;
        let half = h * k(0.5);
        let (q, v) = (&state.q, &state.v);
        // Stage 1 at θ = 0, where dexp⁻¹ is the identity.
        let kv1 = s.evaluate(t, q, v)?;
        let kq1 = v;
        let (kq2, kv2) = s.stage(t + half, q, &scaled(kq1, half), &(v + scaled(&kv1, half)))?;
        let (kq3, kv3) = s.stage(t + half, q, &scaled(&kq2, half), &(v + scaled(&kv2, half)))?;
        let (kq4, kv4) = s.stage(t_to, q, &scaled(&kq3, h), &(v + scaled(&kv3, h)))?;
        let sixth = h * k(1.0 / 6.0);
        let third = h * k(1.0 / 3.0);
        let theta = kq1 * sixth + kq2 * third + kq3 * third + kq4 * sixth;
        let v_new = v + kv1 * sixth + kv2 * third + kv3 * third + kv4 * sixth;
        let q_new = s.retract(q, &theta);
        s.commit(state, t_to, q_new, v_new)
    }
}
