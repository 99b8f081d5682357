//! Pruned models against the full model they came from: a locked joint is the full model with
//! those coordinates held (zero velocity and acceleration), merging fixed joints changes no
//! dynamics at all, and a sub-tree is the full model with the dropped joints held.

use articulated_dynamics::model::{JointKind, Model};
use articulated_dynamics::prune::{keep, lock, merge_fixed, PruneError};
use articulated_dynamics::random::{random_model, random_state, Rng};
use articulated_dynamics::reference::Reference;
use nalgebra::{DMatrix, DVector};

/// The full model's coordinates with the locked joints' at `values`, the others from `q`
/// (positions) or zero (velocities), for a reduced model whose joints are the full model's minus
/// the locked ones.
fn expand(full: &Model, locked: &[(&str, Vec<f64>)], q: &[f64], positions: bool) -> Vec<f64> {
    let mut out = Vec::new();
    let mut at = 0;
    for j in &full.joints {
        let n = if positions { j.kind.nq() } else { j.kind.nv() };
        match locked.iter().find(|(name, _)| *name == j.name) {
            Some((_, v)) if positions => out.extend_from_slice(v),
            Some(_) => out.extend(std::iter::repeat_n(0.0, n)),
            None => {
                out.extend_from_slice(&q[at..at + n]);
                at += n;
            }
        }
    }
    out
}

/// The rows and columns of the full model's velocities that the reduced model keeps.
fn kept_velocities(full: &Model, locked: &[(&str, Vec<f64>)]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut at = 0;
    for j in &full.joints {
        if !locked.iter().any(|(name, _)| *name == j.name) {
            out.extend(at..at + j.kind.nv());
        }
        at += j.kind.nv();
    }
    out
}

fn max_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let scale = b.amax().max(1.0);
    (a - b).amax() / scale
}

/// Every reduced quantity against the full model's, at three random states of the reduced one.
fn agrees(full: &Model, reduced: &Model, locked: &[(&str, Vec<f64>)], tol: f64) {
    let (rf, rr) = (
        Reference::new(full).unwrap(),
        Reference::new(reduced).unwrap(),
    );
    let keep = kept_velocities(full, locked);
    assert_eq!(keep.len(), reduced.nv());
    for seed in 0..3 {
        let (q, v, a) = random_state(reduced, seed);
        let (qf, vf, af) = (
            expand(full, locked, &q, true),
            expand(full, locked, &v, false),
            expand(full, locked, &a, false),
        );
        let mf = rf
            .mass_matrix(&qf)
            .unwrap()
            .select_rows(&keep)
            .select_columns(&keep);
        assert!(max_diff(&rr.mass_matrix(&q).unwrap(), &mf) < tol, "M");
        let tf = rf
            .inverse_dynamics(&qf, &vf, &af)
            .unwrap()
            .select_rows(&keep);
        let tr = rr.inverse_dynamics(&q, &v, &a).unwrap();
        let d = DMatrix::from_column_slice(tr.len(), 1, (tr - &tf).as_slice());
        assert!(d.amax() < tol * tf.amax().max(1.0), "τ: {d}");
        // Forward dynamics with the locked coordinates held: the kept block of M solves it.
        let qdd = rr.forward_dynamics(&q, &v, tf.as_slice()).unwrap();
        let back = DVector::from_vec(a.clone());
        assert!(
            (qdd - back).amax() < 1e3 * tol * (1.0 + a.iter().fold(0.0f64, |m, x| m.max(x.abs())))
        );
        let (cf, cr) = (
            rf.center_of_mass(&qf).unwrap(),
            rr.center_of_mass(&q).unwrap(),
        );
        assert!((cf - cr).amax() < tol, "centre of mass");
        let (ef, er) = (
            rf.potential_energy(&qf).unwrap(),
            rr.potential_energy(&q).unwrap(),
        );
        assert!(
            (ef - er).abs() < tol * ef.abs().max(1.0),
            "potential energy"
        );
    }
}

#[test]
fn locked_joints_hold_their_coordinates() {
    let mut rng = Rng::new(7);
    for seed in 0..40 {
        let full = random_model(seed, 2 + seed as usize % 8);
        // Lock one moving joint at a random value (a random state's coordinates for it).
        let moving: Vec<usize> = (0..full.joints.len())
            .filter(|&i| full.joints[i].kind != JointKind::Fixed)
            .collect();
        if moving.len() < 2 {
            continue;
        }
        let i = moving[rng.below(moving.len())];
        let (qf, _, _) = random_state(&full, seed + 100);
        let at = full.q_offset(i);
        let values = qf[at..at + full.joints[i].kind.nq()].to_vec();
        let name = full.joints[i].name.clone();
        let locked_model = lock(&full, &name, &values).unwrap();
        let locked = [(name.as_str(), values)];
        agrees(&full, &locked_model, &locked, 1e-12);
        // Merging the new fixed joint changes nothing more.
        let merged = merge_fixed(&locked_model);
        assert!(merged.bodies.len() <= locked_model.bodies.len());
        merged.check().unwrap();
        agrees(&full, &merged, &locked, 1e-12);
    }
}

#[test]
fn merging_fixed_joints_changes_no_dynamics() {
    let mut merged_some = 0;
    for seed in 0..60 {
        let full = random_model(seed, 2 + seed as usize % 10);
        let merged = merge_fixed(&full);
        merged.check().unwrap();
        if merged.bodies.len() < full.bodies.len() {
            merged_some += 1;
        }
        agrees(&full, &merged, &[], 1e-12);
    }
    assert!(
        merged_some > 5,
        "the random models have fixed joints to merge"
    );
}

#[test]
fn a_sub_tree_lumps_the_rest_as_a_payload() {
    for seed in 0..30 {
        let full = random_model(seed, 4 + seed as usize % 8);
        // Keep the first half of the bodies (pre-order: each one's parent comes first).
        let n = full.bodies.len() / 2;
        let names: Vec<&str> = full.bodies[..n].iter().map(|b| b.name.as_str()).collect();
        let reduced = merge_fixed(&keep(&full, &names, &[]).unwrap());
        let locked: Vec<(&str, Vec<f64>)> = full.joints[n..]
            .iter()
            .filter(|j| j.kind != JointKind::Fixed)
            .map(|j| (j.name.as_str(), j.kind.neutral()))
            .collect();
        assert!(reduced.nv() <= full.nv());
        agrees(&full, &reduced, &locked, 1e-12);
    }
}

#[test]
fn bad_requests_are_refused_with_a_message() {
    let full = random_model(3, 5);
    assert_eq!(
        lock(&full, "nope", &[0.0]),
        Err(PruneError::UnknownJoint("nope".into()))
    );
    let j = full
        .joints
        .iter()
        .find(|j| j.kind.nq() == 1)
        .expect("a one-coordinate joint");
    let e = lock(&full, &j.name, &[0.0, 1.0]).unwrap_err();
    assert!(e.to_string().contains("2 values"), "{e}");
    assert!(matches!(
        lock(&full, &j.name, &[f64::NAN]),
        Err(PruneError::Value { .. })
    ));
    let leaf = &full.bodies[full.bodies.len() - 1].name;
    let e = keep(&full, &[leaf.as_str()], &[]).unwrap_err();
    assert!(matches!(e, PruneError::NotConnected { .. }), "{e}");
    assert!(matches!(
        keep(&full, &["ghost"], &[]),
        Err(PruneError::UnknownBody(_))
    ));
}
