//! Generated code against the reference: the double pendulum inline and the 7-DOF arm from URDF.

use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use nalgebra::SVector;

articulated::chain! {
    /// The planar double pendulum.
    pub chain DoublePendulum {
        gravity: [0.0, 0.0, -9.81];
        body upper { mass: 1.0, com: [0.0, 0.0, -0.5], inertia: diag(0.02, 0.02, 0.001) }
        body lower { mass: 0.7, com: [0.0, 0.0, -0.35], inertia: diag(0.01, 0.01, 0.0005) }
        joint shoulder: revolute(y) { parent: world, child: upper }
        joint elbow: revolute(y) { parent: upper, child: lower, xyz: [0.0, 0.0, -1.0] }
    }
}

#[derive(articulated::Chain)]
#[chain(urdf = "../models/arm7.urdf")]
struct Arm7;

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn double_pendulum_matches_reference() {
    let model = load_model(
        std::path::Path::new(articulated_models::DOUBLE_PENDULUM.chain),
        false,
    )
    .unwrap();
    let r = Reference::new(&model).unwrap();
    let q = SVector::<f64, 2>::new(0.3, -0.7);
    let v = SVector::<f64, 2>::new(1.1, 0.4);
    let a = SVector::<f64, 2>::new(-0.2, 0.9);
    let m = DoublePendulum::mass_matrix(&q);
    assert!(
        max_diff(
            m.as_slice(),
            r.mass_matrix(q.as_slice()).unwrap().as_slice()
        ) < 1e-12
    );
    let tau = DoublePendulum::inverse_dynamics(&q, &v, &a);
    assert!(
        max_diff(
            tau.as_slice(),
            r.inverse_dynamics(q.as_slice(), v.as_slice(), a.as_slice())
                .unwrap()
                .as_slice()
        ) < 1e-12
    );
    let qdd = DoublePendulum::forward_dynamics(&q, &v, &tau).unwrap();
    assert!(max_diff(qdd.as_slice(), a.as_slice()) < 1e-10);
    println!("{:?}", DoublePendulum::MASS_MATRIX_OPS);
}

#[test]
fn arm7_matches_reference() {
    let model = load_model(
        std::path::Path::new(articulated_models::ARM7.urdf.unwrap()),
        false,
    )
    .unwrap();
    let r = Reference::new(&model).unwrap();
    let q = SVector::<f64, 7>::from_fn(|i, _| 0.3 * i as f64 - 0.8);
    let v = SVector::<f64, 7>::from_fn(|i, _| 0.5 - 0.2 * i as f64);
    let a = SVector::<f64, 7>::from_fn(|i, _| 0.1 * i as f64);
    let m = Arm7::mass_matrix(&q);
    assert!(
        max_diff(
            m.as_slice(),
            r.mass_matrix(q.as_slice()).unwrap().as_slice()
        ) < 1e-12
    );
    let tau = Arm7::inverse_dynamics(&q, &v, &a);
    assert!(
        max_diff(
            tau.as_slice(),
            r.inverse_dynamics(q.as_slice(), v.as_slice(), a.as_slice())
                .unwrap()
                .as_slice()
        ) < 1e-12
    );
    let qdd = Arm7::forward_dynamics(&q, &v, &tau).unwrap();
    assert!(max_diff(qdd.as_slice(), a.as_slice()) < 1e-9);
    println!(
        "M {} | ID {} | FD {}",
        Arm7::MASS_MATRIX_OPS,
        Arm7::INVERSE_DYNAMICS_OPS,
        Arm7::FORWARD_DYNAMICS_OPS
    );
}
