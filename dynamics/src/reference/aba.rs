//! The articulated-body algorithm (Featherstone 2008, RBDA §7.3, Table 7.1): forward dynamics
//! `q̈ = M(q)⁻¹·(τ − N(q, q̇)·q̇ − g(q))` in O(n).

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use alloc::vec::Vec;

use super::tree::Tree;
use crate::scalar::Scalar;
use crate::spatial::{Force, Mat6, Motion};

/// The result of [`aba`].
#[derive(Clone, Debug, PartialEq)]
pub struct AbaOutput<T> {
    /// `q̈`, one entry per velocity coordinate.
    pub qdd: Vec<T>,
    /// The pivots of the `LDLᵀ` factorization of each joint's `D_i = S_iᵀ·I_i^A·S_i` (RBDA
    /// eq. 7.43), in velocity order: all must be positive for `M` to be positive definite. The
    /// generic code does not look at them (it may not compare scalars); the f64 front door does.
    pub pivots: Vec<T>,
    /// The diagonal of each `D_i` before factorization, in velocity order (a scale for
    /// `pivots`).
    pub diag: Vec<T>,
}

/// `LDLᵀ` of the leading `n × n` block of `d`, without pivoting: on return the strict lower
/// triangle holds `L` and the diagonal holds the pivots.
fn ldl<T: Scalar>(d: &mut [[T; 6]; 6], n: usize) {
    for j in 0..n {
        let mut dj = d[j][j];
        for k in 0..j {
            dj = dj - d[j][k] * d[j][k] * d[k][k];
        }
        d[j][j] = dj;
        for i in j + 1..n {
            let mut x = d[i][j];
            for k in 0..j {
                x = x - d[i][k] * d[j][k] * d[k][k];
            }
            d[i][j] = x / dj;
        }
    }
}

/// Solves `D·x = b` with the factor from [`ldl`].
fn ldl_solve<T: Scalar>(f: &[[T; 6]; 6], n: usize, b: [T; 6]) -> [T; 6] {
    let mut x = b;
    for i in 0..n {
        for k in 0..i {
            x[i] = x[i] - f[i][k] * x[k];
        }
    }
    for i in 0..n {
        x[i] = x[i] / f[i][i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            x[i] = x[i] - f[k][i] * x[k];
        }
    }
    x
}

/// What a node hands its parent (RBDA eqs. 7.34–7.37 for multi-axis joints): the articulated
/// inertia `I^a = I^A − U·D⁻¹·Uᵀ` and `U·D⁻¹·u`, from the node's `I^A`, the columns of `U`, the
/// factor of `D` ([`ldl`]) and `u`, for `n` motion axes.
fn handed_on<T: Scalar>(
    ia: &Mat6<T>,
    u_cols: &[Force<T>; 6],
    d: &[[T; 6]; 6],
    u: [T; 6],
    n: usize,
) -> (Mat6<T>, Force<T>) {
    let mut i_a = *ia;
    let mut ud_u = Force::zero();
    // Rows of D⁻¹·Uᵀ: solve D·Y = Uᵀ column by column (6 right-hand sides).
    let mut dinv_ut = [[T::zero(); 6]; 6]; // dinv_ut[k][col]
    for col in 0..6 {
        let mut b = [T::zero(); 6];
        for k in 0..n {
            b[k] = u_cols[k].to_array()[col];
        }
        let y = ldl_solve(d, n, b);
        for k in 0..n {
            dinv_ut[k][col] = y[k];
        }
    }
    let dinv_u = ldl_solve(d, n, u);
    for k in 0..n {
        let uk = u_cols[k].to_array();
        for r in 0..6 {
            for col in 0..6 {
                i_a.0[r][col] = i_a.0[r][col] - uk[r] * dinv_ut[k][col];
            }
        }
        ud_u = ud_u + u_cols[k].scale(dinv_u[k]);
    }
    (i_a, ud_u)
}

/// Forward dynamics by the articulated-body algorithm (RBDA Table 7.1, with multi-DOF joints as
/// in RBDA §7.3: `U_i = I_i^A·S_i`, `D_i = S_iᵀ·U_i + armature·1`, `u_i = τ_i − S_iᵀ·p_i^A`;
/// the rotor's inertia is felt by its joint alone, so it enters `D_i` and nothing else).
///
/// Labels ([`Scalar::label`]), per node `n`: velocity `n_w_x, …`, `n_v_x, …`, bias acceleration
/// `n_cw_x, …`, `n_cv_x, …`, `U`'s columns `n_u{k}_n_x, …`, `u` as `n_tu{k}`, `D` as `n_d{k}{l}`
/// and its pivots `n_pivot{k}`, the articulated inertia handed to the parent `n_ia{r}{c}` (upper
/// triangle) and its bias force `n_pa_n_x, …`, `n_pa_f_x, …`, both in the parent's frame
/// `n_ia_up{r}{c}`, `n_pa_up_n_x, …`, the acceleration `n_dw_x, …`, `n_dv_x, …`.
///
/// Pass 1: velocities, `c_i = v_i ×m (S·q̇_i)`, `I_i^A = I_i`, `p_i^A = v_i ×f (I_i·v_i)`.
/// Pass 2 (leaves in): `I^a = I^A − U·D⁻¹·Uᵀ`, `p^a = p^A + I^a·c + U·D⁻¹·u`, added to the
/// parent through `X_upᵀ`. Pass 3: `a_i = X_up·a_λ + c_i`, `q̈_i = D⁻¹·(u − Uᵀ·a_i)`,
/// `a_i += S·q̈_i`. With `with_gravity` the world accelerates by `−a_g`.
pub fn aba<T: Scalar>(
    tree: &Tree<T>,
    q: &[T],
    v: &[T],
    tau: &[T],
    with_gravity: bool,
) -> AbaOutput<T> {
    let nb = tree.nodes.len();
    let x_up = tree.x_up(q);
    let mut vel: Vec<Motion<T>> = Vec::with_capacity(nb);
    let mut c: Vec<Motion<T>> = Vec::with_capacity(nb);
    let mut ia: Vec<Mat6<T>> = Vec::with_capacity(nb);
    let mut pa: Vec<Force<T>> = Vec::with_capacity(nb);
    for (i, node) in tree.nodes.iter().enumerate() {
        let v_j = node.s_mul(v);
        let (v_i, c_i) = match node.parent {
            None => (v_j, Motion::zero()),
            Some(p) => {
                let v_i = x_up[i].apply_motion(vel[p]) + v_j;
                (v_i, v_i.cross_motion(v_j))
            }
        };
        let n = &node.name;
        vel.push(v_i.label(format_args!("{n}_w"), format_args!("{n}_v")));
        c.push(c_i.label(format_args!("{n}_cw"), format_args!("{n}_cv")));
        ia.push(node.inertia.to_mat6());
        pa.push(v_i.cross_force(node.inertia.mul_motion(v_i)));
    }

    let zero6 = [[T::zero(); 6]; 6];
    // Per node: U (columns), the LDLᵀ factor of D, u.
    let mut u_cols: Vec<[Force<T>; 6]> = alloc::vec![[Force::zero(); 6]; nb];
    let mut d_fac: Vec<[[T; 6]; 6]> = alloc::vec![zero6; nb];
    let mut u_vec: Vec<[T; 6]> = alloc::vec![[T::zero(); 6]; nb];
    let mut pivots = alloc::vec![T::zero(); tree.nv];
    let mut diag = alloc::vec![T::zero(); tree.nv];
    for (i, node) in tree.nodes.iter().enumerate().rev() {
        let n = node.nv();
        let mut d = zero6;
        let name = &node.name;
        for k in 0..n {
            let s_k = node.s_col(k);
            u_cols[i][k] = ia[i]
                .mul_motion(s_k)
                .label(format_args!("{name}_u{k}_n"), format_args!("{name}_u{k}_f"));
            u_vec[i][k] = (tau[node.v_at + k] - s_k.dot(pa[i])).label(format_args!("{name}_tu{k}"));
        }
        for k in 0..n {
            for l in 0..n {
                let mut x = node.s_col(k).dot(u_cols[i][l]);
                if k == l && node.armature != 0.0 {
                    x = x + T::from_f64(node.armature);
                }
                d[k][l] = x.label(format_args!("{name}_d{k}{l}"));
            }
            diag[node.v_at + k] = d[k][k];
        }
        ldl(&mut d, n);
        for k in 0..n {
            d[k][k] = d[k][k].label(format_args!("{name}_pivot{k}"));
            pivots[node.v_at + k] = d[k][k];
        }
        d_fac[i] = d;
        if let Some(p) = node.parent {
            let (i_a, ud_u) = handed_on(&ia[i], &u_cols[i], &d, u_vec[i], n);
            let i_a = i_a.label_symmetric(format_args!("{name}_ia"));
            let p_a = (pa[i] + i_a.mul_motion(c[i]) + ud_u)
                .label(format_args!("{name}_pa_n"), format_args!("{name}_pa_f"));
            let ia_up = i_a
                .to_parent(&x_up[i])
                .label_symmetric(format_args!("{name}_ia_up"));
            let pa_up = x_up[i].inv_apply_force(p_a).label(
                format_args!("{name}_pa_up_n"),
                format_args!("{name}_pa_up_f"),
            );
            ia[p] = ia[p].add(&ia_up);
            pa[p] = pa[p] + pa_up;
        }
    }

    let a0 = tree.base_acceleration(with_gravity);
    let mut acc: Vec<Motion<T>> = Vec::with_capacity(nb);
    let mut qdd = alloc::vec![T::zero(); tree.nv];
    for (i, node) in tree.nodes.iter().enumerate() {
        let a_par = match node.parent {
            None => a0,
            Some(p) => acc[p],
        };
        let mut a_i = x_up[i].apply_motion(a_par) + c[i];
        let n = node.nv();
        let mut b = [T::zero(); 6];
        for k in 0..n {
            b[k] = u_vec[i][k] - a_i.dot(u_cols[i][k]);
        }
        let x = ldl_solve(&d_fac[i], n, b);
        for k in 0..n {
            qdd[node.v_at + k] = x[k];
            a_i = a_i + node.s_col(k).scale(x[k]);
        }
        let n = &node.name;
        acc.push(a_i.label(format_args!("{n}_dw"), format_args!("{n}_dv")));
    }
    AbaOutput { qdd, pivots, diag }
}
