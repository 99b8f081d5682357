//! The recursive Newton–Euler algorithm (Featherstone 2008, RBDA §5.3, Table 5.1): inverse
//! dynamics `τ = M(q)·a + N(q, q̇)·q̇ + g(q)`, and the spatial force each joint transmits.

use alloc::vec::Vec;

use super::tree::Tree;
use crate::scalar::Scalar;
use crate::spatial::{Force, Transform};

/// The spatial forces `f[i]` each tree node's joint transmits from the parent to the node, in the
/// node's frame, about its origin (RBDA Table 5.1, lines 10 and 15), for the state `(q, v, a)`.
/// With `with_gravity`, gravity enters as the fictitious base acceleration `−a_g` (RBDA §5.3), so
/// the forces are the physical ones.
///
/// Forward pass: `v_i = X_up·v_λ + S·q̇_i`, `a_i = X_up·a_λ + S·q̈_i + v_i ×m (S·q̇_i)`,
/// `f_i = I_i·a_i + v_i ×f (I_i·v_i)`; backward pass: `f_λ += X_upᵀ·f_i`.
///
/// Labels ([`Scalar::label`]), per node `n`: velocity `n_w_x, …` (angular) and `n_v_x, …`
/// (linear), acceleration `n_dw_x, …` and `n_dv_x, …`, and those of [`transmit`].
pub fn node_forces<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
    with_gravity: bool,
) -> Vec<Force<T>> {
    let (x_up, mut f) = inertial_forces(tree, q, v, a, with_gravity);
    transmit(tree, &x_up, &mut f);
    f
}

/// The forward pass of [`node_forces`]: the transforms `X_up` and, per node, the net force its
/// body needs for its motion, `f_i = I_i·a_i + v_i ×f (I_i·v_i)` (gravity included as a base
/// acceleration with `with_gravity`), in the node's frame about its origin.
pub fn inertial_forces<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
    with_gravity: bool,
) -> (Vec<Transform<T>>, Vec<Force<T>>) {
    let x_up = tree.x_up(q);
    let a0 = tree.base_acceleration(with_gravity);
    let mut vel = Vec::with_capacity(tree.nodes.len());
    let mut acc = Vec::with_capacity(tree.nodes.len());
    let mut f = Vec::with_capacity(tree.nodes.len());
    for (i, node) in tree.nodes.iter().enumerate() {
        let v_j = node.s_mul(v);
        let (v_i, a_i) = match node.parent {
            None => (v_j, x_up[i].apply_motion(a0) + node.s_mul(a)),
            Some(p) => {
                let v_i = x_up[i].apply_motion(vel[p]) + v_j;
                let a_i = x_up[i].apply_motion(acc[p]) + node.s_mul(a) + v_i.cross_motion(v_j);
                (v_i, a_i)
            }
        };
        let n = &node.name;
        let v_i = v_i.label(format_args!("{n}_w"), format_args!("{n}_v"));
        let a_i = a_i.label(format_args!("{n}_dw"), format_args!("{n}_dv"));
        let inertia = &node.inertia;
        f.push(inertia.mul_motion(a_i) + v_i.cross_force(inertia.mul_motion(v_i)));
        vel.push(v_i);
        acc.push(a_i);
    }
    (x_up, f)
}

/// The backward pass of Newton–Euler (RBDA Table 5.1, lines 13–16): each node's own force `f_i`
/// becomes the force its joint transmits, `f_λ += X_upᵀ·f_i` from the leaves in. Labels
/// ([`Scalar::label`]): `n_n_x, …` and `n_f_x, …` for the transmitted couple and force, `n_up_n_x,
/// …` and `n_up_f_x, …` for the same in the parent's frame.
pub fn transmit<T: Scalar>(tree: &Tree<T>, x_up: &[Transform<T>], f: &mut [Force<T>]) {
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let n = &node.name;
        f[i] = f[i].label(format_args!("{n}_n"), format_args!("{n}_f"));
        if let Some(p) = node.parent {
            let up = x_up[i].inv_apply_force(f[i]);
            f[p] = f[p] + up.label(format_args!("{n}_up_n"), format_args!("{n}_up_f"));
        }
    }
}

/// Hemami's other way round (Hemami, Dariush & Barin 2005, §5: "the sequence can start from the
/// ground upwards"): from the wrench `base` the world exerts on the root body (a measured ground
/// reaction), in the root body's frame about its origin, the wrench each further joint transmits,
/// body by body up a serial chain: `f_c = X_up[c]·(f_i − h_i)` with `h_i` the body's
/// [`inertial_forces`]. Returns one wrench per model joint, as [`joint_forces`].
///
/// Given the true base wrench this equals [`joint_forces`]; on measured motion their difference
/// is the consistency check of the data. Needs a serial chain
/// ([`Model::is_serial`](crate::model::Model::is_serial)): where a
/// body has two children, how the remainder splits between them is not determined.
pub fn bottom_up<T: Scalar>(
    tree: &Tree<T>,
    x_up: &[Transform<T>],
    inertial: &[Force<T>],
    base: Force<T>,
) -> Vec<Force<T>> {
    let mut f = alloc::vec![Force::zero(); tree.nodes.len()];
    let Some(&root) = tree.body_node.first() else {
        return Vec::new();
    };
    f[root] = base;
    for (c, node) in tree.nodes.iter().enumerate().skip(root + 1) {
        if let Some(i) = node.parent {
            let n = &node.name;
            f[c] = x_up[c]
                .apply_force(f[i] - inertial[i])
                .label(format_args!("{n}_n"), format_args!("{n}_f"));
        }
    }
    tree.body_node.iter().map(|&b| f[b]).collect()
}

/// The generalized forces `τ_i = Sᵢᵀ·f_i` of the transmitted forces `f` (RBDA Table 5.1,
/// line 14).
pub fn project<T: Scalar>(tree: &Tree<T>, f: &[Force<T>]) -> Vec<T> {
    let mut tau = alloc::vec![T::zero(); tree.nv];
    for (node, f_i) in tree.nodes.iter().zip(f) {
        node.s_tr_mul(*f_i, &mut tau);
    }
    tau
}

/// Inverse dynamics by RNEA: `τ_i = Sᵢᵀ·f_i` (RBDA Table 5.1, line 14). With `with_gravity` this
/// is `M·a + N·q̇ + g`; without, `M·a + N·q̇`. So `bias = rnea(q, v, 0, false)` and
/// `gravity = rnea(q, 0, 0, true)`. The joints' rotors add `armature·a` (the armature is part
/// of `M`).
pub fn rnea<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T], a: &[T], with_gravity: bool) -> Vec<T> {
    let mut tau = project(tree, &node_forces(tree, q, v, a, with_gravity));
    for node in &tree.nodes {
        node.add_armature(a, &mut tau);
    }
    tau
}

/// The spatial force each **model** joint transmits (the parent on the child), in the child body
/// frame, about the child frame origin, angular first `[couple; force]`, with gravity: Hemami's
/// joint couple and reaction force. For an Euler joint this is the force into its last
/// (massive) node; the massless frames in between pass it on unchanged.
pub fn joint_forces<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T], a: &[T]) -> Vec<Force<T>> {
    let f = node_forces(tree, q, v, a, true);
    tree.body_node.iter().map(|&n| f[n]).collect()
}
