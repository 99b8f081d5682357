//! The implicit midpoint rule on the manifold, solved by Newton's method.

// The Newton solve's LU of the `NV × NV` Jacobian, indexed by loop counters below `NV`: an
// exception to the crate's indexing rule.
#![allow(clippy::indexing_slicing)]

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, RealField, Scalar, U1};

use super::{k, scaled, Cause, Fault, Integrator, Quantity, SecondOrder, State, Step};

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

/// The Newton matrix `J = I − (h/2)·∂f/∂u` of a step, LU-factorized in place with partial
/// pivoting (`P·J = L·U`, unit `L` below the diagonal, `U` on and above; `pivots[k]` the row
/// swapped with row `k` at step `k`).
struct Newton<T: Scalar, V: Dim>
where
    DefaultAllocator: Allocator<V> + Allocator<V, V>,
{
    lu: OMatrix<T, V, V>,
    pivots: OVector<usize, V>,
    /// False when a pivot was zero or not finite.
    factored: bool,
}

impl<T: RealField + Copy, V: Dim> Newton<T, V>
where
    DefaultAllocator: Allocator<V> + Allocator<V, V>,
{
    fn new(dim: V) -> Self {
        Newton {
            lu: OMatrix::<T, V, V>::identity_generic(dim, dim),
            pivots: OVector::<usize, V>::from_element_generic(dim, U1, 0),
            factored: false,
        }
    }

    /// `J` at `u` by forward differences of `f` (`a_u = f(u)`), factored.
    fn refresh<F>(
        &mut self,
        u: &OVector<T, V>,
        a_u: &OVector<T, V>,
        half: T,
        f: &mut F,
    ) -> Result<(), Cause<T>>
    where
        F: FnMut(&OVector<T, V>) -> Result<OVector<T, V>, Cause<T>>,
    {
        let sqrt_eps = T::default_epsilon().sqrt();
        self.lu.fill_with_identity();
        for j in 0..u.len() {
            let d = sqrt_eps * u[j].abs().max(T::one());
            let mut uj = u.clone();
            uj[j] += d;
            let col = (f(&uj)? - a_u) * (half / d);
            let mut c = self.lu.column_mut(j);
            c -= col;
        }
        self.factored = self.factor();
        Ok(())
    }

    /// The factorization; false when a pivot is zero or not finite.
    fn factor(&mut self) -> bool {
        let (a, pivots) = (&mut self.lu, &mut self.pivots);
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

    /// Solves `J·x = b` with the factors.
    fn solve(&self, mut b: OVector<T, V>) -> OVector<T, V> {
        let (lu, pivots) = (&self.lu, &self.pivots);
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
}

impl<T: RealField + Copy> ImplicitMidpoint<T> {
    /// Solves `u = v + (h/2)·f(u)` for the midpoint velocity `u` by simplified Newton
    /// iterations (the [struct docs](Self)), with `half = h/2` and
    /// `f(u) = a(t_n + h/2, q_n ⊕ (h/2)·w(u), u)`.
    fn solve<V, F>(
        &mut self,
        v: &OVector<T, V>,
        half: T,
        mut f: F,
    ) -> Result<OVector<T, V>, Cause<T>>
    where
        V: Dim,
        F: FnMut(&OVector<T, V>) -> Result<OVector<T, V>, Cause<T>>,
        DefaultAllocator: Allocator<V> + Allocator<V, V>,
    {
        let (tolerance, max_iterations) = (self.tolerance, self.max_iterations);
        let stats = &mut self.stats;
        // `f`, counting the evaluations that succeed.
        let mut f = |u: &OVector<T, V>| {
            let a = f(u)?;
            stats.evaluations += 1;
            Ok(a)
        };
        let mut newton = Newton::new(v.shape_generic().0);
        let mut u = v.clone();
        let mut a_u = f(&u)?;
        // The Newton matrix at the current iterate; refreshed when convergence is slow.
        let mut refresh = true;
        let mut previous: Option<T> = None;
        let mut iterations = 0;
        loop {
            let residual = &u - v - scaled(&a_u, half);
            let fresh = refresh;
            if refresh {
                newton.refresh(&u, &a_u, half, &mut f)?;
                refresh = false;
            }
            iterations += 1;
            stats.iterations += 1;
            let failed = |correction| Cause::NewtonFailed {
                iterations,
                correction,
            };
            if !newton.factored {
                return Err(failed(None));
            }
            let delta = newton.solve(residual);
            u -= &delta;
            let size = delta.amax();
            let scale = u.amax() + v.amax();
            if size <= tolerance * scale {
                return Ok(u);
            }
            if !size.is_finite() || iterations >= max_iterations {
                return Err(failed(Some(size)));
            }
            match previous {
                // Stalled at rounding level: converged as far as it can.
                Some(p) if size >= p * k(0.5) && size <= T::default_epsilon() * k(1e3) * scale => {
                    return Ok(u)
                }
                // Growing although the matrix was fresh: Newton diverges.
                Some(p) if size > p && fresh => return Err(failed(Some(size))),
                // Slow (or growing on an old matrix): refresh the matrix at the next iterate.
                Some(p) if size > p * k(0.25) && !fresh => refresh = true,
                _ => {}
            }
            previous = Some(size);
            a_u = match f(&u) {
                Ok(a) => a,
                // An iterate that left the finite numbers is Newton's failure, not the state's.
                Err(Cause::NonFinite {
                    quantity: Quantity::Position | Quantity::Velocity,
                    ..
                }) => return Err(failed(Some(size))),
                Err(cause) => return Err(cause),
            };
        }
    }
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
        let (mut s, h) = Step::begin(system, state, t_to, step, true)?;
        let half = h * k(0.5);
        let t_m = state.t + half;
        let (q, v) = (&state.q, &state.v);
        self.stats.steps += 1;
        // w(u), the local-coordinate rate at the midpoint θ = (h/2)·u.
        let rate =
            |s: &Step<'_, T, Q, V, S>, u: &OVector<T, V>| s.local_velocity(&scaled(u, half), u);
        let u = self
            .solve(v, half, |u| {
                let q_m = s.retract(q, &scaled(&rate(&s, u), half));
                s.evaluate(t_m, &q_m, u).map_err(|fault| fault.cause)
            })
            .map_err(s.at(t_m))?;
        let q_new = s.retract(q, &scaled(&rate(&s, &u), h));
        let v_new = scaled(&u, k(2.0)) - v;
        s.commit(state, t_to, q_new, v_new)
    }
}
