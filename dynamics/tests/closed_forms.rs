//! The reference against dynamics written out by hand: a single pendulum, a planar double
//! pendulum (Lagrange), and a free rigid body (Newton–Euler, Hemami et al. 2005, eq. 1).

mod common;

use articulated_dynamics::model::{JointKind, Param, Value};
use articulated_dynamics::reference::Reference;
use common::*;
use nalgebra::{Matrix3, Vector3};

const Y: [f64; 3] = [0.0, 1.0, 0.0];
const G: f64 = 9.81;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

/// A rod hanging from a revolute joint about y: the centre of mass `l` below the joint.
/// `M = I_yy + m·l²` and `g(θ) = m·g·l·sin θ` (rotating by θ about +y lifts the bob toward −x,
/// the potential `−m·g·l·cos θ` grows, so holding it takes `+∂V/∂θ`).
#[test]
fn single_pendulum() {
    let (m, l, iyy) = (2.0, 0.7, 0.05);
    let model = model(
        vec![body("bob", m, [0.0, 0.0, -l], diag(0.03, iyy, 0.01))],
        vec![joint(
            "pivot",
            JointKind::Revolute { axis: Y },
            None,
            [0.0; 3],
            [0.0; 3],
        )],
    );
    let r = Reference::new(&model).unwrap();
    for &th in &[0.0, 0.3, -1.2, 2.5] {
        let mm = r.mass_matrix(&[th]).unwrap();
        assert!(close(mm[(0, 0)], iyy + m * l * l, 1e-14), "{mm}");
        let g = r.gravity(&[th]).unwrap();
        assert!(
            close(g[0], m * G * l * th.sin(), 1e-14),
            "{g} vs {}",
            m * G * l * th.sin()
        );
        let b = r.bias(&[th], &[1.7]).unwrap();
        assert!(
            b[0].abs() < 1e-14,
            "a lone pendulum has no velocity-product torque: {b}"
        );
        let qdd = r.forward_dynamics(&[th], &[1.7], &[0.0]).unwrap();
        let expected = -m * G * l * th.sin() / (iyy + m * l * l);
        assert!(close(qdd[0], expected, 1e-13), "{qdd} vs {expected}");
    }
}

/// The same pendulum with its mass a runtime parameter: `with_params` must read it.
#[test]
fn single_pendulum_with_parameter_mass() {
    let (l, iyy) = (0.7, 0.05);
    let mut model = model(
        vec![body("bob", 1.0, [0.0, 0.0, -l], diag(0.03, iyy, 0.01))],
        vec![joint(
            "pivot",
            JointKind::Revolute { axis: Y },
            None,
            [0.0; 3],
            [0.0; 3],
        )],
    );
    model.params = vec![Param {
        name: "m".into(),
        default: 2.0,
    }];
    model.bodies[0].mass = Value::Param(0);
    for (r, m) in [
        (Reference::new(&model).unwrap(), 2.0),
        (Reference::with_params(&model, &[3.5]).unwrap(), 3.5),
    ] {
        let mm = r.mass_matrix(&[0.4]).unwrap();
        assert!(close(mm[(0, 0)], iyy + m * l * l, 1e-14));
        let g = r.gravity(&[0.4]).unwrap();
        assert!(close(g[0], m * G * l * 0.4f64.sin(), 1e-14));
    }
}

/// A planar double pendulum, both joints about y, link 1 of length `l1` with its centre of mass
/// at `c1`, link 2's at `c2` (Lagrange, angles from the downward vertical):
/// `M11 = I1 + m1 c1² + I2 + m2 (l1² + c2² + 2 l1 c2 cos θ2)`, `M12 = I2 + m2 (c2² + l1 c2 cos θ2)`,
/// `M22 = I2 + m2 c2²`; with `h = m2 l1 c2 sin θ2`, bias `= [−h (2 θ̇1 θ̇2 + θ̇2²); h θ̇1²]`;
/// gravity `= [(m1 c1 + m2 l1) g sin θ1 + m2 c2 g sin(θ1+θ2); m2 c2 g sin(θ1+θ2)]`.
#[test]
fn planar_double_pendulum() {
    let (m1, m2, l1, c1, c2, i1, i2) = (1.3, 0.8, 0.9, 0.4, 0.35, 0.07, 0.03);
    let model = double_pendulum_model(m1, m2, l1, c1, c2, i1, i2);
    let r = Reference::new(&model).unwrap();
    for &(t1, t2, d1, d2) in &[
        (0.3, -0.8, 1.1, -0.6),
        (2.0, 1.0, -0.4, 2.2),
        (0.0, 0.0, 1.0, 1.0),
    ] {
        let (s2, co2) = f64::sin_cos(t2);
        let m11 = i1 + m1 * c1 * c1 + i2 + m2 * (l1 * l1 + c2 * c2 + 2.0 * l1 * c2 * co2);
        let m12 = i2 + m2 * (c2 * c2 + l1 * c2 * co2);
        let m22 = i2 + m2 * c2 * c2;
        let mm = r.mass_matrix(&[t1, t2]).unwrap();
        for (got, want) in [
            (mm[(0, 0)], m11),
            (mm[(0, 1)], m12),
            (mm[(1, 0)], m12),
            (mm[(1, 1)], m22),
        ] {
            assert!(close(got, want, 1e-14), "M: {got} vs {want}");
        }
        let h = m2 * l1 * c2 * s2;
        let b = r.bias(&[t1, t2], &[d1, d2]).unwrap();
        assert!(close(b[0], -h * (2.0 * d1 * d2 + d2 * d2), 1e-13), "{b}");
        assert!(close(b[1], h * d1 * d1, 1e-13), "{b}");
        let g = r.gravity(&[t1, t2]).unwrap();
        let s12 = (t1 + t2).sin();
        assert!(
            close(
                g[0],
                (m1 * c1 + m2 * l1) * G * t1.sin() + m2 * c2 * G * s12,
                1e-13
            ),
            "{g}"
        );
        assert!(close(g[1], m2 * c2 * G * s12, 1e-13), "{g}");
    }
}

/// One free rigid body on a quaternion free joint, centre of mass at its origin, full inertia
/// `I`. In our velocity ordering `[v; ω]` (both in the body frame) the bias is
/// `[m·ω×v; ω×(I·ω)]`: Newton's law in a rotating frame and Euler's equations with the
/// gyroscopic term (Hemami et al. 2005, eq. 1; Wieber 2005, eq. 2). Forward dynamics with
/// `τ = 0` gives `v̇ = Rᵀg − ω×v` and `I·ω̇ = −ω×(I·ω)`.
#[test]
fn free_rigid_body() {
    let m = 3.0;
    let i = [[0.20, 0.03, -0.01], [0.03, 0.15, 0.02], [-0.01, 0.02, 0.10]];
    let model = model(
        vec![body("body", m, [0.0; 3], i)],
        vec![joint(
            "free",
            JointKind::FreeQuaternion,
            None,
            [0.0; 3],
            [0.0; 3],
        )],
    );
    let r = Reference::new(&model).unwrap();
    let quat = {
        let q = [0.8, -0.3, 0.4, 0.2];
        let n = q.iter().map(|x: &f64| x * x).sum::<f64>().sqrt();
        q.map(|x| x / n)
    };
    let q = [0.5, -1.0, 2.0, quat[0], quat[1], quat[2], quat[3]];
    let v = [0.3, -0.7, 1.1, 1.5, -0.4, 0.9];
    let im = Matrix3::from_fn(|r, c| i[r][c]);
    let lin = Vector3::new(v[0], v[1], v[2]);
    let w = Vector3::new(v[3], v[4], v[5]);
    let want_lin = w.cross(&lin) * m;
    let want_ang = w.cross(&(im * w));
    let b = r.bias(&q, &v).unwrap();
    for k in 0..3 {
        assert!(close(b[k], want_lin[k], 1e-14), "{b}");
        assert!(close(b[3 + k], want_ang[k], 1e-14), "{b}");
    }
    let qdd = r.forward_dynamics(&q, &v, &[0.0; 6]).unwrap();
    let g_body = quat_rot(quat).transpose() * Vector3::new(0.0, 0.0, -G);
    let want_vdot = g_body - w.cross(&lin);
    let want_wdot = im.try_inverse().unwrap() * (-w.cross(&(im * w)));
    for k in 0..3 {
        assert!(close(qdd[k], want_vdot[k], 1e-13), "{qdd} vs {want_vdot}");
        assert!(
            close(qdd[3 + k], want_wdot[k], 1e-13),
            "{qdd} vs {want_wdot}"
        );
    }
    // And M is block-diagonal [m·1, 0; 0, I].
    let mm = r.mass_matrix(&q).unwrap();
    for a in 0..6 {
        for c in 0..6 {
            let want = match (a < 3, c < 3) {
                (true, true) if a == c => m,
                (false, false) => i[a - 3][c - 3],
                _ => 0.0,
            };
            assert!(close(mm[(a, c)], want, 1e-14), "{mm}");
        }
    }
}
