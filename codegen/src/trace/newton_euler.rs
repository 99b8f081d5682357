//! Inverse dynamics by the Newton–Euler recursion on classical accelerations (Luh, Walker & Paul
//! 1980; in the customized form of Khalil & Kleinfinger 1987, Khalil & Dombre 2002 §9.5), a
//! second formulation beside the reference's spatial RNEA that the generator traces when it
//! gives fewer operations.
//!
//! The spatial RNEA (RBDA §5.3) carries each body's spatial velocity and acceleration, including
//! the linear velocity of its origin, and forms `f = I·a + v ×* I·v`. Here the forward pass
//! carries only the angular velocity `ω`, the angular acceleration `ω̇` and the **classical**
//! linear acceleration `V̇` of each origin (all in the body's frame), and the force on a body
//! about its origin is
//!
//! `F = m·V̇ + U·h`, `N = Ī·ω̇ + ω × (Ī·ω) + h × V̇`, with `U = (ω̇×) + (ω×)(ω×)`,
//!
//! (`m`, `h = m·c`, `Ī`: the inertia about the origin). The linear velocity never appears: the
//! terms of the spatial form that contain it cancel. After [`super::regroup`] most bodies have
//! `m = 0`, which is where this form gains most.
//!
//! Forward pass for node `i` with parent `p`, `X_up = (E, r)` (`r`: the node's origin in the
//! parent's frame), `S·q̇ = [s_ω; s_v]` and `S·q̈ = [α; β]` (both constant-axis in the node's
//! frame, as in [`articulated_dynamics::reference::Tree`]), `w = E·ω_p`:
//!
//! - `ω_i = w + s_ω`
//! - `ω̇_i = E·ω̇_p + α + w × s_ω`
//! - `V̇_i = E·(V̇_p + U_p·r) + β + (2·w + s_ω) × s_v`
//!
//! The last line is the spatial acceleration's linear part plus `ω_i × v_i` (the classical
//! acceleration of a moving frame's origin) with the linear velocities cancelled; for a
//! prismatic joint it is the familiar Coriolis term `2·w × s_v`, for a free joint at the root
//! `β + ω × v`. The root's parent is the world: `ω = ω̇ = 0`, `V̇ = −g` (gravity as a base
//! acceleration, RBDA §5.3). The backward pass is the spatial one, `f_p += X_upᵀ·f_i`, and
//! `τ_i = Sᵢᵀ·f_i`.

use articulated_dynamics::reference::{project, transmit, Tree};
use articulated_dynamics::spatial::{Force, Mat3, Transform, Vec3};
use articulated_dynamics::Scalar;

/// `τ = M(q)·a + N(q, q̇)·q̇ (+ g(q) with `with_gravity`)`, as
/// [`articulated_dynamics::reference::rnea()`] computes it, by the classical-acceleration
/// Newton–Euler recursion (see the [module docs](self)).
///
/// Labels ([`Scalar::label`]), per node `n`: `n_w_x, …` (`ω`), `n_dw_x, …` (`ω̇`), `n_dv_x, …`
/// (`V̇`), `n_u_xx, …` (`U`), and those of the backward pass
/// ([`articulated_dynamics::reference::transmit`]).
pub fn classical_rnea<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
    with_gravity: bool,
) -> Vec<T> {
    let mut tau = project(tree, &classical_node_forces(tree, q, v, a, with_gravity));
    for node in &tree.nodes {
        node.add_armature(a, &mut tau);
    }
    tau
}

/// The forces each node's joint transmits, as [`articulated_dynamics::reference::node_forces`]
/// computes them, by the classical-acceleration recursion.
pub fn classical_node_forces<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
    with_gravity: bool,
) -> Vec<Force<T>> {
    let (x_up, mut f) = classical_inertial_forces(tree, q, v, a, with_gravity);
    transmit(tree, &x_up, &mut f);
    f
}

/// The forward pass: `X_up` and each body's own force about its origin, as
/// [`articulated_dynamics::reference::inertial_forces`] computes them.
pub fn classical_inertial_forces<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    a: &[T],
    with_gravity: bool,
) -> (Vec<Transform<T>>, Vec<Force<T>>) {
    let x_up = tree.x_up(q);
    let n = tree.nodes.len();
    let mut omega: Vec<Vec3<T>> = Vec::with_capacity(n);
    let mut omega_dot: Vec<Vec3<T>> = Vec::with_capacity(n);
    let mut accel: Vec<Vec3<T>> = Vec::with_capacity(n);
    let mut u: Vec<Mat3<T>> = Vec::with_capacity(n);
    let mut f: Vec<Force<T>> = Vec::with_capacity(n);
    let base = tree.base_acceleration(with_gravity).lin;
    for (i, node) in tree.nodes.iter().enumerate() {
        let x = &x_up[i];
        let (sv, sa) = (node.s_mul(v), node.s_mul(a));
        let (w, wd, lin) = match node.parent {
            None => (Vec3::zero(), Vec3::zero(), x.e.mul_vec(base)),
            Some(p) => (
                x.e.mul_vec(omega[p]),
                x.e.mul_vec(omega_dot[p]),
                x.e.mul_vec(accel[p] + u[p].mul_vec(x.r)),
            ),
        };
        let n = &node.name;
        let om = (w + sv.ang).label(format_args!("{n}_w"));
        let om_dot = (wd + sa.ang + w.cross(sv.ang)).label(format_args!("{n}_dw"));
        let acc = (lin + sa.lin + (w + w + sv.ang).cross(sv.lin)).label(format_args!("{n}_dv"));
        let u_i = u_matrix(om, om_dot).label(format_args!("{n}_u"));
        let inertia = &node.inertia;
        let force = acc.scale(inertia.m) + u_i.mul_vec(inertia.h);
        let i_om = inertia.i.mul_vec(om);
        let couple = inertia.i.mul_vec(om_dot) + om.cross(i_om) + inertia.h.cross(acc);
        f.push(Force::new(couple, force));
        omega.push(om);
        omega_dot.push(om_dot);
        accel.push(acc);
        u.push(u_i);
    }
    (x_up, f)
}

/// `U = (ω̇×) + (ω×)(ω×)`, written as `(ω̇×) + ω·ωᵀ − |ω|²·1` so the diagonal is
/// `−(ω_j² + ω_k²)`: two squares and a sum, no cancelling `ω_i²` terms.
fn u_matrix<T: Scalar>(om: Vec3<T>, om_dot: Vec3<T>) -> Mat3<T> {
    let w = om.0;
    let mut u = Mat3::skew(om_dot);
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        u.0[i][i] = -(w[j] * w[j] + w[k] * w[k]);
        u.0[i][j] = u.0[i][j] + w[i] * w[j];
        u.0[i][k] = u.0[i][k] + w[i] * w[k];
    }
    u
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::Reference;

    use super::*;

    /// Equal to the reference's spatial RNEA (inverse dynamics, bias, gravity) on random trees
    /// with every joint kind (free joints at the root, prismatic joints anywhere), to rounding.
    #[test]
    fn equals_the_spatial_rnea_on_random_trees() {
        let mut worst = 0.0f64;
        for seed in 0..200u64 {
            let model = random_model(seed, 1 + (seed as usize % 12));
            let reference = Reference::new(&model).unwrap();
            let (q, v, a) = random_state(&model, seed);
            let zero = vec![0.0; model.nv()];
            let tree = reference.tree();
            let cases = [
                (
                    classical_rnea(tree, &q, &v, &a, true),
                    reference.inverse_dynamics(&q, &v, &a).unwrap(),
                ),
                (
                    classical_rnea(tree, &q, &v, &zero, false),
                    reference.bias(&q, &v).unwrap(),
                ),
                (
                    classical_rnea(tree, &q, &zero, &zero, true),
                    reference.gravity(&q).unwrap(),
                ),
            ];
            for (got, want) in cases {
                let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
                for (g, w) in got.iter().zip(want.iter()) {
                    let e = (g - w).abs() / scale;
                    assert!(e < 1e-12, "seed {seed}: {g} vs {w}");
                    worst = worst.max(e);
                }
            }
        }
        assert!(worst < 1e-12, "{worst:e}");
    }
}
