//! Forward dynamics by CRBA + `LᵀDL` with the limbs condensed where they branch off.
//!
//! The sparse `LᵀDL` of [`super::forward`] eliminates each coordinate against all of its
//! ancestors: on a humanoid, every arm joint's elimination updates the 9 × 9 block of the free
//! base and the waist, and the arm's entries with those 9 coordinates must be computed first,
//! each a force carried down the waist. Here each subtree hanging off a branching body `P`
//! (the torso: the arms and the neck) is eliminated against its own coordinates only, and its
//! effect on the rest of the tree (the trunk) is one 6 × 6 matrix at `P`:
//!
//! - with `Φ` the forces `F_l = I_c·S_l` of the subtree's coordinates in `P`'s frame (the
//!   CRBA's own, carried to `P`) and `Ψ` the motions of the trunk's coordinates in `P`'s
//!   frame, `M_LT = Φᵀ·Ψ`; so the trunk's Schur complement is
//!   `M_TT − Ψᵀ·K·Ψ` with `K = Φ·M_LL⁻¹·Φᵀ`, and its right-hand side `b_T − Ψᵀ·f` with
//!   `f = Φ·M_LL⁻¹·b_L`;
//! - `K = Wᵀ·D⁻¹·W` and `f = Wᵀ·D⁻¹·z` with `M_LL = LᵀDL`, `W = L⁻ᵀ·Φᵀ`, `z = L⁻ᵀ·b_L`;
//! - `Ψᵀ·K·Ψ` is computed as the CRBA computes `M` from a composite inertia: `K` carried up
//!   from `P` to the root (`Xᵀ·K·X` per joint), each trunk joint's column `K_j·S_s` carried up
//!   to its ancestors;
//! - the trunk is solved by the sparse `LᵀDL`, then each subtree from `P`'s acceleration
//!   `a_P = Ψ·q̈_T`: `q̈_L = L⁻¹·D⁻¹·(z − W·a_P)`.
//!
//! The same `q̈` as the sparse `LᵀDL` of the whole `M`: the same order of elimination (each
//! subtree before the rest), the updates of the rest grouped through `K`.
//!
//! What it saves: an arm of 7 joints below 9 trunk coordinates costs the sparse `LᵀDL` about
//! 1,540 operations (`Σ a(a+1)/2` updates for `a` = 9…15 ancestors, and the solves) and the CRBA
//! 7 × 3 forces carried down the waist; here about 1,000 (its own `LᵀDL`, `W`, `K`, `f`), against
//! three `Xᵀ·K·X` for the trunk (about 140 operations each). Not at the root: a leg below the 6
//! coordinates of a free base costs the same either way (about 770 and 790 operations), and the
//! whole upper body as one subtree would cost more. The generator keeps this form where it has
//! the fewest operations: on the shipped humanoid, 11,478 against 12,547 for the sparse `LᵀDL`.

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use articulated_dynamics::model::Model;
use articulated_dynamics::reference::{ltdl_factor_of, Tree};
use articulated_dynamics::spatial::{Force, Inertia, Mat6, Motion, Transform};
use articulated_dynamics::Scalar;

use crate::sym::Sym;

/// Whether `model` has a body that [`cut_points`] would condense at: one not attached to the
/// world with two or more child joints whose subtrees have coordinates. (Its tree then has such
/// a node: a body is the last node of its joint's expansion, so it has a parent node.)
pub(crate) fn applies(model: &Model) -> bool {
    let nb = model.joints.len();
    // Each body's subtree's coordinates, from the leaves in (a joint's parent comes first).
    let mut nv = vec![0; nb];
    for b in (0..nb).rev() {
        nv[b] += model.joints[b].nv();
        if let Some(p) = model.joints[b].parent {
            nv[p] += nv[b];
        }
    }
    (0..nb).any(|b| {
        model.joints[b].parent.is_some()
            && (0..nb)
                .filter(|&c| model.joints[c].parent == Some(b) && nv[c] > 0)
                .count()
                >= 2
    })
}

/// The branching bodies whose subtrees are condensed: every body other than the root with two
/// or more child subtrees that have coordinates, and not itself inside a condensed subtree.
pub(crate) fn cut_points(tree: &Tree<Sym>) -> Vec<usize> {
    let mut cuts: Vec<usize> = Vec::new();
    for (p, node) in tree.nodes.iter().enumerate() {
        if node.parent.is_none() || cuts.iter().any(|&c| is_descendant(tree, p, c)) {
            continue;
        }
        if children_with_coordinates(tree, p).len() >= 2 {
            cuts.push(p);
        }
    }
    cuts
}

/// Whether node `i` is a strict descendant of node `a`.
fn is_descendant(tree: &Tree<Sym>, i: usize, a: usize) -> bool {
    let mut j = i;
    while let Some(p) = tree.nodes[j].parent {
        if p == a {
            return true;
        }
        j = p;
    }
    false
}

/// The children of `p` whose subtrees have coordinates.
fn children_with_coordinates(tree: &Tree<Sym>, p: usize) -> Vec<usize> {
    (p + 1..tree.nodes.len())
        .filter(|&c| tree.nodes[c].parent == Some(p) && !subtree_coordinates(tree, c).is_empty())
        .collect()
}

/// The coordinates of node `c`'s subtree (contiguous: nodes are in depth-first order).
fn subtree_coordinates(tree: &Tree<Sym>, c: usize) -> core::ops::Range<usize> {
    let lo = tree.nodes[c].v_at;
    let mut hi = lo + tree.nodes[c].nv();
    for (i, node) in tree.nodes.iter().enumerate().skip(c + 1) {
        if !is_descendant(tree, i, c) {
            break;
        }
        hi = hi.max(node.v_at + node.nv());
    }
    lo..hi
}

/// `LᵀDL` of the rows and columns `idx` of `m` (row-major `nv × nv`, its lower triangle read),
/// eliminating from the last of `idx`: the reference's factorization, its structural zeros
/// skipped.
fn factor(m: &mut [Sym], nv: usize, idx: &[usize]) {
    ltdl_factor_of(m, nv, idx, |x| x.constant() == Some(0.0));
}

/// `L⁻ᵀ·b` for the factor of `idx` ([`factor`]): `w_i = b_i − Σ_{k > i} L_ki·w_k`.
fn solve_lt<V: Copy>(
    l: &[Sym],
    nv: usize,
    idx: &[usize],
    b: &mut [V],
    mul_sub: impl Fn(V, Sym, V) -> V,
) {
    for (a, &k) in idx.iter().enumerate().rev() {
        for (ai, &i) in idx[..a].iter().enumerate() {
            let lki = l[k * nv + i];
            if lki.constant() != Some(0.0) {
                b[ai] = mul_sub(b[ai], lki, b[a]);
            }
        }
    }
}

/// `Xᵀ·K·X` for a symmetric `K` (B coordinates) and `x` from A to B: the upper triangle
/// computed, mirrored.
fn carry_sym(k: &Mat6<Sym>, x: &Transform<Sym>) -> Mat6<Sym> {
    let xm = x.to_mat6();
    let t = k.mul_mat(&xm);
    let mut r = Mat6::zero();
    for i in 0..6 {
        for j in i..6 {
            let mut s = Sym::zero();
            for row in 0..6 {
                s = s + xm.0[row][i] * t.0[row][j];
            }
            r.0[i][j] = s;
            r.0[j][i] = s;
        }
    }
    r
}

/// What a condensed subtree keeps for its back-substitution: its branching body `p`, its
/// coordinates, the rows of `W = L⁻ᵀ·Φᵀ` and `z = L⁻ᵀ·b_L`.
struct Limb {
    p: usize,
    idx: Vec<usize>,
    w: Vec<[Sym; 6]>,
    z: Vec<Sym>,
}

/// `M·q̈ = b` with the subtrees of `cuts` condensed (module docs). `m` row-major `nv × nv` from
/// [`super::crba::crba_with_composites`] with its composite inertias `ic` and transforms `x_up`.
/// Returns `q̈` and each coordinate's pivot with its unreduced `M_kk`.
pub(crate) fn solve(
    tree: &Tree<Sym>,
    ic: &[Inertia<Sym>],
    x_up: &[Transform<Sym>],
    mut m: Vec<Sym>,
    mut b: Vec<Sym>,
    cuts: &[usize],
) -> (Vec<Sym>, Vec<(Sym, Sym)>) {
    let nv = tree.nv;
    let unreduced: Vec<Sym> = (0..nv).map(|k| m[k * nv + k]).collect();
    let mut in_limb = vec![false; nv];
    let mut limbs: Vec<Limb> = Vec::new();
    for &p in cuts {
        let mut k_p = Mat6::zero();
        let mut f_p = [Sym::zero(); 6];
        for c in children_with_coordinates(tree, p) {
            let idx: Vec<usize> = subtree_coordinates(tree, c).collect();
            for &l in &idx {
                in_limb[l] = true;
            }
            let phi = forces_at_branch(tree, ic, x_up, c);
            let (w, z) = condense(&mut m, &b, nv, &idx, phi, &mut k_p, &mut f_p);
            limbs.push(Limb { p, idx, w, z });
        }
        for r in 0..6 {
            for s in 0..r {
                k_p.0[r][s] = k_p.0[s][r];
            }
        }
        carry_to_root(tree, x_up, &mut m, &mut b, k_p, Force::from_array(f_p), p);
    }
    // The trunk's system, by the sparse LᵀDL.
    let trunk: Vec<usize> = (0..nv).filter(|&k| !in_limb[k]).collect();
    factor(&mut m, nv, &trunk);
    let mut x: Vec<Sym> = trunk.iter().map(|&k| b[k]).collect();
    solve_lt(&m, nv, &trunk, &mut x, |a, l, b| a - l * b);
    let mut qdd = vec![Sym::zero(); nv];
    for (a, &k) in trunk.iter().enumerate() {
        x[a] = (x[a] / m[k * nv + k]).label(format_args!("y_{k}"));
    }
    solve_l(&m, nv, &trunk, &x, &mut qdd);
    // Each subtree from its branching body's acceleration.
    let mut a_at: Vec<Option<Motion<Sym>>> = vec![None; tree.nodes.len()];
    for limb in &limbs {
        let a_p = acceleration(tree, x_up, &qdd, &mut a_at, limb.p).to_array();
        let idx = &limb.idx;
        let mut y: Vec<Sym> = Vec::with_capacity(idx.len());
        for (a, &l) in idx.iter().enumerate() {
            let mut z = limb.z[a];
            for r in 0..6 {
                z = z - limb.w[a][r] * a_p[r];
            }
            y.push((z / m[l * nv + l]).label(format_args!("y_{l}")));
        }
        solve_l(&m, nv, idx, &y, &mut qdd);
    }
    let pairs = (0..nv).map(|k| (m[k * nv + k], unreduced[k])).collect();
    (qdd, pairs)
}

/// `Φ` of the subtree at `c`: each of its coordinates' `F = I_c·S`, carried into the frame of
/// `c`'s parent as `crba_columns` carries it (so the graph shares the CRBA's own nodes).
fn forces_at_branch(
    tree: &Tree<Sym>,
    ic: &[Inertia<Sym>],
    x_up: &[Transform<Sym>],
    c: usize,
) -> Vec<[Sym; 6]> {
    let mut phi = Vec::new();
    for (i, node) in tree.nodes.iter().enumerate() {
        if i != c && !is_descendant(tree, i, c) {
            continue;
        }
        for k in 0..node.nv() {
            let mut f: Force<Sym> = ic[i].mul_motion(node.s_col(k));
            let mut j = i;
            loop {
                f = x_up[j].inv_apply_force(f);
                match tree.nodes[j].parent {
                    Some(p) if j != c => j = p,
                    _ => break,
                }
            }
            phi.push(f.to_array());
        }
    }
    phi
}

/// Factors the subtree's block `idx` of `m` in place and adds its `Wᵀ·D⁻¹·W` to the upper
/// triangle of `k_p` and its `Wᵀ·D⁻¹·z` to `f_p`; returns `W`'s rows and `z`.
fn condense(
    m: &mut [Sym],
    b: &[Sym],
    nv: usize,
    idx: &[usize],
    phi: Vec<[Sym; 6]>,
    k_p: &mut Mat6<Sym>,
    f_p: &mut [Sym; 6],
) -> (Vec<[Sym; 6]>, Vec<Sym>) {
    factor(m, nv, idx);
    let mut w = phi;
    solve_lt(m, nv, idx, &mut w, |a, l, b| {
        core::array::from_fn(|r| a[r] - l * b[r])
    });
    let mut z: Vec<Sym> = idx.iter().map(|&l| b[l]).collect();
    solve_lt(m, nv, idx, &mut z, |a, l, b| a - l * b);
    for (a, &l) in idx.iter().enumerate() {
        let inv_d = (Sym::one() / m[l * nv + l]).label(format_args!("inv_d_{l}"));
        let wd: [Sym; 6] = core::array::from_fn(|r| w[a][r] * inv_d);
        for r in 0..6 {
            for s in r..6 {
                k_p.0[r][s] = k_p.0[r][s] + wd[r] * w[a][s];
            }
            f_p[r] = f_p[r] + wd[r] * z[a];
        }
    }
    (w, z)
}

/// Takes `Ψᵀ·K·Ψ` from the trunk's entries of `m` and `Ψᵀ·f` from `b`: `K` and `f` carried
/// from `p` to the root as the CRBA carries a composite inertia, each trunk column `K_j·S_s`
/// carried to the ancestors.
fn carry_to_root(
    tree: &Tree<Sym>,
    x_up: &[Transform<Sym>],
    m: &mut [Sym],
    b: &mut [Sym],
    k_p: Mat6<Sym>,
    f_p: Force<Sym>,
    p: usize,
) {
    let nv = tree.nv;
    // Subtracts `x` from the entry (s, row) and from its mirror.
    let mut take = |s: usize, row: usize, x: Sym| {
        let v = m[s * nv + row] - x;
        m[s * nv + row] = v;
        m[row * nv + s] = v;
    };
    let (mut k_j, mut f_j, mut j) = (k_p, f_p, p);
    loop {
        let node = &tree.nodes[j];
        for k in 0..node.nv() {
            let s = node.v_at + k;
            b[s] = b[s] - node.s_col(k).dot(f_j);
            let mut col = k_j.mul_motion(node.s_col(k));
            for l in 0..=k {
                take(s, node.v_at + l, node.s_col(l).dot(col));
            }
            let mut jj = j;
            while let Some(pp) = tree.nodes[jj].parent {
                col = x_up[jj].inv_apply_force(col);
                jj = pp;
                let nj = &tree.nodes[jj];
                for l in 0..nj.nv() {
                    take(s, nj.v_at + l, nj.s_col(l).dot(col));
                }
            }
        }
        match node.parent {
            None => break,
            Some(pp) => {
                k_j = carry_sym(&k_j, &x_up[j]);
                f_j = x_up[j].inv_apply_force(f_j);
                j = pp;
            }
        }
    }
}

/// `L·q̈ = y` for the factor of `idx` ([`factor`]), from its first coordinate: each
/// `q̈_k = y_k − Σ_{i < k} L_ki·q̈_i`, labelled, into `qdd`.
fn solve_l(m: &[Sym], nv: usize, idx: &[usize], y: &[Sym], qdd: &mut [Sym]) {
    for (a, &k) in idx.iter().enumerate() {
        let mut acc = y[a];
        for &i in &idx[..a] {
            let lki = m[k * nv + i];
            if lki.constant() != Some(0.0) {
                acc = acc - lki * qdd[i];
            }
        }
        qdd[k] = acc.label(format_args!("qdd_{k}"));
    }
}

/// Node `j`'s acceleration `Σ X·S·q̈` over its joint and its ancestors' (no velocity terms),
/// in its frame, memoised in `a_at`.
fn acceleration(
    tree: &Tree<Sym>,
    x_up: &[Transform<Sym>],
    qdd: &[Sym],
    a_at: &mut [Option<Motion<Sym>>],
    j: usize,
) -> Motion<Sym> {
    if let Some(a) = a_at[j] {
        return a;
    }
    let node = &tree.nodes[j];
    let mut a = match node.parent {
        None => Motion::zero(),
        Some(p) => x_up[j].apply_motion(acceleration(tree, x_up, qdd, a_at, p)),
    };
    for k in 0..node.nv() {
        a = a + node.s_col(k).scale(qdd[node.v_at + k]);
    }
    a_at[j] = Some(a);
    a
}

#[cfg(test)]
mod tests {
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::Reference;

    use super::applies;
    use crate::sym::Var;
    use crate::trace::forward::{trace_variant, variants, FdMethod};

    /// On random trees of every joint kind that branch off a body other than the root, the
    /// condensed forward dynamics is the reference's (ABA) to `max(1e-12, 1e-13·κ(M))` of the
    /// largest value, and the product of its pivots is `det M` (each subtree's pivots times
    /// those of the trunk's Schur complement). Not vacuous: most of these trees condense.
    #[test]
    fn condensed_forward_dynamics_is_the_references() {
        let mut condensed = 0;
        for seed in 0..60u64 {
            let model = random_model(seed, 4 + (seed as usize % 11));
            if model.has_mimic() || !applies(&model) {
                continue;
            }
            let reference = Reference::new(&model).unwrap();
            let (q, v, tau) = random_state(&model, seed);
            let m = reference.mass_matrix(&q).unwrap();
            let eig = m.clone().symmetric_eigenvalues();
            let tol = 1e-12f64.max(1e-13 * eig.amax() / eig.amin());
            let want = reference.forward_dynamics(&q, &v, &tau).unwrap();
            let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            let input = |var: Var| match var {
                Var::Q(i) => q[i],
                Var::V(i) => v[i],
                Var::Tau(i) => tau[i],
                other => panic!("unexpected input {other:?}"),
            };
            let det = m.determinant();
            for variant in variants(&model) {
                if variant.method != Some(FdMethod::CrbaCondensed) {
                    continue;
                }
                let traced = trace_variant(&model, variant);
                let got = traced.graph.eval(&traced.values, input);
                for (k, (g, w)) in got.iter().zip(want.iter()).enumerate() {
                    assert!(
                        (g - w).abs() <= tol * scale,
                        "seed {seed} {variant:?} q̈_{k}: {g} vs {w}"
                    );
                }
                let pivots = traced.pivots.expect("forward dynamics has pivots");
                let firsts: Vec<_> = pivots.pairs.iter().map(|p| p.0).collect();
                let product: f64 = traced.graph.eval(&firsts, input).iter().product();
                assert!(
                    (product - det).abs() <= 1e-9 * det.abs(),
                    "seed {seed} {variant:?}: pivots {product} vs det {det}"
                );
                condensed += 1;
            }
        }
        assert!(condensed >= 20, "only {condensed} condensed traces");
    }
}
