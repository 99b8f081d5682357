//! Helpers shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector};

/// `max |a − b| / max(max |b|, floor)`.
pub fn rel_err_mat(a: &DMatrix<f64>, b: &DMatrix<f64>, floor: f64) -> f64 {
    let scale = b.amax().max(floor);
    (a - b).amax() / scale
}

/// `max |a − b| / max(max |b|, floor)`.
pub fn rel_err_vec(a: &DVector<f64>, b: &DVector<f64>, floor: f64) -> f64 {
    let scale = b.amax().max(floor);
    (a - b).amax() / scale
}

use articulated_dynamics::model::{Body, Drive, Joint, JointKind, Model, Placement, Value};

/// A body with constant mass properties.
pub fn body(name: &str, mass: f64, com: [f64; 3], inertia: [[f64; 3]; 3]) -> Body {
    Body {
        name: name.into(),
        mass: Value::Const(mass),
        com: com.map(Value::Const),
        inertia: inertia.map(|r| r.map(Value::Const)),
    }
}

/// A joint with a constant placement.
pub fn joint(
    name: &str,
    kind: JointKind,
    parent: Option<usize>,
    xyz: [f64; 3],
    rpy: [f64; 3],
) -> Joint {
    Joint {
        name: name.into(),
        kind,
        parent,
        placement: Placement {
            xyz: xyz.map(Value::Const),
            rpy: rpy.map(Value::Const),
        },
        drive: Drive::FREE,
        mimic: None,
    }
}

/// A model with default gravity `[0, 0, −9.81]` and no parameters.
pub fn model(bodies: Vec<Body>, joints: Vec<Joint>) -> Model {
    Model::new("Test", bodies, joints)
}

/// `diag(a, b, c)`.
pub fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
}

/// Hamilton product of quaternions `[w, x, y, z]`.
pub fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [w1, x1, y1, z1] = a;
    let [w2, x2, y2, z2] = b;
    [
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ]
}

/// `exp` of the rotation vector `φ` as a unit quaternion.
pub fn quat_exp(phi: [f64; 3]) -> [f64; 4] {
    let n = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
    if n < 1e-300 {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let (s, c) = (0.5 * n).sin_cos();
    [c, s * phi[0] / n, s * phi[1] / n, s * phi[2] / n]
}

/// Rotation matrix of a unit quaternion (rows).
pub fn quat_rot(q: [f64; 4]) -> nalgebra::Matrix3<f64> {
    nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
        .to_rotation_matrix()
        .into_inner()
}

/// The configuration reached from `q` by moving along the velocity `v` for time `h`, exactly
/// for constant `v` on every joint (quaternions by the exponential map, body-frame angular
/// velocity; a free quaternion joint's position moves by `R·v_lin·h`, which is exact to first
/// order and symmetric in `h`, enough for central differences). Mimic joints have no coordinate
/// of their own.
pub fn integrate(model: &Model, q: &[f64], v: &[f64], h: f64) -> Vec<f64> {
    let mut out = q.to_vec();
    let (mut qa, mut va) = (0, 0);
    for j in &model.joints {
        match j.kind {
            JointKind::SphericalQuaternion => {
                let q0 = [q[qa], q[qa + 1], q[qa + 2], q[qa + 3]];
                let dq = quat_exp([v[va] * h, v[va + 1] * h, v[va + 2] * h]);
                out[qa..qa + 4].copy_from_slice(&quat_mul(q0, dq));
            }
            JointKind::FreeQuaternion => {
                let q0 = [q[qa + 3], q[qa + 4], q[qa + 5], q[qa + 6]];
                let r = quat_rot(q0);
                let d = r * nalgebra::Vector3::new(v[va], v[va + 1], v[va + 2]) * h;
                for k in 0..3 {
                    out[qa + k] = q[qa + k] + d[k];
                }
                let dq = quat_exp([v[va + 3] * h, v[va + 4] * h, v[va + 5] * h]);
                out[qa + 3..qa + 7].copy_from_slice(&quat_mul(q0, dq));
            }
            // A mimic joint owns no coordinate (`j.nq() = 0`): it moves with the one it follows.
            _ => {
                for k in 0..j.nq() {
                    out[qa + k] = q[qa + k] + h * v[va + k];
                }
            }
        }
        qa += j.nq();
        va += j.nv();
    }
    out
}

/// The planar double pendulum of the closed-form tests: both joints about y, link 1 of length
/// `l1` with its centre of mass `c1` below the shoulder, link 2's `c2` below the elbow, the
/// moments about y `i1`, `i2` (the others' values do not enter the planar motion).
pub fn double_pendulum_model(
    m1: f64,
    m2: f64,
    l1: f64,
    c1: f64,
    c2: f64,
    i1: f64,
    i2: f64,
) -> Model {
    let y = JointKind::Revolute {
        axis: [0.0, 1.0, 0.0],
    };
    model(
        vec![
            body("upper", m1, [0.0, 0.0, -c1], diag(0.1, i1, 0.02)),
            body("lower", m2, [0.0, 0.0, -c2], diag(0.05, i2, 0.01)),
        ],
        vec![
            joint("shoulder", y, None, [0.0; 3], [0.0; 3]),
            joint("elbow", y, Some(0), [0.0, 0.0, -l1], [0.0; 3]),
        ],
    )
}
