//! Regrouping of inertial parameters: moving onto each body's parent the part of its inertia
//! that the body's own joint cannot move, so the generated code multiplies by fewer terms.
//!
//! A spatial inertia `I_s` attached to node `i` can be attached to the parent instead, expressed
//! there through the joint's fixed placement `X_T` (`X_Tᵀ·I_s·X_T`), without changing the
//! kinetic or potential energy of the system for any `(q, q̇)`, when
//! - it is invariant under the joint's motion, `X_J(q)ᵀ·I_s·X_J(q) = I_s` for every `q`, and
//! - it has no inertia along the joint's motion, `I_s·S = 0`.
//!
//! Then its velocity `X_J·w + S·q̇_i` (`w` the parent's velocity through `X_T`) gives the same
//! energy `½·wᵀ·I_s·w` as the parent's, and its centre of mass does not move with `q_i`. The
//! Lagrangian is unchanged, so are `M(q)`, `N(q, q̇)·q̇`, `g(q)` and inverse dynamics; the
//! forces transmitted by each joint are not (they are never computed from a regrouped tree).
//! This is Khalil and Kleinfinger's regrouping of the base inertial parameters (Khalil & Dombre,
//! *Modeling, identification and control of robots*, 2002, §9.5), here in spatial form:
//!
//! | joint | movable part `I_s` (mass `m`, first moment `h`, rotational inertia `Ī` about the origin) |
//! |---|---|
//! | revolute about `u` | the mass: `m`, `h_s = u·(u·h)`, and `Ī_s = a·(1 − u·uᵀ)`, where `a` is chosen, for a coordinate axis `u = ±e_k`, to zero one diagonal entry of `Ī` (`a = Ī_jj`, `j = k + 1 mod 3`); `a = 0` otherwise |
//! | prismatic | the rotational inertia `Ī` (with `m = 0`, `h = 0` it does not change under translation) |
//! | spherical (quaternion) | the mass at the origin (`m`, `h = 0`, `Ī = 0`) |
//! | fixed | everything |
//! | free | nothing |
//!
//! Nodes are visited from the leaves to the root, so what a node receives from its children is
//! regrouped further with its own. Parts moved to the world (a root's parent) vanish: the world
//! does not move. The regrouped inertias need not be physical (`Ī` may lose positive
//! definiteness); the recursions traced on them are linear in the inertias.
//!
//! Regrouping pays when it turns entries into exact zeros that the products fold away (a
//! revolute child leaves `m = 0`, `h·u = 0` and one `Ī` entry `0`), and can cost when the moved
//! part densifies a sparse parent, or when parameters make the regrouped values expressions
//! evaluated at run time. [`crate::generate`] traces each output with and without it and keeps
//! the one with fewer operations.

use articulated_dynamics::reference::{NodeJoint, Tree};
use articulated_dynamics::spatial::{Inertia, Mat3, Vec3};
use articulated_dynamics::Scalar;

use crate::sym::Sym;

/// Moves every node's movable inertia onto its parent (see the [module docs](self)).
///
/// # Panics
/// Outside [`crate::sym::trace`] (the tree holds `Sym`s of the current trace).
pub fn regroup(tree: &mut Tree<Sym>) {
    for i in (0..tree.nodes.len()).rev() {
        let node = &tree.nodes[i];
        let Some(moved) = movable(node.joint, &node.inertia) else {
            continue;
        };
        let kept = sub(&node.inertia, &moved);
        let parent = node.parent;
        let up = moved.to_parent(&node.x_tree);
        tree.nodes[i].inertia = kept;
        if let Some(p) = parent {
            tree.nodes[p].inertia = tree.nodes[p].inertia.add(&up);
        }
    }
}

/// The part of `inertia` a node's joint cannot move (`None` when there is none).
fn movable(joint: NodeJoint<Sym>, inertia: &Inertia<Sym>) -> Option<Inertia<Sym>> {
    let zero = Sym::zero();
    match joint {
        NodeJoint::Revolute(u) => {
            let h = u.scale(u.dot(inertia.h));
            let i = match coordinate_axis(&u) {
                Some(k) => {
                    let j = (k + 1) % 3;
                    let a = inertia.i.0[j][j];
                    let mut ring = Mat3::identity();
                    for r in 0..3 {
                        for c in 0..3 {
                            ring.0[r][c] = (ring.0[r][c] - u.0[r] * u.0[c]) * a;
                        }
                    }
                    ring
                }
                None => Mat3::zero(),
            };
            Some(Inertia { m: inertia.m, h, i })
        }
        NodeJoint::Prismatic(_) => Some(Inertia {
            m: zero,
            h: Vec3::zero(),
            i: inertia.i,
        }),
        NodeJoint::Quaternion => Some(Inertia {
            m: inertia.m,
            h: Vec3::zero(),
            i: Mat3::zero(),
        }),
        NodeJoint::Fixed => Some(*inertia),
        NodeJoint::FreeQuaternion => None,
    }
}

/// `k` when `u` is the constant `±e_k`.
pub(crate) fn coordinate_axis(u: &Vec3<Sym>) -> Option<usize> {
    let c = u.0.map(Sym::constant);
    let is = |x: Option<f64>, v: f64| x.is_some_and(|x| x.abs() == v);
    (0..3).find(|&k| (0..3).all(|j| is(c[j], if j == k { 1.0 } else { 0.0 })))
}

/// `a − b`, entry by entry.
fn sub(a: &Inertia<Sym>, b: &Inertia<Sym>) -> Inertia<Sym> {
    Inertia {
        m: a.m - b.m,
        h: a.h - b.h,
        i: a.i.sub(&b.i),
    }
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::{aba, crba, joint_forces, rnea, Reference};

    use super::*;
    use crate::sym::{self, Var};

    fn max_rel(got: &[f64], want: &[f64]) -> f64 {
        let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
        got.iter()
            .zip(want)
            .map(|(g, w)| (g - w).abs() / scale)
            .fold(0.0, f64::max)
    }

    /// M, inverse dynamics and ABA's q̈ traced on the regrouped tree equal the reference's on
    /// the tree as described (random trees with every joint kind, random states), while the
    /// joint forces, which regrouping does not preserve, differ.
    #[test]
    fn regrouping_keeps_the_dynamics_and_moves_the_joint_forces() {
        let mut worst = 0.0f64;
        let mut forces_moved = 0;
        for seed in 0..60u64 {
            let model = random_model(seed, 1 + (seed as usize % 8));
            let reference = Reference::new(&model).unwrap();
            let (q, v, a) = random_state(&model, seed);
            let (nq, nv) = (model.nq(), model.nv());
            let (graph, (m, tau, qdd, forces)) = sym::trace(|| {
                let ins = |n: usize, f: fn(usize) -> Var| (0..n).map(move |i| Sym::input(f(i)));
                let (qs, vs, as_): (Vec<Sym>, Vec<Sym>, Vec<Sym>) = (
                    ins(nq, Var::Q).collect(),
                    ins(nv, Var::V).collect(),
                    ins(nv, Var::A).collect(),
                );
                let mut tree = Tree::new(&model, &[]);
                regroup(&mut tree);
                let m = crba(&tree, &qs);
                let tau = rnea(&tree, &qs, &vs, &as_, true);
                // ABA driven by τ = ID(q, v, a) must give back a.
                let qdd = aba(&tree, &qs, &vs, &tau, true).qdd;
                let forces: Vec<Sym> = joint_forces(&tree, &qs, &vs, &as_)
                    .into_iter()
                    .flat_map(|f| f.ang.0.into_iter().chain(f.lin.0))
                    .collect();
                (m, tau, qdd, forces)
            });
            let input = |var| match var {
                Var::Q(i) => q[i],
                Var::V(i) => v[i],
                Var::A(i) => a[i],
                _ => unreachable!(),
            };
            let got = |s: &[Sym]| graph.eval(s, input);
            let want_m = reference.mass_matrix(&q).unwrap();
            let want_m: Vec<f64> = want_m.transpose().iter().copied().collect();
            let want_tau: Vec<f64> = reference
                .inverse_dynamics(&q, &v, &a)
                .unwrap()
                .iter()
                .copied()
                .collect();
            let want_f: Vec<f64> = reference
                .joint_wrenches(&q, &v, &a)
                .unwrap()
                .iter()
                .flat_map(|w| w.couple.into_iter().chain(w.force))
                .collect();
            for (got, want) in [
                (got(&m), want_m),
                (got(&tau), want_tau),
                (got(&qdd), a.clone()),
            ] {
                let e = max_rel(&got, &want);
                assert!(e < 1e-11, "seed {seed}: {e:e}");
                worst = worst.max(e);
            }
            if max_rel(&got(&forces), &want_f) > 1e-6 {
                forces_moved += 1;
            }
        }
        assert!(worst < 1e-11, "{worst:e}");
        assert!(
            forces_moved > 30,
            "regrouping moved the joint forces of {forces_moved} trees"
        );
    }

    /// On a chain of revolute joints about coordinate axes, no body keeps any mass (the root's
    /// goes to the world), any first moment along its axis or one diagonal inertia entry.
    #[test]
    fn a_revolute_chain_keeps_no_mass() {
        let src =
            "chain C { body a { mass: 2.0, com: [0.1, 0.2, 0.3], inertia: diag(0.1, 0.2, 0.3) } \
                   body b { mass: 3.0, com: [0.3, -0.2, 0.1], inertia: diag(0.3, 0.2, 0.1) } \
                   joint ja: revolute(z) { parent: world, child: a } \
                   joint jb: revolute(y) { parent: a, child: b, xyz: [0.0, 0.0, 0.5] } }";
        let def: crate::parse::ChainDef = syn::parse_str(src).unwrap();
        let model = crate::lower::lower(&def).unwrap().model;
        let (_, inertias) = sym::trace(|| {
            let mut tree = Tree::new(&model, &[]);
            regroup(&mut tree);
            tree.nodes
                .iter()
                .map(|n| {
                    let i = n.inertia;
                    let c = |s: Sym| s.constant().unwrap();
                    (c(i.m), i.h.0.map(c), i.i.0.map(|r| r.map(c)))
                })
                .collect::<Vec<_>>()
        });
        // The root's mass goes to the world.
        assert!(inertias.iter().all(|(m, _, _)| *m == 0.0));
        // Body b turns about y: h_y = 0 and Ī_zz = 0 (j = y + 1 = z).
        assert_eq!(inertias[1].1[1], 0.0);
        assert_eq!(inertias[1].2[2][2], 0.0);
        // Body a turns about z: h_z = 0 and Ī_xx = 0.
        assert_eq!(inertias[0].1[2], 0.0);
        assert_eq!(inertias[0].2[0][0], 0.0);
    }
}
