//! The composite-rigid-body algorithm as the generator traces it: the reference's CRBA
//! (Featherstone 2008, RBDA §6.2) with the composite inertias carried to the parent in fewer
//! operations.
//!
//! The reference computes `I_λ += X_upᵀ·I_c·X_up` as `Eᵀ·Ī·E` and two cross-product terms, all
//! nine entries of each. Here:
//!
//! - **Only the upper triangle** of `Ī` is computed (it is symmetric; the graph cannot know that
//!   `(EᵀĪE)_ij` and `(EᵀĪE)_ji` are equal, so the reference's form costs both), with the
//!   translation terms in the form `−(y·rᵀ + r·hᵀ)` off the diagonal and `Σ_{k≠a} r_k·(y_k + h_k)`
//!   on it, `y = Eᵀh`, `h = y + m·r` (RBDA eq. 2.66 expanded by `(a×)(b×) = b·aᵀ − (a·b)·1`), so
//!   no term cancels another.
//! - **A revolute joint about a coordinate axis** `e_k` is applied separately from its fixed
//!   placement, `X_up = X_J(q)·X_T`, and its rotation by double angles: with `c = cos q`,
//!   `s = ±sin q` the entries of `E_J` in the plane `(j, l)` normal to the axis,
//!   `C = c² − s²`, `S = 2·c·s` (once per joint), the block `[[a, b], [b, d]]` of `Ī` becomes
//!   `p ± (t·C − b·S)` and `t·S + b·C` with `p = (a + d)/2`, `t = (a − d)/2`, and the entries
//!   coupling the plane to the axis rotate as a 2-vector. That is a dozen operations where
//!   `E_Jᵀ·Ī·E_J` takes about forty.
//!
//! The rest (each `F = I_c·S_i`, carried up by `X_upᵀ`, `M_ji = S_jᵀ·F`) is the reference's
//! own code ([`articulated_dynamics::reference::crba_columns`]).

use articulated_dynamics::reference::{
    centroidal, composite_inertias_with, crba_columns, NodeJoint, Tree,
};
use articulated_dynamics::spatial::{Inertia, Mat3, Transform, Vec3};
use articulated_dynamics::Scalar;

/// `M(q)`, row-major `nv × nv`, as [`articulated_dynamics::reference::crba()`] computes it (see
/// the [module docs](self)). `axis(u)` is `Some(k)` when the revolute axis `u` is `±e_k` and
/// should be applied by double angles.
///
/// The same operations as the reference's, in another order: each body's columns are taken as
/// soon as its composite inertia is complete (when the pass from the leaves reaches it), before
/// that inertia is carried to its parent, where the reference first builds every composite
/// inertia and then every column. The emitted code follows the order of tracing, so in the
/// reference's order every composite inertia (ten values a body) lives from the first pass to
/// the second. Alone this order measured no faster (LLVM spilled other values instead); with
/// the entries stored as computed and the hoisting of `codegen::emit`, the humanoid's `M` takes
/// fewer instructions than in the reference's order.
pub fn crba<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    axis: impl Fn(&Vec3<T>) -> Option<usize>,
) -> Vec<T> {
    crba_with_composites(tree, q, axis).0
}

/// [`crba`], with each node's composite inertia (in its own frame) and `X_up`: what the
/// condensed forward dynamics ([`super::condensed`]) builds on.
pub fn crba_with_composites<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    axis: impl Fn(&Vec3<T>) -> Option<usize>,
) -> (Vec<T>, Vec<Inertia<T>>, Vec<Transform<T>>) {
    let nv = tree.nv;
    let x_up = tree.x_up(q);
    let mut ic: Vec<Inertia<T>> = tree.nodes.iter().map(|n| n.inertia).collect();
    let mut m = vec![T::zero(); nv * nv];
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        // Complete: every child comes after its parent and has been added.
        ic[i] = ic[i].label(format_args!("{}_ic", node.name));
        crba_columns(tree, &x_up, &ic[i], i, &mut m);
        if let Some(p) = node.parent {
            let up = carried(tree, q, &axis, &ic[i], i, &x_up[i])
                .label(format_args!("{}_ic_up", node.name));
            ic[p] = ic[p].add(&up);
        }
    }
    (m, ic, x_up)
}

/// The centroidal momentum matrix `A_G(q)` (`articulated_dynamics::reference::centroidal`) with
/// the composite inertias carried as [`crba`] carries them.
pub fn centroidal_momentum_matrix<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    axis: impl Fn(&Vec3<T>) -> Option<usize>,
) -> Vec<T> {
    centroidal::centroidal_momentum_matrix_with(tree, q, |ic, i, x_up| {
        carried(tree, q, &axis, ic, i, x_up)
    })
}

/// The Coriolis matrix (`articulated_dynamics::reference::centroidal::coriolis_matrix_with`)
/// with its composite inertias and their rates carried as [`crba`] carries them.
pub fn coriolis_matrix<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    axis: impl Fn(&Vec3<T>) -> Option<usize>,
) -> Vec<T> {
    centroidal::coriolis_matrix_with(tree, q, v, |ic, i, x_up| {
        carried(tree, q, &axis, ic, i, x_up)
    })
}

/// `X_upᵀ·I_c·X_up` for node `i`: by double angles through a revolute joint about a coordinate
/// axis, then the fixed placement; by [`to_parent`] otherwise.
fn carried<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    axis: &impl Fn(&Vec3<T>) -> Option<usize>,
    ic: &Inertia<T>,
    i: usize,
    x_up: &Transform<T>,
) -> Inertia<T> {
    let node = &tree.nodes[i];
    match node.joint {
        NodeJoint::Revolute(u) => match axis(&u) {
            Some(k) => {
                let e = node.joint_transform(q).e;
                let turned = rotate_about(ic, &e, k, &node.name);
                to_parent(&turned, &node.x_tree)
            }
            None => to_parent(ic, x_up),
        },
        _ => to_parent(ic, x_up),
    }
}

/// `M(q)` as [`crba`] computes it, but with the entries between a joint and its ancestors
/// taken in the frame of the root body of its subtree rather than carried up joint by joint.
///
/// [`crba`] carries each `F = I_c·S` up to every ancestor, one transform per pair of joints:
/// `O(n²)` transforms on a chain of `n` joints. Here each body's frame is placed once in its
/// root body's frame (`X_rel`, one composition per body), each joint's `S` and each `F` are
/// turned into that frame once, and an entry is one dot product: `O(n)` transforms and `O(n²)`
/// dot products, which pays on long chains (the 50-body chain: about half the operations) and
/// not on short ones, where the generator keeps [`crba`]. The root body's frame, not the
/// world's: the root's own joint (a free base) then moves nothing in these quantities.
pub fn crba_in_root_frame<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    axis: impl Fn(&Vec3<T>) -> Option<usize>,
) -> Vec<T> {
    let nv = tree.nv;
    let (x_up, ic) =
        composite_inertias_with(tree, q, |ic, i, x_up| carried(tree, q, &axis, ic, i, x_up));
    // Each body's frame in its root body's frame (the root's own: the identity).
    let mut x_rel: Vec<Transform<T>> = Vec::with_capacity(tree.nodes.len());
    for (i, node) in tree.nodes.iter().enumerate() {
        let x = match node.parent {
            None => Transform::identity(),
            Some(p) => {
                let x = x_up[i].after(&x_rel[p]);
                Transform {
                    e: x.e.label(format_args!("{}_rel_e", node.name)),
                    r: x.r.label(format_args!("{}_rel_r", node.name)),
                }
            }
        };
        x_rel.push(x);
    }
    let s_rel: Vec<Vec<_>> = tree
        .nodes
        .iter()
        .enumerate()
        .map(|(j, nj)| {
            (0..nj.nv())
                .map(|l| {
                    x_rel[j].inv_apply_motion(nj.s_col(l)).label(
                        format_args!("{}_s{l}_rel_w", nj.name),
                        format_args!("{}_s{l}_rel_v", nj.name),
                    )
                })
                .collect()
        })
        .collect();
    let mut m = vec![T::zero(); nv * nv];
    for (i, node) in tree.nodes.iter().enumerate() {
        let n = &node.name;
        for k in 0..node.nv() {
            let col = node.v_at + k;
            let f = ic[i]
                .mul_motion(node.s_col(k))
                .label(format_args!("{n}_fs{k}_n"), format_args!("{n}_fs{k}_f"));
            for l in 0..node.nv() {
                m[(node.v_at + l) * nv + col] = node.s_col(l).dot(f);
            }
            if node.parent.is_none() {
                continue;
            }
            let f = x_rel[i].inv_apply_force(f).label(
                format_args!("{n}_fs{k}_rel_n"),
                format_args!("{n}_fs{k}_rel_f"),
            );
            let mut j = i;
            while let Some(p) = tree.nodes[j].parent {
                j = p;
                let nj = &tree.nodes[j];
                for (l, s) in s_rel[j].iter().enumerate() {
                    let row = nj.v_at + l;
                    let x = s.dot(f);
                    m[row * nv + col] = x;
                    m[col * nv + row] = x;
                }
            }
        }
        node.add_armature_to_diagonal(&mut m, nv);
    }
    m
}

/// `Xᵀ·I·X` for `x` from A to B (`I` in B coordinates, the result in A coordinates), the upper
/// triangle computed and mirrored.
fn to_parent<T: Scalar>(inertia: &Inertia<T>, x: &Transform<T>) -> Inertia<T> {
    let (e, r, m) = (&x.e, x.r, inertia.m);
    let y = e.tr_mul_vec(inertia.h);
    let h = y + r.scale(m);
    // Ī·E, then (Eᵀ·Ī·E)_ab = Σ_k E_ka·(Ī·E)_kb for a ≤ b, plus the translation terms: with
    // `h = y + m·r`, `y·rᵀ + r·yᵀ + m·r·rᵀ = y·rᵀ + r·hᵀ` off the diagonal, and on it
    // `2·r·y + m·r·r − 2·r_a·y_a − m·r_a² = Σ_{k≠a} r_k·(y_k + h_k)` (no cancelling terms).
    let ie = inertia.i.mul_mat(e);
    let mut i_a = Mat3::zero();
    for a in 0..3 {
        for b in a..3 {
            let rot = e.0[0][a] * ie.0[0][b] + e.0[1][a] * ie.0[1][b] + e.0[2][a] * ie.0[2][b];
            let v = if a == b {
                let (j, l) = ((a + 1) % 3, (a + 2) % 3);
                rot + r.0[j] * (y.0[j] + h.0[j]) + r.0[l] * (y.0[l] + h.0[l])
            } else {
                rot - y.0[a] * r.0[b] - r.0[a] * h.0[b]
            };
            i_a.0[a][b] = v;
            i_a.0[b][a] = v;
        }
    }
    Inertia { m, h, i: i_a }
}

/// `E_Jᵀ·I·E_J` for the rotation `E_J` about the coordinate axis `e_k` (a revolute joint's, no
/// translation), by double angles; labelled `{name}_cos2`, `{name}_sin2` (the double angle's),
/// `{name}_mean`, `{name}_half_diff` (`p`, `t`) and the result, the composite inertia in the joint frame, `{name}_icj_*` ([`Scalar::label`]).
fn rotate_about<T: Scalar>(inertia: &Inertia<T>, e: &Mat3<T>, k: usize, name: &str) -> Inertia<T> {
    let (j, l) = ((k + 1) % 3, (k + 2) % 3);
    // E restricted to the plane (j, l) is [[c, s], [−s, c]].
    let (c, s) = (e.0[j][j], e.0[j][l]);
    let two = T::from_f64(2.0);
    let half = T::from_f64(0.5);
    let c2 = (c * c - s * s).label(format_args!("{name}_cos2"));
    let s2 = (c * s * two).label(format_args!("{name}_sin2"));
    let ii = &inertia.i.0;
    let (a, b, d) = (ii[j][j], ii[j][l], ii[l][l]);
    let p = ((a + d) * half).label(format_args!("{name}_mean"));
    let t = ((a - d) * half).label(format_args!("{name}_half_diff"));
    let u = t * c2 - b * s2;
    let mut out = inertia.i;
    out.0[j][j] = p + u;
    out.0[l][l] = p - u;
    let off = t * s2 + b * c2;
    out.0[j][l] = off;
    out.0[l][j] = off;
    // Eᵀ·[x_j; x_l] = [c·x_j − s·x_l; s·x_j + c·x_l].
    let turn = |x: T, z: T| (c * x - s * z, s * x + c * z);
    let (jk, lk) = turn(ii[j][k], ii[l][k]);
    out.0[j][k] = jk;
    out.0[k][j] = jk;
    out.0[l][k] = lk;
    out.0[k][l] = lk;
    let mut h = inertia.h;
    (h.0[j], h.0[l]) = turn(inertia.h.0[j], inertia.h.0[l]);
    Inertia {
        m: inertia.m,
        h,
        i: out,
    }
    .label(format_args!("{name}_icj"))
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::Reference;

    use super::*;

    fn coordinate_axis(u: &Vec3<f64>) -> Option<usize> {
        (0..3).find(|&k| (0..3).all(|j| u.0[j].abs() == if j == k { 1.0 } else { 0.0 }))
    }

    /// Both ways equal to the reference's CRBA on random trees with every joint kind (Euler
    /// joints give revolute nodes about coordinate axes, so both paths run).
    #[test]
    fn equals_the_reference_crba_on_random_trees() {
        let mut worst = 0.0f64;
        let mut double_angle = 0;
        for seed in 0..200u64 {
            let model = random_model(seed, 1 + (seed as usize % 12));
            let reference = Reference::new(&model).unwrap();
            let (q, _, _) = random_state(&model, seed);
            let tree = reference.tree();
            double_angle += tree
                .nodes
                .iter()
                .filter(
                    |n| matches!(n.joint, NodeJoint::Revolute(u) if coordinate_axis(&u).is_some()),
                )
                .count();
            let want = reference.mass_matrix(&q).unwrap();
            let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            let n = model.nv();
            for got in [
                crba(tree, &q, coordinate_axis),
                crba_in_root_frame(tree, &q, coordinate_axis),
            ] {
                for r in 0..n {
                    for c in 0..n {
                        let e = (got[r * n + c] - want[(r, c)]).abs() / scale;
                        assert!(e < 1e-13, "seed {seed} ({r}, {c}): {e:e}");
                        worst = worst.max(e);
                    }
                }
            }
        }
        assert!(
            double_angle > 100,
            "{double_angle} nodes took the double-angle path"
        );
        assert!(worst < 1e-13, "{worst:e}");
    }
}
