//! The implicit midpoint rule on the manifold, solved by Newton's method.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, RealField};

use super::{
    begin, commit, evaluate, k, local_velocity, retract, scaled, Cause, Fault, Integrator,
    Quantity, SecondOrder, State,
};

/// Counters of an [`ImplicitMidpoint`] since it was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MidpointStats {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations, all steps together.
    pub iterations: usize,
    /// Evaluations of the acceleration (Jacobians included).
    pub evaluations: usize,
}

/// The implicit midpoint rule (the one-stage Gauss method; Hairer, Lubich & Wanner 2006,
/// *Geometric Numerical Integration*, 2nd ed., ch. II (Gauss methods) and ch. V (symmetric
/// methods)): order 2, symmetric, for long horizons (why this method: [the module
/// docs](super)).
///
/// With the midpoint velocity `u = (v_n + v_{n+1})/2` as unknown, a step solves
/// `u = v_n + (h/2)·a(t_n + h/2, q_n ⊕ (h/2)·w(u), u)` and sets `v_{n+1} = 2u − v_n`,
/// `q_{n+1} = q_n ⊕ h·w(u)`, where `w(u)` is the local-coordinate rate at the midpoint
/// ([`crate::configuration::local_velocity`] at `θ = (h/2)·u`): `u` itself for vectors and
/// rotations (`dexp⁻¹_θ(ω) = ω` when `θ ∥ ω`, so the Gauss condition holds exactly), the
/// velocity rotated into the midpoint orientation for a free joint's position.
///
/// Newton's method: the Jacobian `I − (h/2)·∂a/∂u` (total derivative, through `q` too) by
/// forward differences with steps `√ε·max(1, |u_j|)`, computed once per step at `u = v_n`
/// (`NV + 1` evaluations) and LU-factorized with partial pivoting; then simplified Newton
/// iterations (one evaluation each) until the correction is below
/// `tolerance·(|u|∞ + |v_n|∞)`, or stops shrinking at rounding level (below `1000ε` times
/// that).
/// When a correction is more than a quarter of the one before (slow convergence, a large
/// step), the Jacobian is recomputed at the current iterate. No convergence in
/// `max_iterations`, a correction that grows although the Jacobian is fresh, or a singular
/// Jacobian stop the integration with [`Cause::NewtonFailed`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplicitMidpoint<T> {
    /// Relative size of the last Newton correction that counts as converged (default `4ε`).
    pub tolerance: T,
    /// Most Newton iterations per step (default 16).
    pub max_iterations: usize,
    stats: MidpointStats,
}

impl<T: RealField + Copy> ImplicitMidpoint<T> {
    /// The implicit midpoint rule with the default Newton settings.
    pub fn new() -> Self {
        ImplicitMidpoint {
            tolerance: T::default_epsilon() * k(4.0),
            max_iterations: 16,
            stats: MidpointStats::default(),
        }
    }

    /// The counters.
    pub fn stats(&self) -> MidpointStats {
        self.stats
    }
}

impl<T: RealField + Copy> Default for ImplicitMidpoint<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// LU factorization with partial pivoting in place (`P·A = L·U`, unit `L` below the diagonal,
/// `U` on and above; `pivots[k]` the row swapped with row `k` at step `k`). False when a pivot
/// is zero or not finite.
fn lu_in_place<T, V>(a: &mut OMatrix<T, V, V>, pivots: &mut OVector<usize, V>) -> bool
where
    T: RealField + Copy,
    V: Dim,
    DefaultAllocator: Allocator<V> + Allocator<V, V>,
{
    let n = a.nrows();
    for col in 0..n {
        let (mut best, mut size) = (col, a[(col, col)].abs());
        for row in col + 1..n {
            if a[(row, col)].abs() > size {
                (best, size) = (row, a[(row, col)].abs());
            }
        }
        if !(size > T::zero() && size.is_finite()) {
            return false;
        }
        pivots[col] = best;
        a.swap_rows(col, best);
        let p = a[(col, col)];
        for row in col + 1..n {
            let f = a[(row, col)] / p;
            a[(row, col)] = f;
            for j in col + 1..n {
                let x = a[(col, j)];
                a[(row, j)] -= f * x;
            }
        }
    }
    true
}

/// Solves `A·x = b` with the factors of [`lu_in_place`].
fn lu_solve<T, V>(
    lu: &OMatrix<T, V, V>,
    pivots: &OVector<usize, V>,
    mut b: OVector<T, V>,
) -> OVector<T, V>
where
    T: RealField + Copy,
    V: Dim,
    DefaultAllocator: Allocator<V> + Allocator<V, V>,
{
    let n = lu.nrows();
    for k in 0..n {
        b.swap_rows(k, pivots[k]);
    }
    for i in 0..n {
        let mut x = b[i];
        for j in 0..i {
            x -= lu[(i, j)] * b[j];
        }
        b[i] = x;
    }
    for i in (0..n).rev() {
        let mut x = b[i];
        for j in i + 1..n {
            x -= lu[(i, j)] * b[j];
        }
        b[i] = x / lu[(i, i)];
    }
    b
}

/// `a(t_m, q_n ⊕ (h/2)·w(u), u)`.
fn midpoint_acceleration<T, Q, V, S>(
    system: &mut S,
    vs: bool,
    t_m: T,
    half: T,
    q: &OVector<T, Q>,
    u: &OVector<T, V>,
) -> Result<OVector<T, V>, Cause<T>>
where
    T: RealField + Copy,
    Q: Dim,
    V: Dim,
    S: SecondOrder<T, Q, V> + ?Sized,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    let coords = system.coordinates();
    let w = local_velocity(coords, vs, &scaled(u, half), u);
    let q_m = retract(coords, vs, q, &scaled(&w, half));
    evaluate(system, t_m, &q_m, u)
}

impl<T, Q, V> Integrator<T, Q, V> for ImplicitMidpoint<T>
where
    T: RealField + Copy,
    Q: Dim,
    V: Dim,
    DefaultAllocator: Allocator<Q> + Allocator<V> + Allocator<V, V>,
{
    fn advance<S: SecondOrder<T, Q, V> + ?Sized>(
        &mut self,
        system: &mut S,
        state: &mut State<T, Q, V>,
        t_to: T,
        step: usize,
    ) -> Result<(), Fault<T>> {
        let t = state.t;
        let (h, vs) = begin(system, state, t_to, true).map_err(|cause| Fault { t, step, cause })?;
        let half = h * k(0.5);
        let t_m = t + half;
        let fault = |cause| Fault {
            t: t_m,
            step,
            cause,
        };
        let (q, v) = (&state.q, &state.v);
        self.stats.steps += 1;

        let sqrt_eps = T::default_epsilon().sqrt();
        let dim = v.shape_generic().0;
        let mut jac = OMatrix::<T, V, V>::identity_generic(dim, dim);
        let mut pivots = OVector::<usize, V>::from_element_generic(dim, nalgebra::U1, 0);
        let mut u = v.clone();
        let mut a_u = midpoint_acceleration(system, vs, t_m, half, q, &u).map_err(fault)?;
        self.stats.evaluations += 1;
        // The Newton matrix at the current iterate; refreshed when convergence is slow.
        let mut refresh = true;
        let mut fresh;
        let mut factored = false;
        let mut previous: Option<T> = None;
        let mut iterations = 0;
        loop {
            let residual = &u - v - scaled(&a_u, half);
            if refresh {
                // J = I − (h/2)·∂a/∂u by forward differences at u.
                jac.fill_with_identity();
                for j in 0..v.len() {
                    let d = sqrt_eps * u[j].abs().max(T::one());
                    let mut uj = u.clone();
                    uj[j] += d;
                    let aj = midpoint_acceleration(system, vs, t_m, half, q, &uj).map_err(fault)?;
                    self.stats.evaluations += 1;
                    let col = (aj - &a_u) * (half / d);
                    let mut c = jac.column_mut(j);
                    c -= col;
                }
                factored = lu_in_place(&mut jac, &mut pivots);
                (refresh, fresh) = (false, true);
            } else {
                fresh = false;
            }
            iterations += 1;
            self.stats.iterations += 1;
            let failed = |correction| {
                fault(Cause::NewtonFailed {
                    iterations,
                    correction,
                })
            };
            if !factored {
                return Err(failed(None));
            }
            let delta = lu_solve(&jac, &pivots, residual);
            u -= &delta;
            let size = delta.amax();
            let scale = u.amax() + v.amax();
            if size <= self.tolerance * scale {
                break;
            }
            if !size.is_finite() || iterations >= self.max_iterations {
                return Err(failed(Some(size)));
            }
            match previous {
                // Stalled at rounding level: converged as far as it can.
                Some(p) if size >= p * k(0.5) && size <= T::default_epsilon() * k(1e3) * scale => {
                    break
                }
                // Growing although the matrix was fresh: Newton diverges.
                Some(p) if size > p && fresh => return Err(failed(Some(size))),
                // Slow (or growing on an old matrix): refresh the matrix at the next iterate.
                Some(p) if size > p * k(0.25) && !fresh => refresh = true,
                _ => {}
            }
            previous = Some(size);
            a_u = match midpoint_acceleration(system, vs, t_m, half, q, &u) {
                Ok(a) => a,
                // An iterate that left the finite numbers is Newton's failure, not the state's.
                Err(Cause::NonFinite {
                    quantity: Quantity::Position | Quantity::Velocity,
                    ..
                }) => return Err(failed(Some(size))),
                Err(cause) => return Err(fault(cause)),
            };
            self.stats.evaluations += 1;
        }

        let coords = system.coordinates();
        let w = local_velocity(coords, vs, &scaled(&u, half), &u);
        let q_new = retract(coords, vs, q, &scaled(&w, h));
        let v_new = scaled(&u, k(2.0)) - v;
        commit(state, t_to, q_new, v_new, step)
    }
}
