//! Many copies of one chain stepped together: [`Ensemble`], the classic Runge–Kutta step of
//! [`Rk4`](super::Rk4) for every state of a batch, each stage's accelerations from one call of
//! the chain's batch forward dynamics (`C::forward_dynamics_batch_with_each`, in lanes where the
//! chain asks for them: `lanes: 4`).
//!
//! For ensembles, Monte Carlo runs and rollouts: thousands of copies of a robot, each with its
//! own state and its own joint forces. Each copy's step is [`Rk4`](super::Rk4)'s, stage by
//! stage and operation by operation (the same Munthe-Kaas stages on quaternion joints), so a
//! copy stepped in an ensemble follows the trajectory it follows alone; the tests hold the two
//! to each other.

use alloc::vec::Vec;

use nalgebra::{RealField, SVector};

use super::k;
use crate::configuration;
use crate::lanes::{check_batch, BatchLengths};
use crate::{ForwardDynamics, SingularMassMatrix};

/// The scratch of an ensemble's steps: the stages of every copy, kept from one step to the next
/// so that a step allocates nothing once the ensemble's size is reached.
///
/// ```
/// # use articulated::nalgebra::SVector;
/// # use articulated::integrate::{ControlledChain, Ensemble, Integrator, Rk4, State};
/// articulated::chain! {
///     chain Pendulum {
///         lanes: 4;
///         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// // Ten pendulums released from ten angles, each under its own constant torque.
/// let mut q: Vec<_> = (0..10).map(|i| SVector::<f64, 1>::new(0.1 * i as f64)).collect();
/// let mut v = vec![SVector::<f64, 1>::zeros(); 10];
/// let tau: Vec<_> = (0..10).map(|i| SVector::<f64, 1>::new(0.01 * i as f64)).collect();
/// let mut faults = vec![None; 10];
/// let mut ensemble = Ensemble::new();
/// ensemble.rk4::<Pendulum>(&mut q, &mut v, &tau, &[()], 0.01, &mut faults).unwrap();
///
/// // The seventh, stepped alone, lands where it did in the ensemble.
/// let mut alone = ControlledChain::<f64, Pendulum, _>::new(|_t: f64, _q: &_, _v: &_| tau[7]);
/// let mut state = State::new(0.0, SVector::<f64, 1>::new(0.7), SVector::zeros());
/// Rk4.advance(&mut alone, &mut state, 0.01, 0).unwrap();
/// assert!((state.q[0] - q[7][0]).abs() < 1e-15 && faults.iter().all(Option::is_none));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Ensemble<T: nalgebra::Scalar, const NQ: usize, const NV: usize> {
    /// The stage's positions `q_n ⊕ θ`.
    q: Vec<SVector<T, NQ>>,
    /// The stage's velocities.
    vel: Vec<SVector<T, NV>>,
    /// The stage's local coordinates `θ`.
    theta: Vec<SVector<T, NV>>,
    /// The slopes of `θ` at each stage (`kq1 = v`).
    kq: [Vec<SVector<T, NV>>; 4],
    /// The accelerations at each stage.
    kv: [Vec<Result<SVector<T, NV>, SingularMassMatrix>>; 4],
}

impl<T: RealField + Copy, const NQ: usize, const NV: usize> Ensemble<T, NQ, NV> {
    /// An ensemble with no scratch yet (the first step sizes it).
    pub fn new() -> Self {
        Ensemble {
            q: Vec::new(),
            vel: Vec::new(),
            theta: Vec::new(),
            kq: Default::default(),
            kv: Default::default(),
        }
    }

    /// One step of size `h` of [`Rk4`](super::Rk4) for every copy: `(q[i], v[i])` advanced
    /// under the joint forces `tau[i]`, held over the step, with the parameters `p[i]` (or
    /// `p[0]` for every copy where `p` holds one set: a sweep gives each copy its own payload,
    /// in lanes with its neighbours).
    ///
    /// A copy whose forward dynamics fails at a stage (a singular `M`, a non-finite
    /// acceleration: a NaN in its state or its forces), or whose result is not finite, is left
    /// as it was, with the first failure in `faults[i]`; `faults[i]` is `None` for every copy that advanced. The others
    /// are not affected.
    ///
    /// # Errors
    /// [`BatchLengths`] where `v`, `tau` or `faults` is not as long as `q`, or `p` holds
    /// neither one set nor one per copy (nothing is stepped).
    #[allow(clippy::too_many_arguments)]
    pub fn rk4<C: ForwardDynamics<T, NQ, NV>>(
        &mut self,
        q: &mut [SVector<T, NQ>],
        v: &mut [SVector<T, NV>],
        tau: &[SVector<T, NV>],
        p: &[C::Params],
        h: T,
        faults: &mut [Option<SingularMassMatrix>],
    ) -> Result<(), BatchLengths> {
        let n = q.len();
        check_batch(
            n,
            &[("v", v.len()), ("tau", tau.len()), ("faults", faults.len())],
            p.len(),
        )?;
        let coords = C::COORDINATES;
        let vector_space = configuration::is_vector_space(coords);
        self.size(n);
        let half = h * k(0.5);
        let sixth = h * k(1.0 / 6.0);
        let third = h * k(1.0 / 3.0);
        let retract = |q: &SVector<T, NQ>, theta: &SVector<T, NV>| {
            if vector_space {
                let mut out = *q;
                for (x, d) in out.iter_mut().zip(theta.iter()) {
                    *x += *d;
                }
                out
            } else {
                configuration::integrate(coords, q, theta)
            }
        };
        let local_velocity = |theta: &SVector<T, NV>, vel: &SVector<T, NV>| {
            if vector_space {
                *vel
            } else {
                configuration::local_velocity(coords, theta, vel)
            }
        };
        let Ensemble {
            q: q_stage,
            vel,
            theta,
            kq: [kq1, kq2, kq3, kq4],
            kv: [kv1, kv2, kv3, kv4],
        } = self;
        // Stage 1 at θ = 0, where dexp⁻¹ is the identity.
        C::forward_dynamics_batch_with_each(q, v, tau, p, kv1)?;
        for (kq, v) in kq1.iter_mut().zip(v.iter()) {
            *kq = *v;
        }
        // Stages 2 to 4: θ = kq_{s−1}·c and vel = v + kv_{s−1}·c, their slopes at q_n ⊕ θ.
        let mut stage =
            |kq_prev: &[SVector<T, NV>],
             kv_prev: &[Result<SVector<T, NV>, SingularMassMatrix>],
             c: T,
             kq_next: &mut [SVector<T, NV>],
             kv_next: &mut [Result<SVector<T, NV>, SingularMassMatrix>]| {
                let inputs = q.iter().zip(v.iter()).zip(kq_prev).zip(kv_prev);
                let stage = q_stage.iter_mut().zip(vel.iter_mut()).zip(theta.iter_mut());
                for ((((q_n, v_n), kq), kv), ((qs, vel), theta)) in inputs.zip(stage) {
                    // A copy that failed goes on from zero accelerations; it is not committed.
                    let kv = kv.as_ref().copied().unwrap_or_else(|_| SVector::zeros());
                    *theta = kq * c;
                    *vel = v_n + kv * c;
                    *qs = retract(q_n, theta);
                }
                for ((kq, theta), vel) in kq_next.iter_mut().zip(theta.iter()).zip(vel.iter()) {
                    *kq = local_velocity(theta, vel);
                }
                C::forward_dynamics_batch_with_each(q_stage, vel, tau, p, kv_next)
            };
        stage(kq1, kv1, half, kq2, kv2)?;
        stage(kq2, kv2, half, kq3, kv3)?;
        stage(kq3, kv3, h, kq4, kv4)?;
        let slopes = kq1.iter().zip(kq2.iter()).zip(kq3.iter()).zip(kq4.iter());
        let accelerations = kv1.iter().zip(kv2.iter()).zip(kv3.iter()).zip(kv4.iter());
        let copies = q.iter_mut().zip(v.iter_mut()).zip(faults.iter_mut());
        for ((((kq1, kq2), kq3), kq4), ((((a1, a2), a3), a4), ((q_n, v_n), fault))) in
            slopes.zip(accelerations.zip(copies))
        {
            let (k1, k2, k3, k4) = match (a1, a2, a3, a4) {
                (Ok(a), Ok(b), Ok(c), Ok(d)) => (a, b, c, d),
                _ => {
                    *fault = [a1, a2, a3, a4].into_iter().find_map(|a| a.err());
                    continue;
                }
            };
            let theta = kq1 * sixth + kq2 * third + kq3 * third + kq4 * sixth;
            let v_new = *v_n + k1 * sixth + k2 * third + k3 * third + k4 * sixth;
            let q_new = retract(q_n, &theta);
            // A result that overflowed: refused like a non-finite acceleration, at its first
            // non-finite velocity (or 0 for a position).
            if let Some(k) = q_new
                .iter()
                .chain(v_new.iter())
                .position(|x| !x.is_finite())
            {
                *fault = Some(SingularMassMatrix {
                    velocity: k.saturating_sub(NQ),
                });
                continue;
            }
            *q_n = q_new;
            *v_n = v_new;
            *fault = None;
        }
        Ok(())
    }

    /// Every scratch vector `n` long.
    fn size(&mut self, n: usize) {
        self.q.resize(n, SVector::zeros());
        self.vel.resize(n, SVector::zeros());
        self.theta.resize(n, SVector::zeros());
        for k in &mut self.kq {
            k.resize(n, SVector::zeros());
        }
        for k in &mut self.kv {
            k.resize(n, Ok(SVector::zeros()));
        }
    }
}
