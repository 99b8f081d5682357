//! The reference's derivatives (`reference::derivatives`, forward-mode duals through RNEA and the
//! `LᵀDL` of `M`) against central finite differences of the reference's values, on random trees
//! with every joint kind (quaternion joints moved along the tangent displacement, the body-frame
//! increment). Forward dynamics is differenced through ABA, a different algorithm from the
//! CRBA + `LᵀDL` + RNEA the derivatives are built from; `M⁻¹` is checked against `M`.

mod common;

use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::Reference;
use common::*;
use nalgebra::DMatrix;
use proptest::prelude::*;

/// The largest entry's relative error, with a floor of 1 on the scale.
fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    rel_err_mat(a, b, 1.0)
}

/// Column `k` of `∂f/∂δ` by central differences along tangent coordinate `k`, and of `∂f/∂x`
/// for a velocity-sized argument `x`.
fn central<F: Fn(&[f64]) -> Vec<f64>>(
    f: F,
    n: usize,
    h: f64,
    along: impl Fn(usize, f64) -> Vec<f64>,
) -> DMatrix<f64> {
    let cols: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let (p, m) = (f(&along(k, h)), f(&along(k, -h)));
            p.iter().zip(&m).map(|(p, m)| (p - m) / (2.0 * h)).collect()
        })
        .collect();
    DMatrix::from_fn(cols.first().map_or(0, Vec::len), n, |i, j| cols[j][i])
}

fn unit(n: usize, k: usize, h: f64) -> Vec<f64> {
    (0..n).map(|i| if i == k { h } else { 0.0 }).collect()
}

/// Errors of `(∂τ/∂q, ∂τ/∂v, ∂q̈/∂q, ∂q̈/∂v, M⁻¹·M − I)` on a random tree.
fn errors(seed: u64, n: usize) -> [f64; 5] {
    let model = random_model(seed, n);
    let r = Reference::new(&model).unwrap();
    let (q, v, a) = random_state(&model, seed);
    let nv = model.nv();
    let tau: Vec<f64> = r
        .inverse_dynamics(&q, &v, &a)
        .unwrap()
        .iter()
        .map(|t| t + 0.5)
        .collect();
    let h = 1e-6;
    let (dq, dv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
    let id = |q: &[f64], v: &[f64]| r.inverse_dynamics(q, v, &a).unwrap().as_slice().to_vec();
    let fd_dq = central(
        |qk| id(qk, &v),
        nv,
        h,
        |k, h| integrate(&model, &q, &unit(nv, k, 1.0), h),
    );
    let add =
        |x: &[f64], d: Vec<f64>| -> Vec<f64> { x.iter().zip(d).map(|(x, d)| x + d).collect() };
    let fd_dv = central(|vk| id(&q, vk), nv, h, |k, h| add(&v, unit(nv, k, h)));
    let [ddq, ddv, minv] = r.forward_dynamics_derivatives(&q, &v, &tau).unwrap();
    let fdyn = |q: &[f64], v: &[f64]| r.forward_dynamics(q, v, &tau).unwrap().as_slice().to_vec();
    let fd_ddq = central(
        |qk| fdyn(qk, &v),
        nv,
        h,
        |k, h| integrate(&model, &q, &unit(nv, k, 1.0), h),
    );
    let fd_ddv = central(|vk| fdyn(&q, vk), nv, h, |k, h| add(&v, unit(nv, k, h)));
    let m = r.mass_matrix(&q).unwrap();
    let identity = DMatrix::identity(nv, nv);
    [
        rel(&dq, &fd_dq),
        rel(&dv, &fd_dv),
        rel(&ddq, &fd_ddq),
        rel(&ddv, &fd_ddv),
        rel(&(&minv * &m), &identity).max(rel(&r.mass_matrix_inverse(&q).unwrap(), &minv)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Every derivative against central differences (1e-6 relative: the differences' own error
    /// is about 1e-9), `M⁻¹·M = I` to 1e-10.
    #[test]
    fn derivatives_match_central_differences(seed in any::<u64>(), n in 1usize..=8) {
        let e = errors(seed, n);
        for (k, &x) in e[..4].iter().enumerate() {
            prop_assert!(x < 1e-6, "seed {seed}, n {n}: derivative {k} off by {x:e}");
        }
        prop_assert!(e[4] < 1e-10, "seed {seed}, n {n}: M⁻¹·M − I = {:e}", e[4]);
    }
}

/// A wrong tangent convention shows: differencing along `q + h·e` on the quaternion's own
/// components (instead of the body-frame increment) does not give the derivatives.
#[test]
fn the_quaternion_tangent_is_the_body_frame_increment() {
    use articulated_dynamics::model::JointKind;
    let (seed, model) = (0..200u64)
        .map(|s| (s, random_model(s, 3)))
        .find(|(_, m)| {
            m.joints
                .iter()
                .any(|j| j.kind == JointKind::SphericalQuaternion)
        })
        .unwrap();
    let r = Reference::new(&model).unwrap();
    let (q, v, a) = random_state(&model, seed);
    let nv = model.nv();
    let (dq, _) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
    let id = |q: &[f64]| r.inverse_dynamics(q, &v, &a).unwrap().as_slice().to_vec();
    let body_frame = central(id, nv, 1e-6, |k, h| {
        integrate(&model, &q, &unit(nv, k, 1.0), h)
    });
    // The world-frame increment exp(δ/2) ⊗ q differs from q ⊗ exp(δ/2).
    let world_frame = central(id, nv, 1e-6, |k, h| {
        let mut out = q.clone();
        let (mut qa, mut va) = (0, 0);
        for j in &model.joints {
            if j.kind == JointKind::SphericalQuaternion && (va..va + 3).contains(&k) {
                let q0 = [q[qa], q[qa + 1], q[qa + 2], q[qa + 3]];
                let mut phi = [0.0; 3];
                phi[k - va] = h;
                out[qa..qa + 4].copy_from_slice(&quat_mul(quat_exp(phi), q0));
            } else if (va..va + j.kind.nv()).contains(&k) {
                return integrate(&model, &q, &unit(nv, k, 1.0), h);
            }
            qa += j.kind.nq();
            va += j.kind.nv();
        }
        out
    });
    assert!(rel(&dq, &body_frame) < 1e-6);
    assert!(
        rel(&dq, &world_frame) > 1e-3,
        "the two conventions coincide here: pick another state"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Carpentier & Mansard's analytical recursion (world frame) against the forward-mode duals
    /// (local frames): two formulations from different equations, to 1e-11 of the largest entry.
    #[test]
    fn analytical_and_forward_mode_derivatives_agree(seed in any::<u64>(), n in 1usize..=12) {
        use articulated_dynamics::reference::derivatives::{
            inverse_dynamics_derivatives, inverse_dynamics_derivatives_analytic,
        };
        let model = random_model(seed, n);
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let (dq, dv) = inverse_dynamics_derivatives(r.tree(), &q, &v, &a);
        let (aq, av) = inverse_dynamics_derivatives_analytic(r.tree(), &q, &v, &a);
        let nv = model.nv();
        let m = |x: &[f64]| DMatrix::from_row_slice(nv, nv, x);
        let (eq, ev) = (rel(&m(&aq), &m(&dq)), rel(&m(&av), &m(&dv)));
        prop_assert!(eq < 1e-11 && ev < 1e-11, "seed {seed}, n {n}: dq {eq:e}, dv {ev:e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Where `v = q̇` (no quaternion joint), τ's velocity terms are `Σ Γ_ijk·v_j·v_k` with the
    /// Christoffel symbols symmetric in `j, k`, so `∂τ/∂v = 2·N` (the generator's variant
    /// `coriolis` rests on it). Trees with a quaternion joint are skipped: there `v ≠ q̇`.
    #[test]
    fn velocity_derivatives_are_twice_the_coriolis_matrix_where_v_is_q_dot(
        seed in any::<u64>(),
        n in 1usize..=8,
    ) {
        use articulated_dynamics::model::JointKind;
        let model = random_model(seed, n);
        let quaternion = model.joints.iter().any(|j| {
            matches!(j.kind, JointKind::SphericalQuaternion | JointKind::FreeQuaternion)
        });
        prop_assume!(!quaternion);
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed);
        let (_, dv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
        let twice_n = r.coriolis_matrix(&q, &v).unwrap() * 2.0;
        let e = rel(&twice_n, &dv);
        prop_assert!(e < 1e-11, "seed {seed}, n {n}: {e:e}");
    }
}
