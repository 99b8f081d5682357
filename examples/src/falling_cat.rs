//! The falling cat (Wieber 2005, §4.2 and §5.2): two halves joined at the waist
//! (`models/falling_cat.chain`), dropped on its back at rest, turns over by moving its waist
//! alone, with zero angular momentum throughout.
//!
//! # The motion
//! One *cycle* bends the spine and swings the bend around a cone: the waist's yaw and pitch
//! (`R = Rz(yaw)·Ry(pitch)·Rx(twist)`) follow
//!
//! ```text
//! yaw = β·e(s)·sin 2πs,   pitch = −β·e(s)·cos 2πs,   twist = 0,    s = t/T (each cycle)
//! ```
//!
//! so the bend starts as a pike (a negative pitch swings the rear half down under the belly),
//! goes round by the cat's right side (a positive yaw swings the tail to the right), over the
//! back, by the left side and back. The envelope `e(s)` rises from 0 to 1 over the first quarter
//! of the cycle and falls back over the last (quintic smoothstep `h(u) = 10u³ − 15u⁴ + 6u⁵`);
//! while it is 1, the angle between the two halves is `β` where the bend is a pure pitch or yaw
//! and up to 5 % less in between (for `β ≤ 60°`: `cos bend = cos yaw·cos pitch`, a near-cone).
//! Since `h = h' = h'' = 0` at 0, the path's first two derivatives vanish at both ends of a
//! cycle: each cycle starts and ends straight and at rest, with `s = t/T` run at a constant rate,
//! and the joint accelerations are continuous. The same *path* (`β`) at another *speed* (`T`) is
//! `s` run faster or slower.
//!
//! # Why it turns, and why the speed does not matter
//! With the momentum `k_G = 0` and the shape `s` (the joint angles) given, the body's angular
//! velocity is fixed: `ω = −A(s)·ṡ`, linear in `ṡ` (Wieber 2005, §4.1: a nonholonomic
//! constraint). So the orientation reached depends on the path in shape space, not on how fast it
//! is run, and a closed path can leave the body turned: here about the long axis (by symmetry of
//! the straight cat the small-loop rotation is about it; a large loop also tilts the axis
//! slightly, which [`Cycle::swing`] reports). Gravity only accelerates the centre of mass
//! (Wieber 2005, §4.2), so it changes none of this.
//!
//! # Why a planner and not feedback
//! The state (the orientation and the shape, 6 numbers) has more dimensions than the controls
//! (the 3 joint rates) and the system has no drift (at rest nothing moves), so no turning of the
//! whole body can happen without a change of shape. Brockett's theorem (Brockett 1983, cited by
//! Wieber 2005, §5.2) then forbids any continuous, time-invariant feedback `ṡ = u(orientation,
//! s)` from stabilizing an orientation: the velocities such a system can take near the goal do
//! not fill a neighbourhood of zero (a pure rotation with `ṡ = 0` is not among them), which
//! Brockett's necessary condition requires. Discontinuous or time-varying laws are needed; ours
//! is open loop and time-varying: [`plan`] chooses the number of cycles and the bend `β` such
//! that the simulated turn is the one asked for, and the joints then follow `s(t)`.

use std::f64::consts::PI;

use articulated::integrate::{Dopri5Stats, State};
use articulated::model::Model;
use articulated::nalgebra::{Const, Quaternion, SVector, UnitQuaternion, Vector3};
use articulated::prelude::*;

pub use crate::free_floating::Conservation;
use crate::free_floating::{self, base_orientation, swing_angle, twist_angle, Hybrid, JointMotion};

/// The cat, generated from `models/falling_cat.chain`: 10 positions (the front half's position
/// and quaternion, the waist's yaw, pitch and twist), 9 velocities. `M` and `nle` move it; the
/// centre of mass and the centroidal momentum `[k_G; p]` measure it.
#[derive(Chain)]
#[chain(
    file = "../models/falling_cat.chain",
    outputs = [mass_matrix_and_nonlinear_effects, center_of_mass, centroidal_momentum]
)]
pub struct FallingCat;

/// Positions.
pub const NQ: usize = 10;
/// Velocities.
pub const NV: usize = 9;
/// A state of the cat.
pub type CatState = State<f64, Const<NQ>, Const<NV>>;
type V3 = SVector<f64, 3>;

/// The cat's long axis in its own frame (x, towards the head).
pub fn long_axis() -> Vector3<f64> {
    Vector3::x()
}

/// The quintic smoothstep `h(u) = 10u³ − 15u⁴ + 6u⁵` on `[0, 1]` (0 before, 1 after) and its
/// first two derivatives: `h(0) = 0`, `h(1) = 1`, `h' = h'' = 0` at both ends.
pub fn smoothstep(u: f64) -> [f64; 3] {
    if u <= 0.0 {
        [0.0; 3]
    } else if u >= 1.0 {
        [1.0, 0.0, 0.0]
    } else {
        let u2 = u * u;
        [
            u2 * u * (10.0 - 15.0 * u + 6.0 * u2),
            30.0 * u2 * (1.0 - u) * (1.0 - u),
            60.0 * u * (1.0 - u) * (1.0 - 2.0 * u),
        ]
    }
}

/// The bend envelope `e(s)` and its derivatives: up over `[0, ¼]`, 1, down over `[¾, 1]`.
fn envelope(s: f64) -> [f64; 3] {
    const RAMP: f64 = 0.25;
    if s < RAMP {
        let [h, h1, h2] = smoothstep(s / RAMP);
        [h, h1 / RAMP, h2 / (RAMP * RAMP)]
    } else if s > 1.0 - RAMP {
        let [h, h1, h2] = smoothstep((1.0 - s) / RAMP);
        [h, -h1 / RAMP, h2 / (RAMP * RAMP)]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// `cycles` bend-and-swing cycles (module docs) of bend `bend` (`β`, rad) and period `period`
/// (`T`, s), one after the other from `t = 0`; straight and at rest after the last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeCycles {
    /// The bend `β` while the envelope is 1 (rad).
    pub bend: f64,
    /// The period of one cycle (s).
    pub period: f64,
    /// How many cycles.
    pub cycles: usize,
}

impl ConeCycles {
    /// The whole motion's duration, `cycles·T`.
    pub fn duration(&self) -> f64 {
        self.cycles as f64 * self.period
    }

    /// The waist's path in shape space at `s ∈ [0, 1]` and its first two derivatives in `s`.
    pub fn path(&self, s: f64) -> [V3; 3] {
        let [e, e1, e2] = envelope(s);
        let w = 2.0 * PI;
        let (sin, cos) = (w * s).sin_cos();
        let (r, r1, r2) = (self.bend * e, self.bend * e1, self.bend * e2);
        // With c = [sin, −cos] (w = 2π): p = r·c; p' = r'·c + r·w·c⊥, c⊥ = [cos, sin];
        // p'' = (r'' − r·w²)·c + 2·r'·w·c⊥.
        // The pitch's sign puts the pike (the rear half under the belly) first.
        let p = V3::new(r * sin, -r * cos, 0.0);
        let p1 = V3::new(r1 * sin + r * w * cos, -(r1 * cos - r * w * sin), 0.0);
        let a = r2 - r * w * w;
        let b = 2.0 * r1 * w;
        let p2 = V3::new(a * sin + b * cos, -(a * cos - b * sin), 0.0);
        [p, p1, p2]
    }
}

impl JointMotion<3> for ConeCycles {
    fn at(&self, t: f64) -> [V3; 3] {
        if !(t > 0.0 && t < self.duration()) {
            return [V3::zeros(); 3];
        }
        let u = t / self.period;
        let [p, p1, p2] = self.path(u - u.floor());
        let ds = 1.0 / self.period;
        [p, p1 * ds, p2 * (ds * ds)]
    }
}

/// The angle between the two halves' long axes for the waist angles `[yaw, pitch, twist]`:
/// `cos = cos yaw·cos pitch` (the rear's x axis is `Rz(yaw)·Ry(pitch)·x`).
pub fn bend_angle(waist: &[f64]) -> f64 {
    (waist[0].cos() * waist[1].cos()).clamp(-1.0, 1.0).acos()
}

/// The cat on its back: turned by π about its long axis (its back towards the ground).
pub fn on_its_back() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
}

/// Integration settings: Dormand–Prince 5(4) with these tolerances, the states recorded
/// `samples` times per cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// States recorded per cycle (at least 1: the end of each cycle).
    pub samples: usize,
}

impl Default for Settings {
    /// `rtol = 1e-11`, `atol = 1e-12`, 100 samples per cycle.
    fn default() -> Self {
        Settings {
            rtol: 1e-11,
            atol: 1e-12,
            samples: 100,
        }
    }
}

/// A simulated fall: the recorded states (the first at `t = 0`) and the integrator's counters.
#[derive(Clone, Debug)]
pub struct Fall {
    /// The motion.
    pub motion: ConeCycles,
    /// The states, the initial one first, then `samples` per cycle.
    pub states: Vec<CatState>,
    /// Dormand–Prince's counters.
    pub stats: Dopri5Stats,
}

/// What a fall did to the cat's orientation, in its own frame at the start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycle {
    /// `Q₀⁻¹ ⊗ Q_end` on the branch the integration followed.
    pub net: Quaternion<f64>,
    /// Its rotation about the long axis (rad): the twist angle of [`twist_angle`].
    pub roll: f64,
    /// How far it tilts the long axis (rad).
    pub swing: f64,
}

impl Cycle {
    /// The turn of a quaternion `net`.
    pub fn of(net: Quaternion<f64>) -> Self {
        let axis = long_axis();
        Cycle {
            net,
            roll: twist_angle(&net, &axis),
            swing: swing_angle(&UnitQuaternion::new_normalize(net), &axis),
        }
    }

    /// The turn after `n` of these in a row: `net^n` (the dynamics do not depend on where the
    /// cat points, so each cycle, started straight and at rest, turns it by the same `net` in its
    /// own frame).
    pub fn repeated(&self, n: usize) -> Self {
        let mut q = Quaternion::identity();
        for _ in 0..n {
            q *= self.net;
        }
        Cycle::of(q)
    }
}

impl Fall {
    /// The turn from the first state to the last.
    pub fn turn(&self) -> Cycle {
        let first = base_orientation(self.states[0].q.as_slice());
        let last = base_orientation(self.states[self.states.len() - 1].q.as_slice());
        Cycle::of((first.inverse() * last).into_inner())
    }

    /// The roll (rotation about the long axis since the start, rad) at each recorded state,
    /// with the time, unwrapped: the twist angle is taken modulo 2π nearest the previous one (it
    /// jumps by 4π where a recorded quaternion's `(x, w)` crosses the negative `w` axis).
    pub fn roll(&self) -> Vec<(f64, f64)> {
        let first = base_orientation(self.states[0].q.as_slice()).inverse();
        let mut prev = 0.0;
        self.states
            .iter()
            .map(|s| {
                let net = (first * base_orientation(s.q.as_slice())).into_inner();
                let a = twist_angle(&net, &long_axis());
                prev = a - 2.0 * PI * ((a - prev) / (2.0 * PI)).round();
                (s.t, prev)
            })
            .collect()
    }
}

/// Drops the cat on its back at rest at the origin, runs `motion` with Dormand–Prince.
///
/// # Errors
/// An integration fault, as text.
pub fn fall(motion: ConeCycles, settings: Settings) -> Result<Fall, String> {
    let mut system = Hybrid::<FallingCat, _, 3>::new(motion);
    let start = system
        .start(0.0, [0.0; 3], on_its_back())
        .map_err(|e| e.to_string())?;
    let dt = motion.period / settings.samples.max(1) as f64;
    let (states, stats) = free_floating::record(
        &mut system,
        start,
        (motion.duration(), dt),
        (settings.rtol, settings.atol),
    )?;
    Ok(Fall {
        motion,
        states,
        stats,
    })
}

/// The turn of one cycle of bend `bend` (any period: it does not matter).
///
/// # Errors
/// An integration fault, as text.
pub fn one_cycle(bend: f64, settings: Settings) -> Result<Cycle, String> {
    let motion = ConeCycles {
        bend,
        period: 1.0,
        cycles: 1,
    };
    let settings = Settings {
        samples: 1,
        ..settings
    };
    Ok(fall(motion, settings)?.turn())
}

/// The largest bend a plan may use (rad): 60°, well short of the waist's Euler singularity at
/// 90° of pitch and about what a cat's spine gives.
pub const MAX_BEND: f64 = PI / 3.0;

/// A planned manoeuvre: how many cycles, the bend that gives the turn asked for, and the turn
/// the plan predicts from one simulated cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plan {
    /// Cycles.
    pub cycles: usize,
    /// The bend `β` (rad).
    pub bend: f64,
    /// The predicted turn (`Cycle::repeated(cycles)` of one cycle of bend `bend`).
    pub predicted: Cycle,
    /// Cycles simulated to find it.
    pub evaluations: usize,
}

/// The fewest cycles (up to `max_cycles`) whose roll reaches `target` (rad, > 0) with a bend of
/// at most [`MAX_BEND`], and the bend that gives exactly `target`: the roll of `n` cycles as a
/// function of `β` is 0 at 0 and grows with `β`, and is solved by the Illinois variant of
/// regula falsi (a secant kept inside a bracket), each evaluation one simulated cycle.
///
/// # Errors
/// No number of cycles up to `max_cycles` reaches the target, or an integration fault.
pub fn plan(target: f64, max_cycles: usize, settings: Settings) -> Result<Plan, String> {
    let mut evaluations = 0;
    let mut roll = |bend: f64, n: usize| -> Result<(Cycle, f64), String> {
        evaluations += 1;
        let c = one_cycle(bend, settings)?;
        Ok((c, c.repeated(n).roll))
    };
    let (widest, _) = roll(MAX_BEND, 1)?;
    for n in 1..=max_cycles {
        let full = widest.repeated(n).roll;
        if full < target {
            continue;
        }
        // Bracket [lo, hi] with roll(lo) < target ≤ roll(hi).
        let (mut lo, mut f_lo) = (0.0, -target);
        let (mut hi, mut f_hi) = (MAX_BEND, full - target);
        let mut side = 0i8;
        let mut best = (MAX_BEND, widest.repeated(n), f_hi.abs());
        for _ in 0..60 {
            let x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let (c, r) = roll(x, n)?;
            let f = r - target;
            if f.abs() < best.2 {
                best = (x, c.repeated(n), f.abs());
            }
            if f.abs() < 1e-12 || hi - lo < 1e-14 {
                break;
            }
            if f < 0.0 {
                (lo, f_lo) = (x, f);
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            } else {
                (hi, f_hi) = (x, f);
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            }
        }
        return Ok(Plan {
            cycles: n,
            bend: best.0,
            predicted: best.1,
            evaluations,
        });
    }
    Err(format!(
        "{max_cycles} cycles at the largest bend ({:.0}°) turn the cat by {:.1}°, short of {:.1}°",
        MAX_BEND.to_degrees(),
        widest.repeated(max_cycles).roll.to_degrees(),
        target.to_degrees()
    ))
}

/// [`Conservation`] over a fall's recorded states, `model` being `models/falling_cat.chain`
/// loaded by the reference.
///
/// # Errors
/// The reference's, as text.
pub fn conservation(model: &Model, fall: &Fall) -> Result<Conservation, String> {
    free_floating::conservation::<FallingCat, NQ, NV>(model, &fall.states)
}
