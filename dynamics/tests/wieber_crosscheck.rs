//! The spatial recursions (RNEA, CRBA; Featherstone 2008) against Wieber's formulation from
//! plain 3D kinematics (Wieber 2005, eqs. 6–8), on random trees using every joint kind.

mod common;

use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::{jacobian, Reference};
use common::{rel_err_mat, rel_err_vec};
use proptest::prelude::*;

/// Agreement required, relative to the largest entry of the compared quantity.
const TOL: f64 = 1e-12;

fn compare(seed: u64, n: usize) -> (f64, f64, f64) {
    let model = random_model(seed, n);
    let r = Reference::new(&model).unwrap();
    let (q, v, _) = random_state(&model, seed.wrapping_mul(31).wrapping_add(7));
    let w = jacobian::wieber(&model, &[], &q, &v).unwrap();
    let m = r.mass_matrix(&q).unwrap();
    let b = r.bias(&q, &v).unwrap();
    let g = r.gravity(&q).unwrap();
    // Relative to the largest entry of the quantity; when that entry vanishes (a lone revolute
    // has no bias, a vertical axis feels no gravity) relative to its natural size instead:
    // `max|M|·max|v|²` for the bias, `max|M|·|g|` for gravity (per metre of lever).
    let m_max = w.mass_matrix.amax();
    let v_max = v.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    let em = rel_err_mat(&m, &w.mass_matrix, 1e-300);
    let eb = rel_err_vec(
        &b,
        &(&w.n * nalgebra::DVector::from_column_slice(&v)),
        (m_max * v_max * v_max).max(1e-300),
    );
    let eg = rel_err_vec(&g, &(-&w.gravity_force), (m_max * 9.81).max(1e-300));
    (em, eb, eg)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    #[test]
    fn rnea_crba_match_wieber(seed in any::<u64>(), n in 1usize..=30) {
        let (em, eb, eg) = compare(seed, n);
        prop_assert!(em < TOL, "M differs by {em:e} (relative)");
        prop_assert!(eb < TOL, "bias differs by {eb:e} (relative)");
        prop_assert!(eg < TOL, "gravity differs by {eg:e} (relative)");
    }
}

#[test]
fn report_max_errors() {
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for seed in 0..200u64 {
        let (em, eb, eg) = compare(seed, 1 + (seed as usize % 30));
        worst = (worst.0.max(em), worst.1.max(eb), worst.2.max(eg));
    }
    eprintln!(
        "max relative errors over 200 random trees: M {:e}, bias {:e}, gravity {:e}",
        worst.0, worst.1, worst.2
    );
    assert!(worst.0 < TOL && worst.1 < TOL && worst.2 < TOL, "{worst:?}");
}

/// The reference's energies (`½·vᵀ·M·v`; the centres of mass through its spatial transforms)
/// against the same from Wieber's body Jacobians and centres of mass: `Σ ½·m·|J_t·v|² +
/// ½·(J_R·v)ᵀ·I·(J_R·v)` and `−Σ m·gᵀ·x`.
#[test]
fn energies_match_the_body_jacobians() {
    for seed in 0..100u64 {
        let model = random_model(seed, 1 + (seed as usize % 12));
        let r = Reference::new(&model).unwrap();
        let (q, v, _) = random_state(&model, seed);
        let bodies = jacobian::body_jacobians(&model, &[], &q, &v).unwrap();
        let v_ = nalgebra::DVector::from_column_slice(&v);
        let g = nalgebra::Vector3::new(0.0, 0.0, -9.81);
        let (mut kinetic, mut potential, mut scale) = (0.0, 0.0, 0.0f64);
        for b in &bodies {
            let (vc, w) = (&b.jt * &v_, &b.jr * &v_);
            let w = nalgebra::Vector3::new(w[0], w[1], w[2]);
            kinetic += 0.5 * b.mass * vc.norm_squared() + 0.5 * w.dot(&(b.inertia * w));
            potential -= b.mass * g.dot(&b.com);
            scale = scale.max(b.mass * 9.81 * b.com.norm());
        }
        let k = r.kinetic_energy(&q, &v).unwrap();
        assert!(
            (k - kinetic).abs() <= 1e-12 * kinetic.max(1e-300),
            "seed {seed}: {k} vs {kinetic}"
        );
        let p = r.potential_energy(&q).unwrap();
        assert!(
            (p - potential).abs() <= 1e-12 * scale.max(1e-300),
            "seed {seed}: {p} vs {potential}"
        );
    }
}
