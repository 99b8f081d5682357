//! The sparse `LᵀDL` factorization of a tree's joint-space inertia matrix (Featherstone 2008,
//! RBDA §6.5): `M = Lᵀ·D·L`, eliminating from the last coordinate to the first. In depth-first
//! coordinate order a coordinate's descendants come after it, so this order causes no fill-in on
//! a tree: the structural zeros of `M` stay zeros, and a symbolic scalar folds every product
//! with them away. The generator traces it for forward dynamics by CRBA + `LᵀDL`.

use alloc::vec::Vec;

use crate::scalar::Scalar;

/// Solves `M·x = b` by `M = LᵀDL` (RBDA Table 6.3 and eqs. 6.30–6.32). `m` is row-major
/// `n × n`, symmetric, read in its lower triangle. Returns `x` and, for each coordinate `k`, the
/// pivot `D_k` with the unreduced `M_kk` it came from (all pivots must be positive for `M` to be
/// positive definite; the generic code does not compare them).
///
/// Labels ([`Scalar::label`]): `L`'s entries `l_{k}_{i}`, the pivots `d_{k}`, the entries of
/// `M` reduced by coordinate `k` as `m_{i}_{j}_less_{k}`, the solutions `y_{k}` of `D·y = z` and
/// the results `qdd_{k}`.
pub fn ltdl_solve<T: Scalar>(m: Vec<T>, b: Vec<T>, n: usize) -> (Vec<T>, Vec<(T, T)>) {
    let (m, pivots) = ltdl_factor(m, n);
    // Lᵀ·z = b (upper triangular), from the last coordinate up.
    let mut x = b;
    for k in (0..n).rev() {
        for i in 0..k {
            x[i] = x[i] - m[k * n + i] * x[k];
        }
    }
    // D·y = z.
    for (k, xk) in x.iter_mut().enumerate() {
        *xk = *xk / m[k * n + k];
    }
    let y = x.clone();
    // L·x = y, from the first coordinate down.
    for k in 0..n {
        for i in 0..k {
            x[k] = x[k] - m[k * n + i] * x[i];
        }
    }
    // Labels, the results first: where `x_k = y_k` (a coordinate without ancestors), the first
    // label wins.
    for (k, (xk, yk)) in x.iter_mut().zip(y).enumerate() {
        *xk = xk.label(format_args!("qdd_{k}"));
        yk.label(format_args!("y_{k}"));
    }
    (x, pivots)
}

/// Factors `M = LᵀDL` in place (`m` row-major `n × n`, symmetric, read in its lower triangle):
/// returns `L` below the diagonal and `D` on it, and each pivot `D_k` with the unreduced `M_kk`
/// it came from (RBDA Table 6.3).
pub fn ltdl_factor<T: Scalar>(mut m: Vec<T>, n: usize) -> (Vec<T>, Vec<(T, T)>) {
    let unreduced: Vec<T> = (0..n).map(|k| m[k * n + k]).collect();
    let all: Vec<usize> = (0..n).collect();
    ltdl_factor_of(&mut m, n, &all, |_| false);
    let pivots = (0..n).map(|k| (m[k * n + k], unreduced[k])).collect();
    (m, pivots)
}

/// [`ltdl_factor`] of the rows and columns `idx` of `m` (row-major `n × n`, its lower triangle
/// read; `idx` ascending), in place: `L` below the diagonal and `D` on it, labelled with the
/// coordinates of `m`. An entry `zero` says is zero is skipped (the generator's symbolic zeros:
/// the same result, traced faster). The condensed forward dynamics factors each subtree this
/// way (`articulated_codegen::trace::condensed`).
pub fn ltdl_factor_of<T: Scalar>(m: &mut [T], n: usize, idx: &[usize], zero: impl Fn(T) -> bool) {
    for (a, &k) in idx.iter().enumerate().rev() {
        let d = m[k * n + k].label(format_args!("d_{k}"));
        m[k * n + k] = d;
        // `i` descends, as in RBDA Table 6.3: row k's entries left of `i` are still unscaled
        // when the update of row `i` reads them.
        for (b, &i) in idx[..a].iter().enumerate().rev() {
            let mki = m[k * n + i];
            if zero(mki) {
                continue;
            }
            let l = (mki / d).label(format_args!("l_{k}_{i}"));
            for &j in &idx[..=b] {
                let mkj = m[k * n + j];
                if zero(mkj) {
                    continue;
                }
                m[i * n + j] = (m[i * n + j] - mkj * l).label(format_args!("m_{i}_{j}_less_{k}"));
            }
            m[k * n + i] = l;
        }
    }
}

/// A factorization from [`ltdl_factor`] with the reciprocals of its pivots, to solve many
/// right-hand sides with one division per pivot in all.
#[derive(Clone, Debug)]
pub struct Ltdl<T> {
    /// `L` below the diagonal (the diagonal is not read).
    pub l: Vec<T>,
    /// `1/D_k`.
    pub inv_d: Vec<T>,
    /// The size.
    pub n: usize,
}

impl<T: Scalar> Ltdl<T> {
    /// Factors `m` (as [`ltdl_factor`]); returns the factorization and the pivots with their
    /// unreduced values.
    pub fn new(m: Vec<T>, n: usize) -> (Self, Vec<(T, T)>) {
        let (l, pivots) = ltdl_factor(m, n);
        let inv_d = (0..n)
            .map(|k| (T::one() / l[k * n + k]).label(format_args!("inv_d_{k}")))
            .collect();
        (Ltdl { l, inv_d, n }, pivots)
    }

    /// `M⁻¹·b`.
    pub fn solve(&self, mut x: Vec<T>) -> Vec<T> {
        let (m, n) = (&self.l, self.n);
        for k in (0..n).rev() {
            for i in 0..k {
                x[i] = x[i] - m[k * n + i] * x[k];
            }
        }
        for (xk, &r) in x.iter_mut().zip(&self.inv_d) {
            *xk = *xk * r;
        }
        for k in 0..n {
            for i in 0..k {
                x[k] = x[k] - m[k * n + i] * x[i];
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::ltdl_solve;
    use crate::random::Rng;

    /// A random symmetric positive definite matrix with the sparsity of a tree (coordinate `i`'s
    /// parent before it): `M_ij ≠ 0` only between a coordinate and its ancestors.
    fn tree_matrix(rng: &mut Rng, parent: &[Option<usize>]) -> Vec<f64> {
        let n = parent.len();
        // L unit lower-triangular with the tree's pattern, D positive: M = LᵀDL.
        let mut l = vec![0.0; n * n];
        for k in 0..n {
            l[k * n + k] = 1.0;
            let mut a = parent[k];
            while let Some(i) = a {
                l[k * n + i] = rng.range(-1.0, 1.0);
                a = parent[i];
            }
        }
        let d: Vec<f64> = (0..n).map(|_| rng.range(0.1, 2.0)).collect();
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                m[i * n + j] = (0..n).map(|k| l[k * n + i] * d[k] * l[k * n + j]).sum();
            }
        }
        m
    }

    #[test]
    fn solves_tree_systems_and_returns_the_pivots() {
        let mut rng = Rng::new(7);
        for trial in 0..50 {
            let n = 1 + trial % 9;
            let parent: Vec<Option<usize>> = (0..n)
                .map(|k| (k > 0).then(|| rng.below(k)).filter(|_| rng.unit() < 0.8))
                .collect();
            let m = tree_matrix(&mut rng, &parent);
            let x_true: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
            let b: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| m[i * n + j] * x_true[j]).sum())
                .collect();
            let (x, pivots) = ltdl_solve(m.clone(), b, n);
            for (got, want) in x.iter().zip(&x_true) {
                assert!((got - want).abs() < 1e-10, "trial {trial}: {got} vs {want}");
            }
            // The product of the pivots is det(M); each unreduced value is M's diagonal.
            let det = nalgebra::DMatrix::from_row_slice(n, n, &m).determinant();
            let prod: f64 = pivots.iter().map(|p| p.0).product();
            assert!((prod - det).abs() <= 1e-10 * det.abs(), "trial {trial}");
            for (k, p) in pivots.iter().enumerate() {
                assert_eq!(p.1, m[k * n + k]);
                assert!(p.0 > 0.0);
            }
        }
    }
}
