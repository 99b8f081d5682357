//! Simulation with contacts (`articulated::contact`) against closed forms, at 1 ms steps: a box
//! on a slope that sticks and one that slides, a box dropped flat without and with restitution,
//! a sphere rolling down a slope, a box pushed along the ground, and Painlevé's rod.
//!
//! Each expectation comes from Newtonian mechanics, not from the stepper: a block on an incline
//! sticks when `tan θ ≤ μ` and otherwise slides with `a = g·(sin θ − μ·cos θ)`; a solid sphere
//! rolls without slipping with `a = (5/7)·g·sin θ`; a block sliding on flat ground stops after
//! `v²/(2μg)`.

use articulated::contact::{ContactError, Ground, Settings, Sphere, StepReport, TimeStepper};
use articulated::integrate::State;
use articulated::nalgebra::{SVector, Vector3};
use articulated::{Chain, MassMatrixAndNonlinearEffects};

const G: f64 = 9.81;
const H: f64 = 1e-3;
/// The block's half side (m); a cube of 1 kg.
const A: f64 = 0.1;

/// A 1 kg cube of side 0.2 m on a free base, its centre at the frame `block`'s origin.
#[derive(Chain)]
#[chain(file = "../models/block.chain")]
struct Block;

articulated::chain! {
    /// A solid ball of 1 kg and radius 0.1 m on a free base (`I = 2/5·m·r²`).
    chain Ball {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local];
        frames: [ball];
        body ball { mass: 1.0, com: [0.0, 0.0, 0.0], inertia: diag(0.004, 0.004, 0.004) }
        joint base: free(quaternion) { parent: world, child: ball }
    }
}

articulated::chain! {
    /// A thin rod of 1 kg and 1 m along its x axis on a free base.
    chain Rod {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local];
        frames: [rod];
        body rod { mass: 1.0, com: [0.0, 0.0, 0.0], inertia: diag(0.0001, 0.08333333333333333, 0.08333333333333333) }
        joint base: free(quaternion) { parent: world, child: rod }
    }
}

type State13 = State<f64, articulated::nalgebra::Const<7>, articulated::nalgebra::Const<6>>;

/// The block's eight corners as points with friction `mu` and restitution `e`.
fn corners(mu: f64, e: f64) -> [Sphere; 8] {
    core::array::from_fn(|k| Sphere {
        frame: 0,
        offset: [
            if k & 1 == 0 { -A } else { A },
            if k & 2 == 0 { -A } else { A },
            if k & 4 == 0 { -A } else { A },
        ],
        radius: 0.0,
        friction: mu,
        restitution: e,
    })
}

/// A slope through the origin rising towards −x at `theta`: its normal, and the way down it.
fn slope(theta: f64) -> (Vector3<f64>, Vector3<f64>) {
    let (s, c) = theta.sin_cos();
    (Vector3::new(s, 0.0, c), Vector3::new(c, 0.0, -s))
}

/// A free body resting on the slope `theta` (turned about y by `theta`) with its centre
/// `height` above it along the normal.
fn on_slope(theta: f64, height: f64) -> State13 {
    let (n, _) = slope(theta);
    let p = n * height;
    let half = 0.5 * theta;
    let q = SVector::from([p.x, p.y, p.z, half.cos(), 0.0, half.sin(), 0.0]);
    State::new(0.0, q, SVector::zeros())
}

fn unforced(_t: f64, _q: &SVector<f64, 7>, _v: &SVector<f64, 6>) -> SVector<f64, 6> {
    SVector::zeros()
}

/// Steps `state` for `seconds`, asserting each step converged; `each` sees every new state.
fn run<C, const P: usize>(
    stepper: &mut TimeStepper<'_, C, Unforced, 7, 6, 1, P>,
    state: &mut State13,
    seconds: f64,
    mut each: impl FnMut(&State13, &StepReport),
) where
    C: articulated::contact::ContactOutputs<7, 6, 1>,
{
    let steps = (seconds / H).round() as usize;
    for k in 0..steps {
        let report = stepper.step(state, H).unwrap();
        assert!(report.converged, "step {k}: {report:?}");
        each(state, &report);
    }
}

type Unforced = fn(f64, &SVector<f64, 7>, &SVector<f64, 6>) -> SVector<f64, 6>;

fn block<'a>(
    grounds: &'a [Ground],
    spheres: &'a [Sphere],
) -> TimeStepper<'a, Block, Unforced, 7, 6, 1, 8> {
    TimeStepper::new(grounds, spheres, Settings::default(), unforced as Unforced).unwrap()
}

/// The lowest corner's distance from a ground of normal `n` through the origin.
fn lowest(state: &State13, n: &Vector3<f64>) -> f64 {
    let q = &state.q;
    let r = articulated::nalgebra::UnitQuaternion::from_quaternion(
        articulated::nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]),
    );
    let centre = Vector3::new(q[0], q[1], q[2]);
    corners(0.0, 0.0)
        .iter()
        .map(|s| n.dot(&(centre + r * Vector3::from(s.offset))))
        .fold(f64::INFINITY, f64::min)
}

/// The block left on a slope of `tan θ = ratio·μ` for 1 s: how far it went down the slope and
/// the total force of the ground at the end, after asserting at every step that it stayed on the
/// slope (1e-6 m: the convex relaxation would lift a sliding contact by μ·‖u_t‖·h each step,
/// 0.3 mm per step at 1 m/s).
fn on_a_slope(ratio: f64) -> (f64, Vector3<f64>) {
    let mu: f64 = 0.5;
    let theta = (ratio * mu).atan();
    let (n, down) = slope(theta);
    let grounds = [Ground::new(n.into(), 0.0).unwrap()];
    let spheres = corners(mu, 0.0);
    let mut stepper = block(&grounds, &spheres);
    let mut state = on_slope(theta, A);
    let start = Vector3::new(state.q[0], state.q[1], state.q[2]);
    run(&mut stepper, &mut state, 1.0, |s, _| {
        let height = lowest(s, &n);
        assert!(height.abs() <= 1e-6, "height {height:e} at t = {}", s.t);
    });
    let moved = Vector3::new(state.q[0], state.q[1], state.q[2]) - start;
    let total = stepper.forces().map(|f| Vector3::from(f.force)).sum();
    (moved.dot(&down), total)
}

#[test]
fn a_block_sticks_on_a_slope_below_its_friction_angle() {
    let (moved, total) = on_a_slope(0.8);
    assert!(moved.abs() <= 1e-6, "drifted {moved:e} m");
    // The ground carries the weight: the forces sum to m·g upwards.
    assert!(
        (total - Vector3::new(0.0, 0.0, G)).norm() <= 1e-6 * G,
        "{total}"
    );
}

#[test]
fn a_block_slides_down_a_slope_steeper_than_its_friction_angle() {
    let (moved, _) = on_a_slope(1.2);
    // Symplectic Euler from rest: s_N = a·h²·N(N + 1)/2.
    let (mu, theta) = (0.5_f64, (1.2_f64 * 0.5).atan());
    let a = G * (theta.sin() - mu * theta.cos());
    let expected = 0.5 * a * 1.0 * (1.0 + H);
    assert!(
        (moved - expected).abs() <= 0.01 * expected,
        "{moved} against {expected}"
    );
}

/// The block's total energy, `½·vᵀ·M·v + m·g·z`.
fn energy(s: &State13) -> f64 {
    let (m, _) = Block::mass_matrix_and_nonlinear_effects(&s.q, &s.v);
    0.5 * s.v.dot(&(m * s.v)) + G * s.q[2]
}

#[test]
fn a_block_dropped_flat_without_restitution_comes_to_rest_on_its_face() {
    let drop = 0.5;
    let up = Vector3::z();
    let grounds = [Ground::new(up.into(), 0.0).unwrap()];
    let spheres = corners(0.8, 0.0);
    let mut stepper = block(&grounds, &spheres);
    let mut state = on_slope(0.0, A + drop);
    let mut e = energy(&state);
    let mut deepest: f64 = 0.0;
    run(&mut stepper, &mut state, 1.5, |s, _| {
        let now = energy(s);
        assert!(
            now <= e + 1e-9 * G * drop,
            "energy rose by {:e} at t = {}",
            now - e,
            s.t
        );
        e = now;
        deepest = deepest.min(lowest(s, &up));
    });
    assert!(deepest >= -1e-3, "penetrated {deepest:e} m");
    assert!(lowest(&state, &up).abs() <= 1e-6 && state.v.norm() <= 1e-6);
    let total: f64 = stepper.forces().map(|f| f.force[2]).sum();
    assert!((total - G).abs() <= 1e-6 * G, "normal forces {total}");
}

#[test]
fn a_block_dropped_with_full_restitution_bounces_back_near_its_height_and_never_above() {
    let drop = 0.5;
    let up = Vector3::z();
    let grounds = [Ground::new(up.into(), 0.0).unwrap()];
    let spheres = corners(0.8, 1.0);
    let mut stepper = block(&grounds, &spheres);
    let mut state = on_slope(0.0, A + drop);
    let (mut landed, mut apex) = (false, 0.0_f64);
    run(&mut stepper, &mut state, 1.2, |s, _| {
        let height = lowest(s, &up);
        assert!(height <= drop + 1e-9, "rose to {height} at t = {}", s.t);
        // It bounces within the step that would close its gap (speculative contact).
        landed |= s.v[2] > 0.0;
        if landed {
            apex = apex.max(height);
        }
    });
    assert!(
        landed && apex >= 0.95 * drop,
        "rebounded to {apex} of {drop}"
    );
}

#[test]
fn a_ball_rolls_down_a_slope_without_slipping() {
    let theta: f64 = 0.3;
    let (n, down) = slope(theta);
    let grounds = [Ground::new(n.into(), 0.0).unwrap()];
    let spheres = [Sphere {
        radius: 0.1,
        ..Sphere::point(0, 0.5)
    }];
    let mut stepper: TimeStepper<'_, Ball, Unforced, 7, 6, 1, 1> = TimeStepper::new(
        &grounds,
        &spheres,
        Settings::default(),
        unforced as Unforced,
    )
    .unwrap();
    let mut state = on_slope(theta, 0.1);
    let start = Vector3::new(state.q[0], state.q[1], state.q[2]);
    run(&mut stepper, &mut state, 1.0, |_, _| {});
    let moved = (Vector3::new(state.q[0], state.q[1], state.q[2]) - start).dot(&down);
    let expected = 0.5 * (5.0 / 7.0) * G * theta.sin() * (1.0 + H);
    assert!(
        (moved - expected).abs() <= 0.01 * expected,
        "{moved} against {expected}"
    );
    // Rolling: the contact point does not slip, ω·r equals the speed (v is in the ball's axes).
    let speed = state.v.fixed_rows::<3>(0).norm();
    let spin = state.v.fixed_rows::<3>(3).norm();
    assert!(
        (spin * 0.1 - speed).abs() <= 1e-6 * speed,
        "{spin} rad/s at {speed} m/s"
    );
}

#[test]
fn a_block_pushed_along_the_ground_stops_where_friction_says() {
    let (mu, v0) = (0.5, 2.0);
    let up = Vector3::z();
    let grounds = [Ground::new(up.into(), 0.0).unwrap()];
    let spheres = corners(mu, 0.0);
    let mut stepper = block(&grounds, &spheres);
    let mut state = on_slope(0.0, A);
    state.v[0] = v0;
    let mut stopped = None;
    run(&mut stepper, &mut state, 0.6, |s, _| {
        if stopped.is_none() && s.v[0] <= 1e-9 {
            stopped = Some((s.t, s.q[0]));
        }
        assert!(lowest(s, &up).abs() <= 1e-6);
    });
    let (t, x) = stopped.expect("it stops");
    let (t_exact, x_exact) = (v0 / (mu * G), v0 * v0 / (2.0 * mu * G));
    assert!(
        (t - t_exact).abs() <= 0.01 * t_exact,
        "stopped at {t} s, not {t_exact}"
    );
    assert!(
        (x - x_exact).abs() <= 0.01 * x_exact,
        "stopped after {x} m, not {x_exact}"
    );
    assert!(
        (state.q[0] - x).abs() <= 1e-9,
        "crept on from {x} to {}",
        state.q[0]
    );
}

#[test]
fn painleves_rod_ends_finite_or_says_it_did_not_converge() {
    // A rod leaning at 30° on one end, sliding towards it fast with a high friction coefficient:
    // the configuration of Painlevé's paradox, where the rigid contact problem has no solution
    // or several.
    let up = Vector3::z();
    let grounds = [Ground::new(up.into(), 0.0).unwrap()];
    let spheres = [Sphere {
        offset: [-0.5, 0.0, 0.0],
        ..Sphere::point(0, 1.5)
    }];
    let settings = Settings {
        max_iterations: 200,
        ..Settings::default()
    };
    let mut stepper: TimeStepper<'_, Rod, Unforced, 7, 6, 1, 1> =
        TimeStepper::new(&grounds, &spheres, settings, unforced as Unforced).unwrap();
    let tilt: f64 = -30f64.to_radians();
    let (s, c) = (0.5 * tilt).sin_cos();
    let centre = [0.5 * tilt.cos().abs(), 0.0, 0.5 * tilt.sin().abs()];
    let q = SVector::from([centre[0], centre[1], centre[2], c, 0.0, s, 0.0]);
    // Moving towards −x, the foot of the rod first.
    let v = SVector::from([-4.0 * tilt.cos(), 0.0, 4.0 * tilt.sin(), 0.0, 0.0, 0.0]);
    let mut state = State::new(0.0, q, v);
    for _ in 0..500 {
        match stepper.step(&mut state, H) {
            Ok(report) => assert!(report.residual.is_finite()),
            Err(e) => panic!("{e}"),
        }
        assert!(state.q.iter().chain(state.v.iter()).all(|x| x.is_finite()));
    }
}

#[test]
fn bad_scenes_are_refused_by_name() {
    assert_eq!(Ground::new([0.0; 3], 0.0), Err(ContactError::Ground));
    assert_eq!(
        Ground::new([0.0, 0.0, 1.0], f64::NAN),
        Err(ContactError::Ground)
    );
    let grounds = [Ground::new([0.0, 0.0, 2.0], 0.0).unwrap()];
    assert_eq!(grounds[0].normal(), [0.0, 0.0, 1.0]);
    let far = [Sphere::point(3, 0.5)];
    let err = TimeStepper::<Block, Unforced, 7, 6, 1, 1>::new(
        &grounds,
        &far,
        Settings::default(),
        unforced as Unforced,
    )
    .err();
    assert_eq!(
        err,
        Some(ContactError::UnknownFrame {
            sphere: 0,
            frame: 3,
            frames: 1
        })
    );
    let bad = [Sphere {
        restitution: 1.5,
        ..Sphere::point(0, 0.5)
    }];
    let err = TimeStepper::<Block, Unforced, 7, 6, 1, 1>::new(
        &grounds,
        &bad,
        Settings::default(),
        unforced as Unforced,
    )
    .err();
    assert_eq!(err, Some(ContactError::Sphere { sphere: 0 }));
    // Four corners on the ground do not fit three pairs; the state stays as it was.
    let spheres = corners(0.5, 0.0);
    let mut small = TimeStepper::<Block, Unforced, 7, 6, 1, 3>::new(
        &grounds,
        &spheres,
        Settings::default(),
        unforced as Unforced,
    )
    .unwrap();
    let mut state = on_slope(0.0, A);
    let before = state;
    assert_eq!(
        small.step(&mut state, H),
        Err(ContactError::Capacity {
            needed: 4,
            capacity: 3
        })
    );
    assert_eq!(state, before);
    // A NaN state is an error, not a NaN.
    let mut state = on_slope(0.0, A);
    state.v[2] = f64::NAN;
    let mut stepper = block(&grounds, &spheres);
    assert_eq!(stepper.step(&mut state, H), Err(ContactError::NonFinite));
}

/// The humanoid with the outputs the contact stepping needs, its feet as frames.
#[derive(Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local],
    frames = [left_foot, right_foot]
)]
struct Humanoid;

/// Four points under each sole: heel and toes, 0.05 m to each side, 0.09 m below the foot's
/// frame (its sole at the neutral configuration with the pelvis at 1.11 m).
fn soles(mu: f64) -> [Sphere; 8] {
    core::array::from_fn(|k| Sphere {
        frame: k / 4,
        offset: [
            if k & 1 == 0 { -0.06 } else { 0.16 },
            if k & 2 == 0 { -0.05 } else { 0.05 },
            -0.09,
        ],
        radius: 0.0,
        friction: mu,
        restitution: 0.0,
    })
}

/// The humanoid standing on eight points, its joints held by springs and dampers about zero:
/// the ground carries its weight, the feet neither sink nor slide, and the step factored along
/// the kinematic tree gives the velocities of the dense factorization (the run-time stepper,
/// fed the same generated dynamics) to rounding.
#[test]
fn the_humanoid_stands_on_its_soles_and_the_tree_factorization_is_the_dense_one() {
    use articulated::contact::dynamic;
    use articulated::nalgebra::{DVector, Matrix6xX};
    use articulated::{FrameJacobiansLocal, FramePlacements};
    type Hold = fn(f64, &SVector<f64, 38>, &SVector<f64, 37>) -> SVector<f64, 37>;
    fn hold(_t: f64, q: &SVector<f64, 38>, _v: &SVector<f64, 37>) -> SVector<f64, 37> {
        let mut tau = SVector::zeros();
        for k in 6..37 {
            tau[k] = -2000.0 * q[k + 1];
        }
        tau
    }
    let grounds = [Ground::new([0.0, 0.0, 1.0], 0.0).unwrap()];
    let spheres = soles(0.8);
    let mut stepper: TimeStepper<'_, Humanoid, Hold, 38, 37, 2, 8> =
        TimeStepper::new(&grounds, &spheres, Settings::default(), hold as Hold).unwrap();
    assert!(stepper.factors_along_the_tree());
    let damping = SVector::from_fn(|k, _| if k < 6 { 0.0 } else { 50.0 });
    stepper.set_damping(damping).unwrap();
    let mut q = SVector::<f64, 38>::zeros();
    q[2] = 1.11;
    q[3] = 1.0;
    let mut state = State::new(0.0, q, SVector::zeros());
    let mut dense = dynamic::TimeStepper::new();
    let coordinates = <Humanoid as Chain<f64>>::COORDINATES;
    let mass: f64 = 82.05;
    for step in 0..500 {
        // The dense stepper from the same state, with the same dynamics.
        let (m, nle) = Humanoid::mass_matrix_and_nonlinear_effects(&state.q, &state.v);
        let placements = Humanoid::frame_placements(&state.q);
        let jacobians = Humanoid::frame_jacobians_local(&state.q)
            .map(|j| Matrix6xX::from_fn(37, |r, c| j[(r, c)]));
        let (mut qd, mut vd) = (
            DVector::from_column_slice(state.q.as_slice()),
            DVector::from_column_slice(state.v.as_slice()),
        );
        let tau = DVector::from_column_slice(hold(state.t, &state.q, &state.v).as_slice());
        let d = DVector::from_column_slice(damping.as_slice());
        let at = dynamic::At {
            m: &DMatrixOf::from_column_slice(37, 37, m.as_slice()),
            nle: &DVector::from_column_slice(nle.as_slice()),
            tau: &tau,
            placements: &placements,
            jacobians: &jacobians,
            damping: Some(&d),
            limits: &[],
        };
        let dense_report = dense
            .step(
                coordinates,
                &mut qd,
                &mut vd,
                &at,
                &grounds,
                &spheres,
                &Settings::default(),
                H,
            )
            .unwrap();
        let report = stepper.step(&mut state, H).unwrap();
        assert!(
            report.converged && dense_report.converged,
            "step {step}: {report:?}"
        );
        let gap = (DVector::from_column_slice(state.v.as_slice()) - vd).amax();
        assert!(
            gap <= 1e-8,
            "step {step}: the tree and dense steps differ by {gap:e}"
        );
    }
    let total: Vector3<f64> = stepper.forces().map(|f| Vector3::from(f.force)).sum();
    // Still swaying a little after half a second: within 1 % of static equilibrium.
    assert!((total.z - mass * G).abs() <= 1e-2 * mass * G, "{total}");
    assert!(total.xy().norm() <= 1e-2 * mass * G, "{total}");
    assert!(
        (state.q[2] - 1.11).abs() <= 2e-3,
        "the pelvis at {}",
        state.q[2]
    );
    for f in stepper.forces() {
        assert!(f.distance >= -1e-4 && f.force[2] > 0.0, "{f:?}");
    }
}

type DMatrixOf = articulated::nalgebra::DMatrix<f64>;

articulated::chain! {
    /// The cube with its scene in the description: a floor, its four lower corners as points.
    chain Crate {
        gravity: [0.0, 0.0, -9.81];
        outputs: [];
        grounds: [floor: [0.0, 0.0, 2.0, 0.0]];
        spheres: [
            a: sphere(box_body, [-0.1, -0.1, -0.1], 0.0),
            b: sphere(box_body, [0.1, -0.1, -0.1], 0.0),
            c: sphere(box_body, [-0.1, 0.1, -0.1], 0.0),
            d: sphere(box_body, [0.1, 0.1, -0.1], 0.0)
        ];
        friction: 0.5;
        restitution: 0.25;
        body box_body { mass: 1.0, com: [0.0, 0.0, 0.0],
                        inertia: diag(0.006666666666666667, 0.006666666666666667, 0.006666666666666667) }
        joint base: free(quaternion) { parent: world, child: box_body }
    }
}

/// A scene declared in the description (`grounds`, `spheres`, `friction`, `restitution`) is the
/// type's `GROUNDS` and `SPHERES`, the normal made a unit vector, and the outputs the stepping
/// reads come with it: pushed, the crate stops where friction says.
#[test]
fn a_scene_in_the_description_steps_as_one_in_code() {
    assert_eq!(
        Crate::GROUNDS,
        &[Ground::new([0.0, 0.0, 1.0], 0.0).unwrap()]
    );
    assert_eq!(Crate::SPHERES.len(), 4);
    assert_eq!(Crate::SPHERES[1].offset, [0.1, -0.1, -0.1]);
    assert_eq!(
        (Crate::SPHERES[3].friction, Crate::SPHERES[3].restitution),
        (0.5, 0.25)
    );
    assert_eq!(<Crate as Chain<f64>>::FRAMES, ["box_body"]);
    let mut stepper: TimeStepper<'_, Crate, Unforced, 7, 6, 1, 4> = TimeStepper::new(
        Crate::GROUNDS,
        Crate::SPHERES,
        Settings::default(),
        unforced as Unforced,
    )
    .unwrap();
    let mut state = on_slope(0.0, A);
    state.v[0] = 2.0;
    run(&mut stepper, &mut state, 0.6, |_, _| {});
    let expected = 4.0 / (2.0 * 0.5 * G);
    assert!(
        (state.q[0] - expected).abs() <= 0.01 * expected,
        "{}",
        state.q[0]
    );
}

articulated::chain! {
    /// A pendulum of 1 kg (nearly a point) on a massless rod of 1 m about y, its joint limited
    /// to ±0.5 rad.
    chain Stopped {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local];
        frames: [bob];
        body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(1e-6, 1e-6, 1e-6) }
        joint pivot: revolute(y) { parent: world, child: bob, lower: -0.5, upper: 0.5 }
    }
}

/// Joint limits held as unilateral rows of the contact problem: a pendulum thrown at its upper
/// limit stops there without passing it (a plastic impact: it keeps `m·g·l·(1 − cos 0.5)`
/// of energy, all potential), swings back and never passes either limit; pushed into the limit
/// by a constant couple it rests there, the limit carrying the couple less gravity's,
/// `τ − m·g·l·sin 0.5`.
#[test]
fn joint_limits_are_hard_stops_in_the_contact_problem() {
    type Law = fn(f64, &SVector<f64, 1>, &SVector<f64, 1>) -> SVector<f64, 1>;
    let free: Law = |_, _, _| SVector::zeros();
    let mut stepper: TimeStepper<'_, Stopped, Law, 1, 1, 1, 2> =
        TimeStepper::new(&[], &[], Settings::default(), free).unwrap();
    stepper.hold_joint_limits();
    let energy =
        |s: &State<f64, articulated::nalgebra::Const<1>, articulated::nalgebra::Const<1>>| {
            0.5 * s.v[0] * s.v[0] + G * (1.0 - s.q[0].cos())
        };
    let mut state = State::new(0.0, SVector::from([0.3]), SVector::from([3.0]));
    let (mut hit, mut after) = (false, f64::NAN);
    for _ in 0..2000 {
        stepper.step(&mut state, H).unwrap();
        assert!(
            state.q[0].abs() <= 0.5 + 1e-9,
            "passed a limit: {}",
            state.q[0]
        );
        // Stopped at the limit: the impact, spread over the step that closes the gap and the
        // next, has taken all the kinetic energy.
        if !hit && stepper.limit_forces().any(|(_, f)| f != 0.0) && state.v[0] <= 0.0 {
            hit = true;
            after = energy(&state);
        }
    }
    let at_the_stop = G * (1.0 - 0.5f64.cos());
    assert!(
        hit && (after - at_the_stop).abs() <= 1e-2 * at_the_stop,
        "{after} against {at_the_stop}"
    );

    let push: Law = |_, _, _| SVector::from([8.0]);
    let mut stepper: TimeStepper<'_, Stopped, Law, 1, 1, 1, 2> =
        TimeStepper::new(&[], &[], Settings::default(), push).unwrap();
    stepper.hold_joint_limits();
    let mut state = State::new(0.0, SVector::from([0.5]), SVector::zeros());
    for _ in 0..100 {
        stepper.step(&mut state, H).unwrap();
    }
    let forces: Vec<(usize, f64)> = stepper.limit_forces().collect();
    let expected = -(8.0 - G * 0.5f64.sin());
    assert_eq!(forces.len(), 1);
    assert!(
        (forces[0].1 - expected).abs() <= 1e-9,
        "{forces:?} against {expected}"
    );
    assert!((state.q[0] - 0.5).abs() <= 1e-12 && state.v[0].abs() <= 1e-12);
}
