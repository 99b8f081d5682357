//! Savitzky–Golay differentiation against closed forms (polynomials, sines, noise) and the
//! conversion of `(q, q̇, q̈)` to `(v, v̇)` against rotations whose angular velocity is known in
//! closed form.

use articulated::differentiate::{velocities, CoordinatesError, DifferentiateError, SavitzkyGolay};
use articulated::invert::couples;
use articulated::nalgebra::{Matrix3, SVector, Vector3};
use articulated::prelude::*;
use articulated::Coordinates;
use articulated_dynamics::random::Rng;

/// Uniform times `t0 + i·dt`, or jittered by up to `jitter·dt` (still increasing).
fn times(n: usize, t0: f64, dt: f64, jitter: f64, rng: &mut Rng) -> Vec<f64> {
    (0..n)
        .map(|i| t0 + dt * (i as f64 + rng.symmetric(jitter)))
        .collect()
}

/// `(value, first, second)` of `Σ c_m t^m`.
fn poly(c: &[f64], t: f64) -> (f64, f64, f64) {
    let mut out = (0.0, 0.0, 0.0);
    for (m, &cm) in c.iter().enumerate() {
        let m_i = m as i32;
        out.0 += cm * t.powi(m_i);
        if m >= 1 {
            out.1 += cm * m as f64 * t.powi(m_i - 1);
        }
        if m >= 2 {
            out.2 += cm * (m * (m - 1)) as f64 * t.powi(m_i - 2);
        }
    }
    out
}

/// A standard normal deviate (Box–Muller).
fn gauss(rng: &mut Rng) -> f64 {
    let u = 1.0 - rng.unit();
    let v = rng.unit();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

#[test]
fn exact_on_polynomials_up_to_the_degree() {
    let mut rng = Rng::new(7);
    for degree in 0..=6usize {
        for half_window in [degree.div_ceil(2), degree / 2 + 2, 8] {
            let sg = SavitzkyGolay::new(half_window, degree).unwrap();
            for jitter in [0.0, 0.45] {
                for poly_degree in 0..=degree {
                    let c: Vec<f64> = (0..=poly_degree).map(|_| rng.symmetric(2.0)).collect();
                    let t = times(3 * sg.window(), -0.4, 0.03, jitter, &mut rng);
                    // Two columns: the polynomial and 1 − 2× it.
                    let y: Vec<f64> = t
                        .iter()
                        .flat_map(|&t| {
                            let p = poly(&c, t).0;
                            [p, 1.0 - 2.0 * p]
                        })
                        .collect();
                    let d = sg.differentiate(&t, &y, 2).unwrap();
                    assert_eq!(d.t.len(), t.len() - 2 * half_window);
                    for (row, &ti) in d.t.iter().enumerate() {
                        let (p0, p1, p2) = poly(&c, ti);
                        let scale = 1.0 + c.iter().map(|x| x.abs()).sum::<f64>();
                        // Derivatives scale as 1/h and 1/h² (h ≈ k·dt).
                        let h = 0.03 * half_window.max(1) as f64;
                        let tol = [1e-12 * scale, 1e-11 * scale / h, 1e-10 * scale / (h * h)];
                        let got = [d.value[2 * row], d.first[2 * row], d.second[2 * row]];
                        let want = [p0, p1, if degree >= 2 { p2 } else { 0.0 }];
                        for k in 0..3 {
                            assert!(
                                (got[k] - want[k]).abs() <= tol[k],
                                "p {degree} k {half_window} jitter {jitter} poly {poly_degree} \
                                 derivative {k}: {} vs {}",
                                got[k],
                                want[k]
                            );
                        }
                        let got2 = [d.value[2 * row + 1], d.first[2 * row + 1]];
                        assert!((got2[0] - (1.0 - 2.0 * p0)).abs() <= 2.0 * tol[0]);
                        assert!((got2[1] + 2.0 * p1).abs() <= 2.0 * tol[1]);
                    }
                }
            }
        }
    }
}

/// Largest error of value, first and second derivative of `sin` at the centres near `t = 1`.
fn sine_errors(sg: &SavitzkyGolay, dt: f64, jitter: f64) -> [f64; 3] {
    let mut rng = Rng::new(11);
    // The jitter pattern is drawn once per sample index, so halving dt scales the same grid.
    let n = 2 * sg.window() + 1;
    let t = times(n, 1.0 - dt * (n / 2) as f64, dt, jitter, &mut rng);
    let y: Vec<f64> = t.iter().map(|t| t.sin()).collect();
    let d = sg.differentiate(&t, &y, 1).unwrap();
    let mut err = [0.0f64; 3];
    for (row, &ti) in d.t.iter().enumerate() {
        err[0] = err[0].max((d.value[row] - ti.sin()).abs());
        err[1] = err[1].max((d.first[row] - ti.cos()).abs());
        err[2] = err[2].max((d.second[row] + ti.sin()).abs());
    }
    err
}

#[test]
fn error_on_a_sine_shrinks_at_the_expected_rate() {
    // p = 3, k = 3: on a uniform grid the symmetric window cancels the odd term, so value and
    // first derivative are O(Δ⁴) and the second O(Δ²); on a jittered grid O(Δ⁴), O(Δ³), O(Δ²).
    let sg = SavitzkyGolay::new(3, 3).unwrap();
    for (jitter, expected) in [(0.0, [4.0, 4.0, 2.0]), (0.3, [4.0, 3.0, 2.0])] {
        let dts = [0.04, 0.02, 0.01, 0.005];
        let errs: Vec<[f64; 3]> = dts.iter().map(|&dt| sine_errors(&sg, dt, jitter)).collect();
        for d in 0..3 {
            for w in errs.windows(2) {
                let order = (w[0][d] / w[1][d]).log2();
                println!("jitter {jitter}, derivative {d}: observed order {order:.3}");
                assert!(
                    (order - expected[d]).abs() < 0.3,
                    "jitter {jitter}, derivative {d}: order {order}, expected {}",
                    expected[d]
                );
            }
        }
    }
}

#[test]
fn noise_is_reduced() {
    let mut rng = Rng::new(3);
    let (dt, sigma) = (0.01, 1e-3);
    let n = 2000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|t| t.sin() + sigma * gauss(&mut rng))
        .collect();
    let sg = SavitzkyGolay::new(10, 3).unwrap();
    let d = sg.differentiate(&t, &y, 1).unwrap();
    let rms = |e: &mut dyn Iterator<Item = f64>| {
        let (s, c) = e.fold((0.0, 0), |(s, c), x| (s + x * x, c + 1));
        (s / c as f64).sqrt()
    };
    let e0 = rms(&mut d.t.iter().enumerate().map(|(r, t)| d.value[r] - t.sin()));
    let e1 = rms(&mut d.t.iter().enumerate().map(|(r, t)| d.first[r] - t.cos()));
    let e2 = rms(&mut d.t.iter().enumerate().map(|(r, t)| d.second[r] + t.sin()));
    // Plain central differences of the same samples.
    let c1 = rms(&mut (1..n - 1).map(|i| (y[i + 1] - y[i - 1]) / (2.0 * dt) - t[i].cos()));
    let c2 =
        rms(&mut (1..n - 1).map(|i| (y[i + 1] - 2.0 * y[i] + y[i - 1]) / (dt * dt) + t[i].sin()));
    println!("σ {sigma}: value {e0:.2e}, first {e1:.2e} (central {c1:.2e}), second {e2:.2e} (central {c2:.2e})");
    // For 21 samples and p = 3: ‖w₀‖ ≈ 0.32, so the value keeps a third of the noise.
    assert!(e0 < 0.45 * sigma, "value {e0}");
    // Against the three-point differences: about 1/7 of their noise in the first derivative
    // (0.094·σ/Δ against σ/(√2·Δ)), 1/180 in the second.
    assert!(e1 < 0.2 * c1, "first {e1} vs central {c1}");
    assert!(e2 < 0.02 * c2, "second {e2} vs central {c2}");
}

#[test]
fn every_error_is_reported() {
    use DifferentiateError::*;
    assert_eq!(
        SavitzkyGolay::new(1, 3),
        Err(DegreeTooHigh {
            degree: 3,
            window: 3
        })
    );
    assert_eq!(
        SavitzkyGolay::new(20, 11),
        Err(DegreeAboveMax { degree: 11 })
    );
    let sg = SavitzkyGolay::new(2, 2).unwrap();
    let t: Vec<f64> = (0..8).map(|i| i as f64 * 0.1).collect();
    let y: Vec<f64> = t.iter().flat_map(|t| [*t, t * t]).collect();
    assert!(sg.differentiate(&t, &y, 2).is_ok());
    assert_eq!(
        sg.differentiate(&t[..4], &y[..8], 2),
        Err(TooFewSamples {
            samples: 4,
            window: 5
        })
    );
    assert_eq!(
        sg.differentiate(&t, &y[..15], 2),
        Err(LengthMismatch {
            times: 8,
            values: 15,
            columns: 2
        })
    );
    let mut bad = t.clone();
    bad[5] = f64::NAN;
    assert_eq!(
        sg.differentiate(&bad, &y, 2),
        Err(TimeNotFinite { index: 5 })
    );
    bad[5] = f64::INFINITY;
    assert_eq!(
        sg.differentiate(&bad, &y, 2),
        Err(TimeNotFinite { index: 5 })
    );
    let mut bad = t.clone();
    bad[6] = bad[5];
    assert_eq!(
        sg.differentiate(&bad, &y, 2),
        Err(TimesNotIncreasing { index: 6 })
    );
    bad[6] = bad[4];
    assert_eq!(
        sg.differentiate(&bad, &y, 2),
        Err(TimesNotIncreasing { index: 6 })
    );
    let mut bad = y.clone();
    bad[2 * 3 + 1] = f64::NEG_INFINITY;
    assert_eq!(
        sg.differentiate(&t, &bad, 2),
        Err(SampleNotFinite {
            index: 3,
            column: 1
        })
    );
    bad[2 * 3 + 1] = f64::NAN;
    assert_eq!(
        sg.differentiate(&t, &bad, 2),
        Err(SampleNotFinite {
            index: 3,
            column: 1
        })
    );
    // One sample at a time: the edges have no window; outputs must fit.
    let (mut a, mut b, mut c) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    assert_eq!(
        sg.derivatives_at(&t, &y, 2, 1, &mut a, &mut b, &mut c),
        Err(NoWindow { index: 1 })
    );
    assert_eq!(
        sg.derivatives_at(&t, &y, 2, 6, &mut a, &mut b, &mut c),
        Err(NoWindow { index: 6 })
    );
    assert_eq!(
        sg.derivatives_at(&t, &y, 2, 3, &mut a[..1], &mut b, &mut c),
        Err(OutputLength {
            found: 1,
            columns: 2
        })
    );
    assert!(sg
        .derivatives_at(&t, &y, 2, 5, &mut a, &mut b, &mut c)
        .is_ok());
    assert!((b[1] - 1.0).abs() < 1e-12 && (c[1] - 2.0).abs() < 1e-10);
    // An absurd window is only too large, not an overflow.
    let huge = SavitzkyGolay::new(usize::MAX, 2).unwrap();
    assert_eq!(huge.window(), usize::MAX);
    assert_eq!(huge.centres(8).len(), 0);
    assert_eq!(
        huge.differentiate(&t, &y, 2),
        Err(TooFewSamples {
            samples: 8,
            window: usize::MAX
        })
    );
    // A window whose times crowd at one end is reported, not turned into garbage.
    let sg = SavitzkyGolay::new(2, 4).unwrap();
    let t = [0.0, 1e-9, 2e-9, 3e-9, 1.0, 2.0];
    let y = [0.0; 6];
    assert_eq!(
        sg.differentiate(&t, &y, 1),
        Err(IllConditioned { index: 2 })
    );
    for e in [
        TooFewSamples {
            samples: 4,
            window: 5,
        },
        TimesNotIncreasing { index: 6 },
        SampleNotFinite {
            index: 3,
            column: 1,
        },
    ] {
        assert!(!e.to_string().is_empty());
    }
}

// ---- (q, q̇, q̈) → (v, v̇) ----

/// Hamilton product, written out independently of the crate's.
fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let (aw, av) = (a[0], Vector3::new(a[1], a[2], a[3]));
    let (bw, bv) = (b[0], Vector3::new(b[1], b[2], b[3]));
    let v = bv * aw + av * bw + av.cross(&bv);
    [aw * bw - av.dot(&bv), v.x, v.y, v.z]
}

fn add(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

fn scale(s: f64, a: [f64; 4]) -> [f64; 4] {
    a.map(|x| s * x)
}

/// A rotation about a fixed unit axis `n` by the angle `a(t)`, with its two derivatives:
/// `(cos(a/2), sin(a/2)·n)`.
fn axis_rotation(n: [f64; 3], a: f64, a1: f64, a2: f64) -> [[f64; 4]; 3] {
    let (s, c) = (0.5 * a).sin_cos();
    let q = [c, s * n[0], s * n[1], s * n[2]];
    let dq = [-s, c * n[0], c * n[1], c * n[2]]; // ∂q/∂a ·2
    let q1 = scale(0.5 * a1, dq);
    let q2 = add(scale(0.5 * a2, dq), scale(-0.25 * a1 * a1, q));
    [q, q1, q2]
}

fn convert(
    coords: &[Coordinates],
    q: &[f64],
    q1: &[f64],
    q2: &[f64],
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let nq = q.len();
    let nv: usize = coords.iter().map(|c| c.nv()).sum();
    let (mut qo, mut v, mut vd) = (vec![0.0; nq], vec![0.0; nv], vec![0.0; nv]);
    velocities(coords, q, q1, q2, &mut qo, &mut v, &mut vd).unwrap();
    (qo, v, vd)
}

#[test]
fn constant_angular_velocity() {
    // q(t) = exp(ω t / 2): the body turns at the constant ω, ω̇ = 0.
    let w: [f64; 3] = [0.3, -1.2, 0.7];
    let norm = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let n = w.map(|x| x / norm);
    for t in [0.0, 0.4, 2.5, 7.0] {
        let [q, q1, q2] = axis_rotation(n, norm * t, norm, 0.0);
        let (qo, v, vd) = convert(&[Coordinates::Quaternion], &q, &q1, &q2);
        for k in 0..3 {
            assert!((v[k] - w[k]).abs() < 1e-14, "t {t}: ω {v:?}");
            assert!(vd[k].abs() < 1e-14, "t {t}: ω̇ {vd:?}");
        }
        for k in 0..4 {
            assert!((qo[k] - q[k]).abs() < 1e-15);
        }
    }
}

/// `q(t) = qz(α) ⊗ qx(β)`, scaled by `s(t)` (1 for a unit quaternion), and the closed-form body
/// angular velocity `ω = β̇·e_x + α̇·Rx(β)ᵀ·e_z = (β̇, α̇ sin β, α̇ cos β)` and its rate.
fn two_axis(t: f64, scaled: bool) -> ([[f64; 4]; 3], [f64; 3], [f64; 3]) {
    let (al, al1, al2) = (
        0.7 * (1.3 * t).sin() + 0.2 * t,
        0.91 * (1.3 * t).cos() + 0.2,
        -1.183 * (1.3 * t).sin(),
    );
    let (be, be1, be2) = (
        0.5 * (0.9 * t).cos(),
        -0.45 * (0.9 * t).sin(),
        -0.405 * (0.9 * t).cos(),
    );
    let [a, a1, a2] = axis_rotation([0.0, 0.0, 1.0], al, al1, al2);
    let [b, b1, b2] = axis_rotation([1.0, 0.0, 0.0], be, be1, be2);
    let q = qmul(a, b);
    let q1 = add(qmul(a1, b), qmul(a, b1));
    let q2 = add(add(qmul(a2, b), scale(2.0, qmul(a1, b1))), qmul(a, b2));
    let (s, s1, s2) = if scaled {
        (
            1.0 + 0.2 * (3.0 * t).sin(),
            0.6 * (3.0 * t).cos(),
            -1.8 * (3.0 * t).sin(),
        )
    } else {
        (1.0, 0.0, 0.0)
    };
    let qs = scale(s, q);
    let qs1 = add(scale(s1, q), scale(s, q1));
    let qs2 = add(add(scale(s2, q), scale(2.0 * s1, q1)), scale(s, q2));
    let (sb, cb) = be.sin_cos();
    let w = [be1, al1 * sb, al1 * cb];
    let wd = [be2, al2 * sb + al1 * be1 * cb, al2 * cb - al1 * be1 * sb];
    ([qs, qs1, qs2], w, wd)
}

#[test]
fn time_varying_angular_velocity() {
    for scaled in [false, true] {
        for i in 0..40 {
            let t = 0.37 * i as f64;
            let ([q, q1, q2], w, wd) = two_axis(t, scaled);
            let (qo, v, vd) = convert(&[Coordinates::Quaternion], &q, &q1, &q2);
            for k in 0..3 {
                assert!((v[k] - w[k]).abs() < 1e-14, "t {t}: ω {v:?} vs {w:?}");
                assert!((vd[k] - wd[k]).abs() < 1e-13, "t {t}: ω̇ {vd:?} vs {wd:?}");
            }
            let norm: f64 = qo.iter().map(|x| x * x).sum();
            assert!((norm - 1.0).abs() < 1e-15);
        }
    }
}

#[test]
fn vector_coordinates_are_copied_and_errors_named() {
    let coords = [
        Coordinates::Vector(2),
        Coordinates::Quaternion,
        Coordinates::Vector(1),
    ];
    let ([q, q1, q2], w, wd) = two_axis(0.8, false);
    let qa = [0.1, 0.2, q[0], q[1], q[2], q[3], 0.3];
    let q1a = [1.0, 2.0, q1[0], q1[1], q1[2], q1[3], 3.0];
    let q2a = [4.0, 5.0, q2[0], q2[1], q2[2], q2[3], 6.0];
    let (qo, v, vd) = convert(&coords, &qa, &q1a, &q2a);
    assert_eq!(qo[..2], [0.1, 0.2]);
    assert_eq!(qo[6], 0.3);
    assert_eq!([v[0], v[1], v[5]], [1.0, 2.0, 3.0]);
    assert_eq!([vd[0], vd[1], vd[5]], [4.0, 5.0, 6.0]);
    assert!((v[2] - w[0]).abs() < 1e-14 && (vd[4] - wd[2]).abs() < 1e-13);

    let (mut qo, mut v, mut vd) = ([0.0; 7], [0.0; 6], [0.0; 6]);
    assert_eq!(
        velocities(&coords, &qa[..6], &q1a, &q2a, &mut qo, &mut v, &mut vd),
        Err(CoordinatesError::Length {
            slice: "q",
            found: 6,
            expected: 7
        })
    );
    assert_eq!(
        velocities(&coords, &qa, &q1a, &q2a, &mut qo, &mut v[..5], &mut vd),
        Err(CoordinatesError::Length {
            slice: "v",
            found: 5,
            expected: 6
        })
    );
    let zero = [0.1, 0.2, 0.0, 0.0, 0.0, 0.0, 0.3];
    assert_eq!(
        velocities(&coords, &zero, &q1a, &q2a, &mut qo, &mut v, &mut vd),
        Err(CoordinatesError::DegenerateQuaternion { joint: 1 })
    );
}

// A free body: position in the world and a quaternion; velocities [v; ω] in the body frame.
articulated::chain! {
    chain FreeBody {
        gravity: [0.0, 0.0, -9.81];
        body b { mass: 2.0, inertia: diag(0.15, 0.2, 0.3) }
        joint base: free(quaternion) { parent: world, child: b }
    }
}

#[test]
fn free_quaternion_against_newton_euler() {
    // p(t) and q(t) in closed form; the couples the generated inverse dynamics asks for at the
    // converted (v, v̇) must be Newton–Euler's with the world acceleration p̈:
    // f = m·Rᵀ(p̈ − g) in the body frame, n = I·ω̇ + ω × I·ω about the centre of mass (origin).
    assert_eq!(FreeBody::COORDINATES, &[Coordinates::FreeQuaternion]);
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.15, 0.2, 0.3));
    for i in 0..25 {
        let t = 0.29 * i as f64;
        let ([q, q1, q2], w, wd) = two_axis(t, false);
        let p = [t.sin(), 0.5 * (2.0 * t).cos(), 0.3 * t * t];
        let p1 = [t.cos(), -(2.0 * t).sin(), 0.6 * t];
        let p2 = [-t.sin(), -2.0 * (2.0 * t).cos(), 0.6];
        let qa: Vec<f64> = p.iter().chain(&q).copied().collect();
        let q1a: Vec<f64> = p1.iter().chain(&q1).copied().collect();
        let q2a: Vec<f64> = p2.iter().chain(&q2).copied().collect();
        let (qo, v, vd) = convert(FreeBody::COORDINATES, &qa, &q1a, &q2a);
        let tau = FreeBody::inverse_dynamics(
            &SVector::from_column_slice(&qo),
            &SVector::from_column_slice(&v),
            &SVector::from_column_slice(&vd),
        );
        let r = articulated::nalgebra::UnitQuaternion::from_quaternion(
            articulated::nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]),
        )
        .to_rotation_matrix()
        .into_inner();
        let f = r.transpose() * (Vector3::from(p2) - Vector3::new(0.0, 0.0, -9.81)) * 2.0;
        let (w, wd) = (Vector3::from(w), Vector3::from(wd));
        let n = inertia * wd + w.cross(&(inertia * w));
        for k in 0..3 {
            assert!(
                (tau[k] - f[k]).abs() < 1e-12 * (1.0 + f.norm()),
                "t {t}: f {tau} vs {f}"
            );
            assert!(
                (tau[3 + k] - n[k]).abs() < 1e-12 * (1.0 + n.norm()),
                "t {t}: n {tau} vs {n}"
            );
        }
        // The linear velocity is Rᵀ·ṗ.
        let lin = r.transpose() * Vector3::from(p1);
        assert!((Vector3::new(v[0], v[1], v[2]) - lin).norm() < 1e-14);
    }
}

/// Newton–Euler's couples on the free body at time `t` of the closed-form motion.
fn free_body_couples(t: f64) -> ([f64; 7], SVector<f64, 6>) {
    let ([q, _, _], w, wd) = two_axis(t, false);
    let p = [t.sin(), 0.5 * (2.0 * t).cos(), 0.3 * t * t];
    let p2 = [-t.sin(), -2.0 * (2.0 * t).cos(), 0.6];
    let r = articulated::nalgebra::UnitQuaternion::from_quaternion(
        articulated::nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]),
    )
    .to_rotation_matrix()
    .into_inner();
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.15, 0.2, 0.3));
    let f = r.transpose() * (Vector3::from(p2) - Vector3::new(0.0, 0.0, -9.81)) * 2.0;
    let (w, wd) = (Vector3::from(w), Vector3::from(wd));
    let n = inertia * wd + w.cross(&(inertia * w));
    let qa = [p[0], p[1], p[2], q[0], q[1], q[2], q[3]];
    (
        qa,
        SVector::from_column_slice(&[f.x, f.y, f.z, n.x, n.y, n.z]),
    )
}

#[test]
fn free_body_couples_from_samples() {
    // The inverse plant end to end on a quaternion joint: sampled positions and unit
    // quaternions at 1 kHz, smoothed (so no longer exactly unit), converted, inverted.
    let t: Vec<f64> = (0..2001).map(|i| i as f64 * 1e-3).collect();
    let q: Vec<f64> = t.iter().flat_map(|&t| free_body_couples(t).0).collect();
    let sg = SavitzkyGolay::new(5, 4).unwrap();
    let c = couples::<7, 6, _>(FreeBody::COORDINATES, &t, &q, &sg, |q, v, a| {
        FreeBody::inverse_dynamics(q, v, a)
    })
    .unwrap();
    let mut worst: f64 = 0.0;
    let mut largest: f64 = 0.0;
    for (row, &time) in c.t.iter().enumerate() {
        let exact = free_body_couples(time).1;
        let got = SVector::<f64, 6>::from_column_slice(c.row(row).unwrap());
        worst = worst.max((got - exact).amax());
        largest = largest.max(exact.amax());
    }
    println!(
        "free body from samples: max couple error {:.2e} of {largest:.2e}",
        worst
    );
    assert!(worst < 1e-6 * largest, "{worst} of {largest}");
}
