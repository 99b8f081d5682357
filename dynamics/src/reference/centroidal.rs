//! The whole system's quantities (Wieber 2005, §3–5): centre of mass, momenta about it, kinetic
//! and potential energy, and the Coriolis matrix `N(q, q̇)` of eq. 7 itself.
//!
//! Like the other recursions, these run on any [`Scalar`] and never branch on one, so the
//! generator traces them. Conventions as everywhere: world axes for the centre of mass and the
//! momenta, spatial vectors angular first, so the centroidal momentum is `h_G = [k_G; p]` with
//! `k_G` the angular momentum about the centre of mass and `p` the linear momentum.
//!
//! - The centre of mass and its Jacobian come from each subtree's mass and first moment
//!   (`m_c`, `h_c = m_c·c_c` in the node's frame), carried from the leaves in: `h_λ += Eᵀ·h + m·r`.
//!   A motion `S = [ω; v]` of node `j` moves the centre of mass of the subtree it carries at
//!   `v + ω × c_c`, so the column of the Jacobian is `E_jᵀ·(m_c·v − h_c × ω) / m`, the linear
//!   half of `I_c·S` (Orin, Goswami & Lee 2013).
//! - The centroidal momentum matrix `A_G` has the column `X*_{G←j}·I_c[j]·S`: the composite
//!   inertia's momentum for a unit motion of the joint, moved to the centre of mass in world axes
//!   (Orin, Goswami & Lee 2013, eq. 22). The momentum itself, `h_G = A_G·v`, is summed directly:
//!   each body's momentum `I_i·v_i`, carried to the root like a force, then moved to `G`.
//! - Its rate `ḣ_G = A_G·a + Ȧ_G·v` is the sum of the bodies' net forces of Newton–Euler
//!   without gravity, `I_i·a_i + v_i ×* I_i·v_i`, carried in the same way, then moved to `G`:
//!   `k̇_G = k̇_O − x_G × ṗ`, since `ẋ_G × p = 0`.
//! - The Coriolis matrix is the factorization whose `Ṁ − 2N` is skew-symmetric and whose
//!   `N·v` is the bias: with the body Jacobian columns `t = ⁱX_j·S` and their rates
//!   `u = ⁱX_j·(v_j × S)` (every node's `S` is constant in its own frame,
//!   [`super::tree`]), each body adds `Jᵀ·(I·J̇ + B(I, v_i)·J)` with
//!   `B(I, v)·t = ½·(v ×* I·t − I·(v × t) + t ×* I·v)` (Echeandia & Wensing 2021, the
//!   factorization consistent with the Christoffel symbols): `B·v = v ×* I·v` gives the bias, and
//!   `İ − 2B` is the skew map `t ↦ −t ×* I·v`, so `Ṁ − 2N` is skew.

use alloc::vec::Vec;

use super::tree::Tree;
use crate::scalar::Scalar;
use crate::spatial::{Force, Inertia, Mat3, Motion, Transform, Vec3};

/// Each node's subtree mass `m_c` and first moment `h_c` (its own body and its descendants'),
/// in its frame about its origin, from the leaves in: `h_λ += E_upᵀ·h + m·r_up`. Labelled
/// `{node}_mc` and `{node}_hc_x, …`.
pub fn subtree_first_moments<T: Scalar>(
    tree: &Tree<T>,
    x_up: &[Transform<T>],
) -> Vec<(T, Vec3<T>)> {
    let mut moments: Vec<(T, Vec3<T>)> = tree
        .nodes
        .iter()
        .map(|n| (n.inertia.m, n.inertia.h))
        .collect();
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let (m, h) = moments[i];
        let n = &node.name;
        let (m, h) = (
            m.label(format_args!("{n}_mc")),
            h.label(format_args!("{n}_hc")),
        );
        moments[i] = (m, h);
        if let Some(p) = node.parent {
            let x = &x_up[i];
            let up = x.e.tr_mul_vec(h) + x.r.scale(m);
            moments[p] = (moments[p].0 + m, moments[p].1 + up);
        }
    }
    moments
}

/// The whole system's mass and first moment `Σ m_k·x_k` in the world frame: the roots'
/// subtree moments carried to the world.
fn world_first_moment<T: Scalar>(
    tree: &Tree<T>,
    x_up: &[Transform<T>],
    moments: &[(T, Vec3<T>)],
) -> (T, Vec3<T>) {
    let mut mass = T::zero();
    let mut first = Vec3::zero();
    for (i, node) in tree.nodes.iter().enumerate() {
        if node.parent.is_none() {
            let (m, h) = moments[i];
            mass = mass + m;
            first = first + x_up[i].e.tr_mul_vec(h) + x_up[i].r.scale(m);
        }
    }
    (mass, first)
}

/// The centre of mass `x_G` in the world frame, labelled `com_x, …`.
pub fn center_of_mass<T: Scalar>(tree: &Tree<T>, q: &[T]) -> Vec3<T> {
    let x_up = tree.x_up(q);
    let moments = subtree_first_moments(tree, &x_up);
    let (mass, first) = world_first_moment(tree, &x_up, &moments);
    com_from(mass, first)
}

fn com_from<T: Scalar>(mass: T, first: Vec3<T>) -> Vec3<T> {
    let inv_mass = (T::one() / mass).label(format_args!("inv_mass"));
    first.scale(inv_mass).label(format_args!("com"))
}

/// The potential energy of gravity `−Σ m_k·gᵀ·x_k = −gᵀ·(Σ m_k·x_k)`, zero with every centre of
/// mass at the world origin.
pub fn potential_energy<T: Scalar>(tree: &Tree<T>, q: &[T]) -> T {
    let x_up = tree.x_up(q);
    let moments = subtree_first_moments(tree, &x_up);
    let (_, first) = world_first_moment(tree, &x_up, &moments);
    -tree.gravity.dot(first)
}

/// Each node's pose in the world: `X0[i]`, world → node `i` (`E` its orientation transposed,
/// `r` its origin in the world). Labelled `{node}_e0_xx, …`, `{node}_r0_x, …`.
pub fn world_transforms<T: Scalar>(tree: &Tree<T>, x_up: &[Transform<T>]) -> Vec<Transform<T>> {
    let mut x0: Vec<Transform<T>> = Vec::with_capacity(tree.nodes.len());
    for (i, node) in tree.nodes.iter().enumerate() {
        let x = match node.parent {
            None => x_up[i],
            Some(p) => x_up[i].after(&x0[p]),
        };
        let n = &node.name;
        x0.push(Transform {
            e: x.e.label(format_args!("{n}_e0")),
            r: x.r.label(format_args!("{n}_r0")),
        });
    }
    x0
}

/// The centre of mass Jacobian `J_G` (`ẋ_G = J_G·v`), `3 × nv` row-major.
pub fn center_of_mass_jacobian<T: Scalar>(tree: &Tree<T>, q: &[T]) -> Vec<T> {
    let nv = tree.nv;
    let x_up = tree.x_up(q);
    let moments = subtree_first_moments(tree, &x_up);
    let (mass, _) = world_first_moment(tree, &x_up, &moments);
    let inv_mass = (T::one() / mass).label(format_args!("inv_mass"));
    let x0 = world_transforms(tree, &x_up);
    let mut jac = alloc::vec![T::zero(); 3 * nv];
    for (j, node) in tree.nodes.iter().enumerate() {
        let (mc, hc) = moments[j];
        for c in 0..node.nv() {
            let s = node.s_col(c);
            // The linear half of I_c·S: m_c·v − h_c × ω.
            let lin = s.lin.scale(mc) - hc.cross(s.ang);
            let col = x0[j].e.tr_mul_vec(lin).scale(inv_mass);
            for r in 0..3 {
                jac[r * nv + node.v_at + c] = col.0[r];
            }
        }
    }
    jac
}

/// Each node's spatial velocity `v_i` in its frame (RBDA Table 5.1, line 7), labelled
/// `{node}_w_x, …` and `{node}_v_x, …` like RNEA's.
pub fn velocities<T: Scalar>(tree: &Tree<T>, x_up: &[Transform<T>], v: &[T]) -> Vec<Motion<T>> {
    let mut vel: Vec<Motion<T>> = Vec::with_capacity(tree.nodes.len());
    for (i, node) in tree.nodes.iter().enumerate() {
        let v_j = node.s_mul(v);
        let v_i = match node.parent {
            None => v_j,
            Some(p) => x_up[i].apply_motion(vel[p]) + v_j,
        };
        let n = &node.name;
        vel.push(v_i.label(format_args!("{n}_w"), format_args!("{n}_v")));
    }
    vel
}

/// The centroidal momentum `h_G = [k_G; p]`: the angular momentum about the centre of mass and
/// the linear momentum, world axes.
pub fn centroidal_momentum<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> Force<T> {
    let x_up = tree.x_up(q);
    let vel = velocities(tree, &x_up, v);
    let moments = subtree_first_moments(tree, &x_up);
    let (mass, first) = world_first_moment(tree, &x_up, &moments);
    let com = com_from(mass, first);
    // Each subtree's momentum about its node's origin, carried in like RNEA's forces.
    let mut h: Vec<Force<T>> = tree
        .nodes
        .iter()
        .zip(&vel)
        .map(|(n, &v_i)| n.inertia.mul_motion(v_i))
        .collect();
    let mut world = Force::zero();
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let n = &node.name;
        let h_i = h[i].label(format_args!("{n}_hm_n"), format_args!("{n}_hm_f"));
        let up = x_up[i].inv_apply_force(h_i);
        match node.parent {
            Some(p) => h[p] = h[p] + up,
            None => world = world + up,
        }
    }
    // About the world origin; about G: k_G = k_O − x_G × p.
    let (k_o, p) = (world.ang, world.lin);
    Force::new(k_o - com.cross(p), p)
}

/// The rate of the centroidal momentum `ḣ_G = A_G·a + Ȧ_G·v = [k̇_G; ṗ]`, world axes, same
/// layout as [`centroidal_momentum`]. The momentum about the world origin `h_O = Σ I_i·v_i` has
/// the rate `Σ (I_i·a_i + v_i ×* I_i·v_i)`: each body's net force of Newton–Euler without
/// gravity ([`super::rnea::inertial_forces`]), summed to the world like the momenta. About the
/// centre of mass `k_G = k_O − x_G × p`, and `ẋ_G × p = 0` (`p = m·ẋ_G`), so
/// `k̇_G = k̇_O − x_G × ṗ`; the linear part `ṗ` is the same about any point. Without gravity:
/// gravity adds `[0; m·g]`, an external force, not part of the motion's rate (Wieber 2005, §5).
/// The rotors' armature is left out, as in [`centroidal_momentum`].
///
/// Labels, per node `n`: those of [`super::rnea::inertial_forces`], and `n_dhm_n_x, …`,
/// `n_dhm_f_x, …` for the subtree's rate about the node's origin.
pub fn centroidal_momentum_rate<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T], a: &[T]) -> Force<T> {
    let (x_up, mut f) = super::rnea::inertial_forces(tree, q, v, a, false);
    let moments = subtree_first_moments(tree, &x_up);
    let (mass, first) = world_first_moment(tree, &x_up, &moments);
    let com = com_from(mass, first);
    // Each subtree's net force about its node's origin, carried in as in `centroidal_momentum`.
    let mut world = Force::zero();
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let n = &node.name;
        let f_i = f[i].label(format_args!("{n}_dhm_n"), format_args!("{n}_dhm_f"));
        let up = x_up[i].inv_apply_force(f_i);
        match node.parent {
            Some(p) => f[p] = f[p] + up,
            None => world = world + up,
        }
    }
    let (dk_o, dp) = (world.ang, world.lin);
    Force::new(dk_o - com.cross(dp), dp)
}

/// The drift of the centroidal momentum `Ȧ_G·v`: [`centroidal_momentum_rate`] at `a = 0`.
pub fn centroidal_momentum_drift<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> Force<T> {
    let zero = alloc::vec![T::zero(); tree.nv];
    centroidal_momentum_rate(tree, q, v, &zero)
}

/// The velocity of the centre of mass, `ẋ_G = p / m`, world frame, labelled `com_v_x, …`.
pub fn center_of_mass_velocity<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> Vec3<T> {
    let mass = tree.nodes.iter().fold(T::zero(), |m, n| m + n.inertia.m);
    let inv_mass = (T::one() / mass).label(format_args!("inv_mass"));
    let p = centroidal_momentum(tree, q, v).lin;
    p.scale(inv_mass).label(format_args!("com_v"))
}

/// The centroidal momentum matrix `A_G(q)` (`h_G = A_G·v`), `6 × nv` row-major, angular rows
/// first. `to_parent` carries a composite inertia to the parent as in
/// [`super::crba::crba_with`].
pub fn centroidal_momentum_matrix_with<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    to_parent: impl Fn(&Inertia<T>, usize, &Transform<T>) -> Inertia<T>,
) -> Vec<T> {
    let nv = tree.nv;
    let (x_up, ic) = super::crba::composite_inertias_with(tree, q, to_parent);
    let moments = subtree_first_moments(tree, &x_up);
    let (mass, first) = world_first_moment(tree, &x_up, &moments);
    let com = com_from(mass, first);
    let x0 = world_transforms(tree, &x_up);
    let mut a = alloc::vec![T::zero(); 6 * nv];
    for (j, node) in tree.nodes.iter().enumerate() {
        // The node's origin seen from the centre of mass.
        let offset = x0[j].r - com;
        for c in 0..node.nv() {
            let f = ic[j].mul_motion(node.s_col(c));
            let (n_w, f_w) = (x0[j].e.tr_mul_vec(f.ang), x0[j].e.tr_mul_vec(f.lin));
            let n_g = n_w + offset.cross(f_w);
            for r in 0..3 {
                a[r * nv + node.v_at + c] = n_g.0[r];
                a[(r + 3) * nv + node.v_at + c] = f_w.0[r];
            }
        }
    }
    a
}

/// [`centroidal_momentum_matrix_with`] with the plain `Xᵀ·I·X`.
pub fn centroidal_momentum_matrix<T: Scalar>(tree: &Tree<T>, q: &[T]) -> Vec<T> {
    centroidal_momentum_matrix_with(tree, q, |ic, _, x| ic.to_parent(x))
}

/// The kinetic energy `½·Σ v_iᵀ·I_i·v_i`, plus the rotors' `½·Σ armature·v_k²` (so that it is
/// `½·vᵀ·M·v` with the `M` of [`crba`](super::crba()), the energy a simulation conserves).
pub fn kinetic_energy<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> T {
    let x_up = tree.x_up(q);
    let vel = velocities(tree, &x_up, v);
    let twice = tree
        .nodes
        .iter()
        .zip(&vel)
        .fold(T::zero(), |sum, (n, &v_i)| {
            sum + v_i.dot(n.inertia.mul_motion(v_i))
        });
    let twice = tree
        .nodes
        .iter()
        .filter(|n| n.armature != 0.0)
        .fold(twice, |sum, n| {
            let armature = T::from_f64(n.armature);
            (n.v_at..n.v_at + n.nv()).fold(sum, |s, k| s + armature * v[k] * v[k])
        });
    twice * T::from_f64(0.5)
}

/// [`coriolis_matrix`] body by body, as its definition reads: for each column, every body below
/// its joint adds `Jᵀ·(I·J̇ + B(I, v_i)·J)`. `O(n·d²)`: the cross-check of the composite form.
pub fn coriolis_matrix_by_bodies<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> Vec<T> {
    let nv = tree.nv;
    let nn = tree.nodes.len();
    let x_up = tree.x_up(q);
    let vel = velocities(tree, &x_up, v);
    // I_i·v_i, the body's momentum, shared by every column.
    let momentum: Vec<Force<T>> = tree
        .nodes
        .iter()
        .zip(&vel)
        .map(|(n, &v_i)| n.inertia.mul_motion(v_i))
        .collect();
    let half = T::from_f64(0.5);
    let mut n_mat = alloc::vec![T::zero(); nv * nv];
    for (j, node) in tree.nodes.iter().enumerate() {
        // The subtree of j: nodes are depth first, so it is j and the run after it whose parents
        // are in it.
        let mut in_subtree = alloc::vec![false; nn];
        in_subtree[j] = true;
        for i in j + 1..nn {
            in_subtree[i] = tree.nodes[i].parent.is_some_and(|p| in_subtree[p]);
        }
        for c in 0..node.nv() {
            let col = node.v_at + c;
            let s = node.s_col(c);
            // t: the Jacobian column in each body's frame; u: its rate.
            let mut t = alloc::vec![Motion::zero(); nn];
            let mut u = alloc::vec![Motion::zero(); nn];
            let mut f = alloc::vec![Force::zero(); nn];
            for i in j..nn {
                if !in_subtree[i] {
                    continue;
                }
                if i == j {
                    t[i] = s;
                    u[i] = vel[j].cross_motion(s);
                } else {
                    let p = tree.nodes[i].parent.unwrap_or(j);
                    t[i] = x_up[i].apply_motion(t[p]);
                    u[i] = x_up[i].apply_motion(u[p]);
                }
                let inertia = &tree.nodes[i].inertia;
                let b = (vel[i].cross_force(inertia.mul_motion(t[i]))
                    - inertia.mul_motion(vel[i].cross_motion(t[i]))
                    + t[i].cross_force(momentum[i]))
                .scale(half);
                f[i] = inertia.mul_motion(u[i]) + b;
            }
            // Sum each subtree's forces into its root, leaves first, and project.
            for i in (j..nn).rev() {
                if !in_subtree[i] {
                    continue;
                }
                let ni = &tree.nodes[i];
                for l in 0..ni.nv() {
                    n_mat[(ni.v_at + l) * nv + col] = ni.s_col(l).dot(f[i]);
                }
                if i > j {
                    let p = ni.parent.unwrap_or(j);
                    f[p] = f[p] + x_up[i].inv_apply_force(f[i]);
                }
            }
            // Then on to the ancestors of j.
            let mut fj = f[j];
            let mut k = j;
            while let Some(p) = tree.nodes[k].parent {
                fj = x_up[k].inv_apply_force(fj);
                k = p;
                let nk = &tree.nodes[k];
                for l in 0..nk.nv() {
                    n_mat[(nk.v_at + l) * nv + col] = nk.s_col(l).dot(fj);
                }
            }
        }
    }
    n_mat
}

/// The rate `İ = v ×* I − I·(v ×)` of a body's inertia `I` (in its frame) moving at `v = [ω; v]`:
/// the world-frame derivative seen in the body's coordinates. It has the shape of an inertia:
/// no mass, `ḣ = ω × h + m·v`, `dĪ = ω×·Ī − Ī·ω× − (h·vᵀ + v·hᵀ − 2·(v·h)·1)`.
pub fn inertia_rate<T: Scalar>(inertia: &Inertia<T>, vel: Motion<T>) -> Inertia<T> {
    let (w, lin) = (vel.ang, vel.lin);
    let wx = Mat3::skew(w);
    let turn = wx.mul_mat(&inertia.i).sub(&inertia.i.mul_mat(&wx));
    let (h, vh) = (inertia.h, lin.dot(inertia.h));
    let mut i = turn;
    for r in 0..3 {
        for c in 0..3 {
            let mut x = h.0[r] * lin.0[c] + lin.0[r] * h.0[c];
            if r == c {
                x = x - (vh + vh);
            }
            i.0[r][c] = turn.0[r][c] - x;
        }
    }
    Inertia {
        m: T::zero(),
        h: w.cross(h) + lin.scale(inertia.m),
        i,
    }
}

/// The Coriolis matrix `N(q, q̇)` of Wieber 2005, eq. 7, `nv × nv` row-major: `N·v` is the bias
/// and `Ṁ − 2N` is skew-symmetric (see the [module docs](self)).
///
/// With the world-frame Jacobian columns `s` (the same for every body below a joint) and their
/// rates `ṡ = v_j × s`, the definition `Σ_i Jᵀ·(I·J̇ + B(I, v_i)·J)` becomes
/// `N_rk = Σ_i s_rᵀ·I_i·ṡ_k + ½·s_rᵀ·İ_i·s_k − ½·(s_k × s_r)ᵀ·I_i·v_i`, a sum over the bodies
/// below both joints, which are those below the deeper one. So three composites per node suffice
/// (inertia `I_c`, its rate `İ_c`, momentum `h_c`, carried from the leaves in, the inertias by
/// `to_parent` as in [`super::crba::crba_with`]): where `k`'s joint is the deeper (or the same),
/// `N_rk = s_rᵀ·(I_c·ṡ_k + ½·İ_c·s_k + ½·s_k ×* h_c)`, a force carried up like CRBA's; where
/// `r`'s is the deeper, `N_rk = ṡ_kᵀ·(I_c·s_r) + s_kᵀ·½·(İ_c·s_r − s_r ×* h_c)`, two forces
/// carried up and dotted with each ancestor's `ṡ` and `s`. `O(n·d)`, like CRBA.
///
/// Labels, per node `n`: `n_idc_*` (the composite inertia rate), `n_hc_n_x, …`, `n_hc_f_x, …`
/// (the composite momentum), those of [`super::crba::composite_inertias_with`].
pub fn coriolis_matrix_with<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    to_parent: impl Fn(&Inertia<T>, usize, &Transform<T>) -> Inertia<T>,
) -> Vec<T> {
    let nv = tree.nv;
    let x_up = tree.x_up(q);
    let vel = velocities(tree, &x_up, v);
    let mut ic: Vec<Inertia<T>> = tree.nodes.iter().map(|n| n.inertia).collect();
    let mut idot: Vec<Inertia<T>> = tree
        .nodes
        .iter()
        .zip(&vel)
        .map(|(n, &v_i)| inertia_rate(&n.inertia, v_i))
        .collect();
    let mut hc: Vec<Force<T>> = tree
        .nodes
        .iter()
        .zip(&vel)
        .map(|(n, &v_i)| n.inertia.mul_motion(v_i))
        .collect();
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let n = &node.name;
        ic[i] = ic[i].label(format_args!("{n}_ic"));
        idot[i] = idot[i].label(format_args!("{n}_idc"));
        hc[i] = hc[i].label(format_args!("{n}_hc_n"), format_args!("{n}_hc_f"));
        if let Some(p) = node.parent {
            let x = &x_up[i];
            ic[p] = ic[p].add(&to_parent(&ic[i], i, x).label(format_args!("{n}_ic_up")));
            idot[p] = idot[p].add(&to_parent(&idot[i], i, x).label(format_args!("{n}_idc_up")));
            hc[p] = hc[p] + x.inv_apply_force(hc[i]);
        }
    }
    let half = T::from_f64(0.5);
    let mut n_mat = alloc::vec![T::zero(); nv * nv];
    for (j, node) in tree.nodes.iter().enumerate() {
        for c in 0..node.nv() {
            let col = node.v_at + c;
            let s = node.s_col(c);
            let s_dot = vel[j].cross_motion(s);
            let idot_s = idot[j].mul_motion(s);
            let s_h = s.cross_force(hc[j]);
            // Column `col` against this node's and its ancestors' coordinates.
            let mut f = ic[j].mul_motion(s_dot) + (idot_s + s_h).scale(half);
            // Row `col` against the ancestors' coordinates.
            let mut a = ic[j].mul_motion(s);
            let mut b = (idot_s - s_h).scale(half);
            for l in 0..node.nv() {
                n_mat[(node.v_at + l) * nv + col] = node.s_col(l).dot(f);
            }
            let mut k = j;
            while let Some(p) = tree.nodes[k].parent {
                let x = &x_up[k];
                f = x.inv_apply_force(f);
                a = x.inv_apply_force(a);
                b = x.inv_apply_force(b);
                k = p;
                let np = &tree.nodes[p];
                for l in 0..np.nv() {
                    let (row, s_l) = (np.v_at + l, np.s_col(l));
                    n_mat[row * nv + col] = s_l.dot(f);
                    n_mat[col * nv + row] = vel[p].cross_motion(s_l).dot(a) + s_l.dot(b);
                }
            }
        }
    }
    n_mat
}

/// [`coriolis_matrix_with`] with the plain `Xᵀ·I·X`.
pub fn coriolis_matrix<T: Scalar>(tree: &Tree<T>, q: &[T], v: &[T]) -> Vec<T> {
    coriolis_matrix_with(tree, q, v, |ic, _, x| ic.to_parent(x))
}
