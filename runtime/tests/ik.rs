//! Inverse kinematics (`articulated::ik`) and the operational-space quantities
//! (`articulated::control::operational_space`) on arm7 (`models/arm7.urdf`, 7 revolute joints
//! with limits; its flange is the link `link7`) and on a chain of quaternion joints.
//!
//! `cargo test -p articulated --test ik -- --nocapture` prints the success rate and the
//! iterations of the 1,000 random targets.

use articulated::control::operational_space::{OperationalSpace, OperationalSpaceError};
use articulated::ik::{self, exp6, jlog6, log6, Goal, IkError, Options, Stop, Task, Vec6};
use articulated::nalgebra::{DMatrix, SMatrix, SVector, Vector3};
use articulated::prelude::*;
use articulated::{Drive, FramePlacement};
use articulated_dynamics::random::Rng;

#[derive(articulated::Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    outputs = [frame_placements, frame_jacobians_local_world_aligned, mass_matrix, mass_matrix_inverse],
    frames = [link7, link4]
)]
struct Arm7;

type Q7 = SVector<f64, 7>;

/// The flange (`link7`); the elbow (`link4`) is the second frame.
const FLANGE: usize = 0;

/// A configuration drawn uniformly within arm7's limits.
fn random_configuration(rng: &mut Rng) -> Q7 {
    let drives = <Arm7 as Chain<f64>>::DRIVES;
    Q7::from_fn(|i, _| rng.range(drives[i].lower, drives[i].upper))
}

/// Whether every coordinate is within its limits.
fn within_limits(q: &Q7) -> bool {
    let drives = <Arm7 as Chain<f64>>::DRIVES;
    q.iter()
        .zip(drives)
        .all(|(x, d)| d.lower <= *x && *x <= d.upper)
}

/// The distance between two placements' origins and the angle between their orientations,
/// measured without the solver's code: `atan2(|axial part of R − Rᵀ|/2, (tr R − 1)/2)` for
/// `R = R_aᵀ·R_b`, accurate at every angle.
fn distance(a: &FramePlacement<f64>, b: &FramePlacement<f64>) -> (f64, f64) {
    let r = a.rotation.transpose() * b.rotation;
    let axial = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    );
    let angle = (0.5 * axial.norm()).atan2(0.5 * (r.trace() - 1.0));
    ((a.translation - b.translation).norm(), angle)
}

// ---- SE(3) ----

#[test]
fn log6_inverts_exp6_and_jlog6_is_its_derivative() {
    let mut rng = Rng::new(7);
    let mut worst = 0.0_f64;
    for case in 0..200 {
        // Angles from 0 (and tiny) to just under π, translations up to 2 m.
        let angle = match case % 4 {
            0 => 1e-9 * rng.unit(),
            1 => 0.05 * rng.unit(),
            2 => 3.1 * rng.unit(),
            _ => 3.1 + 0.04 * rng.unit(),
        };
        let axis =
            Vector3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)).normalize();
        let w = axis * angle;
        let xi = Vec6::new(
            w.x,
            w.y,
            w.z,
            rng.symmetric(2.0),
            rng.symmetric(2.0),
            rng.symmetric(2.0),
        );
        let m = exp6(&xi);
        assert!(
            (log6(&m) - xi).amax() < 1e-12,
            "log6(exp6(ξ)) ≠ ξ for {xi:?}"
        );
        // Central differences of log6(M·exp6(ε·e_k)).
        let j = jlog6(&m);
        let h = 1e-6;
        for k in 0..6 {
            let mut step = Vec6::zeros();
            step[k] = h;
            let up = log6(&compose(&m, &exp6(&step)));
            let down = log6(&compose(&m, &exp6(&-step)));
            let column = (up - down) / (2.0 * h);
            let err = (column - j.column(k)).amax();
            worst = worst.max(err);
            assert!(err < 1e-7, "Jlog6 column {k} off by {err:e} at ξ = {xi:?}");
        }
    }
    println!("Jlog6 against central differences: worst {worst:.1e}");
}

/// `a·b`.
fn compose(a: &FramePlacement<f64>, b: &FramePlacement<f64>) -> FramePlacement<f64> {
    FramePlacement {
        rotation: a.rotation * b.rotation,
        translation: a.rotation * b.translation + a.translation,
    }
}

// ---- Inverse kinematics on arm7 ----

#[test]
fn arm7_reaches_random_poses_from_neutral() {
    let options = Options::default();
    assert_eq!(
        (options.position_tolerance, options.rotation_tolerance),
        (1e-6, 1e-5)
    );
    let mut rng = Rng::new(2024);
    let (mut iterations, mut failures) = (Vec::new(), Vec::new());
    let runs = 1000;
    for _ in 0..runs {
        let truth = random_configuration(&mut rng);
        let target = Arm7::frame_placements(&truth)[FLANGE];
        let tasks = [Task::pose(target), Task::FREE];
        match ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &options) {
            Ok(s) => {
                // Checked again by the kinematics alone.
                let (dp, dr) = distance(&Arm7::frame_placements(&s.q)[FLANGE], &target);
                assert!(
                    dp <= 1e-6 && dr <= 1e-5,
                    "claimed converged at {dp:e} m, {dr:e} rad"
                );
                assert!(s.iterations <= 100 && within_limits(&s.q));
                iterations.push(s.iterations);
            }
            Err(e) => {
                // Every failure says why and how far it got.
                assert!(e.residual.position.is_finite() && e.residual.rotation.is_finite());
                assert!(
                    e.residual.position > 1e-6 || e.residual.rotation > 1e-5,
                    "{e}"
                );
                let (dp, dr) = distance(&Arm7::frame_placements(&e.q)[FLANGE], &target);
                assert!(
                    (dp - e.residual.position).abs() < 1e-12
                        && (dr - e.residual.rotation).abs() < 1e-9
                );
                assert!(within_limits(&e.q));
                failures.push(e);
            }
        }
    }
    iterations.sort_unstable();
    let rate = iterations.len() as f64 / runs as f64;
    let pick = |p: f64| iterations[((iterations.len() - 1) as f64 * p) as usize];
    let mean = iterations.iter().sum::<usize>() as f64 / iterations.len() as f64;
    println!(
        "arm7, 1,000 random poses of link7 from the neutral configuration: {:.1} % reached \
         (1e-6 m, 1e-5 rad); iterations mean {mean:.1}, median {}, 95th percentile {}, max {}",
        100.0 * rate,
        pick(0.5),
        pick(0.95),
        pick(1.0)
    );
    for stop in [Stop::MaxIterations, Stop::Stalled, Stop::Singular] {
        let these: Vec<&IkError<7>> = failures.iter().filter(|e| e.stop == stop).collect();
        if let Some(worst) = these
            .iter()
            .max_by(|a, b| a.residual.position.total_cmp(&b.residual.position))
        {
            println!(
                "  {} stopped {stop:?}; the farthest at {:.2e} m, {:.2e} rad",
                these.len(),
                worst.residual.position,
                worst.residual.rotation
            );
        }
    }
    assert!(rate >= 0.95, "only {:.1} % reached", 100.0 * rate);
}

#[test]
fn an_unreachable_target_returns_the_residual() {
    // 3 m in front of the base, at the height of the shoulder (joint 2, 0.36 m up), from
    // which the arm reaches 0.901 m.
    let reach = 0.2045 + 0.2155 + 0.1845 + 0.2155 + 0.081;
    let far = Vector3::new(3.0, 0.0, 0.36);
    let target = FramePlacement {
        rotation: SMatrix::identity(),
        translation: far,
    };
    for (tasks, pose) in [
        ([Task::position(far), Task::FREE], false),
        ([Task::pose(target), Task::FREE], true),
    ] {
        let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).unwrap_err();
        println!("3 m away ({}): {e}", if pose { "pose" } else { "position" });
        assert!(matches!(e.stop, Stop::Stalled | Stop::MaxIterations), "{e}");
        let reached = Arm7::frame_placements(&e.q)[FLANGE].translation;
        assert!((e.residual.position - (reached - far).norm()).abs() < 1e-12);
        // As close as the arm can come: stretched towards the target; with the orientation
        // asked too, a compromise a little farther.
        if pose {
            assert!(e.residual.position > 3.0 - reach && e.residual.position < 3.0 - reach + 0.2);
            assert!(e.residual.rotation.is_finite());
        } else {
            assert!((e.residual.position - (3.0 - reach)).abs() < 1e-6, "{e}");
        }
        assert!(within_limits(&e.q));
    }
}

#[test]
fn a_zero_gradient_away_from_the_target_is_a_stall() {
    // Straight up, the arm cannot move its flange up: a target above it gives a zero gradient
    // at the start, and the solver stops there rather than call it a solution.
    let above = Vector3::new(0.0, 0.0, 3.0);
    let tasks = [Task::position(above), Task::FREE];
    let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).unwrap_err();
    assert_eq!((e.stop, e.iterations), (Stop::Stalled, 0), "{e}");
    let upright = Arm7::frame_placements(&Q7::zeros())[FLANGE].translation;
    assert_eq!(e.residual.position, (above - upright).norm());
}

#[test]
fn position_only_targets() {
    let mut rng = Rng::new(11);
    let mut reached = 0;
    for _ in 0..200 {
        let truth = random_configuration(&mut rng);
        let p = Arm7::frame_placements(&truth)[FLANGE].translation;
        let tasks = [Task::position(p), Task::FREE];
        let r = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default());
        if let Ok(s) = r {
            let there = Arm7::frame_placements(&s.q)[FLANGE].translation;
            assert!((there - p).norm() <= 1e-6 && s.residual.rotation == 0.0);
            reached += 1;
        }
    }
    println!("position only: {reached} of 200 reached");
    assert!(reached >= 195);
}

#[test]
fn two_frames_with_weights() {
    let mut rng = Rng::new(5);
    // Both reachable together: both reached, whatever the weights.
    for weights in [(1.0, 1.0), (100.0, 1.0), (1.0, 0.01)] {
        let truth = random_configuration(&mut rng);
        let [flange, elbow] = Arm7::frame_placements(&truth);
        let tasks = [
            Task::pose(flange).weighted(weights.0),
            Task::position(elbow.translation).weighted(weights.1),
        ];
        let s = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).unwrap();
        let [f, e] = Arm7::frame_placements(&s.q);
        let (dp, dr) = distance(&f, &flange);
        assert!(dp <= 1e-6 && dr <= 1e-5 && (e.translation - elbow.translation).norm() <= 1e-6);
    }
    // In conflict: the flange where it is at `truth`, the elbow where it is with the shoulder
    // (joint 2) turned 0.4 rad further, 0.17 m away. The heavier frame comes closer, and
    // swapping the weights swaps them.
    let truth = Q7::from([0.3, 0.7, -0.2, -1.2, 0.4, 0.8, 0.1]);
    let flange = Arm7::frame_placements(&truth)[FLANGE];
    let mut turned = truth;
    turned[1] += 0.4;
    let off = Arm7::frame_placements(&turned)[1];
    // Each kind of goal on each frame, so that both kinds' weights are seen.
    for pose_on_flange in [true, false] {
        let errors = |wf: f64, we: f64| {
            let tasks = if pose_on_flange {
                [Task::pose(flange), Task::position(off.translation)]
            } else {
                [Task::position(flange.translation), Task::pose(off)]
            };
            let tasks = [tasks[0].weighted(wf), tasks[1].weighted(we)];
            let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &truth, &Options::default()).unwrap_err();
            assert_eq!(e.stop, Stop::Stalled, "{e}");
            // A minimum of the weighted cost ½·Σ w_k·|e_k|²: its gradient, by central
            // differences, vanishes.
            let gradient = gradient(&tasks, &e.q);
            assert!(gradient < 1e-7, "|∇f| = {gradient:e} at {e}");
            let [f, el] = Arm7::frame_placements(&e.q);
            (
                distance(&f, &flange).0,
                (el.translation - off.translation).norm(),
            )
        };
        let (flange_heavy, elbow_light) = errors(100.0, 1.0);
        let (flange_light, elbow_heavy) = errors(1.0, 100.0);
        println!(
            "conflict ({} on the flange): flange weight 100: flange {flange_heavy:.2e} m, elbow \
             {elbow_light:.2e} m; elbow weight 100: flange {flange_light:.2e} m, elbow \
             {elbow_heavy:.2e} m",
            if pose_on_flange { "pose" } else { "position" }
        );
        assert!(flange_heavy < elbow_light && elbow_heavy < flange_light);
        assert!(flange_heavy < flange_light && elbow_heavy < elbow_light);
    }
}

/// The largest entry of the gradient of `½·Σ w_k·|e_k|²` at `q`, by central differences, the
/// errors as the module docs define them (`log6` for a pose, checked above).
fn gradient(tasks: &[Task; 2], q: &Q7) -> f64 {
    let cost = |q: &Q7| {
        let placed = Arm7::frame_placements(q);
        tasks
            .iter()
            .zip(&placed)
            .map(|(task, m)| {
                let e = match task.goal {
                    Goal::Pose(target) => log6(&FramePlacement {
                        rotation: m.rotation.transpose() * target.rotation,
                        translation: m.rotation.transpose() * (target.translation - m.translation),
                    })
                    .norm_squared(),
                    Goal::Position(p) => (p - m.translation).norm_squared(),
                    Goal::Free => 0.0,
                };
                0.5 * task.weight * e
            })
            .sum::<f64>()
    };
    let h = 1e-6;
    (0..7)
        .map(|k| {
            let (mut up, mut down) = (*q, *q);
            up[k] += h;
            down[k] -= h;
            ((cost(&up) - cost(&down)) / (2.0 * h)).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn joint_limits_hold_the_configuration_in_its_box() {
    // arm7's kinematics with every joint held to ±0.3 rad, a target from ±1 rad.
    let tight = [Drive {
        lower: -0.3,
        upper: 0.3,
        ..Drive::FREE
    }; 7];
    let truth = Q7::from([1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0]);
    let target = Arm7::frame_placements(&truth)[FLANGE];
    let tasks = [Task::pose(target), Task::FREE];
    let e = ik::solve_with(
        <Arm7 as Chain<f64>>::COORDINATES,
        &tight,
        Arm7::frame_placements,
        Arm7::frame_jacobians_local_world_aligned,
        &tasks,
        &Q7::zeros(),
        &Options::default(),
    )
    .unwrap_err();
    println!(
        "limits ±0.3 rad, target from ±1 rad: {e}; q = {:?}",
        e.q.as_slice()
    );
    assert!(e.q.iter().all(|x| x.abs() <= 0.3));
    assert!(e.q.iter().any(|x| x.abs() == 0.3), "no joint at its limit");
    // The same target with arm7's own limits is reached, from a start outside them too.
    assert!(ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).is_ok());
    let outside = Q7::from([3.5, 0.0, -4.0, 0.0, 0.0, 0.0, 0.0]);
    let s = ik::solve::<Arm7, 7, 7, 2>(&tasks, &outside, &Options::default()).unwrap();
    assert!(within_limits(&s.q), "{:?}", s.q.as_slice());
    // With nothing to reach, the start comes back clamped into the limits.
    let s = ik::solve::<Arm7, 7, 7, 2>(&[Task::FREE; 2], &outside, &Options::default()).unwrap();
    assert_eq!((s.q[0], s.q[2], s.iterations), (2.96, -2.96, 0));
}

#[test]
fn refused_inputs_say_why() {
    let tasks = [Task::position(Vector3::new(f64::NAN, 0.0, 0.0)), Task::FREE];
    let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).unwrap_err();
    assert_eq!(e.stop, Stop::Task { frame: 0 });
    let tasks = [Task::FREE, Task::position(Vector3::zeros()).weighted(-1.0)];
    let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &Options::default()).unwrap_err();
    assert_eq!(e.stop, Stop::Task { frame: 1 });
    let tasks = [Task::position(Vector3::new(0.3, 0.0, 0.5)), Task::FREE];
    let mut q0 = Q7::zeros();
    q0[2] = f64::NAN;
    let e = ik::solve::<Arm7, 7, 7, 2>(&tasks, &q0, &Options::default()).unwrap_err();
    assert_eq!(e.stop, Stop::NonFinite, "{e}");
    // Nothing asked: already there.
    let s =
        ik::solve::<Arm7, 7, 7, 2>(&[Task::FREE; 2], &Q7::zeros(), &Options::default()).unwrap();
    assert_eq!(s.iterations, 0);
}

// ---- Quaternion joints ----

articulated::chain! {
    /// Two ball joints and a hinge: the wrist's pose needs every quaternion to turn.
    chain Balls {
        outputs: [frame_placements, frame_jacobians_local_world_aligned];
        frames: [tip];
        body upper { mass: 1.0, com: [0.0, 0.0, 0.2], inertia: diag(0.01, 0.01, 0.001) }
        body fore { mass: 1.0, com: [0.0, 0.0, 0.2], inertia: diag(0.01, 0.01, 0.001) }
        body hand { mass: 0.5, com: [0.0, 0.0, 0.1], inertia: diag(0.001, 0.001, 0.001) }
        joint shoulder: spherical(quaternion) { parent: world, child: upper }
        joint elbow: revolute(y) { parent: upper, child: fore, xyz: [0.0, 0.0, 0.4] }
        joint wrist: spherical(quaternion) { parent: fore, child: hand, xyz: [0.0, 0.0, 0.4] }
        frame tip { parent: hand, xyz: [0.05, 0.0, 0.15] }
    }
}

#[test]
fn quaternion_joints_step_on_their_manifold() {
    let mut rng = Rng::new(3);
    let unit = |rng: &mut Rng| {
        let q = SVector::<f64, 4>::from_fn(|_, _| rng.symmetric(1.0));
        q / q.norm()
    };
    let (mut reached, runs) = (0, 200);
    for _ in 0..runs {
        let mut truth = SVector::<f64, 9>::zeros();
        truth.fixed_rows_mut::<4>(0).copy_from(&unit(&mut rng));
        truth[4] = rng.symmetric(2.5);
        truth.fixed_rows_mut::<4>(5).copy_from(&unit(&mut rng));
        let [target] = Balls::frame_placements(&truth);
        let mut start = SVector::<f64, 9>::zeros();
        (start[0], start[5]) = (1.0, 1.0);
        start[4] = 0.5;
        let tasks = [Task::pose(target)];
        match ik::solve::<Balls, 9, 7, 1>(&tasks, &start, &Options::default()) {
            Ok(s) => {
                let (dp, dr) = distance(&Balls::frame_placements(&s.q)[0], &target);
                assert!(dp <= 1e-6 && dr <= 1e-5);
                // Stepped by the exponential map: both quaternions unit to rounding.
                for at in [0, 5] {
                    let norm = s.q.fixed_rows::<4>(at).norm();
                    assert!((norm - 1.0).abs() < 1e-14, "|Q| = {norm}");
                }
                reached += 1;
            }
            Err(e) => assert!(e.residual.position.is_finite(), "{e}"),
        }
    }
    println!("two ball joints and a hinge: {reached} of {runs} poses reached");
    assert!(reached >= 190);
}

// ---- Operational space ----

/// `A⁻¹` by nalgebra's dynamic LU.
fn inverse(a: DMatrix<f64>) -> DMatrix<f64> {
    a.try_inverse().unwrap()
}

/// The largest entry of `a − b` over the largest of `b`.
fn relative(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn operational_space_inertia_against_a_direct_inverse() {
    let mut rng = Rng::new(17);
    let mut worst = 0.0_f64;
    for _ in 0..100 {
        let q = random_configuration(&mut rng);
        let m = Arm7::mass_matrix(&q);
        let m_inv = Arm7::mass_matrix_inverse(&q).unwrap();
        let j6 = Arm7::frame_jacobians_local_world_aligned(&q)[FLANGE];
        let j3: SMatrix<f64, 3, 7> = j6.fixed_rows::<3>(3).into_owned();
        let tol = articulated::control::operational_space::RANK_TOLERANCE;
        for (os, j) in [
            (
                OperationalSpace::from_mass_matrix(&m, &j6, tol).map(dynamic),
                DMatrix::from_column_slice(6, 7, j6.as_slice()),
            ),
            (
                OperationalSpace::from_mass_matrix_inverse(&m_inv, &j6, tol).map(dynamic),
                DMatrix::from_column_slice(6, 7, j6.as_slice()),
            ),
            (
                OperationalSpace::from_mass_matrix(&m, &j3, tol).map(dynamic),
                DMatrix::from_column_slice(3, 7, j3.as_slice()),
            ),
        ] {
            let (lambda, jbar) = os.unwrap();
            let md = DMatrix::from_column_slice(7, 7, m.as_slice());
            let m_inv_d = inverse(md);
            let direct = inverse(&j * &m_inv_d * j.transpose());
            let jbar_direct = &m_inv_d * j.transpose() * &direct;
            let r = j.nrows();
            let identity = (&j * &jbar - DMatrix::identity(r, r)).amax();
            let err = relative(&lambda, &direct).max(relative(&jbar, &jbar_direct));
            worst = worst.max(err);
            assert!(err < 1e-8, "Λ or J̄ off by {err:e}");
            assert!(identity < 1e-9, "J·J̄ − I = {identity:e}");
        }
    }
    println!("Λ and J̄ against nalgebra's dynamic inverse: worst relative {worst:.1e}");
}

/// `(Λ, J̄)` as dynamic matrices.
fn dynamic<const R: usize>(os: OperationalSpace<R, 7>) -> (DMatrix<f64>, DMatrix<f64>) {
    (
        DMatrix::from_column_slice(R, R, os.inertia.as_slice()),
        DMatrix::from_column_slice(7, R, os.jbar.as_slice()),
    )
}

#[test]
fn torques_in_the_null_space_leave_the_task_alone() {
    let mut rng = Rng::new(19);
    for _ in 0..50 {
        let q = random_configuration(&mut rng);
        let m = Arm7::mass_matrix(&q);
        let j = Arm7::frame_jacobians_local_world_aligned(&q)[FLANGE];
        let os = OperationalSpace::from_mass_matrix(&m, &j, 1e-10).unwrap();
        let tau = SVector::<f64, 7>::from_fn(|_, _| rng.symmetric(10.0));
        let projected = os.project_torque(&j, &tau);
        // The task's acceleration J·M⁻¹·τ_null is zero.
        let a = j * m.cholesky().unwrap().solve(&projected);
        assert!(a.amax() < 1e-9 * tau.amax(), "J·M⁻¹·N·τ = {:e}", a.amax());
        assert!((os.null_space_projector(&j) * tau - projected).amax() < 1e-12 * tau.amax());
    }
}

#[test]
fn a_rank_deficient_jacobian_is_an_error() {
    let q = Q7::from([0.3, 0.7, -0.2, -1.2, 0.4, 0.8, 0.1]);
    let m = Arm7::mass_matrix(&q);
    let tol = articulated::control::operational_space::RANK_TOLERANCE;
    // Two identical rows.
    let mut j = Arm7::frame_jacobians_local_world_aligned(&q)[FLANGE];
    let row = j.row(3).into_owned();
    j.set_row(4, &row);
    let e = OperationalSpace::from_mass_matrix(&m, &j, tol).unwrap_err();
    println!("two identical rows: {e}");
    assert!(
        matches!(e, OperationalSpaceError::RankLoss { smallest, largest, .. } if smallest <= tol * largest)
    );
    // Straight up, the arm is singular: joints 1, 3, 5, 7 turn the flange about one axis.
    let zero = Q7::zeros();
    let j = Arm7::frame_jacobians_local_world_aligned(&zero)[FLANGE];
    let e = OperationalSpace::from_mass_matrix(&Arm7::mass_matrix(&zero), &j, tol).unwrap_err();
    println!("arm straight up: {e}");
    assert!(matches!(e, OperationalSpaceError::RankLoss { .. }));
    // The position rows alone lose rank there too (no motion along the arm), but not at q.
    let j3: SMatrix<f64, 3, 7> = j.fixed_rows::<3>(3).into_owned();
    assert!(OperationalSpace::from_mass_matrix(&Arm7::mass_matrix(&zero), &j3, tol).is_err());
    let jq: SMatrix<f64, 3, 7> = Arm7::frame_jacobians_local_world_aligned(&q)[FLANGE]
        .fixed_rows::<3>(3)
        .into_owned();
    assert!(OperationalSpace::from_mass_matrix(&m, &jq, tol).is_ok());
    // A mass matrix that is not positive definite.
    let e = OperationalSpace::from_mass_matrix(&-m, &jq, tol).unwrap_err();
    assert_eq!(e, OperationalSpaceError::MassMatrix);
}
