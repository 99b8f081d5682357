//! Eigenvalues of a symmetric 3×3 matrix by cyclic Jacobi rotations (Golub & Van Loan 2013,
//! *Matrix Computations*, §8.5.2), for the inertia checks.

/// The eigenvalues of the symmetric matrix `a`, in ascending order. Only the upper triangle is
/// read. Non-finite input gives non-finite output (the caller checks finiteness first).
pub(crate) fn symmetric_eigenvalues(a: [[f64; 3]; 3]) -> [f64; 3] {
    let mut m = a;
    m[1][0] = m[0][1];
    m[2][0] = m[0][2];
    m[2][1] = m[1][2];
    for _sweep in 0..50 {
        let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        let diag = m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2];
        if off <= f64::EPSILON * f64::EPSILON * diag || off == 0.0 || !off.is_finite() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            // Choose the rotation that zeroes m[p][q] (Golub & Van Loan, Algorithm 8.5.1).
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // m ← Jᵀ m J with J the rotation in the (p, q) plane.
            for row in &mut m {
                let (rp, rq) = (row[p], row[q]);
                row[p] = c * rp - s * rq;
                row[q] = s * rp + c * rq;
            }
            let (rp, rq) = (m[p], m[q]);
            m[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            m[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
        }
    }
    let mut eig = [m[0][0], m[1][1], m[2][2]];
    eig.sort_by(f64::total_cmp);
    eig
}

#[cfg(test)]
mod tests {
    use super::symmetric_eigenvalues;

    #[test]
    fn diagonal_and_rotated() {
        assert_eq!(
            symmetric_eigenvalues([[3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]),
            [1.0, 2.0, 3.0]
        );
        // [[2, 1, 0], [1, 2, 0], [0, 0, 5]] has eigenvalues 1, 3, 5.
        let e = symmetric_eigenvalues([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        for (got, want) in e.iter().zip([1.0, 3.0, 5.0]) {
            assert!((got - want).abs() < 1e-12, "{e:?}");
        }
        // All ones: eigenvalues 0, 0, 3.
        let e = symmetric_eigenvalues([[1.0; 3]; 3]);
        for (got, want) in e.iter().zip([0.0, 0.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{e:?}");
        }
    }
}
