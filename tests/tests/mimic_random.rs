//! Mimic joints on random trees of every joint kind (free bases, Euler and quaternion joints
//! included), up to 30 bodies, with couplings drawn at random: followers on any branch, before
//! or after the joint they follow, multipliers in `±[0.2, 2]`, offsets in `[−0.5, 0.5]`. Each
//! tree is held to
//! - its hand-written equivalent: the same tree with every joint independent, and `G` and `o`
//!   built here from the couplings, `M = Gᵀ·M_tree·G`,
//!   `τ = Gᵀ·τ_tree(G·q + o, G·v, G·a)`;
//! - Wieber's formulation, where a mimic joint's Jacobian column adds to the followed joint's;
//! - and the generator's graphs of every dynamics output (`Traced::eval`, what the generated
//!   code computes, without compiling it) against the reference.

mod common;

use articulated::nalgebra::{DMatrix, DVector};
use articulated::reference::jacobian::wieber;
use articulated::reference::Reference;
use articulated_codegen::options::Output;
use articulated_codegen::sym::Var;
use articulated_codegen::trace::trace;
use articulated_dynamics::model::{JointKind, Mimic, Model};
use articulated_dynamics::random::{random_model, random_state, Rng};
use common::{condition, fd_tol, rel_err};

/// Trees: `(seed, bodies)`.
const TREES: [(u64, usize); 8] = [
    (11, 2),
    (12, 3),
    (13, 5),
    (14, 8),
    (15, 12),
    (16, 16),
    (17, 22),
    (18, 30),
];

/// `model` with about half of its revolute and prismatic joints following another one.
fn with_mimics(mut model: Model, seed: u64) -> Model {
    let mut rng = Rng::new(seed);
    let one_axis: Vec<usize> = (0..model.nb())
        .filter(|&i| {
            matches!(
                model.joints[i].kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            )
        })
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

/// The tree with every joint independent, and `G` (`nv_tree × nv`) with `v_tree = G·v`, written
/// from the couplings.
fn hand_written(model: &Model) -> (Model, DMatrix<f64>) {
    let mut tree = model.clone();
    for j in &mut tree.joints {
        j.mimic = None;
    }
    // Where each joint's first coordinate is, in the tree and in the model.
    let (mut at_tree, mut at_model) = (Vec::new(), Vec::new());
    let (mut t, mut m) = (0, 0);
    for j in &model.joints {
        at_tree.push(t);
        at_model.push(m);
        t += j.kind.nv();
        m += if j.mimic.is_some() { 0 } else { j.kind.nv() };
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
    (tree, g)
}

fn rows(m: &DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

#[test]
fn coupled_random_trees_agree_with_their_hand_written_equivalents_wieber_and_the_generator() {
    let mut coupled = 0;
    for (seed, n) in TREES {
        let model = with_mimics(random_model(seed, n), seed);
        let mimics = model.joints.iter().filter(|j| j.mimic.is_some()).count();
        coupled += mimics;
        let label = format!("random tree {seed} ({n} bodies, {mimics} mimic joints)");
        let r = Reference::new(&model).unwrap_or_else(|e| panic!("{label}: {e}"));
        let (tree, g) = hand_written(&model);
        let rt = Reference::new(&tree).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let nv = model.nv();

        // The hand-written equivalent: the tree's q is the model's with each follower's
        // `multiplier·q_leader + offset` inserted (quaternions make q and v differ in length).
        let qt = tree_positions(&model, &q);
        let (vd, ad) = (
            DVector::from_column_slice(&v),
            DVector::from_column_slice(&a),
        );
        let (vt, at) = (&g * &vd, &g * &ad);
        let m = r.mass_matrix(&q).unwrap();
        let m_hand = g.transpose() * rt.mass_matrix(&qt).unwrap() * &g;
        let e_m = rel_err(m.as_slice(), m_hand.as_slice());
        let tau = r.inverse_dynamics(&q, &v, &a).unwrap();
        let tau_hand = g.transpose()
            * rt.inverse_dynamics(&qt, vt.as_slice(), at.as_slice())
                .unwrap();
        let e_tau = rel_err(tau.as_slice(), tau_hand.as_slice());
        // Wieber.
        let w = wieber(&model, &[], &q, &v).unwrap();
        let e_w = rel_err(w.mass_matrix.as_slice(), m.as_slice());
        println!("{label}: M {e_m:.1e}, tau {e_tau:.1e}, Wieber {e_w:.1e}");
        assert!(e_m < 1e-13 && e_tau < 1e-12 && e_w < 1e-12, "{label}");

        // The generator's graphs.
        let tau_in: Vec<f64> = tau.iter().map(|t| t - 0.25).collect();
        let input = |var: Var| match var {
            Var::Q(i) => q[i],
            Var::V(i) => v[i],
            Var::A(i) => a[i],
            Var::Tau(i) => tau_in[i],
            _ => 0.0,
        };
        let graph = |output| {
            let (values, ok) = trace(&model, output).eval(input);
            assert!(ok, "{label}: {output:?} refused");
            values
        };
        let e = [
            rel_err(&graph(Output::MassMatrix), &rows(&m)),
            rel_err(&graph(Output::InverseDynamics), tau.as_slice()),
            rel_err(&graph(Output::Bias), r.bias(&q, &v).unwrap().as_slice()),
            rel_err(&graph(Output::Gravity), r.gravity(&q).unwrap().as_slice()),
            rel_err(
                &graph(Output::CentroidalMomentumMatrix),
                &rows(&r.centroidal_momentum_matrix(&q).unwrap()),
            ),
            rel_err(
                &graph(Output::CoriolisMatrix),
                &rows(&r.coriolis_matrix(&q, &v).unwrap()),
            ),
        ];
        let derivatives = graph(Output::InverseDynamicsDerivatives);
        let (dq, dv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
        let e_d = rel_err(&derivatives[..nv * nv], &rows(&dq))
            .max(rel_err(&derivatives[nv * nv..], &rows(&dv)));
        let tol = fd_tol(condition(&m));
        let qdd = graph(Output::ForwardDynamics);
        let e_fd = rel_err(
            &qdd,
            r.forward_dynamics(&q, &v, &tau_in).unwrap().as_slice(),
        );
        let graphs: Vec<String> = e.iter().map(|e| format!("{e:.1e}")).collect();
        println!(
            "{label}: graphs [{}], dtau {e_d:.1e}, qdd {e_fd:.1e} (tol {tol:.1e})",
            graphs.join(", ")
        );
        assert!(e.iter().all(|&e| e < 1e-12), "{label}: {e:?}");
        assert!(e_d < 1e-11, "{label}: derivatives {e_d:e}");
        assert!(e_fd < tol, "{label}: forward dynamics {e_fd:e}");
    }
    assert!(coupled >= 12, "only {coupled} mimic joints drawn");
}

/// The tree's positions: the model's, with each follower's `multiplier·q_leader + offset`
/// inserted where its joint is.
fn tree_positions(model: &Model, q: &[f64]) -> Vec<f64> {
    let at = |i: usize| model.q_offset(i);
    let mut out = Vec::new();
    for (i, j) in model.joints.iter().enumerate() {
        match j.mimic {
            Some(c) => out.push(c.multiplier * q[at(c.joint)] + c.offset),
            None => out.extend_from_slice(&q[at(i)..at(i) + j.kind.nq()]),
        }
    }
    out
}
