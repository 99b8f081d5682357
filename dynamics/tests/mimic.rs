//! Mimic joints ([`Mimic`]): a joint whose coordinate is `multiplier·q_j + offset` leaves `q` and
//! `v`, and the dynamics are those of the tree with the coupling built in. Held to three things
//! computed without the reference's [`Coupling`]:
//! - closed forms: a parallelogram (the second link counter-rotates, so it only translates) and a
//!   gear pair on one axis;
//! - Wieber's formulation (`reference::jacobian`), where a mimic joint's Jacobian column adds to
//!   the followed joint's, a separate code path from the reference's `Gᵀ·M·G`;
//! - the hand-written equivalent: the same tree with every joint independent, and `G` written
//!   out here as a matrix, `M = Gᵀ·M_tree·G`, `τ = Gᵀ·τ_tree(G·q + o, G·v, G·a)`.

mod common;

use articulated_dynamics::model::{JointKind, Mimic, Model, ModelError};
use articulated_dynamics::reference::jacobian::wieber;
use articulated_dynamics::reference::{Error, Reference};
use common::{body, diag, joint, model, rel_err_mat, rel_err_vec};
use nalgebra::{DMatrix, DVector};

const Z: JointKind = JointKind::Revolute {
    axis: [0.0, 0.0, 1.0],
};
const Y: JointKind = JointKind::Revolute {
    axis: [0.0, 1.0, 0.0],
};

fn mimic(joint: usize, multiplier: f64, offset: f64) -> Option<Mimic> {
    Some(Mimic {
        joint,
        multiplier,
        offset,
    })
}

/// A parallelogram in the vertical x-z plane (gravity −z, the joints about y): a bar of length
/// `l` turns by `θ` about the world's y axis; at its tip a platform turns by `−θ`, so it keeps its
/// attitude and its centre of mass goes round a circle of radius `l`.
fn parallelogram(m1: f64, c1: f64, i1: f64, m2: f64, l: f64) -> Model {
    let mut tip = joint("tip", Y, Some(0), [l, 0.0, 0.0], [0.0; 3]);
    tip.mimic = mimic(0, -1.0, 0.0);
    model(
        vec![
            body("bar", m1, [c1, 0.0, 0.0], diag(0.01, i1, 0.02)),
            body("platform", m2, [0.1, 0.05, -0.2], diag(0.3, 0.4, 0.5)),
        ],
        vec![joint("base", Y, None, [0.0; 3], [0.0; 3]), tip],
    )
}

#[test]
fn a_parallelogram_s_platform_only_translates() {
    let (m1, c1, i1, m2, l) = (2.0, 0.4, 0.05, 3.0, 0.9);
    let r = Reference::new(&parallelogram(m1, c1, i1, m2, l)).unwrap();
    assert_eq!((r.nq(), r.nv()), (1, 1));
    for theta in [-2.0, -0.3, 0.0, 0.7, 2.5] {
        let m = r.mass_matrix(&[theta]).unwrap()[(0, 0)];
        // The bar about its joint, and the platform as a point mass at distance l.
        let closed = i1 + m1 * c1 * c1 + m2 * l * l;
        assert!((m - closed).abs() < 1e-13 * closed, "M {m} vs {closed}");
        // Turning about +y by θ takes +x to −z: the centres of mass sink by c·sin θ, so the
        // potential is −(m1·c1 + m2·l)·g·sin θ (plus a constant) and g(q) is its derivative.
        let g = r.gravity(&[theta]).unwrap()[0];
        let closed = -(m1 * c1 + m2 * l) * 9.81 * theta.cos();
        assert!((g - closed).abs() < 1e-13 * 40.0, "g {g} vs {closed}");
        // A constant mass matrix: no velocity-product force.
        let bias = r.bias(&[theta], &[3.0]).unwrap()[0];
        assert!(bias.abs() < 1e-13, "bias {bias}");
        // The platform's attitude is the identity: the kinetic energy of its rotation is zero.
        let e = r.kinetic_energy(&[theta], &[1.5]).unwrap();
        assert!((e - 0.5 * (i1 + m1 * c1 * c1 + m2 * l * l) * 2.25).abs() < 1e-13);
    }
}

#[test]
fn a_gear_pair_on_one_axis_reflects_its_inertia_by_the_ratio_squared() {
    // A disk geared to turn k times as fast relative to the arm it rides on, on the same axis.
    let (i1, i2, k, a) = (0.2, 0.03, 4.0, 0.01);
    let mut gear = joint("gear", Z, Some(0), [0.0; 3], [0.0; 3]);
    gear.mimic = mimic(0, k, 0.5);
    gear.drive.armature = a;
    let m = model(
        vec![
            body("arm", 1.0, [0.0; 3], diag(0.1, 0.1, i1)),
            body("disk", 0.5, [0.0; 3], diag(0.01, 0.01, i2)),
        ],
        vec![joint("shaft", Z, None, [0.0; 3], [0.0; 3]), gear],
    );
    let r = Reference::new(&m).unwrap();
    let mm = r.mass_matrix(&[0.3]).unwrap()[(0, 0)];
    // The disk turns at (1 + k)·θ̇; its rotor, at k·θ̇ relative to the arm, adds k²·a.
    let closed = i1 + i2 * (1.0 + k) * (1.0 + k) + k * k * a;
    assert!((mm - closed).abs() < 1e-14, "{mm} vs {closed}");
    let qdd = r.forward_dynamics(&[0.3], &[2.0], &[1.0]).unwrap()[0];
    assert!((qdd - 1.0 / closed).abs() < 1e-13, "{qdd}");
}

/// A branching tree: a mimic joint on one branch follows a joint on another, and an independent
/// joint below the mimic joint is moved by both.
fn gripper() -> Model {
    let mut finger2 = joint("finger2", Y, Some(0), [0.0, -0.05, 0.1], [0.0, 0.0, 0.2]);
    finger2.mimic = mimic(1, -0.7, 0.2);
    let slide = JointKind::Prismatic {
        axis: [0.6, 0.0, 0.8],
    };
    model(
        vec![
            body("palm", 1.2, [0.01, 0.0, 0.05], diag(0.01, 0.02, 0.015)),
            body("finger1", 0.3, [0.0, 0.0, 0.04], diag(0.002, 0.003, 0.001)),
            body(
                "finger2",
                0.25,
                [0.02, 0.0, 0.03],
                diag(0.002, 0.002, 0.001),
            ),
            body("tip2", 0.1, [0.0, 0.01, 0.02], diag(5e-4, 4e-4, 3e-4)),
        ],
        vec![
            joint("wrist", Z, None, [0.0, 0.0, 0.3], [0.1, 0.0, 0.0]),
            joint("finger1", Y, Some(0), [0.0, 0.05, 0.1], [0.0, 0.0, -0.2]),
            finger2,
            joint("tip2", slide, Some(2), [0.0, 0.0, 0.08], [0.3, 0.0, 0.0]),
        ],
    )
}

/// The tree with every joint independent, and `G` and `o`, written out: tree coordinate `k` is
/// `Σ_j G[k][j]·q_j + o[k]`.
fn hand_written(m: &Model) -> (Model, DMatrix<f64>, DVector<f64>) {
    let mut tree = m.clone();
    for j in &mut tree.joints {
        j.mimic = None;
    }
    // gripper(): tree coordinates wrist, finger1, finger2, tip2; model's wrist, finger1, tip2.
    let g = DMatrix::from_row_slice(
        4,
        3,
        &[
            1.0, 0.0, 0.0, //
            0.0, 1.0, 0.0, //
            0.0, -0.7, 0.0, //
            0.0, 0.0, 1.0,
        ],
    );
    (tree, g, DVector::from_vec(vec![0.0, 0.0, 0.2, 0.0]))
}

fn states() -> Vec<[DVector<f64>; 3]> {
    (0..6)
        .map(|k| {
            let x = k as f64;
            let v3 = |a: f64, b: f64, c: f64| DVector::from_vec(vec![a, b, c]);
            [
                v3(0.3 * x - 0.8, 1.1 - 0.4 * x, 0.05 * x - 0.1),
                v3(1.5 - x, 0.3 * x, 0.7 - 0.2 * x),
                v3(0.4 * x, -2.0 + x, 0.5),
            ]
        })
        .collect()
}

#[test]
fn a_mimic_joint_is_its_hand_written_equivalent() {
    let m = gripper();
    let (tree, g, o) = hand_written(&m);
    let (r, rt) = (Reference::new(&m).unwrap(), Reference::new(&tree).unwrap());
    assert_eq!((r.nq(), r.nv(), rt.nv()), (3, 3, 4));
    for [q, v, a] in states() {
        let (qt, vt, at) = (&g * &q + &o, &g * &v, &g * &a);
        let mt = rt.mass_matrix(qt.as_slice()).unwrap();
        let m_hand = g.transpose() * &mt * &g;
        let mm = r.mass_matrix(q.as_slice()).unwrap();
        assert!(rel_err_mat(&mm, &m_hand, 1.0) < 1e-14);
        let tau_t = rt
            .inverse_dynamics(qt.as_slice(), vt.as_slice(), at.as_slice())
            .unwrap();
        let tau_hand = g.transpose() * tau_t;
        let tau = r
            .inverse_dynamics(q.as_slice(), v.as_slice(), a.as_slice())
            .unwrap();
        assert!(rel_err_vec(&tau, &tau_hand, 1.0) < 1e-14);
        // Forward dynamics solves the reduced equations: M·q̈ + h = τ.
        let qdd = r
            .forward_dynamics(q.as_slice(), v.as_slice(), tau.as_slice())
            .unwrap();
        assert!(rel_err_vec(&qdd, &a, 1.0) < 1e-12, "{qdd} vs {a}");
        // Whole-body quantities are the tree's at the tree's state.
        let e = r.kinetic_energy(q.as_slice(), v.as_slice()).unwrap();
        let et = rt.kinetic_energy(qt.as_slice(), vt.as_slice()).unwrap();
        assert!((e - et).abs() < 1e-14 * et.max(1.0));
        assert!((e - 0.5 * v.dot(&(&mm * &v))).abs() < 1e-14 * e.max(1.0));
        let h = r.centroidal_momentum(q.as_slice(), v.as_slice()).unwrap();
        let a_g = r.centroidal_momentum_matrix(q.as_slice()).unwrap();
        assert!(rel_err_vec(&DVector::from_column_slice(h.as_slice()), &(&a_g * &v), 1.0) < 1e-14);
        let j_com = r.center_of_mass_jacobian(q.as_slice()).unwrap();
        let j_hand = rt.center_of_mass_jacobian(qt.as_slice()).unwrap() * &g;
        assert!(rel_err_mat(&j_com, &j_hand, 1.0) < 1e-14);
        // The wrenches are the tree's, body by body.
        let w = r
            .joint_wrenches(q.as_slice(), v.as_slice(), a.as_slice())
            .unwrap();
        let wt = rt
            .joint_wrenches(qt.as_slice(), vt.as_slice(), at.as_slice())
            .unwrap();
        assert_eq!(w, wt);
    }
}

#[test]
fn wieber_s_columns_agree_with_the_coupled_recursions() {
    let m = gripper();
    let r = Reference::new(&m).unwrap();
    for [q, v, _] in states() {
        let w = wieber(&m, &[], q.as_slice(), v.as_slice()).unwrap();
        let mm = r.mass_matrix(q.as_slice()).unwrap();
        assert!(rel_err_mat(&w.mass_matrix, &mm, 1.0) < 1e-13);
        let bias = r.bias(q.as_slice(), v.as_slice()).unwrap();
        assert!(rel_err_vec(&(&w.n * &v), &bias, 1.0) < 1e-13);
        let gravity = r.gravity(q.as_slice()).unwrap();
        assert!(rel_err_vec(&(-&w.gravity_force), &gravity, 1.0) < 1e-13);
        let n = r.coriolis_matrix(q.as_slice(), v.as_slice()).unwrap();
        assert!(rel_err_vec(&(&n * &v), &bias, 1.0) < 1e-13);
    }
}

#[test]
fn derivatives_of_a_coupled_chain_are_its_finite_differences() {
    let r = Reference::new(&gripper()).unwrap();
    let [q, v, tau] = states()[3].clone();
    let [dq, dv, minv] = r
        .forward_dynamics_derivatives(q.as_slice(), v.as_slice(), tau.as_slice())
        .unwrap();
    let fd = |q: &DVector<f64>, v: &DVector<f64>| {
        r.forward_dynamics(q.as_slice(), v.as_slice(), tau.as_slice())
            .unwrap()
    };
    let h = 1e-6;
    for k in 0..3 {
        let e = DVector::from_fn(3, |i, _| if i == k { h } else { 0.0 });
        let num_q = (fd(&(&q + &e), &v) - fd(&(&q - &e), &v)) / (2.0 * h);
        let num_v = (fd(&q, &(&v + &e)) - fd(&q, &(&v - &e))) / (2.0 * h);
        assert!(rel_err_vec(&dq.column(k).into(), &num_q, 1.0) < 1e-6);
        assert!(rel_err_vec(&dv.column(k).into(), &num_v, 1.0) < 1e-6);
    }
    let m = r.mass_matrix(q.as_slice()).unwrap();
    assert!((minv * m - DMatrix::identity(3, 3)).amax() < 1e-12);
}

#[test]
fn a_bad_mimic_is_a_model_error_naming_the_joint() {
    let problem = |f: fn(&mut Model)| {
        let mut m = gripper();
        f(&mut m);
        match Reference::new(&m) {
            Err(Error::InvalidModel(ModelError::Mimic { joint, problem })) => (joint, problem),
            other => panic!("{other:?}"),
        }
    };
    let (joint, p) = problem(|m| m.joints[2].mimic = mimic(9, 1.0, 0.0));
    assert_eq!(joint, "finger2");
    assert!(p.contains("does not exist"), "{p}");
    let (_, p) = problem(|m| m.joints[2].mimic = mimic(2, 1.0, 0.0));
    assert!(p.contains("itself"), "{p}");
    let (joint, p) = problem(|m| m.joints[3].mimic = mimic(2, 1.0, 0.0));
    assert_eq!(joint, "tip2");
    assert!(
        p.contains("`finger2`, which is a mimic joint itself"),
        "{p}"
    );
    let (_, p) = problem(|m| m.joints[2].mimic = mimic(1, f64::NAN, 0.0));
    assert!(p.contains("finite"), "{p}");
    let (_, p) = problem(|m| m.joints[2].drive.damping = 1.0);
    assert!(p.contains("no damping, friction or limits"), "{p}");
    let (_, p) = problem(|m| {
        m.joints[0].kind = JointKind::SphericalQuaternion;
        m.joints[2].mimic = mimic(0, 1.0, 0.0);
    });
    assert!(p.contains("only revolute and prismatic"), "{p}");
}

/// Locking the joint a mimic joint follows locks both: the locked chain is the coupled one with
/// that coordinate held still, so its `M` is the coupled `M`'s principal sub-matrix and its `τ`
/// the coupled `τ`'s rows at `v = a = 0` on the locked coordinate. Then `keep` of the palm and
/// the branch without the fingers, which merges them as a payload: the mimic joint's index is
/// renumbered.
#[test]
fn locking_a_followed_joint_locks_the_joints_that_follow_it() {
    use articulated_dynamics::prune::{keep, lock, merge_fixed, PruneError};
    let m = gripper();
    let r = Reference::new(&m).unwrap();
    let locked = lock(&m, "finger1", &[0.3]).unwrap();
    assert_eq!(locked.joints[2].kind, JointKind::Fixed);
    assert_eq!(locked.joints[2].mimic, None);
    let rl = Reference::new(&locked).unwrap();
    assert_eq!(rl.nv(), 2);
    for [q, v, a] in states() {
        // wrist, finger1 (= 0.3, still), tip2.
        let full = |x: &DVector<f64>, middle: f64| vec![x[0], middle, x[2]];
        let (qf, vf, af) = (full(&q, 0.3), full(&v, 0.0), full(&a, 0.0));
        let (qr, vr, ar) = ([q[0], q[2]], [v[0], v[2]], [a[0], a[2]]);
        let mm = r.mass_matrix(&qf).unwrap();
        let sub = mm.select_rows(&[0, 2]).select_columns(&[0, 2]);
        assert!(rel_err_mat(&rl.mass_matrix(&qr).unwrap(), &sub, 1.0) < 1e-14);
        let tau = r.inverse_dynamics(&qf, &vf, &af).unwrap();
        let sub = DVector::from_vec(vec![tau[0], tau[2]]);
        let tau_locked = rl.inverse_dynamics(&qr, &vr, &ar).unwrap();
        assert!(rel_err_vec(&tau_locked, &sub, 1.0) < 1e-13);
    }
    // A mimic joint alone cannot be locked.
    assert_eq!(
        lock(&m, "finger2", &[0.1]),
        Err(PruneError::Mimic {
            joint: "finger2".into()
        })
    );
    // Nor dropped while the joint it follows moves.
    assert!(matches!(
        keep(&m, &["palm", "finger1"], &[]),
        Err(PruneError::Mimic { .. })
    ));
    // Keeping only the palm locks finger1 (and with it finger2) and tip2 at neutral.
    let palm = merge_fixed(&keep(&m, &["palm"], &[]).unwrap());
    assert_eq!((palm.nb(), palm.nv()), (1, 1));
    // A mimic joint after its fixed neighbours are merged still names the joint it follows.
    let mut shifted = gripper();
    shifted.joints[1].kind = JointKind::Fixed;
    shifted.joints[2].mimic = None;
    shifted.joints[3].mimic = mimic(2, 2.0, 0.0);
    let merged = merge_fixed(&shifted);
    assert_eq!(merged.joints.len(), 3);
    assert_eq!(merged.joints[2].mimic.map(|m| m.joint), Some(1));
    let (rs, rm) = (
        Reference::new(&shifted).unwrap(),
        Reference::new(&merged).unwrap(),
    );
    let q = [0.3, -0.4];
    assert!(
        rel_err_mat(
            &rm.mass_matrix(&q).unwrap(),
            &rs.mass_matrix(&q).unwrap(),
            1.0
        ) < 1e-14
    );
}
