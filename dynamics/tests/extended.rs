//! The ground truth ([`articulated_dynamics::extended`]) against values it did not compute:
//! `mpmath` at 300 bits for its sine, cosine and square root, and dynamics written out by hand
//! (evaluated in double-double too) for its recursions, to 1e-28.

mod common;

use articulated_dynamics::extended::{relative_error, Dd, GroundTruth};
use articulated_dynamics::model::JointKind;
use articulated_dynamics::reference::Reference;
use articulated_dynamics::Scalar;
use common::*;
use core::f64::consts::{FRAC_PI_2, SQRT_2};

const Y: [f64; 3] = [0.0, 1.0, 0.0];

fn dd(hi: f64, lo: f64) -> Dd {
    Dd::from_f64(hi) + Dd::from_f64(lo)
}

/// `|a − b| / max(|b|, floor)`, in double-double.
fn rel(a: Dd, b: Dd, floor: f64) -> f64 {
    (a - b).abs().to_f64() / b.abs().to_f64().max(floor)
}

/// `(x, sin x, cos x)`, each value as `(hi, lo)`, from
/// `mpmath` (`mp.prec = 300`; `hi = float(y)`, `lo = float(y − hi)`), for `x` the `f64` shown.
/// A double-double value as `(hi, lo)`.
type Pair = (f64, f64);

const SIN_COS: [(f64, Pair, Pair); 8] = [
    (
        0.1,
        (0.09983341664682815, 3.08001512929492e-18),
        (0.9950041652780258, -5.50210156918377e-17),
    ),
    (
        1.0,
        (0.8414709848078965, 1.776845092935536e-18),
        (0.5403023058681398, -4.760954612604417e-17),
    ),
    (
        FRAC_PI_2,
        (1.0, -1.874699728327322e-33),
        (6.123233995736766e-17, -1.4973849048591698e-33),
    ),
    (
        3.0,
        (0.1411200080598672, 8.577269787017502e-18),
        (-0.9899924966004454, -4.2060261566099734e-17),
    ),
    (
        -0.7,
        (-0.644217687237691, -2.8740567927338755e-18),
        (0.7648421872844885, -4.013780434022238e-17),
    ),
    (
        20.0,
        (0.9129452507276277, -1.1889007125365703e-17),
        (0.40808206181339196, 2.5226139669269e-17),
    ),
    (
        1000.5,
        (0.9952739571052135, 5.1293231726011145e-17),
        (0.09710690144438526, 3.9534046844460945e-18),
    ),
    (1e-08, (1e-08, -1.6666666666666668e-25), (1.0, -5e-17)),
];

/// `(x, √x)` from `mpmath` as above.
const SQRT: [(f64, (f64, f64)); 4] = [
    (2.0, (SQRT_2, -9.667293313452913e-17)),
    (0.3, (0.5477225575051661, 2.890126723719787e-17)),
    (1e-20, (1e-10, -6.385556158839296e-27)),
    (12345.678, (111.11110655555547, -4.3594669324288495e-15)),
];

#[test]
fn sine_cosine_and_root_match_mpmath() {
    for (x, (sh, sl), (ch, cl)) in SIN_COS {
        let (s, c) = Dd::from_f64(x).sin_cos();
        // Relative to the value, except where it is tiny (cos at π/2 rounded): absolute.
        assert!(rel(s, dd(sh, sl), 1.0) < 1e-31, "sin {x}: {s:?}");
        assert!(rel(c, dd(ch, cl), 1.0) < 1e-31, "cos {x}: {c:?}");
        assert!(rel(s, dd(sh, sl), 0.0) < 1e-30, "sin {x} relative: {s:?}");
        assert!(rel(c, dd(ch, cl), 0.0) < 1e-30, "cos {x} relative: {c:?}");
    }
    for (x, (h, l)) in SQRT {
        let r = Dd::from_f64(x).sqrt();
        assert!(rel(r, dd(h, l), 0.0) < 1e-31, "sqrt {x}: {r:?}");
    }
    assert_eq!(Dd::zero().sqrt(), Dd::zero());
}

#[test]
fn sine_and_cosine_keep_the_pythagorean_identity() {
    for k in -400..400 {
        let x = Dd::from_f64(k as f64 * 0.173) + Dd::from_f64(1e-18 * k as f64);
        let (s, c) = x.sin_cos();
        let one = s * s + c * c;
        assert!((one - Dd::one()).abs().to_f64() < 4e-32, "{k}: {one:?}");
    }
}

/// The planar double pendulum of `closed_forms.rs`, its Lagrangian dynamics written out in
/// double-double: `M`, the bias, gravity and `q̈ = M⁻¹(τ − h)` (Cramer's rule) to 1e-28.
#[test]
fn double_pendulum_matches_lagrange_to_1e_28() {
    let (m1, m2, l1, c1, c2, i1, i2) = (1.3, 0.8, 0.9, 0.4, 0.35, 0.07, 0.03);
    let model = double_pendulum_model(m1, m2, l1, c1, c2, i1, i2);
    let truth = GroundTruth::new(&model).unwrap();
    let d = Dd::from_f64;
    let (m1, m2, l1, c1, c2, i1, i2, g) =
        (d(m1), d(m2), d(l1), d(c1), d(c2), d(i1), d(i2), d(9.81));
    for &(t1, t2, d1, d2, tau1, tau2) in &[
        (0.3, -0.8, 1.1, -0.6, 0.5, -0.2),
        (2.0, 1.0, -0.4, 2.2, 0.0, 0.0),
        (FRAC_PI_2, 1e-9, 30.0, -20.0, 3.0, 1.0),
    ] {
        let (s2, co2) = d(t2).sin_cos();
        let s1 = d(t1).sin_cos().0;
        let s12 = (d(t1) + d(t2)).sin_cos().0;
        let two = d(2.0);
        let m11 = i1 + m1 * c1 * c1 + i2 + m2 * (l1 * l1 + c2 * c2 + two * l1 * c2 * co2);
        let m12 = i2 + m2 * (c2 * c2 + l1 * c2 * co2);
        let m22 = i2 + m2 * c2 * c2;
        let mm = truth.mass_matrix(&[t1, t2]).unwrap();
        for (got, want) in [(mm[0], m11), (mm[1], m12), (mm[2], m12), (mm[3], m22)] {
            assert!(rel(got, want, 0.0) < 1e-28, "M: {got:?} vs {want:?}");
        }
        let h = m2 * l1 * c2 * s2;
        let bias = [
            -h * (two * d(d1) * d(d2) + d(d2) * d(d2)),
            h * d(d1) * d(d1),
        ];
        let grav = [
            (m1 * c1 + m2 * l1) * g * s1 + m2 * c2 * g * s12,
            m2 * c2 * g * s12,
        ];
        let b = truth
            .inverse_dynamics(&[t1, t2], &[d1, d2], &[0.0, 0.0], false)
            .unwrap();
        let gv = truth
            .inverse_dynamics(&[t1, t2], &[0.0, 0.0], &[0.0, 0.0], true)
            .unwrap();
        for k in 0..2 {
            assert!(
                rel(b[k], bias[k], 1.0) < 1e-28,
                "bias {k}: {b:?} vs {bias:?}"
            );
            assert!(rel(gv[k], grav[k], 1.0) < 1e-28, "gravity {k}: {gv:?}");
        }
        let r = [d(tau1) - bias[0] - grav[0], d(tau2) - bias[1] - grav[1]];
        let det = m11 * m22 - m12 * m12;
        let qdd = [
            (m22 * r[0] - m12 * r[1]) / det,
            (m11 * r[1] - m12 * r[0]) / det,
        ];
        let (aba, _) = truth
            .forward_dynamics(&[t1, t2], &[d1, d2], &[tau1, tau2])
            .unwrap();
        let ltdl = truth
            .forward_dynamics_ltdl(&[t1, t2], &[d1, d2], &[tau1, tau2])
            .unwrap();
        for k in 0..2 {
            assert!(
                rel(aba[k], qdd[k], 1.0) < 1e-28,
                "ABA {k}: {aba:?} vs {qdd:?}"
            );
            assert!(rel(ltdl[k], qdd[k], 1.0) < 1e-28, "LᵀDL {k}: {ltdl:?}");
        }
    }
}

/// A free body spinning about a principal axis tilted by a quaternion: with no torque and no
/// gravity component that could turn it, Euler's equations say `I·ω̇ = −ω × (I·ω)`, which is
/// zero about a principal axis; any other ω gives the closed-form gyroscopic acceleration.
#[test]
fn free_body_follows_eulers_equations_to_1e_28() {
    let (ixx, iyy, izz) = (0.2, 0.15, 0.1);
    let model = model(
        vec![body("body", 3.0, [0.0; 3], diag(ixx, iyy, izz))],
        vec![joint(
            "free",
            JointKind::FreeQuaternion,
            None,
            [0.0; 3],
            [0.0; 3],
        )],
    );
    let truth = GroundTruth::new(&model).unwrap();
    let nv = truth.nv();
    assert_eq!(nv, 6);
    // Body-frame velocity `[v; ω]`; q = [x, y, z, w, qx, qy, qz], a unit quaternion (a turn
    // about z): the body-frame equations do not depend on it.
    let (s, c) = (0.3f64.sin(), 0.3f64.cos());
    let q = [0.1, -0.2, 1.0, s, 0.0, 0.0, c];
    let w = [1.5, -40.0, 7.0];
    let v = [0.0, 0.0, 0.0, w[0], w[1], w[2]];
    let (qdd, _) = truth.forward_dynamics(&q, &v, &[0.0; 6]).unwrap();
    let d = Dd::from_f64;
    let (i, w) = ([d(ixx), d(iyy), d(izz)], w.map(d));
    // ω̇ = I⁻¹·(−ω × I·ω), component by component.
    let iw = [i[0] * w[0], i[1] * w[1], i[2] * w[2]];
    let gyro = [
        -(w[1] * iw[2] - w[2] * iw[1]),
        -(w[2] * iw[0] - w[0] * iw[2]),
        -(w[0] * iw[1] - w[1] * iw[0]),
    ];
    for k in 0..3 {
        let want = gyro[k] / i[k];
        let got = qdd[model_angular(k)];
        assert!(rel(got, want, 1.0) < 1e-28, "ω̇_{k}: {got:?} vs {want:?}");
    }
}

/// Where the angular part of a free joint's velocity sits (`[v; ω]`).
fn model_angular(k: usize) -> usize {
    3 + k
}

/// Rounded to `f64`, the ground truth is the reference, and `relative_error` measures the
/// reference's own error at rounding level.
#[test]
fn ground_truth_rounds_to_the_reference() {
    let model = model(
        vec![
            body("a", 1.3, [0.1, 0.0, -0.4], diag(0.1, 0.07, 0.02)),
            body("b", 0.8, [0.0, 0.05, -0.35], diag(0.05, 0.03, 0.01)),
        ],
        vec![
            joint(
                "j1",
                JointKind::Revolute { axis: Y },
                None,
                [0.0; 3],
                [0.0; 3],
            ),
            joint(
                "j2",
                JointKind::Revolute {
                    axis: [1.0, 0.0, 0.0],
                },
                Some(0),
                [0.0, 0.0, -0.9],
                [0.1, 0.2, 0.3],
            ),
        ],
    );
    let reference = Reference::new(&model).unwrap();
    let truth = GroundTruth::new(&model).unwrap();
    let (q, v, tau) = ([0.4, -1.1], [0.7, 2.0], [0.3, -0.5]);
    let want = truth.forward_dynamics(&q, &v, &tau).unwrap().0;
    let got = reference.forward_dynamics(&q, &v, &tau).unwrap();
    let err = relative_error(got.as_slice(), &want);
    assert!(err < 1e-14, "{err:e}");
    let m = reference.mass_matrix(&q).unwrap();
    let m_row_major: Vec<f64> = m.transpose().iter().copied().collect();
    assert!(relative_error(&m_row_major, &truth.mass_matrix(&q).unwrap()) < 1e-15);
    // A wrong value is seen as wrong.
    assert!(relative_error(&[got[0] * (1.0 + 1e-9), got[1]], &want) > 1e-10);
    assert_eq!(relative_error(&[f64::NAN, 0.0], &want), f64::INFINITY);
}
