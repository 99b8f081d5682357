//! The random model generator: deterministic, every joint kind, physical inertias, valid states.

use articulated_dynamics::model::JointKind;
use articulated_dynamics::random::{random_model, random_state};
use nalgebra::Matrix3;

#[test]
fn deterministic() {
    assert_eq!(random_model(42, 20), random_model(42, 20));
    assert_ne!(random_model(42, 20), random_model(43, 20));
    let m = random_model(42, 20);
    assert_eq!(random_state(&m, 5), random_state(&m, 5));
}

#[test]
fn every_joint_kind_and_valid_models() {
    let mut seen = [false; 7];
    for seed in 0..200 {
        let m = random_model(seed, 1 + (seed as usize % 30));
        m.check().unwrap();
        assert_eq!(m.joints.iter().filter(|j| j.parent.is_none()).count(), 1);
        for (i, j) in m.joints.iter().enumerate() {
            let k = match j.kind {
                JointKind::Revolute { .. } => 0,
                JointKind::Prismatic { .. } => 1,
                JointKind::SphericalEuler { .. } => 2,
                JointKind::SphericalQuaternion => 3,
                JointKind::FreeEuler { .. } => 4,
                JointKind::FreeQuaternion => 5,
                JointKind::Fixed => 6,
            };
            assert!(k < 4 || k == 6 || i == 0, "free joint below the root");
            seen[k] = true;
        }
        for b in &m.bodies {
            let mass = b.mass.as_const().unwrap();
            assert!((0.5..=5.0).contains(&mass));
            let i = Matrix3::from_fn(|r, c| b.inertia[r][c].as_const().unwrap());
            assert_eq!(i, i.transpose());
            let e = i.symmetric_eigenvalues();
            let (a, bb, c) = (e[0], e[1], e[2]);
            assert!(a > 0.0 && bb > 0.0 && c > 0.0);
            assert!(
                a < bb + c && bb < a + c && c < a + bb,
                "triangle inequality: {e}"
            );
        }
        let (q, v, a) = random_state(&m, seed);
        assert_eq!((q.len(), v.len(), a.len()), (m.nq(), m.nv(), m.nv()));
        let mut at = 0;
        for j in &m.joints {
            let w = match j.kind {
                JointKind::SphericalQuaternion => Some(at),
                JointKind::FreeQuaternion => Some(at + 3),
                _ => None,
            };
            if let Some(w) = w {
                let n: f64 = q[w..w + 4].iter().map(|x| x * x).sum();
                assert!((n - 1.0).abs() < 1e-14);
            }
            at += j.kind.nq();
        }
    }
    assert_eq!(seen, [true; 7], "joint kinds seen: {seen:?}");
}
