//! The generated frame outputs (issue "Frames") against the interpreted reference
//! (`Reference::frame_*`, itself checked against Pinocchio 4.1 in `pinocchio_frames.rs` and by
//! finite differences in `dynamics/tests/frames.rs`): placements, LOCAL velocities, classical
//! accelerations, and the Jacobians and their time variations in LOCAL, WORLD and
//! LOCAL_WORLD_ALIGNED, at seeded random states, on every joint kind: arm7 (a serial arm, a
//! declared tool frame turned every way), the branching tree, the humanoid on both free bases
//! (soles, hands and the links merged into their bodies: its camera and IMU), the falling cat
//! (a quaternion base and an Euler waist), Hemami's two-link (spherical Euler joints), a
//! gripper with mimic fingers, in `f64`, and one chain in `f32` and generic.
//!
//! `cargo test -p articulated-tests --test generated_frames -- --nocapture` prints each model's
//! worst error.

mod common;

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::frames::ReferenceFrame;
use articulated::reference::Reference;
use articulated_codegen::load::{load_model, FloatingBase};
use articulated_dynamics::model::Model;
use articulated_dynamics::random::random_state;
use common::{abs_err, max_abs};

/// Relative to the largest entry of the reference's value, or absolute below 1.
const TOL: f64 = 1e-11;

#[derive(Chain)]
#[chain(urdf = "../models/arm7.urdf", outputs = [frames], frames = [link7, link4, base])]
struct Arm7;

#[derive(Chain)]
#[chain(urdf = "../models/tree.urdf", outputs = [frames], frames = [left2, right1, head, torso])]
struct Tree;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [frames],
    frames = [left_foot, right_foot, left_hand, right_hand, camera, imu, pelvis]
)]
struct HumanoidQuat;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating,
    outputs = [frames],
    frames = [left_foot, right_hand, camera]
)]
struct HumanoidEuler;

#[derive(Chain)]
#[chain(file = "../models/falling_cat.chain", outputs = [frames], frames = [front, rear])]
struct FallingCat;

#[derive(Chain)]
#[chain(file = "../models/two_link.chain", outputs = [frames], frames = [legs, trunk])]
struct TwoLink;

#[derive(Chain)]
#[chain(
    urdf = "data/gripper_mimic.urdf",
    outputs = [frames],
    frames = [left_tip, right_tip, thumb, palm]
)]
struct Gripper;

// A declared frame turned every way, on a quaternion joint, in three scalars.
articulated::chain! {
    chain Wand {
        outputs: [frames];
        frames: [tip, grip, fixed_in_world];
        body stick { mass: 1.0, com: [0.0, 0.0, -0.4], inertia: diag(0.05, 0.05, 0.001) }
        body end { mass: 0.2, com: [0.0, 0.0, -0.1], inertia: diag(0.001, 0.001, 0.0001) }
        joint ball: spherical(quaternion) { parent: world, child: stick, xyz: [0.1, -0.2, 1.0] }
        joint slide: prismatic([0.0, 0.6, -0.8]) { parent: stick, child: end, xyz: [0.0, 0.0, -0.8] }
        frame tip { parent: end, xyz: [0.03, -0.02, -0.25], rpy: [0.4, -1.1, 2.5] }
        frame grip { parent: stick, xyz: [0.0, 0.05, -0.3], rpy: [-0.7, 0.2, 0.9] }
        frame fixed_in_world { parent: world, xyz: [1.0, 2.0, 3.0], rpy: [0.1, 0.2, 0.3] }
    }
}

articulated::chain! {
    chain WandF32 {
        scalar: f32;
        outputs: [frames];
        frames: [tip, grip];
        body stick { mass: 1.0, com: [0.0, 0.0, -0.4], inertia: diag(0.05, 0.05, 0.001) }
        body end { mass: 0.2, com: [0.0, 0.0, -0.1], inertia: diag(0.001, 0.001, 0.0001) }
        joint ball: spherical(quaternion) { parent: world, child: stick, xyz: [0.1, -0.2, 1.0] }
        joint slide: prismatic([0.0, 0.6, -0.8]) { parent: stick, child: end, xyz: [0.0, 0.0, -0.8] }
        frame tip { parent: end, xyz: [0.03, -0.02, -0.25], rpy: [0.4, -1.1, 2.5] }
        frame grip { parent: stick, xyz: [0.0, 0.05, -0.3], rpy: [-0.7, 0.2, 0.9] }
    }
}

articulated::chain! {
    chain WandGeneric {
        scalar: generic;
        outputs: [frame_placements, frame_jacobians_local];
        frames: [tip];
        body stick { mass: 1.0, com: [0.0, 0.0, -0.4], inertia: diag(0.05, 0.05, 0.001) }
        body end { mass: 0.2, com: [0.0, 0.0, -0.1], inertia: diag(0.001, 0.001, 0.0001) }
        joint ball: spherical(quaternion) { parent: world, child: stick, xyz: [0.1, -0.2, 1.0] }
        joint slide: prismatic([0.0, 0.6, -0.8]) { parent: stick, child: end, xyz: [0.0, 0.0, -0.8] }
        frame tip { parent: end, xyz: [0.03, -0.02, -0.25], rpy: [0.4, -1.1, 2.5] }
    }
}

/// The difference relative to the largest entry of `theirs`, or absolute below 1.
fn err(ours: &[f64], theirs: &[f64]) -> f64 {
    abs_err(ours, theirs) / max_abs(theirs).max(1.0)
}

/// The model a chain was generated from.
fn model(file: &str, floating: FloatingBase) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    load_model(&path, floating).unwrap_or_else(|e| panic!("{e}"))
}

/// A matrix's entries row by row.
fn rows<const R: usize, const C: usize>(m: &articulated::nalgebra::SMatrix<f64, R, C>) -> Vec<f64> {
    (0..R)
        .flat_map(|i| (0..C).map(move |j| m[(i, j)]))
        .collect()
}

fn dense_rows(m: &articulated::nalgebra::DMatrix<f64>) -> Vec<f64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
        .collect()
}

/// Every frame output of `C` against the reference at 16 random states; the worst error.
fn check<C, const NQ: usize, const NV: usize, const NF: usize>(label: &str, model: &Model) -> f64
where
    C: FramePlacements<f64, NQ, NV, NF>
        + FrameVelocities<f64, NQ, NV, NF>
        + FrameAccelerations<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
        + FrameJacobiansWorld<f64, NQ, NV, NF>
        + FrameJacobiansLocalWorldAligned<f64, NQ, NV, NF>
        + FrameJacobianTimeVariationsLocal<f64, NQ, NV, NF>
        + FrameJacobianTimeVariationsWorld<f64, NQ, NV, NF>
        + FrameJacobianTimeVariationsLocalWorldAligned<f64, NQ, NV, NF>,
{
    let r = Reference::new(model).unwrap();
    assert_eq!(C::FRAMES.len(), NF);
    let mut worst = 0.0f64;
    for seed in 0..16 {
        let (q, v, a) = random_state(model, seed);
        let (qs, vs, as_) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NV>::from_column_slice(&v),
            SVector::<f64, NV>::from_column_slice(&a),
        );
        let placements = C::frame_placements(&qs);
        let velocities = C::frame_velocities(&qs, &vs);
        let accelerations = C::frame_accelerations(&qs, &vs, &as_);
        let jacobians = [
            C::frame_jacobians_local(&qs),
            C::frame_jacobians_world(&qs),
            C::frame_jacobians_local_world_aligned(&qs),
        ];
        let rates = [
            C::frame_jacobian_time_variations_local(&qs, &vs),
            C::frame_jacobian_time_variations_world(&qs, &vs),
            C::frame_jacobian_time_variations_local_world_aligned(&qs, &vs),
        ];
        for (k, &name) in C::FRAMES.iter().enumerate() {
            let (rot, pos) = r.frame_placement(&q, name).unwrap();
            let mut errors = vec![
                ("rotation", err(&rows(&placements[k].rotation), &rows(&rot))),
                (
                    "translation",
                    err(placements[k].translation.as_slice(), pos.as_slice()),
                ),
                (
                    "velocity",
                    err(
                        velocities[k].as_slice(),
                        r.frame_velocity(&q, &v, name).unwrap().as_slice(),
                    ),
                ),
                (
                    "acceleration",
                    err(
                        accelerations[k].as_slice(),
                        r.frame_acceleration(&q, &v, &a, name).unwrap().as_slice(),
                    ),
                ),
            ];
            for (i, frame) in [
                ReferenceFrame::Local,
                ReferenceFrame::World,
                ReferenceFrame::LocalWorldAligned,
            ]
            .into_iter()
            .enumerate()
            {
                let j = r.frame_jacobian(&q, name, frame).unwrap();
                let dj = r
                    .frame_jacobian_time_variation(&q, &v, name, frame)
                    .unwrap();
                errors.push(("jacobian", err(&rows(&jacobians[i][k]), &dense_rows(&j))));
                errors.push(("rate", err(&rows(&rates[i][k]), &dense_rows(&dj))));
            }
            for (what, e) in errors {
                assert!(
                    e < TOL,
                    "{label}, frame `{name}`, seed {seed}: {what} off by {e:.1e}"
                );
                worst = worst.max(e);
            }
        }
    }
    println!("{label}: worst error {worst:.1e}");
    worst
}

#[test]
fn generated_frames_agree_with_the_reference() {
    let fixed = FloatingBase::Fixed;
    check::<Arm7, 7, 7, 3>("arm7", &model("../models/arm7.urdf", fixed));
    check::<Tree, { Tree::NQ }, { Tree::NV }, 4>("tree", &model("../models/tree.urdf", fixed));
    check::<HumanoidQuat, { HumanoidQuat::NQ }, { HumanoidQuat::NV }, 7>(
        "humanoid, quaternion base",
        &model("../models/humanoid.urdf", FloatingBase::Quaternion),
    );
    check::<HumanoidEuler, { HumanoidEuler::NQ }, { HumanoidEuler::NV }, 3>(
        "humanoid, Euler base",
        &model("../models/humanoid.urdf", FloatingBase::Euler),
    );
    check::<FallingCat, 10, 9, 2>("falling cat", &model("../models/falling_cat.chain", fixed));
    check::<TwoLink, 6, 6, 2>("two-link", &model("../models/two_link.chain", fixed));
    check::<Gripper, { Gripper::NQ }, { Gripper::NV }, 4>(
        "gripper (mimic)",
        &model("data/gripper_mimic.urdf", fixed),
    );
    let wand = articulated_codegen::load::parse_chain_str(WAND, Path::new("wand.chain"))
        .unwrap()
        .model;
    check::<Wand, 5, 4, 3>("wand", &wand);
}

/// The wand's description, for the reference (the same text as `Wand`'s).
const WAND: &str = r#"chain Wand {
    body stick { mass: 1.0, com: [0.0, 0.0, -0.4], inertia: diag(0.05, 0.05, 0.001) }
    body end { mass: 0.2, com: [0.0, 0.0, -0.1], inertia: diag(0.001, 0.001, 0.0001) }
    joint ball: spherical(quaternion) { parent: world, child: stick, xyz: [0.1, -0.2, 1.0] }
    joint slide: prismatic([0.0, 0.6, -0.8]) { parent: stick, child: end, xyz: [0.0, 0.0, -0.8] }
    frame tip { parent: end, xyz: [0.03, -0.02, -0.25], rpy: [0.4, -1.1, 2.5] }
    frame grip { parent: stick, xyz: [0.0, 0.05, -0.3], rpy: [-0.7, 0.2, 0.9] }
    frame fixed_in_world { parent: world, xyz: [1.0, 2.0, 3.0], rpy: [0.1, 0.2, 0.3] }
}"#;

#[test]
fn f32_and_generic_frames_agree_with_f64() {
    let wand = articulated_codegen::load::parse_chain_str(WAND, Path::new("wand.chain"))
        .unwrap()
        .model;
    let mut worst = 0.0f64;
    for seed in 0..16 {
        let (q, v, a) = random_state(&wand, seed);
        let q64 = SVector::<f64, 5>::from_column_slice(&q);
        let (v64, a64) = (
            SVector::<f64, 4>::from_column_slice(&v),
            SVector::<f64, 4>::from_column_slice(&a),
        );
        let (q32, v32, a32) = (q64.cast::<f32>(), v64.cast::<f32>(), a64.cast::<f32>());
        let widen = |x: &[f32]| x.iter().map(|&x| f64::from(x)).collect::<Vec<f64>>();
        for k in 0..2 {
            let p32 = WandF32::frame_placements(&q32)[k];
            let p64 = Wand::frame_placements(&q64)[k];
            worst = worst.max(err(
                &widen(p32.translation.as_slice()),
                p64.translation.as_slice(),
            ));
            let j32 = WandF32::frame_jacobians_local_world_aligned(&q32)[k];
            let j64 = Wand::frame_jacobians_local_world_aligned(&q64)[k];
            worst = worst.max(err(&widen(j32.as_slice()), j64.as_slice()));
            let acc32 = WandF32::frame_accelerations(&q32, &v32, &a32)[k];
            let acc64 = Wand::frame_accelerations(&q64, &v64, &a64)[k];
            worst = worst.max(err(&widen(acc32.as_slice()), acc64.as_slice()));
        }
        let g = WandGeneric::frame_jacobians_local(&q64)[0];
        assert_eq!(
            g,
            Wand::frame_jacobians_local(&q64)[0],
            "generic = f64 exactly"
        );
        let gp = WandGeneric::frame_placements(&q64)[0];
        assert_eq!(gp, Wand::frame_placements(&q64)[0]);
    }
    println!("f32 against f64: worst {worst:.1e}");
    assert!(worst < 1e-5, "{worst}");
}

/// The generator's frame graphs (`trace::frames`, what the generated code computes, evaluated
/// in f64 without compiling it) against the reference on random trees of 2 to 30 bodies with
/// every joint kind (`random_model`), for five frames each: bodies, and frames with random
/// placements on random bodies and on the world.
#[test]
fn frame_graphs_agree_with_the_reference_on_random_trees() {
    use articulated_codegen::options::Output;
    use articulated_codegen::sym::Var;
    use articulated_codegen::trace::frames::{trace, FrameAt};
    use articulated_dynamics::model::{Frame, Placement, Value};
    use articulated_dynamics::random::Rng;
    let mut worst = 0.0f64;
    for (seed, n) in [(0, 2), (3, 3), (7, 4), (11, 8), (5, 30), (21, 12), (42, 17)] {
        let mut model = articulated_dynamics::random::random_model(seed, n);
        let mut rng = Rng::new(seed + 100);
        let mut c = |r: f64| Value::Const(rng.symmetric(r));
        for k in 0..3 {
            let parent = (k < 2).then(|| (seed as usize * 7 + k * 5) % n);
            model.frames.push(Frame {
                name: format!("extra{k}"),
                parent,
                placement: Placement {
                    xyz: [c(0.3), c(0.3), c(0.3)],
                    rpy: [c(3.0), c(1.5), c(3.0)],
                },
            });
        }
        let names: Vec<String> = [
            model.bodies[0].name.clone(),
            model.bodies[n - 1].name.clone(),
        ]
        .into_iter()
        .chain((0..3).map(|k| format!("extra{k}")))
        .collect();
        let frames: Vec<FrameAt> = names
            .iter()
            .map(|name| {
                let (parent, placement) = model.frame(name).unwrap();
                FrameAt {
                    name: name.clone(),
                    parent,
                    placement,
                }
            })
            .collect();
        let r = Reference::new(&model).unwrap();
        let nv = model.nv();
        for state in 0..3 {
            let (q, v, a) = random_state(&model, seed * 10 + state);
            let input = |var: Var| match var {
                Var::Q(i) => q[i],
                Var::V(i) => v[i],
                Var::A(i) => a[i],
                _ => f64::NAN,
            };
            let values = |o: Output| trace(&model, o, &frames, false).eval(input).0;
            let jacobian_outputs = [
                (
                    Output::FrameJacobiansLocal,
                    Output::FrameJacobianTimeVariationsLocal,
                ),
                (
                    Output::FrameJacobiansWorld,
                    Output::FrameJacobianTimeVariationsWorld,
                ),
                (
                    Output::FrameJacobiansLocalWorldAligned,
                    Output::FrameJacobianTimeVariationsLocalWorldAligned,
                ),
            ];
            let (placements, velocities, accelerations) = (
                values(Output::FramePlacements),
                values(Output::FrameVelocities),
                values(Output::FrameAccelerations),
            );
            let jacobians: Vec<(Vec<f64>, Vec<f64>)> = jacobian_outputs
                .iter()
                .map(|&(j, dj)| (values(j), values(dj)))
                .collect();
            for (k, name) in names.iter().enumerate() {
                let (rot, pos) = r.frame_placement(&q, name).unwrap();
                let expected: Vec<f64> =
                    rows(&rot).into_iter().chain(pos.iter().copied()).collect();
                let mut e = err(&placements[12 * k..12 * (k + 1)], &expected);
                let vel = r.frame_velocity(&q, &v, name).unwrap();
                e = e.max(err(&velocities[6 * k..6 * (k + 1)], vel.as_slice()));
                let acc = r.frame_acceleration(&q, &v, &a, name).unwrap();
                e = e.max(err(&accelerations[6 * k..6 * (k + 1)], acc.as_slice()));
                for (i, frame) in [
                    ReferenceFrame::Local,
                    ReferenceFrame::World,
                    ReferenceFrame::LocalWorldAligned,
                ]
                .into_iter()
                .enumerate()
                {
                    let size = 6 * nv;
                    let j = dense_rows(&r.frame_jacobian(&q, name, frame).unwrap());
                    let dj = dense_rows(
                        &r.frame_jacobian_time_variation(&q, &v, name, frame)
                            .unwrap(),
                    );
                    e = e.max(err(&jacobians[i].0[size * k..size * (k + 1)], &j));
                    e = e.max(err(&jacobians[i].1[size * k..size * (k + 1)], &dj));
                }
                assert!(
                    e < TOL,
                    "random tree {seed} ({n} bodies), `{name}`: off by {e:.1e}"
                );
                worst = worst.max(e);
            }
        }
    }
    println!("random trees: worst {worst:.1e}");
}

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [frame_velocity_derivatives, frame_acceleration_derivatives],
    frames = [left_foot, right_hand]
)]
struct HumanoidDerivatives;

#[derive(Chain)]
#[chain(
    urdf = "data/gripper_mimic.urdf",
    outputs = [frame_velocity_derivatives, frame_acceleration_derivatives],
    frames = [left_tip, thumb]
)]
struct GripperDerivatives;

/// The derivatives of the frames' LOCAL velocities and classical accelerations against central
/// differences of the reference's values along the configuration's tangent (`q ⊕ ε·e_k`,
/// `articulated::configuration`, the same increment as the dynamics' derivatives) and along
/// `v`; `∂v/∂v` and `∂α/∂a` against the reference's Jacobians. The worst error.
fn check_derivatives<C, const NQ: usize, const NV: usize, const NF: usize>(
    label: &str,
    model: &Model,
) -> f64
where
    C: FrameVelocityDerivatives<f64, NQ, NV, NF> + FrameAccelerationDerivatives<f64, NQ, NV, NF>,
{
    let r = Reference::new(model).unwrap();
    let coords = articulated::interpreted::coordinates_of(model);
    let h = 1e-6;
    let mut worst = 0.0f64;
    for seed in 0..4 {
        let (q, v, a) = random_state(model, seed);
        let (qs, vs, as_) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NV>::from_column_slice(&v),
            SVector::<f64, NV>::from_column_slice(&a),
        );
        let vel = C::frame_velocity_derivatives(&qs, &vs);
        let acc = C::frame_acceleration_derivatives(&qs, &vs, &as_);
        for (k, &name) in C::FRAMES.iter().enumerate() {
            // Column by column: ∂/∂q_j by central differences along the tangent, ∂/∂v_j too.
            let (mut vq, mut aq, mut vv, mut av) = (
                vec![0.0; 6 * NV],
                vec![0.0; 6 * NV],
                vec![0.0; 6 * NV],
                vec![0.0; 6 * NV],
            );
            for j in 0..NV {
                let moved = |s: f64| {
                    let mut qq = q.clone();
                    let mut d = vec![0.0; NV];
                    d[j] = s * h;
                    articulated::configuration::integrate_in_place(&coords, &mut qq, &d);
                    qq
                };
                let (qp, qm) = (moved(1.0), moved(-1.0));
                let mut vp = v.clone();
                let mut vm = v.clone();
                vp[j] += h;
                vm[j] -= h;
                let fv = |q: &[f64], v: &[f64]| r.frame_velocity(q, v, name).unwrap();
                let fa = |q: &[f64], v: &[f64]| r.frame_acceleration(q, v, &a, name).unwrap();
                for i in 0..6 {
                    vq[i * NV + j] = (fv(&qp, &v)[i] - fv(&qm, &v)[i]) / (2.0 * h);
                    aq[i * NV + j] = (fa(&qp, &v)[i] - fa(&qm, &v)[i]) / (2.0 * h);
                    vv[i * NV + j] = (fv(&q, &vp)[i] - fv(&q, &vm)[i]) / (2.0 * h);
                    av[i * NV + j] = (fa(&q, &vp)[i] - fa(&q, &vm)[i]) / (2.0 * h);
                }
            }
            let j_local = dense_rows(&r.frame_jacobian(&q, name, ReferenceFrame::Local).unwrap());
            let j_lwa = dense_rows(
                &r.frame_jacobian(&q, name, ReferenceFrame::LocalWorldAligned)
                    .unwrap(),
            );
            let (dv_dq, dv_dv) = vel[k];
            let (da_dq, da_dv, da_da) = acc[k];
            let fd = [
                ("∂v/∂q", err(&rows(&dv_dq), &vq), 1e-6),
                ("∂v/∂v (differences)", err(&rows(&dv_dv), &vv), 1e-6),
                ("∂α/∂q", err(&rows(&da_dq), &aq), 1e-6),
                ("∂α/∂v", err(&rows(&da_dv), &av), 1e-6),
                ("∂v/∂v = J_local", err(&rows(&dv_dv), &j_local), TOL),
                ("∂α/∂a = J_lwa", err(&rows(&da_da), &j_lwa), TOL),
            ];
            for (what, e, tol) in fd {
                assert!(
                    e < tol,
                    "{label} `{name}` seed {seed}: {what} off by {e:.1e}"
                );
                worst = worst.max(e);
            }
        }
    }
    println!("{label}: derivatives' worst error {worst:.1e}");
    worst
}

#[test]
fn frame_derivatives_agree_with_finite_differences() {
    check_derivatives::<
        HumanoidDerivatives,
        { HumanoidDerivatives::NQ },
        { HumanoidDerivatives::NV },
        2,
    >(
        "humanoid, quaternion base",
        &model("../models/humanoid.urdf", FloatingBase::Quaternion),
    );
    check_derivatives::<
        GripperDerivatives,
        { GripperDerivatives::NQ },
        { GripperDerivatives::NV },
        2,
    >(
        "gripper (mimic)",
        &model("data/gripper_mimic.urdf", FloatingBase::Fixed),
    );
}
