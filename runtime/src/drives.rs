//! What a chain's drives do in a simulation beyond the commanded force: the actuator's effort
//! limit, viscous damping, dry friction, a spring and the position limits, from the
//! description's [`Drive`]s ([`Chain::DRIVES`]: URDF's `<dynamics>` and `<limit>`, MJCF's joint
//! `stiffness` and `springref`, the `.chain` joint fields `damping`, `friction`, `lower`,
//! `upper`, `effort`).
//!
//! The armature is not here: it is inertia, already in the generated `M`, `τ` and `q̈`.
//!
//! Per velocity coordinate `k`, with `τ_k` the controller's command:
//!
//! ```text
//! τ_k ← clamp(τ_k, −effort, effort) − damping·v_k − friction·tanh(v_k / friction_speed)
//!       − stiffness·(q_k − rest) + stop_k
//! ```
//!
//! (the spring on revolute and prismatic joints, whose `q_k` is the coordinate of `v_k`).
//!
//! - **Dry friction** is regularized: exact Coulomb friction (sticking while `|τ| < friction`)
//!   needs a complementarity solver, which this runtime does not have. Below `friction_speed`
//!   the friction acts as a stiff damper of coefficient `friction / friction_speed`: an explicit
//!   integrator needs `dt < 2·I·friction_speed / friction` there (`I` the joint's inertia).
//! - **Position limits** are stops, a one-sided spring and damper that only push back into the
//!   range (as MuJoCo's soft limits and most real-time simulators do): past `upper` by `p > 0`,
//!   `stop = min(0, −stop_stiffness·p − stop_damping·min(1, p / stop_depth)·v)`; below `lower`
//!   the mirror image. The damper comes in over the first `stop_depth` of penetration (as in
//!   Hunt and Crossley's contact law), so the force is continuous in the state: an adaptive
//!   integrator (`Dopri5`) resolves a stop by shortening its steps there, where a force that
//!   jumped to `stop_damping·v` at contact would stall it. The penetration is about
//!   `|v|·√(I / stop_stiffness)` at impact speed `v`: stiffer stops penetrate less and need
//!   smaller fixed steps (`√(stop_stiffness / I)·dt ≪ 1` and `stop_damping·dt / I ≪ 1`, `I` the
//!   joint's inertia: a light fingertip needs far smaller steps than an arm).
//! - **The stops store energy**: the spring's `−stop_stiffness·p` is the only conservative part
//!   of a stop (the damper and the clamp to a push only ever take energy out, whatever the
//!   ramp), so the energy stored is its integral over the penetration,
//!   `½·stop_stiffness·p²` per stop ([`Drives::stop_energy`]). Added to the chain's kinetic and
//!   potential energy, it gives a total that does not jump at an impact: it is constant while
//!   nothing dissipates, and only falls through damping, friction and the stops' dampers.
//! - **Speed limits** are reported by [`Drives::over_speed`], not enforced: no physical
//!   mechanism enforces them in a motor.
//!
//! ```
//! # use articulated::nalgebra::SVector;
//! # use articulated::drives::Drives;
//! # use articulated::integrate::{ControlledChain, Integrator, Rk4, State};
//! articulated::chain! {
//!     chain Pendulum {
//!         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
//!         joint pivot: revolute(y) {
//!             parent: world, child: bob, damping: 0.5, lower: -0.2, upper: 0.2
//!         }
//!     }
//! }
//! let drives = Drives::<f64, 1, 1>::of::<Pendulum>().unwrap();
//! let unforced = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::<f64, 1>::zeros();
//! let mut system = ControlledChain::<f64, Pendulum, _>::new(drives.around(unforced));
//! let mut state = State::new(0.0, SVector::<f64, 1>::new(0.1), SVector::<f64, 1>::new(3.0));
//! for k in 0..2000 {
//!     Rk4.advance(&mut system, &mut state, (k + 1) as f64 * 1e-3, k).unwrap();
//! }
//! // Thrown at 3 rad/s toward the stop at 0.2 rad: held near it, damped.
//! assert!(state.q[0] < 0.25);
//! ```

use core::fmt;

use nalgebra::{RealField, SVector};

use crate::generated::{Chain, Coordinates};
use crate::Drive;

/// The drives of a chain with `NQ` positions and `NV` velocities, as forces (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drives<T, const NQ: usize, const NV: usize> {
    /// Per velocity coordinate.
    axes: [Axis<T>; NV],
    /// The stops' spring and damper and the friction's fade-out speed.
    pub smoothing: Smoothing<T>,
}

/// How the drives' non-smooth parts are made smooth (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoothing<T> {
    /// Stiffness of the limit stops (N·m/rad or N/m); `1e4` unless set.
    pub stop_stiffness: T,
    /// Damping of the limit stops (N·m·s/rad or N·s/m); `1e2` unless set.
    pub stop_damping: T,
    /// The penetration over which the stops' damping comes in, from none at contact to
    /// `stop_damping` (rad or m); `1e-3` unless set. Zero gives the full damping at contact
    /// (a force that jumps there).
    pub stop_depth: T,
    /// The speed below which dry friction fades out (rad/s or m/s); `1e-2` unless set.
    pub friction_speed: T,
}

impl<T: RealField + Copy> Default for Smoothing<T> {
    fn default() -> Self {
        let t = |x: f64| nalgebra::convert::<f64, T>(x);
        Smoothing {
            stop_stiffness: t(1e4),
            stop_damping: t(1e2),
            stop_depth: t(1e-3),
            friction_speed: t(1e-2),
        }
    }
}

/// One velocity coordinate's drive, in `T`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Axis<T> {
    damping: T,
    friction: T,
    effort: T,
    speed: T,
    /// For a revolute or prismatic joint with limits: its position's index and the range.
    limits: Option<(usize, T, T)>,
    /// For a revolute or prismatic joint with a spring: its position's index, the stiffness and
    /// the rest position.
    spring: Option<(usize, T, T)>,
}

/// [`Drives::of`] was asked for a chain whose coordinates do not add up to `NQ` and `NV`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrivesMismatch {
    /// The chain's `Σ nq`.
    pub nq: usize,
    /// The chain's `Σ nv`.
    pub nv: usize,
}

impl fmt::Display for DrivesMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the chain has {} positions and {} velocities, not the sizes asked for",
            self.nq, self.nv
        )
    }
}

impl core::error::Error for DrivesMismatch {}

impl<T: RealField + Copy, const NQ: usize, const NV: usize> Drives<T, NQ, NV> {
    /// The drives `C::DRIVES` of the chain `C`, with the default stops and friction speed.
    ///
    /// # Errors
    /// [`DrivesMismatch`] if `C`'s coordinates are not `NQ` positions and `NV` velocities.
    pub fn of<C: Chain<T>>() -> Result<Self, DrivesMismatch> {
        Self::from_drives(C::COORDINATES, C::DRIVES)
    }

    /// The drives of joints with the coordinates `coordinates` (one drive per joint).
    ///
    /// # Errors
    /// [`DrivesMismatch`] if the coordinates are not `NQ` positions and `NV` velocities, or
    /// the two lists differ in length.
    pub fn from_drives(
        coordinates: &[Coordinates],
        drives: &[Drive],
    ) -> Result<Self, DrivesMismatch> {
        let nq: usize = coordinates.iter().map(|c| c.nq()).sum();
        let nv: usize = coordinates.iter().map(|c| c.nv()).sum();
        if nq != NQ || nv != NV || coordinates.len() != drives.len() {
            return Err(DrivesMismatch { nq, nv });
        }
        let mut axes = [Axis::from_drive(&Drive::FREE, None); NV];
        for (slot, axis) in axes.iter_mut().zip(per_velocity(coordinates, drives)) {
            *slot = axis;
        }
        Ok(Drives {
            axes,
            smoothing: Smoothing::default(),
        })
    }

    /// The force the joints feel at `(q, v)` when the controller commands `commanded`: saturated,
    /// damped, with friction and the stops (see the [module docs](self)).
    pub fn force(
        &self,
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        commanded: &SVector<T, NV>,
    ) -> SVector<T, NV> {
        let mut tau = *commanded;
        self.law()
            .apply(q.as_slice(), v.as_slice(), tau.as_mut_slice());
        tau
    }

    fn law(&self) -> Law<'_, T> {
        Law {
            axes: &self.axes,
            smoothing: &self.smoothing,
        }
    }

    /// The controller `controller` with the drives applied to its command: pass it to
    /// [`ControlledChain`](crate::integrate::ControlledChain).
    pub fn around<F>(
        self,
        mut controller: F,
    ) -> impl FnMut(T, &SVector<T, NQ>, &SVector<T, NV>) -> SVector<T, NV>
    where
        F: FnMut(T, &SVector<T, NQ>, &SVector<T, NV>) -> SVector<T, NV>,
    {
        move |t, q, v| {
            let commanded = controller(t, q, v);
            self.force(q, v, &commanded)
        }
    }

    /// The first velocity coordinate faster than its joint's speed limit, if any.
    pub fn over_speed(&self, v: &SVector<T, NV>) -> Option<usize> {
        self.law().over_speed(v.as_slice())
    }

    /// The first position coordinate outside its joint's limits, with how far (positive above
    /// `upper`, negative below `lower`), if any.
    pub fn outside_limits(&self, q: &SVector<T, NQ>) -> Option<(usize, T)> {
        self.law().outside_limits(q.as_slice())
    }

    /// The elastic energy the stops hold at `q`: `½·stop_stiffness·p²` for each coordinate
    /// `p` past its limit (J; see the [module docs](self)). Add it to the chain's potential
    /// energy for a total that a stop's impact does not change.
    pub fn stop_energy(&self, q: &SVector<T, NQ>) -> T {
        self.law().stop_energy(q.as_slice())
    }

    /// The elastic energy the joints' springs hold at `q`: `½·stiffness·(q − rest)²` each (J).
    /// Add it to the chain's potential energy for a total the springs do not change.
    pub fn spring_energy(&self, q: &SVector<T, NQ>) -> T {
        let half = nalgebra::convert::<f64, T>(0.5);
        self.axes
            .iter()
            .filter_map(|a| a.spring)
            .filter_map(|(i, k, rest)| {
                q.as_slice()
                    .get(i)
                    .map(|&x| half * k * (x - rest) * (x - rest))
            })
            .fold(T::zero(), |a, e| a + e)
    }
}

impl<T: RealField + Copy> Axis<T> {
    /// The drive `d` on one velocity coordinate; `position` is the index of its position for a
    /// joint of one position and one velocity (which its limits and spring act on).
    fn from_drive(d: &Drive, position: Option<usize>) -> Self {
        let t = |x: f64| nalgebra::convert::<f64, T>(x);
        let bounded = d.lower > f64::NEG_INFINITY || d.upper < f64::INFINITY;
        Axis {
            damping: t(d.damping),
            friction: t(d.friction),
            effort: t(d.effort),
            speed: t(d.velocity),
            limits: position
                .filter(|_| bounded)
                .map(|i| (i, t(d.lower), t(d.upper))),
            spring: position
                .filter(|_| d.stiffness != 0.0)
                .map(|i| (i, t(d.stiffness), t(d.rest))),
        }
    }
}

/// The drives per velocity coordinate of joints with `coordinates` (one drive per joint); the
/// position limits and springs kept for joints of one position and one velocity.
fn per_velocity<'a, T: RealField + Copy>(
    coordinates: &'a [Coordinates],
    drives: &'a [Drive],
) -> impl Iterator<Item = Axis<T>> + 'a {
    let mut q_at = 0;
    coordinates.iter().zip(drives).flat_map(move |(c, d)| {
        let position = (c.nq() == 1 && c.nv() == 1).then_some(q_at);
        q_at += c.nq();
        core::iter::repeat_n(Axis::from_drive(d, position), c.nv())
    })
}

/// The force law of some drives: their axes, the stops' stiffness and damping, the friction
/// speed.
struct Law<'a, T> {
    axes: &'a [Axis<T>],
    smoothing: &'a Smoothing<T>,
}

impl<T: RealField + Copy> Law<'_, T> {
    /// Applies the drives at `(q, v)` to the command in `tau`.
    fn apply(&self, q: &[T], v: &[T], tau: &mut [T]) {
        let zero = T::zero();
        let Smoothing {
            stop_stiffness,
            stop_damping,
            stop_depth,
            friction_speed,
        } = *self.smoothing;
        for ((f, &v), axis) in tau.iter_mut().zip(v).zip(self.axes) {
            *f = f.clamp(-axis.effort, axis.effort) - axis.damping * v;
            if axis.friction != zero {
                *f -= axis.friction * (v / friction_speed).tanh();
            }
            if let Some((i, k, rest)) = axis.spring {
                if let Some(&x) = q.get(i) {
                    *f -= k * (x - rest);
                }
            }
            let Some((i, lower, upper)) = axis.limits else {
                continue;
            };
            let Some(&x) = q.get(i) else {
                continue;
            };
            let spring = |past: T| {
                let depth = past.abs();
                let ramp = if depth < stop_depth {
                    depth / stop_depth
                } else {
                    T::one()
                };
                -stop_stiffness * past - stop_damping * ramp * v
            };
            if x > upper {
                *f += spring(x - upper).min(zero);
            } else if x < lower {
                *f += spring(x - lower).max(zero);
            }
        }
    }

    fn over_speed(&self, v: &[T]) -> Option<usize> {
        v.iter()
            .zip(self.axes)
            .position(|(v, axis)| v.abs() > axis.speed)
    }

    /// `Σ ½·k·p²` over the stops, `p` the penetration: minus the integral of the spring part
    /// of [`apply`](Self::apply)'s stop force, `−k·p`, from the limit to `p` (the damper and
    /// the clamp are not conservative and have no potential).
    fn stop_energy(&self, q: &[T]) -> T {
        let half_k = self.smoothing.stop_stiffness * nalgebra::convert::<f64, T>(0.5);
        let mut energy = T::zero();
        for (i, lower, upper) in self.axes.iter().filter_map(|axis| axis.limits) {
            let Some(&x) = q.get(i) else {
                continue;
            };
            let past = if x > upper {
                x - upper
            } else if x < lower {
                x - lower
            } else {
                continue;
            };
            energy += half_k * past * past;
        }
        energy
    }

    fn outside_limits(&self, q: &[T]) -> Option<(usize, T)> {
        let mut limits = self.axes.iter().filter_map(|axis| axis.limits);
        limits.find_map(|(i, lower, upper)| {
            let x = *q.get(i)?;
            if x > upper {
                Some((i, x - upper))
            } else if x < lower {
                Some((i, x - lower))
            } else {
                None
            }
        })
    }
}

/// The drives of a [`Model`](crate::model::Model) read at run time (the CLI's `simulate
/// --drives`), on vectors of run-time size: the same forces as [`Drives`].
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, PartialEq)]
pub struct ModelDrives {
    axes: alloc::vec::Vec<Axis<f64>>,
    /// The stops' spring and damper and the friction's fade-out speed.
    pub smoothing: Smoothing<f64>,
}

#[cfg(feature = "alloc")]
impl ModelDrives {
    /// The drives of `model`'s joints, with the default stops and friction speed.
    pub fn of(model: &crate::model::Model) -> Self {
        let coordinates = crate::interpreted::coordinates_of(model);
        let drives: alloc::vec::Vec<Drive> = model
            .joints
            .iter()
            .filter(|j| j.kind != crate::model::JointKind::Fixed && j.mimic.is_none())
            .map(|j| j.drive)
            .collect();
        ModelDrives {
            axes: per_velocity(&coordinates, &drives).collect(),
            smoothing: Smoothing::default(),
        }
    }

    fn law(&self) -> Law<'_, f64> {
        Law {
            axes: &self.axes,
            smoothing: &self.smoothing,
        }
    }

    /// The force the joints feel at `(q, v)` under the command `commanded` (see [`Drives::force`]).
    pub fn force(
        &self,
        q: &nalgebra::DVector<f64>,
        v: &nalgebra::DVector<f64>,
        commanded: &nalgebra::DVector<f64>,
    ) -> nalgebra::DVector<f64> {
        let mut tau = commanded.clone();
        self.law()
            .apply(q.as_slice(), v.as_slice(), tau.as_mut_slice());
        tau
    }

    /// The first velocity coordinate faster than its joint's speed limit, if any.
    pub fn over_speed(&self, v: &nalgebra::DVector<f64>) -> Option<usize> {
        self.law().over_speed(v.as_slice())
    }

    /// The first position coordinate outside its joint's limits, with how far, if any.
    pub fn outside_limits(&self, q: &nalgebra::DVector<f64>) -> Option<(usize, f64)> {
        self.law().outside_limits(q.as_slice())
    }

    /// The elastic energy the stops hold at `q` (see [`Drives::stop_energy`]).
    pub fn stop_energy(&self, q: &nalgebra::DVector<f64>) -> f64 {
        self.law().stop_energy(q.as_slice())
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::*;
    use crate::generated::Coordinates;

    /// Two stopped joints, a free one between them, a spherical one (no stops) after.
    fn law_of(smoothing: &Smoothing<f64>) -> (Vec<Axis<f64>>, Smoothing<f64>) {
        let stopped = |lower, upper| Drive {
            lower,
            upper,
            damping: 0.3,
            ..Drive::FREE
        };
        // Two revolute joints, a prismatic one, a spherical one in Euler angles.
        let coordinates = [
            Coordinates::Vector(1),
            Coordinates::Vector(1),
            Coordinates::Vector(1),
            Coordinates::Vector(3),
        ];
        let drives = [
            stopped(-0.5, 0.5),
            Drive::FREE,
            stopped(0.0, 0.04),
            stopped(-1.0, 1.0),
        ];
        (per_velocity(&coordinates, &drives).collect(), *smoothing)
    }

    /// The stored energy is the potential of the stops' force: at rest (`v = 0`, no damper),
    /// `−∂E/∂q_i` is the force `apply` gives, by central differences across and inside each
    /// range, below and above; and it is zero inside every range.
    #[test]
    fn stop_energy_is_the_potential_of_the_stop_force() {
        let smoothing = Smoothing {
            stop_stiffness: 2.5e3,
            ..Smoothing::default()
        };
        let (axes, smoothing) = law_of(&smoothing);
        let law = Law {
            axes: &axes,
            smoothing: &smoothing,
        };
        let at = |q: &[f64]| law.stop_energy(q);
        let force = |q: &[f64]| {
            let mut tau = vec![0.0; 6];
            law.apply(q, &[0.0; 6], &mut tau);
            tau
        };
        assert_eq!(at(&[0.4, 7.0, 0.02, 2.0, -3.0, 0.0]), 0.0);
        let h = 1e-6;
        for (i, x) in [
            (0, 0.53),
            (0, -0.61),
            (0, 0.2),
            (2, 0.045),
            (2, -0.01),
            (2, 0.01),
        ] {
            let mut q = vec![0.1, 3.0, 0.02, 0.0, 0.0, 0.0];
            q[i] = x;
            let (mut up, mut down) = (q.clone(), q.clone());
            up[i] += h;
            down[i] -= h;
            let slope = (at(&up) - at(&down)) / (2.0 * h);
            let f = force(&q)[i];
            assert!(
                (slope + f).abs() <= 1e-6 * f.abs().max(1.0),
                "q{i} = {x}: −∂E/∂q = {} but the force is {f}",
                -slope
            );
            let range = if i == 0 { -0.5..=0.5 } else { 0.0..=0.04 };
            if !range.contains(&x) {
                assert!(f != 0.0, "q{i} = {x} is past a stop");
            }
        }
        // Both stops at once add up; 0.03 past upper and 0.01 below lower.
        let both = at(&[0.53, 0.0, -0.01, 0.0, 0.0, 0.0]);
        assert!((both - 0.5 * 2.5e3 * (0.03f64.powi(2) + 0.01f64.powi(2))).abs() < 1e-12);
    }
}
