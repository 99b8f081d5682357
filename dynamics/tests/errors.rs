//! Every [`Error`] variant is produced, with a message that names the culprit; nothing panics.

mod common;

use articulated_dynamics::model::{Drive, EulerSeq, JointKind, ModelError, Param, Value};
use articulated_dynamics::reference::{jacobian, Error, Reference, Singularity};
use common::*;

const Y: [f64; 3] = [0.0, 1.0, 0.0];

fn double_pendulum() -> articulated_dynamics::model::Model {
    model(
        vec![
            body("upper", 1.0, [0.0, 0.0, -0.5], diag(0.1, 0.1, 0.01)),
            body("lower", 1.0, [0.0, 0.0, -0.5], diag(0.1, 0.1, 0.01)),
        ],
        vec![
            joint(
                "shoulder",
                JointKind::Revolute { axis: Y },
                None,
                [0.0; 3],
                [0.0; 3],
            ),
            joint(
                "elbow",
                JointKind::Revolute { axis: Y },
                Some(0),
                [0.0, 0.0, -1.0],
                [0.0; 3],
            ),
        ],
    )
}

#[test]
fn wrong_length() {
    let r = Reference::new(&double_pendulum()).unwrap();
    let e = r.mass_matrix(&[0.0]).unwrap_err();
    assert_eq!(
        e,
        Error::Length {
            vector: "q",
            expected: 2,
            found: 1
        }
    );
    assert!(
        e.to_string()
            .contains("`q` has 1 entries but the model needs 2"),
        "{e}"
    );
    let e = r
        .forward_dynamics(&[0.0; 2], &[0.0; 2], &[0.0; 3])
        .unwrap_err();
    assert_eq!(
        e,
        Error::Length {
            vector: "tau",
            expected: 2,
            found: 3
        }
    );
    let e = r.inverse_dynamics(&[0.0; 2], &[0.0; 2], &[]).unwrap_err();
    assert_eq!(
        e,
        Error::Length {
            vector: "a",
            expected: 2,
            found: 0
        }
    );
}

#[test]
fn non_finite_entry() {
    let r = Reference::new(&double_pendulum()).unwrap();
    let e = r.bias(&[0.0; 2], &[0.0, f64::NAN]).unwrap_err();
    assert_eq!(
        e,
        Error::NonFinite {
            vector: "v",
            index: 1
        }
    );
    assert!(e.to_string().contains("`v[1]`"), "{e}");
    let e = r.gravity(&[f64::INFINITY, 0.0]).unwrap_err();
    assert_eq!(
        e,
        Error::NonFinite {
            vector: "q",
            index: 0
        }
    );
}

#[test]
fn zero_quaternion() {
    let m = model(
        vec![
            body("a", 1.0, [0.0; 3], diag(0.1, 0.1, 0.1)),
            body("b", 1.0, [0.1, 0.0, 0.0], diag(0.1, 0.1, 0.1)),
        ],
        vec![
            joint("base", JointKind::FreeQuaternion, None, [0.0; 3], [0.0; 3]),
            joint(
                "ball",
                JointKind::SphericalQuaternion,
                Some(0),
                [0.0; 3],
                [0.0; 3],
            ),
        ],
    );
    let r = Reference::new(&m).unwrap();
    let mut q = m.neutral();
    q[7..11].fill(0.0);
    let e = r.mass_matrix(&q).unwrap_err();
    assert_eq!(
        e,
        Error::Quaternion {
            joint: "ball".into(),
            index: 7
        }
    );
    assert!(e.to_string().contains("`ball`"), "{e}");
    // A quaternion a little off unit (printed to four digits) is normalized: the same M as the
    // unit one it stands for, a 45° turn about z.
    let (c, s) = (
        std::f64::consts::FRAC_PI_8.cos(),
        std::f64::consts::FRAC_PI_8.sin(),
    );
    let mut unit = m.neutral();
    unit[3..7].copy_from_slice(&[c, 0.0, 0.0, s]);
    let mut printed = m.neutral();
    printed[3..7].copy_from_slice(&[0.9239, 0.0, 0.0, 0.3827]);
    let m1 = r.mass_matrix(&unit).unwrap();
    let m2 = r.mass_matrix(&printed).unwrap();
    assert!((m2 - m1).amax() < 1e-3, "normalized, not refused");
    // One far off unit is a mistake, named with its norm: a scaled quaternion, or one in
    // Pinocchio's `[x, y, z, w]` order read as ours with a component typed twice.
    let mut q2 = m.neutral();
    q2[3] = 5.0;
    let e = r.mass_matrix(&q2).unwrap_err();
    assert_eq!(
        e,
        Error::NotUnitQuaternion {
            joint: "base".into(),
            index: 3,
            norm: 5.0
        }
    );
    assert!(e.to_string().contains("scalar first"), "{e}");
    // Just past the tolerance, either way.
    for norm in [1.0 + 1.5e-3, 1.0 - 1.5e-3] {
        let mut q3 = m.neutral();
        q3[7] = norm;
        assert!(
            matches!(
                r.gravity(&q3),
                Err(Error::NotUnitQuaternion { index: 7, .. })
            ),
            "{norm}"
        );
    }
    // The cross-check refuses it too.
    assert!(matches!(
        jacobian::wieber(&m, &[], &q, &[0.0; 9]),
        Err(Error::Quaternion { .. })
    ));
}

#[test]
fn parameters() {
    let mut m = double_pendulum();
    m.params = vec![Param {
        name: "payload".into(),
        default: 1.0,
    }];
    m.bodies[1].mass = Value::Param(0);
    let e = Reference::with_params(&m, &[]).unwrap_err();
    assert_eq!(
        e,
        Error::ParamLength {
            expected: 1,
            found: 0
        }
    );
    assert!(e.to_string().contains("0 parameter values given"), "{e}");
    let e = Reference::with_params(&m, &[f64::NAN]).unwrap_err();
    assert_eq!(
        e,
        Error::ParamNonFinite {
            index: 0,
            name: "payload".into()
        }
    );
    assert!(e.to_string().contains("`payload`"), "{e}");
    m.params[0].default = f64::INFINITY;
    assert!(matches!(
        Reference::new(&m),
        Err(Error::ParamNonFinite { .. })
    ));
}

#[test]
fn invalid_model() {
    let mut m = double_pendulum();
    m.joints[1].kind = JointKind::Revolute {
        axis: [0.0, 2.0, 0.0],
    };
    let e = Reference::new(&m).unwrap_err();
    assert!(
        matches!(&e, Error::InvalidModel(ModelError::AxisNotUnit { joint, .. }) if joint == "elbow"),
        "{e}"
    );
    let mut m = double_pendulum();
    m.bodies.pop();
    assert!(matches!(Reference::new(&m), Err(Error::InvalidModel(_))));
}

/// A massless leaf on a revolute joint: nothing resists its acceleration.
#[test]
fn singular_massless_leaf() {
    let mut m = double_pendulum();
    m.bodies[1] = body("frame", 0.0, [0.0; 3], diag(0.0, 0.0, 0.0));
    let r = Reference::new(&m).unwrap();
    // M is fine to compute, only singular.
    assert_eq!(r.mass_matrix(&[0.1, 0.2]).unwrap()[(1, 1)], 0.0);
    let e = r
        .forward_dynamics(&[0.1, 0.2], &[0.0; 2], &[0.0; 2])
        .unwrap_err();
    assert!(
        matches!(&e, Error::Singular(Singularity::Pivot { joint, .. }) if joint == "elbow"),
        "{e}"
    );
}

/// A massless intermediate frame is fine as long as something massive hangs below it.
#[test]
fn massless_intermediate_frame_is_not_singular() {
    let mut m = double_pendulum();
    m.bodies[0] = body("frame", 0.0, [0.0; 3], diag(0.0, 0.0, 0.0));
    let r = Reference::new(&m).unwrap();
    assert!(r
        .forward_dynamics(&[0.1, 0.2], &[0.3; 2], &[0.0; 2])
        .is_ok());
}

/// A free Euler base (z-y-x) at pitch π/2 is at gimbal lock: yaw and roll turn about the same
/// axis, M is singular.
#[test]
fn singular_gimbal_lock() {
    let m = model(
        vec![body(
            "b",
            1.0,
            [0.1, 0.0, 0.0],
            [[0.2, 0.01, 0.0], [0.01, 0.3, 0.0], [0.0, 0.0, 0.4]],
        )],
        vec![joint(
            "base",
            JointKind::FreeEuler { seq: EulerSeq::ZYX },
            None,
            [0.0; 3],
            [0.0; 3],
        )],
    );
    let r = Reference::new(&m).unwrap();
    let q = [0.0, 0.0, 0.0, 0.3, std::f64::consts::FRAC_PI_2, -0.2];
    let e = r.forward_dynamics(&q, &[0.0; 6], &[0.0; 6]).unwrap_err();
    assert!(
        matches!(&e, Error::Singular(Singularity::Pivot { joint, .. }) if joint == "base"),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("the mass matrix is singular here"),
        "{e}"
    );
    // Away from it, fine.
    let q = [0.0, 0.0, 0.0, 0.3, 1.0, -0.2];
    assert!(r.forward_dynamics(&q, &[0.0; 6], &[0.0; 6]).is_ok());
}

/// Finite but huge inputs overflow: reported, not returned as infinities.
#[test]
fn non_finite_result() {
    let r = Reference::new(&double_pendulum()).unwrap();
    let e = r.bias(&[0.1, 0.2], &[1e200, 1e200]).unwrap_err();
    assert_eq!(e, Error::NonFiniteResult { output: "bias" });
    assert!(e.to_string().contains("overflowed"), "{e}");
    let e = r
        .joint_wrenches(&[0.1, 0.2], &[1e200, 1e200], &[0.0; 2])
        .unwrap_err();
    assert_eq!(
        e,
        Error::NonFiniteResult {
            output: "joint_wrenches"
        }
    );
    let e = r
        .forward_dynamics(&[0.1, 0.2], &[1e200, 1e200], &[0.0; 2])
        .unwrap_err();
    assert!(matches!(e, Error::Singular(_)), "{e}");
}

/// A model of one body of unit mass at the origin on a single joint of `kind`, with the
/// inertia `diag(d)`, built by hand (past the front ends' checks).
fn one_body(
    kind: articulated_dynamics::model::JointKind,
    d: [f64; 3],
) -> articulated_dynamics::model::Model {
    use articulated_dynamics::model::{Body, Joint, Model, Placement, Value};
    let c = Value::Const;
    let inertia = [
        [c(d[0]), c(0.0), c(0.0)],
        [c(0.0), c(d[1]), c(0.0)],
        [c(0.0), c(0.0), c(d[2])],
    ];
    let body = Body {
        name: "b".into(),
        mass: c(1.0),
        com: [c(0.0); 3],
        inertia,
    };
    let joint = Joint {
        name: "j".into(),
        kind,
        parent: None,
        placement: Placement::IDENTITY,
        drive: Drive::FREE,
        mimic: None,
    };
    Model::new("One", vec![body], vec![joint])
}

/// An inertia that is not positive definite, or nearly singular (a model built by hand, past the
/// front ends' checks), makes M indefinite or numerically singular. ABA's pivots need not notice;
/// forward dynamics must still refuse, never return rounding noise.
#[test]
fn indefinite_mass_matrix_is_singular() {
    use articulated_dynamics::model::JointKind;
    use articulated_dynamics::reference::{Error, Reference, Singularity};
    let free = |d| Reference::new(&one_body(JointKind::FreeQuaternion, d)).unwrap();
    let q = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    // A negative principal moment: caught by ABA's own pivots.
    let e = free([1.0, 1.0, -1e-20])
        .forward_dynamics(&q, &[0.0; 6], &[0.0; 6])
        .unwrap_err();
    assert!(matches!(&e, Error::Singular(_)), "{e}");
    // A moment 1e-14 of the others: every ABA pivot is positive and passes its tolerances, but
    // κ(M) = 1e14, past what f64 can invert to three digits; the eigenvalue check refuses it.
    let e = free([1.0, 1.0, 1e-14])
        .forward_dynamics(&q, &[0.0; 6], &[0.0; 6])
        .unwrap_err();
    assert!(
        matches!(&e, Error::Singular(Singularity::Eigenvalues { min, max }) if *min > 0.0 && max / min > 1e13),
        "{e}"
    );
    assert!(e.to_string().contains("numerically singular"), "{e}");
    // The same body at κ(M) = 1e10 is accepted.
    assert!(free([1.0, 1.0, 1e-10])
        .forward_dynamics(&q, &[0.0; 6], &[0.0; 6])
        .is_ok());
}

/// Regression: a model whose only joint is fixed has `nv = 0`; forward dynamics must return the
/// empty acceleration, not panic in the eigenvalue check of `M` (found by `forward_inverts_inverse`).
#[test]
fn forward_dynamics_of_a_model_without_velocities_is_empty() {
    use articulated_dynamics::model::JointKind;
    let r = articulated_dynamics::reference::Reference::new(&one_body(JointKind::Fixed, [1.0; 3]))
        .unwrap();
    assert_eq!(r.forward_dynamics(&[], &[], &[]).unwrap().len(), 0);
}
