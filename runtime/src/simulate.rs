//! Step a system from `t0` to `t_end` and record its states.
//!
//! A [`Simulation`] is the time grid: `t_k = t0 + k·dt` for `k < N` and `t_N = t_end`, with
//! `N = ⌈(t_end − t0)/dt⌉` (a ratio within `1e-9` of an integer counts as that integer, so the
//! last step is never a sliver). It records `N + 1` states, the initial one included:
//! - [`Simulation::run`] hands each state to a closure (no storage; `no_std`);
//! - [`Simulation::run_into`] writes them into a caller-provided slice (`no_std`, no
//!   allocation) and returns how many it wrote;
//! - [`Simulation::record`] appends them to a [`Trajectory`](crate::trajectory::Trajectory)
//!   (`alloc`), which [writes CSV](crate::trajectory::Trajectory::write_csv) (`std`).
//!
//! Each takes a progress callback `FnMut(k, t_k)`, called after step `k` (1 to `N`).
//! Fixed-step methods take one step per interval; [`Dopri5`](crate::integrate::Dopri5) takes
//! as many as its error control needs and lands on each `t_k` (its first step is `dt` unless
//! set otherwise).
//!
//! ```
//! # use articulated::nalgebra::SVector;
//! # use articulated::integrate::{ControlledChain, Rk4, State};
//! # use articulated::simulate::Simulation;
//! articulated::chain! {
//!     chain Pendulum {
//!         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
//!         joint pivot: revolute(y) { parent: world, child: bob }
//!     }
//! }
//! let mut system = ControlledChain::<f64, Pendulum, _>::unforced();
//! let start = State::new(0.0, SVector::<f64, 1>::new(0.5), SVector::<f64, 1>::zeros());
//! let simulation = Simulation::new(0.0, 1.0, 0.01);
//! let mut buffer = [start; 101];
//! let rows = simulation.run_into(&mut system, &mut Rk4, start, &mut buffer, |_k, _t| {})?;
//! assert_eq!(rows, 101);
//! assert_eq!(buffer[100].t, 1.0);
//! # Ok::<(), articulated::integrate::Fault<f64>>(())
//! ```

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, RealField};

use crate::integrate::{k, Cause, Fault, Integrator, SecondOrder, State};

/// A time grid from `t0` to `t_end` with the step (or output spacing) `dt` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Simulation<T> {
    /// Start time.
    pub t0: T,
    /// End time (`≥ t0`).
    pub t_end: T,
    /// Step (`> 0`).
    pub dt: T,
}

impl<T: RealField + Copy> Simulation<T> {
    /// The grid from `t0` to `t_end` with the step `dt`.
    pub fn new(t0: T, t_end: T, dt: T) -> Self {
        Simulation { t0, t_end, dt }
    }

    /// The number of steps `N` (the trajectory has `N + 1` states).
    ///
    /// # Errors
    /// [`Cause::InvalidTime`] when a time is not finite, `t_end < t0`, `dt ≤ 0`, or `N` does
    /// not fit a `usize` below `2⁵³`.
    pub fn steps(&self) -> Result<usize, Cause<T>> {
        let Simulation { t0, t_end, dt } = *self;
        if !(t0.is_finite() && t_end.is_finite() && dt.is_finite() && dt > T::zero()) || t_end < t0
        {
            return Err(Cause::InvalidTime);
        }
        let ratio: f64 = nalgebra::try_convert((t_end - t0) / dt).ok_or(Cause::InvalidTime)?;
        if !(ratio.is_finite() && ratio < 9.0e15) {
            return Err(Cause::InvalidTime);
        }
        let nearest = libm::round(ratio);
        let n = if (ratio - nearest).abs() <= 1e-9 * nearest.max(1.0) {
            nearest
        } else {
            libm::ceil(ratio)
        };
        // `n` is a non-negative integer below 2⁵³: the conversion is exact.
        Ok(n as usize)
    }

    /// The time `t_k` of step `k` of `n` (`t_n = t_end`; `n` from [`steps`](Self::steps)).
    pub fn time(&self, step: usize, n: usize) -> T {
        if step >= n {
            self.t_end
        } else {
            self.t0 + self.dt * k(step as f64)
        }
    }

    /// Steps `system` with `integrator` from `initial` (whose `t` is replaced by `t0`) over the
    /// grid, handing each state to `record`, the initial one first, and calling `progress(k,
    /// t_k)` after each step. Returns the final state.
    ///
    /// # Errors
    /// The first [`Fault`] of the integrator, or of `record` (its [`Cause`] at that state's
    /// time and step), or [`Cause::InvalidTime`] at step 0.
    pub fn run<Q, V, S, I, R, P>(
        &self,
        system: &mut S,
        integrator: &mut I,
        initial: State<T, Q, V>,
        mut record: R,
        mut progress: P,
    ) -> Result<State<T, Q, V>, Fault<T>>
    where
        Q: Dim,
        V: Dim,
        S: SecondOrder<T, Q, V> + ?Sized,
        I: Integrator<T, Q, V> + ?Sized,
        R: FnMut(&State<T, Q, V>) -> Result<(), Cause<T>>,
        P: FnMut(usize, T),
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        let n = self.steps().map_err(Fault::at(self.t0, 0))?;
        let mut state = initial;
        state.t = self.t0;
        record(&state).map_err(Fault::at(self.t0, 0))?;
        for step in 0..n {
            let t_to = self.time(step + 1, n);
            integrator.advance(system, &mut state, t_to, step)?;
            record(&state).map_err(Fault::at(t_to, step))?;
            progress(step + 1, t_to);
        }
        Ok(state)
    }

    /// [`run`](Self::run) into `buffer`: writes the `N + 1` states to its front and returns
    /// `N + 1`. Allocates nothing.
    ///
    /// # Errors
    /// [`Cause::BufferTooSmall`] (at `t0`, step 0, before any step) when `buffer` is shorter
    /// than `N + 1`; otherwise as [`run`](Self::run), with the states up to the fault written.
    pub fn run_into<Q, V, S, I, P>(
        &self,
        system: &mut S,
        integrator: &mut I,
        initial: State<T, Q, V>,
        buffer: &mut [State<T, Q, V>],
        progress: P,
    ) -> Result<usize, Fault<T>>
    where
        Q: Dim,
        V: Dim,
        S: SecondOrder<T, Q, V> + ?Sized,
        I: Integrator<T, Q, V> + ?Sized,
        P: FnMut(usize, T),
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        let fault = Fault::at(self.t0, 0);
        let needed = self.steps().map_err(fault)? + 1;
        if buffer.len() < needed {
            return Err(fault(Cause::BufferTooSmall {
                needed,
                capacity: buffer.len(),
            }));
        }
        let mut written = 0;
        let record = |s: &State<T, Q, V>| {
            if let Some(slot) = buffer.get_mut(written) {
                slot.clone_from(s);
                written += 1;
            }
            Ok(())
        };
        self.run(system, integrator, initial, record, progress)?;
        Ok(needed)
    }

    /// [`run`](Self::run), appending the states to `trajectory`.
    ///
    /// On a fault the trajectory keeps every state up to the last good one: the initial state
    /// and those of the `fault.step` steps that completed (`fault.step + 1` states, ending at
    /// `t_{fault.step}`; `Cause::InvalidTime` at step 0 records none), exactly as a run
    /// without the fault would have recorded them. Write it as usual to see what went wrong.
    ///
    /// # Errors
    /// As [`run`](Self::run).
    #[cfg(feature = "alloc")]
    pub fn record<Q, V, S, I, P>(
        &self,
        system: &mut S,
        integrator: &mut I,
        initial: State<T, Q, V>,
        trajectory: &mut crate::trajectory::Trajectory<T, Q, V>,
        progress: P,
    ) -> Result<(), Fault<T>>
    where
        Q: Dim,
        V: Dim,
        S: SecondOrder<T, Q, V> + ?Sized,
        I: Integrator<T, Q, V> + ?Sized,
        P: FnMut(usize, T),
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        if let Ok(n) = self.steps() {
            // Room for the whole run, up to a million states at a time.
            trajectory.reserve(n.saturating_add(1).min(1 << 20));
        }
        let record = |s: &State<T, Q, V>| {
            trajectory.push(s.clone());
            Ok(())
        };
        self.run(system, integrator, initial, record, progress)
            .map(|_| ())
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use nalgebra::{Const, SVector};

    use super::Simulation;
    use crate::generated::Coordinates;
    use crate::integrate::{Cause, Method, SecondOrder, State, Stepper};
    use crate::trajectory::Trajectory;

    /// A unit oscillator whose acceleration cannot be computed from `t_fault` on.
    struct Oscillator {
        t_fault: f64,
    }

    impl SecondOrder<f64, Const<1>, Const<1>> for Oscillator {
        fn coordinates(&self) -> &[Coordinates] {
            &[Coordinates::Vector(1)]
        }

        fn acceleration(
            &mut self,
            t: f64,
            q: &SVector<f64, 1>,
            _v: &SVector<f64, 1>,
        ) -> Result<SVector<f64, 1>, Cause<f64>> {
            if t >= self.t_fault {
                return Err(Cause::System("past t_fault"));
            }
            Ok(-q)
        }
    }

    /// Issue 31: a run that stops on a fault keeps, in its trajectory, every state before the
    /// fault, bit for bit those of a run without it, and no other.
    #[test]
    fn a_fault_keeps_every_state_before_it() {
        let simulation = Simulation::new(0.0, 1.0, 0.01);
        let start = State::new(0.0, SVector::<f64, 1>::new(1.0), SVector::<f64, 1>::zeros());
        for method in Method::ALL {
            let record = |t_fault: f64| {
                let mut trajectory = Trajectory::new();
                let result = simulation.record(
                    &mut Oscillator { t_fault },
                    &mut Stepper::new(method, 1e-9, 1e-9),
                    start,
                    &mut trajectory,
                    |_, _| {},
                );
                (result, trajectory)
            };
            let (whole, reference) = record(f64::INFINITY);
            assert!(whole.is_ok(), "{method}");
            assert_eq!(reference.len(), 101);
            let (result, kept) = record(0.555);
            let fault = result.expect_err("a fault at 0.555 s");
            assert_eq!(fault.cause, Cause::System("past t_fault"), "{method}");
            // The step that failed: from 0.55 for a method that evaluates inside its step,
            // from 0.56 for Euler, which evaluates at its start only. The states up to its
            // start are kept.
            assert!([55, 56].contains(&fault.step), "{method}: {fault}");
            assert_eq!(kept.len(), fault.step + 1, "{method}");
            assert_eq!(kept.states(), &reference.states()[..kept.len()], "{method}");
            let last = kept.states()[kept.len() - 1].t;
            assert!(
                (last - fault.step as f64 * 0.01).abs() < 1e-12
                    && last <= fault.t
                    && fault.t < last + 0.01,
                "{method}: {last}, {fault}"
            );
        }
    }
}
