//! Identities the dynamics must satisfy, on random trees with every joint kind (ARCHITECTURE.md, "Measuring").

mod common;

use articulated_dynamics::model::{JointKind, Placement};
use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::{jacobian, Reference};
use common::*;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 32,
        ..ProptestConfig::default()
    }
}

fn setup(
    seed: u64,
    n: usize,
) -> (
    articulated_dynamics::model::Model,
    Reference,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
) {
    let model = random_model(seed, n);
    let r = Reference::new(&model).unwrap();
    let (q, v, a) = random_state(&model, seed ^ 0xABCD);
    (model, r, q, v, a)
}

proptest! {
    #![proptest_config(config())]

    /// `M` is symmetric (to rounding) and positive definite (its Cholesky factorization exists).
    #[test]
    fn mass_matrix_symmetric_positive_definite(seed in any::<u64>(), n in 1usize..=30) {
        let (_, r, q, _, _) = setup(seed, n);
        let m = r.mass_matrix(&q).unwrap();
        let asym = (&m - m.transpose()).amax();
        prop_assert!(asym <= 1e-14 * m.amax().max(1e-300), "asymmetry {asym:e}");
        if r.nv() > 0 {
            prop_assert!(m.clone().cholesky().is_some(), "M not positive definite:\n{m}");
        }
    }

    /// `τ = M·a + bias + gravity`, with the three computed separately (CRBA vs RNEA).
    #[test]
    fn inverse_dynamics_is_sum_of_parts(seed in any::<u64>(), n in 1usize..=30) {
        let (_, r, q, v, a) = setup(seed, n);
        let tau = r.inverse_dynamics(&q, &v, &a).unwrap();
        let m = r.mass_matrix(&q).unwrap();
        let sum = &m * DVector::from_column_slice(&a) + r.bias(&q, &v).unwrap() + r.gravity(&q).unwrap();
        let err = rel_err_vec(&tau, &sum, m.amax().max(1e-300));
        prop_assert!(err < 1e-12, "{err:e}");
    }

    /// `∂τ/∂a = M`: τ is affine in `a`, so central differences with a unit step are exact up to
    /// rounding (`~ε·|τ|`).
    #[test]
    fn dtau_da_is_mass_matrix(seed in any::<u64>(), n in 1usize..=12) {
        let (_, r, q, v, a) = setup(seed, n);
        let m = r.mass_matrix(&q).unwrap();
        let nv = r.nv();
        let mut fd = DMatrix::zeros(nv, nv);
        for j in 0..nv {
            let (mut ap, mut am) = (a.clone(), a.clone());
            ap[j] += 1.0;
            am[j] -= 1.0;
            let col = (r.inverse_dynamics(&q, &v, &ap).unwrap() - r.inverse_dynamics(&q, &v, &am).unwrap()) * 0.5;
            fd.set_column(j, &col);
        }
        let err = rel_err_mat(&fd, &m, 1e-300);
        prop_assert!(err < 1e-12, "{err:e}");
    }

    /// `forward(q, v, inverse(q, v, a)) = a` (ABA undoes RNEA). Random states keep Euler joints
    /// away from gimbal lock, but `M` may still be ill-conditioned; the tolerance is scaled by
    /// its condition number.
    #[test]
    fn forward_inverts_inverse(seed in any::<u64>(), n in 1usize..=30) {
        let (_, r, q, v, a) = setup(seed, n);
        let tau = r.inverse_dynamics(&q, &v, &a).unwrap();
        let qdd = r.forward_dynamics(&q, &v, tau.as_slice()).unwrap();
        let m = r.mass_matrix(&q).unwrap();
        let cond = if r.nv() == 0 { 1.0 } else {
            let e = m.symmetric_eigenvalues();
            e.max() / e.min()
        };
        let err = rel_err_vec(&qdd, &DVector::from_column_slice(&a), 1.0);
        prop_assert!(err < 1e-14 * cond.max(100.0), "{err:e} (cond {cond:e})");
    }

    /// Wieber 2005 after eq. 14: with a free Euler base whose translation is in the world frame
    /// and comes first, `𝓕_g = M·[g; 0; …]`, so `gravity = −M·[g; 0; …]`.
    #[test]
    fn gravity_is_mass_matrix_times_g_on_free_euler_base(seed in any::<u64>(), n in 1usize..=30, s in 0usize..12) {
        let mut model = random_model(seed, n);
        let seqs = ["xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz"];
        model.joints[0].kind = JointKind::FreeEuler { seq: articulated_dynamics::model::EulerSeq::parse(seqs[s]).unwrap() };
        model.joints[0].placement = Placement::IDENTITY;
        let r = Reference::new(&model).unwrap();
        let (q, _, _) = random_state(&model, seed);
        let mut g = DVector::zeros(r.nv());
        g[2] = -9.81;
        let m = r.mass_matrix(&q).unwrap();
        let want = -(&m * g);
        let err = rel_err_vec(&r.gravity(&q).unwrap(), &want, 1e-300);
        prop_assert!(err < 1e-12, "{err:e}");
    }

    /// `Ṁ − 2N` is skew-symmetric (Wieber 2005, after eq. 8), with `N` from Wieber's eq. 7 and
    /// `Ṁ` by central differences of the CRBA's `M` along the motion `q(t)` with velocity `v`.
    /// Step `h = 1e-4` (|v| ≤ 1): truncation `≤ h²/6·|d³M/dt³| ≈ 2e-9·|M|` and rounding
    /// `≈ ε·|M|/h ≈ 2e-12·|M|`, so `1e-6·max(|M|, |Ṁ|)` leaves a wide margin while any real
    /// asymmetry (wrong sign or factor in N) is of the size of `|Ṁ|`.
    #[test]
    fn mdot_minus_2n_is_skew(seed in any::<u64>(), n in 1usize..=12) {
        let (model, r, q, v, _) = setup(seed, n);
        let h = 1e-4;
        let mp = r.mass_matrix(&integrate(&model, &q, &v, h)).unwrap();
        let mm = r.mass_matrix(&integrate(&model, &q, &v, -h)).unwrap();
        let mdot = (mp - mm) / (2.0 * h);
        let w = jacobian::wieber(&model, &[], &q, &v).unwrap();
        let s = &mdot - &w.n * 2.0;
        let sym = (&s + s.transpose()).amax();
        let scale = w.mass_matrix.amax().max(mdot.amax()).max(1e-300);
        prop_assert!(sym < 1e-6 * scale, "{sym:e} vs scale {scale:e}");
    }
}

/// The skew test can fail: `Ṁ − N` (one N only) is not skew on a simple model.
#[test]
fn skew_test_is_sensitive() {
    let model = random_model(3, 6);
    let (q, v, _) = random_state(&model, 3);
    let r = Reference::new(&model).unwrap();
    let h = 1e-4;
    let mdot = (r.mass_matrix(&integrate(&model, &q, &v, h)).unwrap()
        - r.mass_matrix(&integrate(&model, &q, &v, -h)).unwrap())
        / (2.0 * h);
    let w = jacobian::wieber(&model, &[], &q, &v).unwrap();
    let s = &mdot - &w.n;
    assert!((&s + s.transpose()).amax() > 1e-3 * mdot.amax());
}
