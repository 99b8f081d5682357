//! Riccati/LQR against closed forms and on random systems, linearization against closed forms
//! and the generated mass matrix, the tangent maps, and the inverted two-link stabilized by
//! LQR and by computed torque.

use articulated::control::computed_torque::{computed_torque, hold};
use articulated::control::linearize::{exact, linearize, linearize_dyn, LinearizeError};
use articulated::control::riccati::{care, lqr, spectral_abscissa, RiccatiError};
use articulated::control::state_feedback::{split_gain, state_feedback};
use articulated::control::tangent::{difference, retract};
use articulated::nalgebra::{DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated::Coordinates;
use articulated_dynamics::random::Rng;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain")]
struct TwoLink;

fn random_matrix(rng: &mut Rng, r: usize, c: usize, scale: f64) -> DMatrix<f64> {
    DMatrix::from_fn(r, c, |_, _| rng.symmetric(scale))
}

/// The largest real part of the eigenvalues, straight from nalgebra.
fn abscissa(a: &DMatrix<f64>) -> f64 {
    a.complex_eigenvalues()
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `‖AᵀP + PA − PBR⁻¹BᵀP + Q‖_F` and the equation's scale
/// `‖Q‖ + 2‖A‖‖P‖ + ‖BR⁻¹Bᵀ‖‖P‖²`.
fn residual(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
    p: &DMatrix<f64>,
) -> (f64, f64) {
    let g = b * r.clone().try_inverse().unwrap() * b.transpose();
    let res = a.transpose() * p + p * a - p * &g * p + q;
    let scale = q.norm() + 2.0 * a.norm() * p.norm() + g.norm() * p.norm() * p.norm();
    (res.norm(), scale)
}

// ---- Riccati ----

#[test]
fn scalar_closed_form() {
    // 2ap − p²b²/r + q = 0, stabilizing root p = r·(a + √(a² + b²q/r))/b².
    for (a, b, q, r) in [
        (1.0, 1.0, 1.0, 1.0),
        (-2.0, 0.5, 3.0, 0.1),
        (5.0, 2.0, 0.0, 1.0),
        (0.0, 1.0, 4.0, 9.0),
        (-1.0, 1.0, 0.0, 1.0),
    ] {
        let m = |x: f64| DMatrix::from_element(1, 1, x);
        let p = care(&m(a), &m(b), &m(q), &m(r)).unwrap()[(0, 0)];
        let exact = r * (a + (a * a + b * b * q / r).sqrt()) / (b * b);
        assert!(
            (p - exact).abs() <= 1e-13 * (1.0 + exact.abs()),
            "a {a} b {b} q {q} r {r}: {p} vs {exact}"
        );
        let design = lqr(&m(a), &m(b), &m(q), &m(r)).unwrap();
        assert!((design.k[(0, 0)] - b * exact / r).abs() <= 1e-13 * (1.0 + exact.abs()));
        assert!(a - b * design.k[(0, 0)] < 0.0);
    }
}

#[test]
fn double_integrator_closed_form() {
    // ẍ = u, Q = diag(q1, q2), R = r: p12 = √(q1 r), p22 = √(r (q2 + 2 p12)),
    // p11 = p12 p22 / r.
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
    for (q1, q2, r) in [(1.0, 1.0, 1.0), (100.0, 0.0, 0.01), (2.0, 5.0, 3.0)] {
        let q = DMatrix::from_diagonal(&articulated::nalgebra::DVector::from_vec(vec![q1, q2]));
        let rm = DMatrix::from_element(1, 1, r);
        let design = lqr(&a, &b, &q, &rm).unwrap();
        let p12 = (q1 * r).sqrt();
        let p22 = (r * (q2 + 2.0 * p12)).sqrt();
        let p11 = p12 * p22 / r;
        let exact = DMatrix::from_row_slice(2, 2, &[p11, p12, p12, p22]);
        assert!(
            (&design.p - &exact).norm() <= 1e-12 * exact.norm(),
            "{} vs {exact}",
            design.p
        );
        assert!((design.k[(0, 0)] - p12 / r).abs() <= 1e-12 * (1.0 + p12 / r));
        assert!((design.k[(0, 1)] - p22 / r).abs() <= 1e-12 * (1.0 + p22 / r));
    }
}

#[test]
fn random_stabilizable_systems() {
    let mut rng = Rng::new(42);
    let mut worst: f64 = 0.0;
    for &(n, m) in &[
        (1, 1),
        (2, 1),
        (3, 2),
        (6, 3),
        (8, 1),
        (12, 6),
        (12, 12),
        (24, 12),
        (24, 24),
    ] {
        for _ in 0..3 {
            // Unstable A (entries of size 1 give eigenvalues up to about √n), random B (then
            // (A, B) is controllable with probability one), Q = CᵀC + 0.1·I, R SPD.
            let a = random_matrix(&mut rng, n, n, 1.0);
            let b = random_matrix(&mut rng, n, m, 1.0);
            let c = random_matrix(&mut rng, n, n, 1.0);
            let q = c.transpose() * &c + DMatrix::identity(n, n) * 0.1;
            let s = random_matrix(&mut rng, m, m, 0.5);
            let r = &s * s.transpose() + DMatrix::identity(m, m);
            let design = lqr(&a, &b, &q, &r).unwrap();
            let (res, scale) = residual(&a, &b, &q, &r, &design.p);
            worst = worst.max(res / scale);
            assert!(
                res < 1e-9 * scale,
                "n {n} m {m}: residual {res:e} of {scale:e}"
            );
            assert!((&design.p - design.p.transpose()).norm() <= 1e-14 * design.p.norm());
            let closed = &a - &b * &design.k;
            let abs = abscissa(&closed);
            assert!(
                abs < 0.0,
                "n {n} m {m}: A − BK has an eigenvalue with real part {abs}"
            );
            // P is positive definite (Q is): its Cholesky factor exists.
            assert!(design.p.clone().cholesky().is_some());
            assert_eq!(spectral_abscissa(&closed).map(|s| s < 0.0), Some(true));
        }
    }
    println!("worst relative residual {worst:.2e}");
}

#[test]
fn failures_are_reported() {
    let m = |r: usize, c: usize, x: &[f64]| DMatrix::from_row_slice(r, c, x);
    let i2 = DMatrix::<f64>::identity(2, 2);
    let i1 = DMatrix::<f64>::identity(1, 1);
    // An unstable mode B cannot reach.
    let a = m(2, 2, &[1.0, 0.0, 0.0, -1.0]);
    let b = m(2, 1, &[0.0, 1.0]);
    assert_eq!(
        care(&a, &b, &i2, &i1),
        Err(RiccatiError::NoStabilizingSolution)
    );
    // The same with the unstable mode coupled but still out of reach of B.
    let a = m(2, 2, &[2.0, 0.0, 1.0, -1.0]);
    assert_eq!(
        care(&a, &b, &i2, &i1),
        Err(RiccatiError::NoStabilizingSolution)
    );
    // A mode on the imaginary axis that Q does not see: not detectable.
    let z = DMatrix::zeros(1, 1);
    assert_eq!(
        care(&z, &i1, &z, &i1),
        Err(RiccatiError::NoStabilizingSolution)
    );
    // An undamped oscillator with no input on it and no weight.
    let a = m(2, 2, &[0.0, 1.0, -1.0, 0.0]);
    let b0 = m(2, 1, &[0.0, 0.0]);
    assert_eq!(
        care(&a, &b0, &DMatrix::zeros(2, 2), &i1),
        Err(RiccatiError::NoStabilizingSolution)
    );
    // Bad input.
    let a = m(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    assert_eq!(
        care(&a, &b, &i2, &DMatrix::zeros(1, 1)),
        Err(RiccatiError::SingularR)
    );
    assert_eq!(care(&a, &b, &i2, &(-&i1)), Err(RiccatiError::SingularR));
    assert_eq!(care(&a, &b, &i1, &i1), Err(RiccatiError::Dimensions));
    assert_eq!(care(&a, &i2, &i2, &i1), Err(RiccatiError::Dimensions));
    let mut nan = a.clone();
    nan[(0, 1)] = f64::NAN;
    assert_eq!(care(&nan, &b, &i2, &i1), Err(RiccatiError::NonFinite("A")));
    assert_eq!(
        care(&a, &b, &m(2, 2, &[1.0, 0.5, 0.0, 1.0]), &i1),
        Err(RiccatiError::NotSymmetric("Q"))
    );
    assert_eq!(
        lqr(&a, &b, &i2, &m(1, 1, &[f64::INFINITY])),
        Err(RiccatiError::NonFinite("R"))
    );
}

// ---- Tangent maps ----

fn random_quaternion(rng: &mut Rng) -> [f64; 4] {
    let q = [0; 4].map(|_| rng.symmetric(1.0));
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

#[test]
fn retract_and_difference_are_inverse() {
    let coords = [
        Coordinates::Vector(2),
        Coordinates::Quaternion,
        Coordinates::FreeQuaternion,
    ];
    let mut rng = Rng::new(9);
    for _ in 0..200 {
        let (a, b) = (random_quaternion(&mut rng), random_quaternion(&mut rng));
        let q0: Vec<f64> = [rng.symmetric(2.0), rng.symmetric(2.0)]
            .into_iter()
            .chain(a)
            .chain([0; 3].map(|_| rng.symmetric(3.0)))
            .chain(b)
            .collect();
        let delta: Vec<f64> = (0..11).map(|_| rng.symmetric(1.5)).collect();
        let mut q1 = vec![0.0; 13];
        assert!(retract(&coords, &q0, &delta, &mut q1));
        let mut back = vec![0.0; 11];
        assert!(difference(&coords, &q1, &q0, &mut back));
        for k in 0..11 {
            assert!((back[k] - delta[k]).abs() < 1e-12, "{back:?} vs {delta:?}");
        }
        for at in [2, 9] {
            let n: f64 = q1[at..at + 4].iter().map(|x| x * x).sum();
            assert!((n - 1.0).abs() < 1e-15);
        }
    }
    // A half turn about z applied to the identity: the quaternion (0, 0, 0, 1), either sign.
    let mut q = [0.0; 4];
    assert!(retract(
        &[Coordinates::Quaternion],
        &[1.0, 0.0, 0.0, 0.0],
        &[0.0, 0.0, std::f64::consts::PI],
        &mut q
    ));
    assert!(q[0].abs() < 1e-16 && (q[3] - 1.0).abs() < 1e-16);
    // A free body displaced along its own x axis after a quarter turn about z moves along y.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut q = [0.0; 7];
    let free = [Coordinates::FreeQuaternion];
    assert!(retract(
        &free,
        &[0.0, 0.0, 0.0, s, 0.0, 0.0, s],
        &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        &mut q
    ));
    assert!(q[0].abs() < 1e-15 && (q[1] - 1.0).abs() < 1e-15 && q[2] == 0.0);
    // Lengths that do not fit are refused.
    assert!(!retract(&free, &[0.0; 6], &[0.0; 6], &mut q));
    assert!(!difference(&free, &[0.0; 7], &[0.0; 7], &mut [0.0; 5]));
}

// ---- Linearization ----

#[test]
fn exact_on_a_linear_system() {
    let mut rng = Rng::new(4);
    let nv = 5;
    let a21 = random_matrix(&mut rng, nv, nv, 50.0);
    let a22 = random_matrix(&mut rng, nv, nv, 3.0);
    let b2 = random_matrix(&mut rng, nv, nv, 0.2);
    let c = random_matrix(&mut rng, nv, 1, 10.0);
    let v0: Vec<f64> = (0..nv).map(|_| rng.symmetric(20.0)).collect();
    let tau0: Vec<f64> = (0..nv).map(|_| rng.symmetric(300.0)).collect();
    let lin = linearize_dyn(&v0, &tau0, |d, v, tau, out| {
        let f = |x: &[f64]| DMatrix::from_column_slice(nv, 1, x);
        let y = &a21 * f(d) + &a22 * f(v) + &b2 * f(tau) + &c;
        out.copy_from_slice(y.as_slice());
        Ok::<(), ()>(())
    })
    .unwrap();
    for i in 0..nv {
        for j in 0..nv {
            assert_eq!(lin.a[(i, j)], 0.0);
            assert_eq!(lin.a[(i, nv + j)], if i == j { 1.0 } else { 0.0 });
            assert_eq!(lin.b[(i, j)], 0.0);
            let e = [
                (lin.a[(nv + i, j)], a21[(i, j)]),
                (lin.a[(nv + i, nv + j)], a22[(i, j)]),
                (lin.b[(nv + i, j)], b2[(i, j)]),
            ];
            for (got, want) in e {
                assert!((got - want).abs() < 1e-8, "{got} vs {want}");
            }
        }
    }
    assert_eq!(
        linearize_dyn(&v0, &tau0[..2], |_, _, _, _| Ok::<(), ()>(())),
        Err(LinearizeError::Length {
            slice: "tau",
            found: 2,
            expected: nv
        })
    );
    assert_eq!(
        linearize_dyn(&v0, &tau0, |_, _, _, _| Err("singular")),
        Err(LinearizeError::Dynamics("singular"))
    );
    assert_eq!(
        linearize_dyn(&v0, &tau0, |_, _, _, out| {
            out[0] = f64::NAN;
            Ok::<(), ()>(())
        }),
        Err(LinearizeError::NotFinite)
    );
}

articulated::chain! {
    chain Pendulum {
        gravity: [0.0, 0.0, -9.81];
        body bob { mass: 2.0, com: [0.0, 0.0, 0.8], inertia: diag(0.05, 0.06, 0.07) }
        joint pivot: revolute(y) { parent: world, child: bob }
    }
}

#[test]
fn planar_pendulum_about_upright() {
    // I θ̈ = m g l sin θ + τ about the pivot, I = I_yy + m l²: about θ = 0,
    // A = [[0, 1], [m g l / I, 0]], B = [[0], [1 / I]].
    let inertia = 0.06 + 2.0 * 0.8 * 0.8;
    let q0 = SVector::<f64, 1>::zeros();
    let lin = linearize(
        &SVector::zeros(),
        &SVector::zeros(),
        |d: &SVector<f64, 1>, v, tau| {
            let mut q = q0;
            retract(
                Pendulum::COORDINATES,
                q0.as_slice(),
                d.as_slice(),
                q.as_mut_slice(),
            );
            Pendulum::forward_dynamics(&q, v, tau)
        },
    )
    .unwrap();
    let want_a = [0.0, 1.0, 2.0 * 9.81 * 0.8 / inertia, 0.0];
    for (k, w) in want_a.iter().enumerate() {
        let got = lin.a[(k / 2, k % 2)];
        assert!(
            (got - w).abs() < 1e-8 * (1.0 + w.abs()),
            "A[{k}] {got} vs {w}"
        );
    }
    assert_eq!(lin.b[(0, 0)], 0.0);
    assert!((lin.b[(1, 0)] - 1.0 / inertia).abs() < 1e-9);
}

/// The two-link system linearized about upright, `q = 0`, `v = 0`, `τ = g(0) = 0`.
fn two_link_upright() -> articulated::control::linearize::Linearization {
    let q0 = SVector::<f64, 6>::zeros();
    let tau0 = TwoLink::gravity(&q0);
    linearize(&SVector::zeros(), &tau0, |d: &SVector<f64, 6>, v, tau| {
        let mut q = q0;
        retract(
            TwoLink::COORDINATES,
            q0.as_slice(),
            d.as_slice(),
            q.as_mut_slice(),
        );
        TwoLink::forward_dynamics(&q, v, tau)
    })
    .unwrap()
}

#[test]
fn two_link_input_matrix_is_the_inverse_mass_matrix() {
    let lin = two_link_upright();
    let m_inv = TwoLink::mass_matrix(&SVector::zeros())
        .try_inverse()
        .unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..6 {
        for j in 0..6 {
            assert_eq!(lin.b[(i, j)], 0.0);
            worst = worst.max((lin.b[(6 + i, j)] - m_inv[(i, j)]).abs());
        }
    }
    println!(
        "two-link B block vs M⁻¹: largest difference {worst:.2e} (max |M⁻¹| {:.2e})",
        m_inv.amax()
    );
    assert!(worst < 1e-6);
    // Upright is unstable: A has an eigenvalue with positive real part.
    assert!(abscissa(&lin.a) > 1.0);
}

/// LQR weights for the two-link system: `Q = diag(100 (per rad²) ×6, 10 (per (rad/s)²) ×6)`,
/// `R = 0.01·I` (per (N·m)²): a 0.1 rad error costs as much as a 10 N·m couple.
fn two_link_lqr() -> (SMatrix<f64, 6, 6>, SMatrix<f64, 6, 6>, DMatrix<f64>) {
    let lin = two_link_upright();
    let mut q = DMatrix::<f64>::zeros(12, 12);
    for i in 0..6 {
        q[(i, i)] = 100.0;
        q[(6 + i, 6 + i)] = 10.0;
    }
    let r = DMatrix::<f64>::identity(6, 6) * 0.01;
    let design = lqr(&lin.a, &lin.b, &q, &r).unwrap();
    let (res, scale) = residual(&lin.a, &lin.b, &q, &r, &design.p);
    assert!(res < 1e-9 * scale, "residual {res:e} of {scale:e}");
    let closed = &lin.a - &lin.b * &design.k;
    let (kq, kv) = split_gain::<6>(&design.k).unwrap();
    (kq, kv, closed)
}

#[test]
fn inverted_two_link_lqr_is_hurwitz() {
    let (_, _, closed) = two_link_lqr();
    let abs = abscissa(&closed);
    let open = abscissa(&two_link_upright().a);
    println!("two-link upright: open-loop abscissa {open:.3}, closed-loop {abs:.3}");
    assert!(abs < 0.0, "A − BK has an eigenvalue with real part {abs}");
}

// The inverted two-link brought back from 10° leans in 16 directions by both laws, with the
// runtime's integrators: `tests/tests/hemami.rs`.

#[test]
fn controllers_check_the_coordinates() {
    let zero = SVector::<f64, 5>::zeros();
    let m = SMatrix::<f64, 5, 5>::zeros();
    assert!(state_feedback(TwoLink::COORDINATES, zero, zero, zero, m, m).is_err());
    assert!(computed_torque(TwoLink::COORDINATES, m, m, hold(zero), |_, _, _| zero).is_err());
    assert!(split_gain::<6>(&DMatrix::zeros(6, 11)).is_none());
}

articulated::chain! {
    /// A pole on a quaternion ball joint on a slider, with its exact derivatives.
    chain BallPole {
        gravity: [0.0, 0.0, -9.81];
        outputs: [forward_dynamics, forward_dynamics_derivatives];
        body carriage { mass: 3.0, com: [0.1, 0.0, 0.05], inertia: diag(0.02, 0.03, 0.04) }
        body pole { mass: 1.0, com: [0.02, 0.0, 0.5], inertia: diag(0.08, 0.075, 0.006) }
        joint slide: prismatic(x) { parent: world, child: carriage }
        joint ball: spherical(quaternion) { parent: carriage, child: pole }
    }
}

/// `exact` against central differences through the runtime's retraction, away from rest (a
/// tilted, spinning pole, so every block of `∂q̈/∂(δ, v)` is non-zero): the same `A`, `B` to
/// the differences' accuracy.
#[test]
fn exact_linearization_matches_central_differences_on_a_quaternion_joint() {
    let tilt = [0.9f64, 0.2, -0.3, 0.25];
    let n = tilt.iter().map(|x| x * x).sum::<f64>().sqrt();
    let q0 = SVector::<f64, 5>::from([0.4, tilt[0] / n, tilt[1] / n, tilt[2] / n, tilt[3] / n]);
    let v0 = SVector::<f64, 4>::from([0.3, 1.5, -0.7, 2.0]);
    let tau0 = SVector::<f64, 4>::from([1.0, 0.5, -0.2, 0.1]);
    let lin = exact::<BallPole, 5, 4>(&q0, &v0, &tau0).unwrap();
    let fd = linearize(&v0, &tau0, |d: &SVector<f64, 4>, v, tau| {
        let mut q = q0;
        retract(
            BallPole::COORDINATES,
            q0.as_slice(),
            d.as_slice(),
            q.as_mut_slice(),
        );
        BallPole::forward_dynamics(&q, v, tau)
    })
    .unwrap();
    let scale = lin.a.amax().max(lin.b.amax());
    let off = (&lin.a - &fd.a).amax().max((&lin.b - &fd.b).amax());
    assert!(off < 1e-7 * scale, "{off:e} of {scale:e}");
    // Not trivially equal: the position block is there.
    assert!(lin.a.view((4, 0), (4, 4)).amax() > 1e-2 * scale);
}
