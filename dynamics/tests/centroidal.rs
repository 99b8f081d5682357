//! The whole-system quantities (`reference::centroidal`) against independent formulas, on random
//! trees with every joint kind, free bases included:
//! - centre of mass, its Jacobian, the centroidal momentum and its matrix against the same sums
//!   over Wieber's body Jacobians (plain 3D kinematics, `reference::jacobian`): `x_G = Σ m·x / m`,
//!   `J_G = Σ m·J_t / m`, `k_G = Σ m·(x − x_G) × J_t·v + R·I·J_R·v`, `p = Σ m·J_t·v`;
//! - the Coriolis matrix: `N·v` is the bias (RNEA), `Ṁ − 2N` is skew-symmetric with `Ṁ` by
//!   central differences of `M`, and where `v = q̇` (no quaternion joint) `N` is the matrix of
//!   the Christoffel symbols of `M` (central differences), on every Euler sequence.

mod common;

use articulated_dynamics::model::{EulerSeq, JointKind, Model};
use articulated_dynamics::random::{random_model, random_state};
use articulated_dynamics::reference::{jacobian, Reference};
use common::*;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use proptest::prelude::*;

const SEQS: [&str; 12] = [
    "xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz",
];

/// What Wieber's body Jacobians give: centre of mass, its Jacobian, `A_G`.
struct FromBodies {
    com: Vector3<f64>,
    com_jacobian: DMatrix<f64>,
    cmm: DMatrix<f64>,
}

fn from_bodies(model: &Model, q: &[f64], v: &[f64]) -> FromBodies {
    let bodies = jacobian::body_jacobians(model, &[], q, v).unwrap();
    let nv = model.nv();
    let mass: f64 = bodies.iter().map(|b| b.mass).sum();
    let com = bodies.iter().map(|b| b.com * b.mass).sum::<Vector3<f64>>() / mass;
    let mut com_jacobian = DMatrix::zeros(3, nv);
    let mut cmm = DMatrix::zeros(6, nv);
    for b in &bodies {
        com_jacobian += &b.jt * (b.mass / mass);
        let ri: Matrix3<f64> = b.rotation * b.inertia;
        for c in 0..nv {
            let t = Vector3::new(b.jt[(0, c)], b.jt[(1, c)], b.jt[(2, c)]);
            let w = Vector3::new(b.jr[(0, c)], b.jr[(1, c)], b.jr[(2, c)]);
            let k = (b.com - com).cross(&t) * b.mass + ri * w;
            for r in 0..3 {
                cmm[(r, c)] += k[r];
                cmm[(r + 3, c)] += b.mass * t[r];
            }
        }
    }
    FromBodies {
        com,
        com_jacobian,
        cmm,
    }
}

/// The largest relative errors of the reference's centroidal quantities against the bodies'.
fn centroidal_errors(seed: u64, n: usize) -> [f64; 5] {
    let model = random_model(seed, n);
    let r = Reference::new(&model).unwrap();
    if r.nv() == 0 {
        // Only fixed joints: nothing moves, no Jacobian to compare.
        return [0.0; 5];
    }
    let (q, v, _) = random_state(&model, seed ^ 0x0C0F_FEE5);
    let want = from_bodies(&model, &q, &v);
    let vv = DVector::from_column_slice(&v);
    let com = r.center_of_mass(&q).unwrap();
    // Relative to the distance scale of the tree: the centre of mass can sit at the origin.
    let e_com = (com - want.com).amax() / want.com.amax().max(1.0);
    let e_jac = rel_err_mat(
        &r.center_of_mass_jacobian(&q).unwrap(),
        &want.com_jacobian,
        1e-300,
    );
    let cmm = r.centroidal_momentum_matrix(&q).unwrap();
    let e_cmm = rel_err_mat(&cmm, &want.cmm, 1e-300);
    let h = DVector::from_column_slice(r.centroidal_momentum(&q, &v).unwrap().as_slice());
    let h_want = &want.cmm * &vv;
    let e_h = rel_err_vec(&h, &h_want, (want.cmm.amax() * vv.amax()).max(1e-300));
    // p = m·ẋ_G.
    let mass: f64 = (0..model.nb())
        .map(|b| match &model.bodies[b].mass {
            articulated_dynamics::model::Value::Const(m) => *m,
            _ => unreachable!("random models have constant masses"),
        })
        .sum();
    let p_from_com = &want.com_jacobian * &vv * mass;
    let e_p = (h.rows(3, 3) - &p_from_com).amax()
        / (mass * want.com_jacobian.amax() * vv.amax()).max(1e-300);
    [e_com, e_jac, e_cmm, e_h, e_p]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn centroidal_quantities_match_the_body_jacobians(seed in any::<u64>(), n in 1usize..=20) {
        let e = centroidal_errors(seed, n);
        let names = ["com", "com jacobian", "A_G", "h_G", "p = m·ẋ_G"];
        for (e, name) in e.iter().zip(names) {
            prop_assert!(*e < 1e-12, "{name} differs by {e:e} (relative)");
        }
    }

    /// `N·v = bias` and `Ṁ − 2N` skew, on any tree (quaternions integrated on their manifold).
    #[test]
    fn coriolis_matrix_gives_bias_and_skew(seed in any::<u64>(), n in 1usize..=10) {
        let model = random_model(seed, n);
        let r = Reference::new(&model).unwrap();
        let (q, v, _) = random_state(&model, seed ^ 0x0DD5);
        let (bias_err, skew_err) = coriolis_errors(&model, &r, &q, &v);
        prop_assert!(bias_err < 1e-12, "N·v differs from the bias by {bias_err:e}");
        prop_assert!(skew_err < 1e-6, "Ṁ − 2N is not skew: {skew_err:e}");
    }

    /// With `v = q̇` (Euler joints for every rotation), `N` is Christoffel-consistent:
    /// `N_ij = Σ_k ½·(∂_k M_ij + ∂_j M_ik − ∂_i M_jk)·v_k`.
    #[test]
    fn coriolis_matrix_is_christoffel_on_euler_joints(seed in any::<u64>(), n in 1usize..=6) {
        let model = all_euler(random_model(seed, n), seed);
        let r = Reference::new(&model).unwrap();
        let (q, v, _) = random_state(&model, seed ^ 0xC4415);
        let err = christoffel_error(&r, &q, &v);
        prop_assert!(err < 1e-6, "N differs from the Christoffel matrix by {err:e}");
    }
}

/// `(|N·v − bias| / scale, |sym(Ṁ − 2N)| / scale)`.
fn coriolis_errors(model: &Model, r: &Reference, q: &[f64], v: &[f64]) -> (f64, f64) {
    let n = r.coriolis_matrix(q, v).unwrap();
    let vv = DVector::from_column_slice(v);
    let bias = r.bias(q, v).unwrap();
    let m = r.mass_matrix(q).unwrap();
    let scale = m.amax() * vv.amax() * vv.amax();
    let bias_err = (&n * &vv - bias).amax() / scale.max(1e-300);
    let h = 1e-4;
    let mdot = (r.mass_matrix(&integrate(model, q, v, h)).unwrap()
        - r.mass_matrix(&integrate(model, q, v, -h)).unwrap())
        / (2.0 * h);
    let s = &mdot - &n * 2.0;
    let skew_err = (&s + s.transpose()).amax() / m.amax().max(mdot.amax()).max(1e-300);
    (bias_err, skew_err)
}

/// The same tree with every quaternion joint replaced by Euler angles of a random sequence, so
/// that `v = q̇` everywhere.
fn all_euler(mut model: Model, seed: u64) -> Model {
    for (k, j) in model.joints.iter_mut().enumerate() {
        let seq = EulerSeq::parse(SEQS[(seed as usize + 5 * k) % 12]).unwrap();
        j.kind = match j.kind {
            JointKind::SphericalQuaternion => JointKind::SphericalEuler { seq },
            JointKind::FreeQuaternion => JointKind::FreeEuler { seq },
            other => other,
        };
    }
    model
}

/// `|N − Γ(v)| / scale` with the Christoffel matrix `Γ(v)` from central differences of `M`.
fn christoffel_error(r: &Reference, q: &[f64], v: &[f64]) -> f64 {
    let nv = r.nv();
    if nv == 0 {
        return 0.0;
    }
    let h = 1e-5;
    // dm[k] = ∂M/∂q_k.
    let dm: Vec<DMatrix<f64>> = (0..nv)
        .map(|k| {
            let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
            qp[k] += h;
            qm[k] -= h;
            (r.mass_matrix(&qp).unwrap() - r.mass_matrix(&qm).unwrap()) / (2.0 * h)
        })
        .collect();
    let gamma = DMatrix::from_fn(nv, nv, |i, j| {
        (0..nv)
            .map(|k| 0.5 * (dm[k][(i, j)] + dm[j][(i, k)] - dm[i][(j, k)]) * v[k])
            .sum::<f64>()
    });
    let n = r.coriolis_matrix(q, v).unwrap();
    let scale = gamma.amax().max(r.mass_matrix(q).unwrap().amax());
    (n - gamma).amax() / scale
}

#[test]
fn report_max_centroidal_errors() {
    let mut worst = [0.0f64; 5];
    for seed in 0..150u64 {
        let e = centroidal_errors(seed, 1 + (seed as usize % 20));
        for (w, e) in worst.iter_mut().zip(e) {
            *w = w.max(e);
        }
    }
    eprintln!("max relative errors over 150 random trees (com, J_G, A_G, h_G, p): {worst:?}");
    assert!(worst.iter().all(|&e| e < 1e-12), "{worst:?}");
}

/// Every Euler sequence on a spherical joint between two bodies, and on a free base: the
/// Christoffel test where Pinocchio's Coriolis matrix fails (its issue 2053).
#[test]
fn coriolis_matrix_on_every_euler_sequence() {
    for (s, seq) in SEQS.iter().enumerate() {
        let seq = EulerSeq::parse(seq).unwrap();
        for free in [false, true] {
            let mut model = random_model(40 + s as u64, 3);
            model.joints[0].kind = if free {
                JointKind::FreeEuler { seq }
            } else {
                JointKind::SphericalEuler { seq }
            };
            model.joints[1].kind = JointKind::SphericalEuler { seq };
            model.joints[2].kind = JointKind::Revolute {
                axis: [0.0, 0.6, 0.8],
            };
            let r = Reference::new(&model).unwrap();
            let (q, v, _) = random_state(&model, s as u64);
            let err = christoffel_error(&r, &q, &v);
            assert!(err < 1e-6, "{seq:?} free {free}: {err:e}");
            let (b, k) = coriolis_errors(&model, &r, &q, &v);
            assert!(b < 1e-12 && k < 1e-6, "{seq:?} free {free}: {b:e} {k:e}");
        }
    }
}

/// The Christoffel test can fail: Wieber's `N` (eq. 7) also gives the bias and a skew `Ṁ − 2N`
/// but is a different factorization, and the test tells them apart.
#[test]
fn christoffel_test_is_sensitive() {
    let model = all_euler(random_model(11, 4), 11);
    let r = Reference::new(&model).unwrap();
    let (q, v, _) = random_state(&model, 11);
    let ours = r.coriolis_matrix(&q, &v).unwrap();
    let w = jacobian::wieber(&model, &[], &q, &v).unwrap();
    assert!((&ours - &w.n).amax() > 1e-3 * ours.amax());
}

/// `ḣ_G` from each body's own motion by Wieber's body Jacobians and their rates:
/// `[Σ (x_k − x_G) × m_k·ẍ_k + R_k·(I_k·ω̇_k + ω_k × I_k·ω_k); Σ m_k·ẍ_k]`.
fn centroidal_rate(model: &Model, q: &[f64], v: &[f64], a: &[f64]) -> [f64; 6] {
    let bodies = jacobian::body_jacobians(model, &[], q, v).unwrap();
    let (vv, aa) = (DVector::from_column_slice(v), DVector::from_column_slice(a));
    let mass: f64 = bodies.iter().map(|b| b.mass).sum();
    let com = bodies.iter().map(|b| b.com * b.mass).sum::<Vector3<f64>>() / mass;
    let (mut moment, mut force) = (Vector3::zeros(), Vector3::zeros());
    let v3 = |x: DVector<f64>| Vector3::new(x[0], x[1], x[2]);
    for b in &bodies {
        let f = v3(&b.jt * &aa + &b.jt_dot * &vv) * b.mass;
        let (w, dw) = (v3(&b.jr * &vv), v3(&b.jr * &aa + &b.jr_dot * &vv));
        moment +=
            (b.com - com).cross(&f) + b.rotation * (b.inertia * dw + w.cross(&(b.inertia * w)));
        force += f;
    }
    [
        moment[0], moment[1], moment[2], force[0], force[1], force[2],
    ]
}

/// The base rows of `M·a + N·v` turned into the external wrench about the centre of mass, world
/// axes, for a root on a free base with the identity placement.
fn base_wrench(r: &Reference, kind: JointKind, q: &[f64], v: &[f64], a: &[f64]) -> [f64; 6] {
    let m = r.mass_matrix(q).unwrap();
    let tau = &m * DVector::from_column_slice(a) + r.bias(q, v).unwrap();
    let com = r.center_of_mass(q).unwrap();
    let (f, n_origin) = match kind {
        // v = q̇: the rows of x are the world force, those of θ the moment about the origin x on
        // the rotation axes u1 = e_a1, u2 = R1·e_a2, u3 = R1·R2·e_a3.
        JointKind::FreeEuler { seq } => {
            let [a1, a2, a3] = seq.0.map(|a| Vector3::from(a.unit()));
            let r1 = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(a1), q[3]);
            let r2 = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(a2), q[4]);
            let axes = Matrix3::from_columns(&[a1, r1 * a2, r1 * r2 * a3]);
            let n = axes.transpose().try_inverse().unwrap() * Vector3::new(tau[3], tau[4], tau[5]);
            (Vector3::new(tau[0], tau[1], tau[2]), n)
        }
        // v = [v; ω] in the base frame: the rows are [f; n] in the base frame.
        _ => {
            let rot = quat_rot([q[3], q[4], q[5], q[6]]);
            (
                rot * Vector3::new(tau[0], tau[1], tau[2]),
                rot * Vector3::new(tau[3], tau[4], tau[5]),
            )
        }
    };
    let x = Vector3::new(q[0], q[1], q[2]);
    let n_g = n_origin + (x - com).cross(&f);
    [n_g[0], n_g[1], n_g[2], f[0], f[1], f[2]]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Wieber 2005, §4: on a free-floating tree (every joint kind below a free base of either
    /// kind, every Euler sequence), the six base rows of `M·q̈ + N·q̇` are the Newton and Euler
    /// equations of the whole system: the external wrench about the centre of mass they stand
    /// for is the rate of the centroidal momentum, summed body by body from plain kinematics.
    #[test]
    fn base_rows_are_the_newton_and_euler_equations(seed in any::<u64>(), n in 1usize..=12, s in 0usize..13) {
        let mut model = random_model(seed, n);
        model.joints[0].kind = match s {
            12 => JointKind::FreeQuaternion,
            s => JointKind::FreeEuler { seq: EulerSeq::parse(SEQS[s]).unwrap() },
        };
        model.joints[0].placement = articulated_dynamics::model::Placement::IDENTITY;
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed ^ 0xBA5E);
        let got = base_wrench(&r, model.joints[0].kind, &q, &v, &a);
        let want = centroidal_rate(&model, &q, &v, &a);
        let scale = want.iter().fold(0.0f64, |s, x| s.max(x.abs())).max(1e-300);
        let err = got.iter().zip(&want).fold(0.0f64, |e, (x, y)| e.max((x - y).abs())) / scale;
        prop_assert!(err < 1e-10, "base rows vs ḣ_G: {err:e}");
    }
}

/// The reference's `ḣ_G` (the bodies' net forces of Newton–Euler summed to the centre of mass)
/// equals the same rate summed body by body from Wieber's body Jacobians and their rates, on
/// random trees of every joint kind; its drift is the rate at `a = 0`.
#[test]
fn centroidal_momentum_rate_matches_the_body_jacobians() {
    let mut worst = [0.0f64; 2];
    for seed in 0..150u64 {
        let model = random_model(seed, 1 + (seed as usize % 15));
        let r = Reference::new(&model).unwrap();
        let (q, v, a) = random_state(&model, seed ^ 0xD0);
        let got = r.centroidal_momentum_rate(&q, &v, &a).unwrap();
        let want = centroidal_rate(&model, &q, &v, &a);
        let scale = want.iter().fold(0.0f64, |s, x| s.max(x.abs())).max(1e-300);
        let err = got
            .iter()
            .zip(&want)
            .fold(0.0f64, |e, (x, y)| e.max((x - y).abs()))
            / scale;
        let zero = vec![0.0; v.len()];
        let drift = r.centroidal_momentum_drift(&q, &v).unwrap();
        let at_zero = r.centroidal_momentum_rate(&q, &v, &zero).unwrap();
        let d = (drift - at_zero).amax() / at_zero.amax().max(1e-300);
        assert!(err < 1e-12 && d == 0.0, "seed {seed}: {err:e} {d:e}");
        worst = [worst[0].max(err), worst[1].max(d)];
    }
    eprintln!("max relative errors over 150 random trees (ḣ_G, drift): {worst:?}");
}

/// The base-row test can fail: with the moment taken about the base origin instead of the
/// centre of mass, it does not hold.
#[test]
fn base_row_test_is_sensitive() {
    let mut model = random_model(9, 5);
    model.joints[0].kind = JointKind::FreeQuaternion;
    model.joints[0].placement = articulated_dynamics::model::Placement::IDENTITY;
    let r = Reference::new(&model).unwrap();
    let (q, v, a) = random_state(&model, 9);
    let got = base_wrench(&r, model.joints[0].kind, &q, &v, &a);
    let want = centroidal_rate(&model, &q, &v, &a);
    let com = r.center_of_mass(&q).unwrap();
    let x = Vector3::new(q[0], q[1], q[2]);
    let f = Vector3::new(got[3], got[4], got[5]);
    // Undo the shift to G: the moment about the base origin.
    let about_origin = Vector3::new(got[0], got[1], got[2]) - (x - com).cross(&f);
    assert!((about_origin - Vector3::new(want[0], want[1], want[2])).amax() > 1e-6);
}

/// The composite form of the Coriolis matrix (`O(n·d)`, what the generator traces) equals the
/// body-by-body one it is derived from, on random trees of every joint kind.
#[test]
fn coriolis_composite_form_equals_the_body_sum() {
    use articulated_dynamics::reference::centroidal;
    for seed in 0..150u64 {
        let model = random_model(seed, 1 + (seed as usize % 15));
        let r = Reference::new(&model).unwrap();
        if r.nv() == 0 {
            continue;
        }
        let (q, v, _) = random_state(&model, seed ^ 0xC0);
        let fast = centroidal::coriolis_matrix(r.tree(), &q, &v);
        let slow = centroidal::coriolis_matrix_by_bodies(r.tree(), &q, &v);
        // Relative to its natural size `max|M|·max|v|` (it can vanish: two branches on a fixed root).
        let v_max = v.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let scale = r.mass_matrix(&q).unwrap().amax() * v_max;
        let err = fast
            .iter()
            .zip(&slow)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()))
            / scale;
        assert!(err < 1e-12, "seed {seed}: {err:e}");
    }
}
