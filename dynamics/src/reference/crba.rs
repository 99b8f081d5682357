//! The composite-rigid-body algorithm (Featherstone 2008, RBDA §6.2, Table 6.2): the joint-space
//! inertia matrix `M(q)`.

use alloc::vec::Vec;

use super::tree::Tree;
use crate::scalar::Scalar;
use crate::spatial::{Inertia, Transform};

/// `M(q)`, row-major `nv × nv`, the joints' armatures on its diagonal.
///
/// Composite inertias `I_c[λ] += X_upᵀ·I_c[i]·X_up` from the leaves in, then for each node
/// `F = I_c[i]·S_i`, `M_ii = S_iᵀ·F`, and `F` is carried to each ancestor `j` (`F = X_upᵀ·F`)
/// giving `M_ji = S_jᵀ·F` and its mirror `M_ij`.
///
/// Labels ([`Scalar::label`]), per node `n`: the composite inertia `n_ic_m`, `n_ic_h_x, …`,
/// `n_ic_i_xx, …`, the same in the parent's frame `n_ic_up_m, …`, and the force `F` of its
/// `k`-th motion `n_fs{k}_n_x, …`, `n_fs{k}_f_x, …`.
pub fn crba<T: Scalar>(tree: &Tree<T>, q: &[T]) -> Vec<T> {
    crba_with(tree, q, |ic, _, x_up| ic.to_parent(x_up))
}

/// [`crba`] with the composite inertias carried to the parent by `to_parent(I_c[i], i, X_up[i])`,
/// which must return `X_upᵀ·I_c[i]·X_up` (in the parent's frame): the generator passes one that
/// costs fewer operations symbolically (`articulated_codegen::crba`).
pub fn crba_with<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    to_parent: impl Fn(&Inertia<T>, usize, &Transform<T>) -> Inertia<T>,
) -> Vec<T> {
    let nv = tree.nv;
    let (x_up, ic) = composite_inertias_with(tree, q, to_parent);
    let mut m = alloc::vec![T::zero(); nv * nv];
    for (i, ic) in ic.iter().enumerate() {
        crba_columns(tree, &x_up, ic, i, &mut m);
    }
    m
}

/// Node `i`'s columns of `M` and their mirror rows, from its composite inertia `ic` and the
/// transforms `x_up` (as [`crba_with`] takes them: `F = I_c·S_k`, carried up by each `X_upᵀ`,
/// `M_jk = S_jᵀ·F`), with its armature on the diagonal; `m` is row-major `nv × nv`. The
/// generator calls it as soon as a composite inertia is complete
/// (`articulated_codegen::trace::crba`).
pub fn crba_columns<T: Scalar>(
    tree: &Tree<T>,
    x_up: &[Transform<T>],
    ic: &Inertia<T>,
    i: usize,
    m: &mut [T],
) {
    let nv = tree.nv;
    let node = &tree.nodes[i];
    let n = &node.name;
    for k in 0..node.nv() {
        let col = node.v_at + k;
        let mut f = ic
            .mul_motion(node.s_col(k))
            .label(format_args!("{n}_fs{k}_n"), format_args!("{n}_fs{k}_f"));
        for l in 0..node.nv() {
            m[(node.v_at + l) * nv + col] = node.s_col(l).dot(f);
        }
        let mut j = i;
        while let Some(p) = tree.nodes[j].parent {
            f = x_up[j].inv_apply_force(f);
            j = p;
            let nj = &tree.nodes[j];
            for l in 0..nj.nv() {
                let row = nj.v_at + l;
                let x = nj.s_col(l).dot(f);
                m[row * nv + col] = x;
                m[col * nv + row] = x;
            }
        }
    }
    node.add_armature_to_diagonal(m, nv);
}

/// Each node's transform from its parent (`X_up`, [`Tree::x_up`]) and its composite inertia
/// (its own and its descendants', in its frame), from the leaves in, each carried to the parent
/// by `to_parent` as in [`crba_with`]; labelled `n_ic_*` and `n_ic_up_*`.
pub fn composite_inertias_with<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    to_parent: impl Fn(&Inertia<T>, usize, &Transform<T>) -> Inertia<T>,
) -> (Vec<Transform<T>>, Vec<Inertia<T>>) {
    let x_up = tree.x_up(q);
    let mut ic: Vec<_> = tree.nodes.iter().map(|n| n.inertia).collect();
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        ic[i] = ic[i].label(format_args!("{}_ic", node.name));
        if let Some(p) = node.parent {
            let up = to_parent(&ic[i], i, &x_up[i]).label(format_args!("{}_ic_up", node.name));
            ic[p] = ic[p].add(&up);
        }
    }
    (x_up, ic)
}
