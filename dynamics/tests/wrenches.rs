//! Joint wrenches (the parent on the child, child frame, about the child origin, gravity
//! included) against Newton–Euler equations written from independent kinematics.

mod common;

use articulated_dynamics::model::JointKind;
use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::{jacobian, Reference, Wrench};
use common::*;
use nalgebra::{DVector, Matrix3, Vector3};
use proptest::prelude::*;

fn parts(w: &Wrench) -> (Vector3<f64>, Vector3<f64>) {
    (Vector3::from(w.couple), Vector3::from(w.force))
}

/// One body on a quaternion spherical joint whose joint frame is rotated and offset from the
/// world origin (so the body origin stays put): the joint transmits exactly the body's
/// Newton–Euler wrench minus gravity, `f = m·(a_c − g)` and `n_o = I_c·ω̇ + ω×(I_c·ω) + c×f`,
/// with `a_c = ω̇×c + ω×(ω×c)` (body frame).
#[test]
fn single_body_is_newton_euler() {
    let m = 2.5;
    let i = [
        [0.12, 0.01, 0.02],
        [0.01, 0.09, -0.015],
        [0.02, -0.015, 0.07],
    ];
    let c = [0.1, -0.2, 0.3];
    let rpy = [0.3, -0.5, 1.1];
    let model = model(
        vec![body("b", m, c, i)],
        vec![joint(
            "ball",
            JointKind::SphericalQuaternion,
            None,
            [0.4, 0.5, -0.6],
            rpy,
        )],
    );
    let r = Reference::new(&model).unwrap();
    let quat = [0.9, 0.1, -0.3, 0.2];
    let n = quat.iter().map(|x: &f64| x * x).sum::<f64>().sqrt();
    let quat = quat.map(|x| x / n);
    let (w, wd) = ([0.7, -1.2, 0.4], [1.5, 0.3, -0.8]);
    let ws = r.joint_wrenches(&quat, &w, &wd).unwrap();
    assert_eq!(ws.len(), 1);
    let (couple, force) = parts(&ws[0]);

    let rx = |a: f64| Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), -a.sin(), 0.0, a.sin(), a.cos());
    let ry = |a: f64| Matrix3::new(a.cos(), 0.0, a.sin(), 0.0, 1.0, 0.0, -a.sin(), 0.0, a.cos());
    let rz = |a: f64| Matrix3::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0);
    let rot = rz(rpy[2]) * ry(rpy[1]) * rx(rpy[0]) * quat_rot(quat);
    let g = rot.transpose() * Vector3::new(0.0, 0.0, -9.81);
    let (w, wd, c) = (Vector3::from(w), Vector3::from(wd), Vector3::from(c));
    let ic = Matrix3::from_fn(|r, k| i[r][k]);
    let a_c = wd.cross(&c) + w.cross(&w.cross(&c));
    let f = (a_c - g) * m;
    let n_o = ic * wd + w.cross(&(ic * w)) + c.cross(&f);
    assert!((force - f).amax() < 1e-13 * f.amax(), "{force} vs {f}");
    assert!(
        (couple - n_o).amax() < 1e-13 * n_o.amax(),
        "{couple} vs {n_o}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Every body's wrench balance: what its parent exerts on it, minus what it exerts on its
    /// children (moved to its own origin), equals its Newton–Euler wrench minus gravity, with
    /// accelerations from Wieber's Jacobians `a_c = J_t·a + J̇_t·v`, `ω̇ = J_R·a + J̇_R·v`.
    #[test]
    fn wrench_balance_per_body(seed in any::<u64>(), n in 1usize..=30) {
        let model = random_model(seed, n);
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed ^ 77);
        let ws = r.joint_wrenches(&q, &v, &a).unwrap();
        let bodies = jacobian::body_jacobians(&model, &[], &q, &v).unwrap();
        let (vv, av) = (DVector::from_column_slice(&v), DVector::from_column_slice(&a));
        let g = Vector3::new(0.0, 0.0, -9.81);
        let scale = ws.iter().map(|w| parts(w).0.amax().max(parts(w).1.amax())).fold(1e-300, f64::max);
        for (k, b) in bodies.iter().enumerate() {
            let rk = b.rotation;
            let (mut n_k, mut f_k) = parts(&ws[k]);
            for (c, jc) in model.joints.iter().enumerate() {
                if jc.parent == Some(k) {
                    let (n_c, f_c) = parts(&ws[c]);
                    let r_kc = rk.transpose() * bodies[c].rotation;
                    let d = rk.transpose() * (bodies[c].origin - b.origin);
                    let f = r_kc * f_c;
                    f_k -= f;
                    n_k -= r_kc * n_c + d.cross(&f);
                }
            }
            let a_c = &b.jt * &av + &b.jt_dot * &vv;
            let w = &b.jr * &vv;
            let wd = &b.jr_dot * &vv + &b.jr * &av;
            let (w, wd) = (Vector3::new(w[0], w[1], w[2]), Vector3::new(wd[0], wd[1], wd[2]));
            let f_net = rk.transpose() * (Vector3::new(a_c[0], a_c[1], a_c[2]) - g) * b.mass;
            let c = rk.transpose() * (b.com - b.origin);
            let n_net = b.inertia * wd + w.cross(&(b.inertia * w)) + c.cross(&f_net);
            prop_assert!((f_k - f_net).amax() < 1e-12 * scale, "body {k}: force {f_k} vs {f_net}");
            prop_assert!((n_k - n_net).amax() < 1e-12 * scale, "body {k}: couple {n_k} vs {n_net}");
        }
    }

    /// A free-floating chain with no generalized force on its free base: forward dynamics, then
    /// the wrench through the free joint must vanish (nothing holds the base). Joint wrenches
    /// also project onto the joint torques: `couple·axis = τ` (revolute), `force·axis = τ`
    /// (prismatic).
    #[test]
    fn free_base_transmits_nothing(seed in any::<u64>(), n in 1usize..=30, euler in any::<bool>()) {
        let mut model = random_model(seed, n);
        model.joints[0].kind = if euler {
            JointKind::FreeEuler { seq: articulated_dynamics::model::EulerSeq::ZYX }
        } else {
            JointKind::FreeQuaternion
        };
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let mut tau = a.clone(); // any joint torques
        tau[..6].fill(0.0);
        let qdd = r.forward_dynamics(&q, &v, &tau).unwrap();
        let ws = r.joint_wrenches(&q, &v, qdd.as_slice()).unwrap();
        let weight: f64 = model.bodies.iter().map(|b| b.mass.as_const().unwrap() * 9.81).sum();
        let (n0, f0) = parts(&ws[0]);
        prop_assert!(n0.amax().max(f0.amax()) < 1e-9 * weight, "root wrench {n0} {f0}");
        let mut va = 0;
        for (j, w) in model.joints.iter().zip(&ws) {
            let (nn, ff) = parts(w);
            match j.kind {
                JointKind::Revolute { axis } => prop_assert!((nn.dot(&Vector3::from(axis)) - tau[va]).abs() < 1e-9 * weight),
                JointKind::Prismatic { axis } => prop_assert!((ff.dot(&Vector3::from(axis)) - tau[va]).abs() < 1e-9 * weight),
                _ => {}
            }
            va += j.kind.nv();
        }
    }
}
