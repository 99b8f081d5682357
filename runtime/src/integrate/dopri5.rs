//! Dormand–Prince 5(4) with error control, as a Runge–Kutta–Munthe-Kaas method.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, RealField, Scalar};

use super::{k, zeros_like, Cause, Fault, Integrator, SecondOrder, State, Step};
use crate::configuration::joints;
use crate::Coordinates;

/// Dormand & Prince (1980), "A family of embedded Runge–Kutta formulae", J. Comput. Appl.
/// Math. 6(1), 19–26; the coefficients of Hairer, Nørsett & Wanner 1993, *Solving Ordinary
/// Differential Equations I*, 2nd ed., §II.5, Table 5.2.
const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    // The fifth-order weights b (b₇ = 0): the last stage is the new state (FSAL).
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// `b − b̂`: the fifth-order weights minus the embedded fourth-order ones.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// The state at the end of the last accepted step and its acceleration (FSAL).
type Kept<T, Q, V> = (State<T, Q, V>, OVector<T, V>);

/// A stage's position and velocity `(q_n ⊕ θ, v)`.
type Point<T, Q, V> = (OVector<T, Q>, OVector<T, V>);

/// The seven stages' slopes `kθ` and `kv`, kept between calls so that a step does not set
/// them up anew.
#[derive(Clone, Debug)]
struct Stages<T: Scalar, V: Dim>
where
    DefaultAllocator: Allocator<V>,
{
    kq: [OVector<T, V>; 7],
    kv: [OVector<T, V>; 7],
}

/// Counters of a [`Dopri5`] since it was made (or [`Dopri5::reset`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dopri5Stats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Evaluations of the acceleration.
    pub evaluations: usize,
}

/// Adaptive Dormand–Prince 5(4): order 5 with an embedded order-4 error estimate, seven
/// stages of which the last is the next step's first (FSAL: six evaluations per accepted step).
///
/// # Tolerance model
/// The local error estimate `err = h·Σ (b_i − b̂_i)·k_i` has `2·NV` components, `NV` for the
/// configuration (in local coordinates `θ`) and `NV` for `v`. Each is weighed by
/// `sc_i = atol + rtol·max(|y_i|, |y'_i|)`, with `y` and `y'` the state before and after the
/// step, and the step is accepted when the RMS norm
/// `‖err‖ = sqrt((1/(2·NV))·Σ (err_i/sc_i)²) ≤ 1` (Hairer, Nørsett & Wanner 1993, §II.4,
/// eq. (4.11)). `|y_i|` is `|v_i|` for velocities and `|q_i|` for `Vector` coordinates; a
/// rotation's error is an angle (radians) and the size of a unit quaternion is 1, so its
/// components have `|y_i| = 1`; a free joint's position components all use the largest
/// `|p_j|` (its error is in the child frame, its value in the joint frame).
///
/// # Step-size control
/// `h_new = h·min(fac_max, max(fac_min, safety·‖err‖^(−1/5)))` (Hairer, Nørsett & Wanner
/// 1993, §II.4, eq. (4.13)), with `safety = 0.9`, `fac_min = 0.2`, `fac_max = 5` by default and
/// `fac_max = 1` for the step after a rejection (ibid., p. 168). A rejected step is retried
/// with `h_new`. Steps are capped by `max_step` and clipped to land on each target time of
/// [`Integrator::advance`] (a clipped step does not shrink the next proposal). The first step
/// is `initial_step` if set, else the first interval `t_to − t` (a simulation's `dt`).
/// When the step asked for falls below `max(min_step, 4ε·|t|)` the integration stops with
/// [`Cause::StepUnderflow`]; after `max_steps` steps within one `advance`, with
/// [`Cause::TooManySteps`].
///
/// # FSAL across calls
/// The acceleration at the end of an accepted step is kept and reused when the next `advance`
/// starts from exactly that state. This assumes `a(t, q, v)` is a function of its arguments;
/// after changing the system (a controller's gains, the parameters) call [`Dopri5::reset`].
#[derive(Clone, Debug)]
pub struct Dopri5<T: Scalar, Q: Dim, V: Dim>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// Relative tolerance.
    pub rtol: T,
    /// Absolute tolerance.
    pub atol: T,
    /// The first step; `None`: the first interval.
    pub initial_step: Option<T>,
    /// The smallest step allowed (default `1e-12`); see also `4ε·|t|`.
    pub min_step: T,
    /// The largest step (default: unbounded).
    pub max_step: T,
    /// Safety factor of the controller (default 0.9).
    pub safety: T,
    /// Smallest ratio of consecutive steps (default 0.2).
    pub fac_min: T,
    /// Largest ratio of consecutive steps (default 5).
    pub fac_max: T,
    /// Most steps (accepted or rejected) in one call of `advance` (default 1 000 000).
    pub max_steps: usize,
    next_step: Option<T>,
    fsal: Option<Kept<T, Q, V>>,
    stages: Option<Stages<T, V>>,
    stats: Dopri5Stats,
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Dopri5<T, Q, V>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// Dormand–Prince with the tolerances `rtol`, `atol` and the default controller.
    pub fn new(rtol: T, atol: T) -> Self {
        Dopri5 {
            rtol,
            atol,
            initial_step: None,
            min_step: k(1e-12),
            max_step: T::max_value().unwrap_or_else(|| k(f64::MAX)),
            safety: k(0.9),
            fac_min: k(0.2),
            fac_max: k(5.0),
            max_steps: 1_000_000,
            next_step: None,
            fsal: None,
            stages: None,
            stats: Dopri5Stats::default(),
        }
    }

    /// The counters.
    pub fn stats(&self) -> Dopri5Stats {
        self.stats
    }

    /// The step the controller proposes next (`None` before the first step).
    pub fn next_step(&self) -> Option<T> {
        self.next_step
    }

    /// Forgets the proposed step, the kept acceleration and the counters.
    pub fn reset(&mut self) {
        self.next_step = None;
        self.fsal = None;
        self.stats = Dopri5Stats::default();
    }
}

impl<T: RealField + Copy, V: Dim> Stages<T, V>
where
    DefaultAllocator: Allocator<V>,
{
    /// Zero slopes shaped like `v`.
    fn new(v: &OVector<T, V>) -> Self {
        Stages {
            kq: core::array::from_fn(|_| zeros_like(v)),
            kv: core::array::from_fn(|_| zeros_like(v)),
        }
    }

    /// `x += h·Σ_j c_j·kθ_j` and `w += h·Σ_j c_j·kv_j` over the first `c.len()` stages, in one
    /// pass (zero weights skipped).
    #[inline(always)]
    fn accumulate(&self, h: T, c: &[f64], x: &mut [T], w: &mut [T]) {
        for ((cj, qj), vj) in c.iter().zip(&self.kq).zip(&self.kv) {
            if *cj != 0.0 {
                let s = h * k(*cj);
                let pairs = qj.as_slice().iter().zip(vj.as_slice());
                for ((x, w), (a, b)) in x.iter_mut().zip(w.iter_mut()).zip(pairs) {
                    *x += s * *a;
                    *w += s * *b;
                }
            }
        }
    }

    /// `(h·Σ_j c_j·kθ_j, v + h·Σ_j c_j·kv_j)`: a stage's local coordinates and velocity, or with
    /// `v = 0` the error estimate.
    #[inline(always)]
    fn combine(&self, h: T, c: &[f64], v: &OVector<T, V>) -> (OVector<T, V>, OVector<T, V>) {
        let mut theta = zeros_like(v);
        let mut vel = v.clone();
        self.accumulate(h, c, theta.as_mut_slice(), vel.as_mut_slice());
        (theta, vel)
    }

    /// Stages 2 to 7 of a step of size `h` from `cur`, whose slopes are stage 1's, written out
    /// so that each one's weights are constants. The seventh stage is at the new state (its
    /// weights are `b`): returns it.
    #[inline(always)]
    fn run<Q, S>(
        &mut self,
        s: &mut Step<'_, T, Q, V, S>,
        cur: &State<T, Q, V>,
        h: T,
        evaluations: &mut usize,
    ) -> Result<Point<T, Q, V>, Fault<T>>
    where
        Q: Dim,
        S: SecondOrder<T, Q, V> + ?Sized,
        DefaultAllocator: Allocator<Q>,
    {
        let vs = s.vector_space();
        // Stage `i`: its state `(q_n ⊕ θ_i, v_i)`, with `kθ_i` (not in a vector space) and
        // `kv_i` set.
        macro_rules! stage {
            ($i:literal) => {{
                let ti = cur.t + h * k(C[$i]);
                let (qi, vel) = if vs {
                    // q ⊕ θ = q + θ: sum straight into q.
                    let (mut qi, mut vel) = (cur.q.clone(), cur.v.clone());
                    let (x, w) = (qi.as_mut_slice(), vel.as_mut_slice());
                    self.accumulate(h, &A[$i][..$i], x, w);
                    (qi, vel)
                } else {
                    let (theta, vel) = self.combine(h, &A[$i][..$i], &cur.v);
                    self.kq[$i] = s.local_velocity(&theta, &vel);
                    (s.retract(&cur.q, &theta), vel)
                };
                *evaluations += 1;
                self.kv[$i] = s.evaluate(ti, &qi, &vel)?;
                (qi, vel)
            }};
        }
        // In a vector space θ̇ = v: a stage's slope is its velocity.
        macro_rules! inner {
            ($i:literal) => {{
                let (_, vel) = stage!($i);
                if vs {
                    self.kq[$i] = vel;
                }
            }};
        }
        inner!(1);
        inner!(2);
        inner!(3);
        inner!(4);
        inner!(5);
        let (q_new, v_new) = stage!(6);
        if vs {
            self.kq[6].clone_from(&v_new);
        }
        Ok((q_new, v_new))
    }
}

/// The RMS error norm of the module's tolerance model.
#[allow(clippy::too_many_arguments)]
fn error_norm<T, Q, V>(
    coords: &[Coordinates],
    vector_space: bool,
    rtol: T,
    atol: T,
    (q0, v0): (&OVector<T, Q>, &OVector<T, V>),
    (q1, v1): (&OVector<T, Q>, &OVector<T, V>),
    err_theta: &OVector<T, V>,
    err_v: &OVector<T, V>,
) -> T
where
    T: RealField + Copy,
    Q: Dim,
    V: Dim,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    let nv = v0.len();
    if nv == 0 {
        return T::zero();
    }
    // Σ (e_i / (atol + rtol·max(|a_i|, |b_i|)))² over three slices.
    let squares = |e: &[T], a: &[T], b: &[T]| {
        let mut sum = T::zero();
        for (e, (a, b)) in e.iter().zip(a.iter().zip(b)) {
            let r = *e / (atol + rtol * a.abs().max(b.abs()));
            sum += r * r;
        }
        sum
    };
    let mut sum = squares(err_v.as_slice(), v0.as_slice(), v1.as_slice());
    if vector_space {
        sum += squares(err_theta.as_slice(), q0.as_slice(), q1.as_slice());
        return (sum / k(2.0 * nv as f64)).sqrt();
    }
    let mut add = |e: T, y: T| {
        let r = e / (atol + rtol * y);
        sum += r * r;
    };
    for (c, iq, iv) in joints(coords) {
        match c {
            Coordinates::Vector(n) => {
                for j in 0..n {
                    add(err_theta[iv + j], q0[iq + j].abs().max(q1[iq + j].abs()));
                }
            }
            Coordinates::Quaternion => {
                for j in 0..3 {
                    add(err_theta[iv + j], T::one());
                }
            }
            Coordinates::FreeQuaternion => {
                let mut p = T::zero();
                for j in 0..3 {
                    p = p.max(q0[iq + j].abs()).max(q1[iq + j].abs());
                }
                for j in 0..3 {
                    add(err_theta[iv + j], p);
                    add(err_theta[iv + 3 + j], T::one());
                }
            }
        }
    }
    (sum / k(2.0 * nv as f64)).sqrt()
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Dopri5<T, Q, V>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// Keeps the state reached and its acceleration for the next call (FSAL).
    fn keep(&mut self, cur: &State<T, Q, V>, a0: OVector<T, V>) {
        match &mut self.fsal {
            Some((s, a)) => {
                s.clone_from(cur);
                a.clone_from(&a0);
            }
            None => self.fsal = Some((cur.clone(), a0)),
        }
    }
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Integrator<T, Q, V> for Dopri5<T, Q, V>
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
        let (mut s, _) = Step::begin(system, state, t_to, step, false)?;
        let mut cur = state.clone();
        let mut a0 = match &self.fsal {
            Some((kept, a)) if kept == state => a.clone(),
            _ => {
                self.stats.evaluations += 1;
                s.evaluate(cur.t, &cur.q, &cur.v)?
            }
        };
        let mut h = self
            .next_step
            .or(self.initial_step)
            .unwrap_or(t_to - cur.t)
            .min(self.max_step);
        let mut after_reject = false;
        let mut steps = 0;
        // Sizes fixed at compile time always fit; a run-time size may have changed.
        if !matches!(&self.stages, Some(st) if st.kq[0].len() == cur.v.len()) {
            self.stages = None;
        }
        let stages = self.stages.get_or_insert_with(|| Stages::new(&cur.v));
        let result = loop {
            let remaining = t_to - cur.t;
            if remaining <= T::zero() {
                break Ok(());
            }
            // Land on t_to; avoid leaving a sliver below 1 % of a step.
            let clipped = h * k(1.01) >= remaining;
            let h_try = if clipped { remaining } else { h };
            let floor = self
                .min_step
                .max(T::default_epsilon() * k(4.0) * cur.t.abs());
            let fault = s.at(cur.t);
            if !clipped && h_try < floor {
                break Err(fault(Cause::StepUnderflow {
                    step: h_try,
                    min: floor,
                }));
            }
            steps += 1;
            if steps > self.max_steps {
                break Err(fault(Cause::TooManySteps {
                    max_steps: self.max_steps,
                }));
            }
            stages.kq[0] = cur.v.clone();
            stages.kv[0] = a0.clone();
            let (q_new, v_new) = match stages.run(&mut s, &cur, h_try, &mut self.stats.evaluations)
            {
                Ok(new) => new,
                Err(f) => break Err(f),
            };
            let (err_theta, err_v) = stages.combine(h_try, &E, &zeros_like(&cur.v));
            let err = error_norm(
                s.coordinates(),
                s.vector_space(),
                self.rtol,
                self.atol,
                (&cur.q, &cur.v),
                (&q_new, &v_new),
                &err_theta,
                &err_v,
            );
            let fac_max = if after_reject { T::one() } else { self.fac_max };
            if err <= T::one() {
                self.stats.accepted += 1;
                // safety·err^(−1/5) ≥ fac_max exactly when err ≤ (safety/fac_max)⁵: no power
                // needed then.
                let r = self.safety / fac_max;
                let fac = if err > r * r * r * r * r {
                    (self.safety * err.powf(k(-0.2))).max(self.fac_min)
                } else {
                    fac_max
                }
                .min(fac_max);
                let h_new = (h_try * fac).min(self.max_step);
                h = if clipped { h_new.max(h) } else { h_new };
                after_reject = false;
                cur.t = if clipped { t_to } else { cur.t + h_try };
                cur.q = q_new;
                cur.v = v_new;
                a0 = stages.kv[6].clone();
            } else {
                // A non-finite error estimate (NaN compares false above) shrinks the most.
                self.stats.rejected += 1;
                let fac = if err.is_finite() {
                    (self.safety * err.powf(k(-0.2))).max(self.fac_min)
                } else {
                    self.fac_min
                };
                h = h_try * fac.min(T::one());
                after_reject = true;
            }
        };
        self.next_step = Some(h);
        self.keep(&cur, a0);
        *state = cur;
        result
    }
}
