//! The reference's frames (`reference::frames`) against what can be computed without them, on
//! random trees of up to 30 bodies with every joint kind (free Euler and quaternion bases,
//! Euler and quaternion spherical joints, fixed joints), with frames added at random placements
//! on random bodies and on the world, with and without mimic joints:
//! - central finite differences (`h = 1e-6`, configurations moved along the tangent by
//!   `common::integrate`, the body-frame increment for quaternions): the LOCAL Jacobian against
//!   `log6(M(q)⁻¹·M(q ⊕ h·eᵢ))/h`, `J̇` in each reference frame against
//!   `(J(q ⊕ h·v) − J(q ⊖ h·v))/2h`, the classical acceleration against the derivative of the
//!   LOCAL_WORLD_ALIGNED velocity and the spatial one against that of the LOCAL velocity, along
//!   `(q ⊕ t·v, v + t·a)`;
//! - identities: `J_local·v` is the frame velocity, the classical acceleration is
//!   `J_lwa·a + J̇_lwa·v` and the spatial one `J_local·a + J̇_local·v`, they differ by
//!   `[0; ω × v]` in LOCAL axes, WORLD is `Ad(⁰M_f)` of LOCAL and LOCAL_WORLD_ALIGNED its
//!   rotation, for `J` and (differentiated) for `J̇`;
//! - mimic joints: a model with them is its independent tree at `q_tree = G·q + o` (`G` and `o`
//!   written here from the `Mimic`s), with `J = J_tree·G` and `J̇ = J̇_tree·G`;
//! - the centre-of-mass Jacobian (`Reference::center_of_mass_jacobian`, another code path) as
//!   the mass-weighted mean of the linear rows of each body's LOCAL_WORLD_ALIGNED Jacobian at
//!   its centre of mass;
//! - closed forms: a planar two-link arm's tip, and the URDF roll-pitch-yaw of a placement
//!   against nalgebra's Euler angles.

mod common;

use std::f64::consts::PI;

use articulated_dynamics::model::{Frame, JointKind, Mimic, Model, Placement, Value};
use articulated_dynamics::random::{random_model, random_state, Rng};
use articulated_dynamics::reference::{Error, Reference, ReferenceFrame};
use common::{body, diag, integrate, joint, model, rel_err_mat};
use nalgebra::{DMatrix, Matrix3, Matrix6, Rotation3, Vector3, Vector6};
use proptest::prelude::*;

/// Finite-difference step.
const H: f64 = 1e-6;
/// Central differences against the reference: truncation `~h²`, rounding `~ε/h ≈ 1e-10`.
const FD_TOL: f64 = 1e-7;
/// Identities between the reference's own values: rounding only.
const TOL: f64 = 1e-12;

/// The largest entry's error, relative to the largest entry of `b` with a floor of 1.
fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    rel_err_mat(a, b, 1.0)
}

fn col(x: Vector6<f64>) -> DMatrix<f64> {
    DMatrix::from_column_slice(6, 1, x.as_slice())
}

fn c(x: f64) -> Value {
    Value::Const(x)
}

/// `model` with a few frames added: about one body in three gets one at a random placement, and
/// one sits on the world. Named `extra{k}`.
fn with_frames(mut model: Model, seed: u64) -> Model {
    let mut rng = Rng::new(seed ^ 0xF7A3_E500);
    let mut parents: Vec<Option<usize>> = (0..model.nb())
        .filter(|_| rng.below(3) == 0)
        .map(Some)
        .collect();
    parents.push(None);
    for (k, parent) in parents.into_iter().enumerate() {
        model.frames.push(Frame {
            name: format!("extra{k}"),
            parent,
            placement: Placement {
                xyz: [0; 3].map(|_| c(rng.range(-0.5, 0.5))),
                rpy: [0; 3].map(|_| c(rng.range(-PI, PI))),
            },
        });
    }
    model
}

/// `model` with about half of its revolute and prismatic joints following another one (as in
/// `tests/tests/mimic_random.rs`).
fn with_mimics(mut model: Model, seed: u64) -> Model {
    let mut rng = Rng::new(seed);
    let one_axis: Vec<usize> = (0..model.nb())
        .filter(|&i| model.joints[i].kind.has_one_axis())
        .collect();
    let mut leaders: Vec<usize> = Vec::new();
    for &f in &one_axis {
        if rng.below(2) != 0 || leaders.contains(&f) {
            continue;
        }
        let free: Vec<usize> = one_axis
            .iter()
            .copied()
            .filter(|&l| l != f && model.joints[l].mimic.is_none())
            .collect();
        if free.is_empty() {
            continue;
        }
        let l = free[rng.below(free.len())];
        let sign = if rng.below(2) == 0 { -1.0 } else { 1.0 };
        model.joints[f].mimic = Some(Mimic {
            joint: l,
            multiplier: sign * rng.range(0.2, 2.0),
            offset: rng.range(-0.5, 0.5),
        });
        leaders.push(l);
    }
    model
}

/// A random tree with extra frames, mimic joints if asked.
fn random_case(seed: u64, n: usize, mimic: bool) -> Model {
    let m = random_model(seed, n);
    let m = if mimic { with_mimics(m, seed) } else { m };
    with_frames(m, seed)
}

fn names(model: &Model) -> Vec<String> {
    model.frame_names().map(String::from).collect()
}

/// `[ω]×`.
fn hat(w: Vector3<f64>) -> Matrix3<f64> {
    w.cross_matrix()
}

/// The rotation vector of `r` (its angle below π).
fn log3(r: &Matrix3<f64>) -> Vector3<f64> {
    let axis = 0.5
        * Vector3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        );
    let s = axis.norm();
    let theta = s.atan2(0.5 * (r.trace() - 1.0));
    if s < 1e-300 {
        return Vector3::zeros();
    }
    axis * (theta / s)
}

/// `log6` of the rigid motion `(r, p)`: the twist `[ω; v]` (angular first) with
/// `exp([ω; v]) = (r, p)`: `ω = log3(r)`, `v = V(ω)⁻¹·p`,
/// `V⁻¹ = 1 − ½[ω]× + (1 − θ·sin θ / (2(1 − cos θ)))/θ²·[ω]×²`.
fn log6(r: &Matrix3<f64>, p: &Vector3<f64>) -> Vector6<f64> {
    let w = log3(r);
    let theta = w.norm();
    let k = if theta < 1e-4 {
        1.0 / 12.0 + theta * theta / 720.0
    } else {
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / (theta * theta)
    };
    let wx = hat(w);
    let v = (Matrix3::identity() - 0.5 * wx + k * wx * wx) * p;
    Vector6::new(w[0], w[1], w[2], v[0], v[1], v[2])
}

/// `Ad(⁰M_f) = [R 0; p̂·R R]`: LOCAL to WORLD.
fn adjoint(r: &Matrix3<f64>, p: &Vector3<f64>) -> Matrix6<f64> {
    let mut ad = Matrix6::zeros();
    ad.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    ad.fixed_view_mut::<3, 3>(3, 3).copy_from(r);
    ad.fixed_view_mut::<3, 3>(3, 0).copy_from(&(hat(*p) * r));
    ad
}

/// `diag(R, R)`: LOCAL to LOCAL_WORLD_ALIGNED.
fn rotation6(r: &Matrix3<f64>) -> Matrix6<f64> {
    adjoint(r, &Vector3::zeros())
}

/// The motion cross product `m ×m` as a matrix, `[ω̂ 0; v̂ ω̂]`.
fn crm(m: &Vector6<f64>) -> Matrix6<f64> {
    let (w, v) = (m.fixed_rows::<3>(0).into(), m.fixed_rows::<3>(3).into());
    let mut x = Matrix6::zeros();
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(w));
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(&hat(w));
    x.fixed_view_mut::<3, 3>(3, 0).copy_from(&hat(v));
    x
}

fn m6(x: Matrix6<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| x[(i, j)])
}

fn unit(n: usize, k: usize) -> Vec<f64> {
    (0..n).map(|i| if i == k { 1.0 } else { 0.0 }).collect()
}

fn axpy(x: &[f64], t: f64, d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(x, d)| x + t * d).collect()
}

/// The worst errors of one model at one state, over every frame, in the order of [`CHECKS`].
const CHECKS: [&str; 8] = [
    "J_local vs log6 differences",
    "dJ vs differences of J",
    "classical acceleration vs d/dt of the LWA velocity",
    "spatial acceleration vs d/dt of the LOCAL velocity",
    "J_local·v = velocity",
    "accelerations = J·a + dJ·v",
    "WORLD, LWA from LOCAL (J and dJ)",
    "classical − spatial = [0; ω × v]",
];

fn errors(model: &Model, seed: u64) -> [f64; 8] {
    let r = Reference::new(model).unwrap();
    let (q, v, a) = random_state(model, seed);
    let nv = model.nv();
    let mut e = [0.0f64; 8];
    let mut note = |k: usize, x: f64| {
        e[k] = if x.is_nan() {
            f64::INFINITY
        } else {
            e[k].max(x)
        }
    };
    for name in names(model) {
        let f = name.as_str();
        let (rot, p) = r.frame_placement(&q, f).unwrap();
        let jac = |q: &[f64], rf| r.frame_jacobian(q, f, rf).unwrap();
        let jdot = |rf| r.frame_jacobian_time_variation(&q, &v, f, rf).unwrap();
        let (j_l, j_w, j_a) = (
            jac(&q, ReferenceFrame::Local),
            jac(&q, ReferenceFrame::World),
            jac(&q, ReferenceFrame::LocalWorldAligned),
        );
        let (jd_l, jd_w, jd_a) = (
            jdot(ReferenceFrame::Local),
            jdot(ReferenceFrame::World),
            jdot(ReferenceFrame::LocalWorldAligned),
        );

        // LOCAL Jacobian: log6(M(q)⁻¹·M(q ⊕ h·eᵢ)) / h, central.
        let twist = |t: f64, k: usize| {
            let (rk, pk) = r
                .frame_placement(&integrate(model, &q, &unit(nv, k), t), f)
                .unwrap();
            log6(&(rot.transpose() * rk), &(rot.transpose() * (pk - p)))
        };
        let fd = DMatrix::from_fn(6, nv, |i, k| (twist(H, k)[i] - twist(-H, k)[i]) / (2.0 * H));
        note(0, rel(&j_l, &fd));

        // J̇ = (J(q ⊕ h·v) − J(q ⊖ h·v)) / 2h, in each reference frame.
        let (qp, qm) = (integrate(model, &q, &v, H), integrate(model, &q, &v, -H));
        for (rf, jd) in [
            (ReferenceFrame::Local, &jd_l),
            (ReferenceFrame::World, &jd_w),
            (ReferenceFrame::LocalWorldAligned, &jd_a),
        ] {
            let fd = (jac(&qp, rf) - jac(&qm, rf)) / (2.0 * H);
            note(1, rel(jd, &fd));
        }

        // Accelerations: d/dt of the velocity along (q ⊕ t·v, v + t·a).
        let vel = |t: f64| {
            let (qt, vt) = (integrate(model, &q, &v, t), axpy(&v, t, &a));
            let local = r.frame_velocity(&qt, &vt, f).unwrap();
            let (rt, _) = r.frame_placement(&qt, f).unwrap();
            (local, rotation6(&rt) * local)
        };
        let ((lp, ap), (lm, am)) = (vel(H), vel(-H));
        let classical = r.frame_acceleration(&q, &v, &a, f).unwrap();
        let spatial = r.frame_spatial_acceleration(&q, &v, &a, f).unwrap();
        note(2, rel(&col(classical), &col((ap - am) / (2.0 * H))));
        note(3, rel(&col(spatial), &col((lp - lm) / (2.0 * H))));

        // Identities.
        let (vd, ad) = (
            DMatrix::from_column_slice(nv, 1, &v),
            DMatrix::from_column_slice(nv, 1, &a),
        );
        let velocity = r.frame_velocity(&q, &v, f).unwrap();
        note(4, rel(&(&j_l * &vd), &col(velocity)));
        note(5, rel(&(&j_a * &ad + &jd_a * &vd), &col(classical)));
        note(5, rel(&(&j_l * &ad + &jd_l * &vd), &col(spatial)));
        let (ad_f, rot6) = (m6(adjoint(&rot, &p)), m6(rotation6(&rot)));
        let w = Vector3::new(velocity[0], velocity[1], velocity[2]);
        let spin = m6(rotation6(&hat(w)));
        // d/dt(Ad·J_l) = Ad·(J̇_l + v_f ×m J_l); d/dt(Rot·J_l) = Rot·(J̇_l + diag(ω̂, ω̂)·J_l).
        for (x, y) in [
            (&j_w, &ad_f * &j_l),
            (&j_a, &rot6 * &j_l),
            (&jd_w, &ad_f * (&jd_l + m6(crm(&velocity)) * &j_l)),
            (&jd_a, &rot6 * (&jd_l + spin * &j_l)),
        ] {
            note(6, rel(x, &y));
        }
        let lin = Vector3::new(velocity[3], velocity[4], velocity[5]);
        let classical_local = rotation6(&rot).transpose() * classical;
        let wv = w.cross(&lin);
        let expected = spatial + Vector6::new(0.0, 0.0, 0.0, wv[0], wv[1], wv[2]);
        note(7, rel(&col(classical_local), &col(expected)));
    }
    e
}

fn check(model: &Model, seed: u64) -> Result<(), String> {
    let e = errors(model, seed);
    for (k, (what, x)) in CHECKS.iter().zip(e).enumerate() {
        let bound = if k < 4 { FD_TOL } else { TOL };
        if x.is_nan() || x > bound {
            return Err(format!("{what}: off by {x:e} (bound {bound:e})"));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Every frame of random trees up to 30 bodies, mimic joints or not, against central
    /// differences (1e-7 relative) and the identities (1e-12).
    #[test]
    fn frames_match_differences_and_identities(
        seed in any::<u64>(),
        n in 1usize..=30,
        mimic in any::<bool>(),
    ) {
        let model = random_case(seed, n, mimic);
        let result = check(&model, seed);
        prop_assert!(result.is_ok(), "seed {seed}, n {n}, mimic {mimic}: {}", result.unwrap_err());
    }
}

/// The worst error of each check over fixed trees, printed (`-- --nocapture`).
#[test]
fn worst_errors_over_fixed_trees() {
    let mut worst = [0.0f64; 8];
    let mut frames = 0;
    for (seed, n) in [(1u64, 2usize), (2, 5), (3, 9), (4, 14), (5, 20), (6, 30)] {
        for mimic in [false, true] {
            let model = random_case(seed, n, mimic);
            frames += names(&model).len();
            for (w, e) in worst.iter_mut().zip(errors(&model, seed)) {
                *w = w.max(e);
            }
            check(&model, seed).unwrap_or_else(|e| panic!("seed {seed}, n {n}: {e}"));
        }
    }
    println!("{frames} frames on 12 random trees:");
    for (what, e) in CHECKS.iter().zip(worst) {
        println!("  {what:<52} {e:.1e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// `J_G = (1/m)·Σ m_k·J_lwa(com_k)[3..6]`: the centre of mass Jacobian from each body's
    /// LOCAL_WORLD_ALIGNED Jacobian at its centre of mass (a frame added there).
    #[test]
    fn the_center_of_mass_jacobian_is_the_mass_weighted_point_jacobians(
        seed in any::<u64>(),
        n in 1usize..=30,
        mimic in any::<bool>(),
    ) {
        let mut model = random_case(seed, n, mimic);
        for (k, b) in model.bodies.clone().iter().enumerate() {
            model.frames.push(Frame {
                name: format!("com{k}"),
                parent: Some(k),
                placement: Placement { xyz: b.com, rpy: [c(0.0); 3] },
            });
        }
        let r = Reference::new(&model).unwrap();
        let (q, _, _) = random_state(&model, seed);
        let mass: f64 = model.bodies.iter().map(|b| b.mass.as_const().unwrap()).sum();
        let mut j_g = DMatrix::zeros(3, model.nv());
        for (k, b) in model.bodies.iter().enumerate() {
            let j = r
                .frame_jacobian(&q, &format!("com{k}"), ReferenceFrame::LocalWorldAligned)
                .unwrap();
            j_g += j.rows(3, 3) * (b.mass.as_const().unwrap() / mass);
        }
        let e = rel(&j_g, &r.center_of_mass_jacobian(&q).unwrap());
        prop_assert!(e < TOL, "seed {seed}, n {n}: {e:e}");
    }
}

/// A planar two-link arm about z, links `l1`, `l2` along x, a frame at the tip: its position
/// `(l1·c1 + l2·c12, l1·s1 + l2·s12, 0)`, the linear rows of `J_lwa` and of `J̇_lwa`, and the
/// classical acceleration, written out.
#[test]
fn a_planar_arm_s_tip_has_its_closed_form() {
    let z = JointKind::Revolute {
        axis: [0.0, 0.0, 1.0],
    };
    let (l1, l2) = (0.7, 0.45);
    let mut m = model(
        vec![
            body("upper", 1.0, [0.3, 0.0, 0.0], diag(0.01, 0.02, 0.03)),
            body("lower", 0.5, [0.2, 0.0, 0.0], diag(0.01, 0.02, 0.03)),
        ],
        vec![
            joint("shoulder", z, None, [0.0; 3], [0.0; 3]),
            joint("elbow", z, Some(0), [l1, 0.0, 0.0], [0.0; 3]),
        ],
    );
    m.frames.push(Frame {
        name: "tip".into(),
        parent: Some(1),
        placement: Placement {
            xyz: [c(l2), c(0.0), c(0.0)],
            rpy: [c(0.0); 3],
        },
    });
    let r = Reference::new(&m).unwrap();
    let (q, v, a): ([f64; 2], [f64; 2], [f64; 2]) = ([0.4, -1.1], [0.8, -0.3], [1.5, 0.7]);
    let (s1, c1) = q[0].sin_cos();
    let (s12, c12) = (q[0] + q[1]).sin_cos();
    let w12 = v[0] + v[1];
    let (_, p) = r.frame_placement(&q, "tip").unwrap();
    let closed_p = Vector3::new(l1 * c1 + l2 * c12, l1 * s1 + l2 * s12, 0.0);
    assert!((p - closed_p).amax() < 1e-15, "{p} vs {closed_p}");
    let jt = DMatrix::from_row_slice(
        3,
        2,
        &[
            -l1 * s1 - l2 * s12,
            -l2 * s12,
            l1 * c1 + l2 * c12,
            l2 * c12,
            0.0,
            0.0,
        ],
    );
    let jt_dot = DMatrix::from_row_slice(
        3,
        2,
        &[
            -l1 * c1 * v[0] - l2 * c12 * w12,
            -l2 * c12 * w12,
            -l1 * s1 * v[0] - l2 * s12 * w12,
            -l2 * s12 * w12,
            0.0,
            0.0,
        ],
    );
    let lwa = ReferenceFrame::LocalWorldAligned;
    let j = r.frame_jacobian(&q, "tip", lwa).unwrap();
    let jd = r.frame_jacobian_time_variation(&q, &v, "tip", lwa).unwrap();
    assert!(rel(&j.rows(3, 3).into(), &jt) < 1e-15);
    assert!(rel(&jd.rows(3, 3).into(), &jt_dot) < 1e-15);
    let angular = DMatrix::from_row_slice(3, 2, &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0]);
    assert_eq!(j.rows(0, 3), angular);
    let acc = r.frame_acceleration(&q, &v, &a, "tip").unwrap();
    let (vd, ad) = (
        DMatrix::from_column_slice(2, 1, &v),
        DMatrix::from_column_slice(2, 1, &a),
    );
    let p_ddot = &jt * &ad + &jt_dot * &vd;
    assert!(
        (acc.fixed_rows::<3>(3) - Vector3::from_column_slice(p_ddot.as_slice())).amax() < 1e-14
    );
    assert!((acc[2] - (a[0] + a[1])).abs() < 1e-15);
}

/// A frame's pose is its body's composed with `(xyz, Rz(yaw)·Ry(pitch)·Rx(roll))`, checked with
/// nalgebra's Euler angles (roll, then pitch, then yaw about the fixed axes), and a frame on the
/// world sits at its placement whatever `q`, with no velocity and a zero Jacobian.
#[test]
fn placements_are_urdf_roll_pitch_yaw() {
    let mut m = random_model(7, 6);
    let (xyz, rpy) = ([0.1, -0.2, 0.3], [0.5, -1.1, 2.4]);
    for (name, parent) in [("on_body", Some(3)), ("on_world", None)] {
        m.frames.push(Frame {
            name: name.into(),
            parent,
            placement: Placement {
                xyz: xyz.map(c),
                rpy: rpy.map(c),
            },
        });
    }
    let r = Reference::new(&m).unwrap();
    let (q, v, a) = random_state(&m, 7);
    let place = Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).into_inner();
    let offset = Vector3::from(xyz);
    let (rb, pb) = r.frame_placement(&q, "body3").unwrap();
    let (rf, pf) = r.frame_placement(&q, "on_body").unwrap();
    assert!((rf - rb * place).amax() < 1e-14);
    assert!((pf - (pb + rb * offset)).amax() < 1e-14);
    let (rw, pw) = r.frame_placement(&q, "on_world").unwrap();
    assert!((rw - place).amax() < 1e-15 && (pw - offset).amax() < 1e-15);
    assert_eq!(
        r.frame_velocity(&q, &v, "on_world").unwrap(),
        Vector6::zeros()
    );
    assert_eq!(
        r.frame_acceleration(&q, &v, &a, "on_world").unwrap(),
        Vector6::zeros()
    );
    for rf in ReferenceFrame::ALL {
        assert_eq!(
            r.frame_jacobian(&q, "on_world", rf).unwrap(),
            DMatrix::zeros(6, m.nv())
        );
    }
}

/// The spatial acceleration is not the classical one: where the frame turns and its origin
/// moves, taking one for the other fails the differences above by far more than their bounds.
#[test]
fn the_spatial_and_classical_accelerations_differ_measurably() {
    let model = random_case(3, 9, false);
    let r = Reference::new(&model).unwrap();
    let (q, v, a) = random_state(&model, 3);
    let f = "body8";
    let (rot, _) = r.frame_placement(&q, f).unwrap();
    let classical = rotation6(&rot).transpose() * r.frame_acceleration(&q, &v, &a, f).unwrap();
    let spatial = r.frame_spatial_acceleration(&q, &v, &a, f).unwrap();
    let gap = rel(&col(classical), &col(spatial));
    println!("classical vs spatial acceleration of {f}: {gap:.2} of the largest entry");
    assert!(gap > 1e-2, "{gap}");
}

#[test]
fn an_unknown_frame_is_an_error_that_names_the_frames() {
    let model = with_frames(random_model(2, 3), 2);
    let r = Reference::new(&model).unwrap();
    let (q, v, _) = random_state(&model, 2);
    assert!(!q.is_empty() && !v.is_empty());
    let e = r
        .frame_jacobian(&q, "gripper", ReferenceFrame::World)
        .unwrap_err();
    assert!(matches!(&e, Error::UnknownFrame { name, .. } if name == "gripper"));
    let text = e.to_string();
    assert!(
        text.contains("`gripper`") && text.contains("`body0`"),
        "{text}"
    );
    assert!(text.contains("`extra0`"), "{text}");
    // Many frames: a dozen are named, and the count.
    let many = with_frames(random_model(2, 30), 2);
    let e = Reference::new(&many)
        .unwrap()
        .frame_placement(&random_state(&many, 2).0, "x");
    let text = e.unwrap_err().to_string();
    assert!(
        text.contains(&format!("({} in all)", names(&many).len())),
        "{text}"
    );
    // Bad states are refused as everywhere else.
    assert!(matches!(
        r.frame_velocity(&q, &v[1..], "body0"),
        Err(Error::Length { vector: "v", .. })
    ));
    let mut nan = q.clone();
    nan[0] = f64::NAN;
    assert!(matches!(
        r.frame_placement(&nan, "body0"),
        Err(Error::NonFinite { vector: "q", .. })
    ));
}

/// The same tree with every joint independent, its `q = G·q + o` and `G` (`nv_tree × nv`),
/// written here from the [`Mimic`]s (not through the reference's `Coupling`).
fn independent(model: &Model, q: &[f64]) -> (Model, Vec<f64>, DMatrix<f64>) {
    let mut tree = model.clone();
    for j in &mut tree.joints {
        j.mimic = None;
    }
    let (mut q_tree, mut at_tree, mut at_model) = (Vec::new(), Vec::new(), Vec::new());
    let (mut t, mut m) = (0, 0);
    for (i, j) in model.joints.iter().enumerate() {
        match j.mimic {
            Some(c) => q_tree.push(c.multiplier * q[model.q_offset(c.joint)] + c.offset),
            None => {
                let at = model.q_offset(i);
                q_tree.extend_from_slice(&q[at..at + j.kind.nq()]);
            }
        }
        at_tree.push(t);
        at_model.push(m);
        t += j.kind.nv();
        m += j.nv();
    }
    let mut g = DMatrix::zeros(t, m);
    for (i, j) in model.joints.iter().enumerate() {
        match j.mimic {
            Some(c) => g[(at_tree[i], at_model[c.joint])] = c.multiplier,
            None => {
                for k in 0..j.kind.nv() {
                    g[(at_tree[i] + k, at_model[i] + k)] = 1.0;
                }
            }
        }
    }
    (tree, q_tree, g)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// A model with mimic joints is its independent tree at `q_tree = G·q + o`,
    /// `v_tree = G·v`, `a_tree = G·a`: the same placements, velocities and accelerations, and
    /// `J = J_tree·G`, `J̇ = J̇_tree·G` in every reference frame.
    #[test]
    fn mimic_frames_are_those_of_the_independent_tree(seed in any::<u64>(), n in 2usize..=30) {
        let model = random_case(seed, n, true);
        let (q, v, a) = random_state(&model, seed);
        let (tree, q_tree, g) = independent(&model, &q);
        let (r, rt) = (Reference::new(&model).unwrap(), Reference::new(&tree).unwrap());
        let along = |x: &[f64]| (&g * DMatrix::from_column_slice(x.len(), 1, x)).as_slice().to_vec();
        let (v_tree, a_tree) = (along(&v), along(&a));
        let mut worst = 0.0f64;
        for name in names(&model) {
            let f = name.as_str();
            let ((rm, pm), (rtr, ptr)) = (
                r.frame_placement(&q, f).unwrap(),
                rt.frame_placement(&q_tree, f).unwrap(),
            );
            worst = worst.max((rm - rtr).amax()).max((pm - ptr).amax());
            let pairs = [
                (r.frame_velocity(&q, &v, f), rt.frame_velocity(&q_tree, &v_tree, f)),
                (
                    r.frame_acceleration(&q, &v, &a, f),
                    rt.frame_acceleration(&q_tree, &v_tree, &a_tree, f),
                ),
            ];
            for (x, y) in pairs {
                worst = worst.max(rel(&col(x.unwrap()), &col(y.unwrap())));
            }
            for rf in ReferenceFrame::ALL {
                let j = rt.frame_jacobian(&q_tree, f, rf).unwrap() * &g;
                worst = worst.max(rel(&r.frame_jacobian(&q, f, rf).unwrap(), &j));
                let jd = rt.frame_jacobian_time_variation(&q_tree, &v_tree, f, rf).unwrap() * &g;
                let ours = r.frame_jacobian_time_variation(&q, &v, f, rf).unwrap();
                worst = worst.max(rel(&ours, &jd));
            }
        }
        prop_assert!(worst < TOL, "seed {seed}, n {n}: off by {worst:e}");
    }
}
