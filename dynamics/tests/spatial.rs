//! The spatial algebra against explicit 6×6 matrices and plain rotation formulas, and the
//! generic recursions run on another scalar (`f32`).

use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::{crba, rnea, Reference, Tree};
use articulated_dynamics::spatial::{Force, Inertia, Mat3, Motion, Transform, Vec3};

fn v3(a: f64, b: f64, c: f64) -> Vec3<f64> {
    Vec3([a, b, c])
}

fn sample() -> (Transform<f64>, Motion<f64>, Force<f64>) {
    let x = Transform::from_pose(Mat3::rpy(0.3, -1.1, 2.0), v3(0.4, -0.2, 0.9));
    let m = Motion::new(v3(0.5, -0.3, 1.2), v3(-0.7, 0.1, 0.4));
    let f = Force::new(v3(1.5, 0.2, -0.6), v3(0.3, -2.0, 0.8));
    (x, m, f)
}

fn max_diff(a: [f64; 6], b: [f64; 6]) -> f64 {
    a.iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `apply_motion` is the matrix `[E 0; −E r× E]` (Featherstone 2008, RBDA eq. 2.24), its inverse
/// undoes it, forces transform so that power is invariant, and `inv_apply_force` is `Xᵀ`.
#[test]
fn transforms_match_matrices() {
    let (x, m, f) = sample();
    let xm = x.to_mat6();
    assert!(max_diff(x.apply_motion(m).to_array(), xm.mul_array(m.to_array())) < 1e-15);
    assert!(
        max_diff(
            x.inv_apply_motion(x.apply_motion(m)).to_array(),
            m.to_array()
        ) < 1e-15
    );
    let power = m.dot(x.inv_apply_force(x.apply_force(f)));
    assert!((power - m.dot(f)).abs() < 1e-14);
    assert!((x.apply_motion(m).dot(x.apply_force(f)) - m.dot(f)).abs() < 1e-14);
    assert!(
        max_diff(
            x.inv_apply_force(f).to_array(),
            xm.transpose().mul_array(f.to_array())
        ) < 1e-15
    );
    // Composition: (X2 ∘ X1)·m = X2·(X1·m).
    let x2 = Transform::from_pose(Mat3::quaternion([0.3, 0.5, -0.2, 0.7]), v3(-0.3, 0.6, 0.1));
    let both = x2.after(&x);
    assert!(
        max_diff(
            both.apply_motion(m).to_array(),
            x2.apply_motion(x.apply_motion(m)).to_array()
        ) < 1e-15
    );
}

/// `Inertia::to_parent` is `Xᵀ·I·X` computed with 6×6 matrices; `from_com` is the
/// parallel-axis theorem (`Ī = I_c + m·(|c|²·1 − c·cᵀ)`).
#[test]
fn inertia_transform_and_parallel_axes() {
    let (x, m, _) = sample();
    let c = v3(0.1, -0.2, 0.3);
    let ic = Mat3([[0.2, 0.01, 0.0], [0.01, 0.3, -0.02], [0.0, -0.02, 0.25]]);
    let i = Inertia::from_com(2.0, c, ic);
    let cc = c.dot(c);
    for r in 0..3 {
        for k in 0..3 {
            let want = ic.0[r][k] + 2.0 * ((if r == k { cc } else { 0.0 }) - c.0[r] * c.0[k]);
            assert!((i.i.0[r][k] - want).abs() < 1e-15);
        }
    }
    let xm = x.to_mat6();
    let want = xm.transpose().mul_mat(&i.to_mat6().mul_mat(&xm));
    let got = i.to_parent(&x).to_mat6();
    for r in 0..6 {
        for k in 0..6 {
            assert!((got.0[r][k] - want.0[r][k]).abs() < 1e-14, "{r},{k}");
        }
    }
    assert!(
        max_diff(
            i.mul_motion(m).to_array(),
            i.to_mat6().mul_array(m.to_array())
        ) < 1e-15
    );
}

/// Rotation conventions: `rpy = Rz·Ry·Rx`, the axis form agrees with the coordinate rotations,
/// a quaternion about z by θ is `Rz(θ)`, and a non-unit quaternion is normalized.
#[test]
fn rotations() {
    let (r, p, y) = (0.3, -0.8, 1.4);
    let want = Mat3::rot_z(y)
        .mul_mat(&Mat3::rot_y(p))
        .mul_mat(&Mat3::rot_x(r));
    assert_eq!(Mat3::rpy(r, p, y), want);
    // Rz(θ) columns: x axis goes to (cos, sin, 0).
    let rz = Mat3::rot_z(0.5f64);
    assert!((rz.0[1][0] - 0.5f64.sin()).abs() < 1e-16);
    for (axis, rot) in [
        ([1.0, 0.0, 0.0], Mat3::<f64>::rot_x(0.7)),
        ([0.0, 1.0, 0.0], Mat3::rot_y(0.7)),
        ([0.0, 0.0, 1.0], Mat3::rot_z(0.7)),
    ] {
        let a = Mat3::rot_axis(Vec3::from_f64(axis), 0.7);
        for i in 0..3 {
            for j in 0..3 {
                assert!((a.0[i][j] - rot.0[i][j]).abs() < 1e-15);
            }
        }
    }
    let (s, c) = 0.35f64.sin_cos();
    let q = Mat3::quaternion([3.0 * c, 0.0, 0.0, 3.0 * s]); // |q| = 3, about z by 0.7
    let rz = Mat3::rot_z(0.7);
    for i in 0..3 {
        for j in 0..3 {
            assert!((q.0[i][j] - rz.0[i][j]).abs() < 1e-15);
        }
    }
}

/// The recursions are generic: on `f32` they agree with `f64` to single precision.
#[test]
fn recursions_run_on_f32() {
    let model = random_model(11, 8);
    let (q, v, a) = random_state(&model, 11);
    let t32: Tree<f32> = Tree::new(&model, &[]);
    let to32 = |x: &[f64]| x.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    let m32 = crba(&t32, &to32(&q));
    let tau32 = rnea(&t32, &to32(&q), &to32(&v), &to32(&a), true);
    let r = Reference::new(&model).unwrap();
    let m64 = r.mass_matrix(&q).unwrap();
    let tau64 = r.inverse_dynamics(&q, &v, &a).unwrap();
    let nv = r.nv();
    for i in 0..nv {
        assert!((tau32[i] as f64 - tau64[i]).abs() < 1e-3 * tau64.amax());
        for j in 0..nv {
            assert!((m32[i * nv + j] as f64 - m64[(i, j)]).abs() < 1e-4 * m64.amax());
        }
    }
}
