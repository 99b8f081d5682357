//! Trajectory CSV (round trip, every error with its line, no panic on any input) and the
//! inverse plant on Hemami's two-link system moving along sines, whose couples are known from
//! the generated inverse dynamics at the exact `(q, v, a)`.
//!
//! `cargo test -p articulated --test samples -- --nocapture noise_table` prints the couple
//! error against the noise added to `q` and the sample rate.

use std::fmt::Write as _;

use articulated::differentiate::{DifferentiateError, SavitzkyGolay};
use articulated::invert::{couples, couples_dyn, InvertError};
use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::samples::{write_csv, CsvError, Samples};
use articulated_dynamics::random::Rng;

#[derive(articulated::Chain)]
#[chain(file = "../models/two_link.chain")]
struct TwoLink;

// ---- CSV ----

#[test]
fn round_trip_of_a_trajectory_file() {
    let mut rng = Rng::new(5);
    let (nq, nv, rows) = (6, 6, 50);
    let mut text = String::from("t");
    for i in 0..nq {
        write!(text, ",q{i}").unwrap();
    }
    for i in 0..nv {
        write!(text, ",v{i}").unwrap();
    }
    text.push('\n');
    let mut t = Vec::new();
    let mut q = Vec::new();
    for r in 0..rows {
        let time = 0.01 * r as f64 + 1e-3 * rng.unit();
        t.push(time);
        write!(text, "{time}").unwrap();
        for _ in 0..nq {
            let x = rng.symmetric(3.0) * 10f64.powi(rng.range(-8.0, 3.0) as i32);
            q.push(x);
            write!(text, ",{x}").unwrap();
        }
        for _ in 0..nv {
            write!(text, ",{:e}", rng.symmetric(1.0)).unwrap();
        }
        text.push('\n');
    }
    let path = std::env::temp_dir().join(format!("articulated-samples-{}.csv", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    let read = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    let s = Samples::parse_csv(&read, nq).unwrap();
    assert_eq!(s.len(), rows);
    assert_eq!(s.times(), &t[..]);
    assert_eq!(s.positions(), &q[..]);
    assert_eq!(s.q(3), Some(&q[18..24]));
    assert_eq!(s.q(rows), None);
    // Fewer q columns than the file has: the rest is ignored.
    let s2 = Samples::parse_csv(&read, 2).unwrap();
    assert_eq!(s2.q(1), Some(&q[6..8]));
    // CRLF, blank lines, spaces and no trailing newline read the same.
    let crlf = format!("\n\n{}", read.replace('\n', "\r\n\r\n").replace(',', " , "));
    assert_eq!(Samples::parse_csv(crlf.trim_end(), nq).unwrap(), s);
    // Columns in another order.
    let swapped = "q1,t,q0\n2,0,1\n4,1,3\n";
    let s3 = Samples::parse_csv(swapped, 2).unwrap();
    assert_eq!(
        (s3.times(), s3.positions()),
        (&[0.0, 1.0][..], &[1.0, 2.0, 3.0, 4.0][..])
    );
    // write_csv round-trips exactly.
    let mut out = Vec::new();
    write_csv(&mut out, "q", &t, nq, &q).unwrap();
    let back = Samples::parse_csv(std::str::from_utf8(&out).unwrap(), nq).unwrap();
    assert_eq!(back, s);
    assert!(write_csv(&mut Vec::new(), "q", &t, nq, &q[1..]).is_err());
}

#[test]
fn each_error_names_its_line() {
    use CsvError::*;
    let e = |text: &str| Samples::parse_csv(text, 2).unwrap_err();
    assert_eq!(e(""), MissingHeader);
    assert_eq!(e("\n  \n\r\n"), MissingHeader);
    assert_eq!(
        e("\nq0,q1\n1,2\n"),
        MissingColumn {
            line: 2,
            column: "t".into()
        }
    );
    assert_eq!(
        e("t,q0,v0\n0,1,2\n"),
        MissingColumn {
            line: 1,
            column: "q1".into()
        }
    );
    assert_eq!(
        e("t,q0,q1,q0\n"),
        DuplicateColumn {
            line: 1,
            column: "q0".into()
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n0.1,1\n"),
        FieldCount {
            line: 3,
            expected: 3,
            found: 2
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n\n0.1,1,2,3\n"),
        FieldCount {
            line: 4,
            expected: 3,
            found: 4
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n0.1,x,2\n"),
        NotANumber {
            line: 3,
            column: "q0".into(),
            field: "x".into()
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,\n"),
        NotANumber {
            line: 2,
            column: "q1".into(),
            field: "".into()
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n0.1,NaN,2\n"),
        NotFinite {
            line: 3,
            column: "q0".into()
        }
    );
    assert_eq!(
        e("t,q0,q1\ninf,1,2\n"),
        NotFinite {
            line: 2,
            column: "t".into()
        }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n0.1,1,2\n0.1,1,2\n"),
        TimesNotIncreasing { line: 4 }
    );
    assert_eq!(
        e("t,q0,q1\n0,1,2\n\n-1,1,2\n"),
        TimesNotIncreasing { line: 4 }
    );
    // Ignored columns are not read: neither a non-finite nor a malformed value there is an
    // error (the field count still is).
    assert!(Samples::parse_csv("t,q0,q1,v0\n0,1,2,nan\n", 2).is_ok());
    assert!(Samples::parse_csv("t,q0,q1,v0\n0,1,2,zz\n", 2).is_ok());
    let msg = e("t,q0,q1\n0,1,2\n0.1,x,2\n").to_string();
    assert!(msg.contains("line 3") && msg.contains("q0"), "{msg}");
    // Samples::new checks the same.
    assert_eq!(
        Samples::new(vec![0.0, 1.0], vec![0.0, f64::NAN], 1),
        Err(NotFinite {
            line: 3,
            column: "q0".into()
        })
    );
    assert_eq!(
        Samples::new(vec![0.0, 0.0], vec![0.0, 0.0], 1),
        Err(TimesNotIncreasing { line: 3 })
    );
}

/// Random text: tokens a CSV reader meets (names, separators, numbers, line ends, non-finite
/// spellings) mixed with arbitrary characters; half the time after a valid header and with
/// rows of number-like fields, so that the row checks are reached too.
fn random_text(rng: &mut Rng) -> String {
    const TOKENS: [&str; 20] = [
        "t", "q0", "q1", "v0", ",", ",", "\n", "\n", "\r", "\r\n", "1", "-", ".", "e", "nan",
        "inf", " ", "0", "1e308", "9e999",
    ];
    const NUMBERS: [&str; 8] = ["0", "1", "-2.5", "3e-3", "0.1", "7", "", "x"];
    let pick = |rng: &mut Rng, n: usize| (rng.next_u64() % n as u64) as usize;
    let mut text = String::new();
    let structured = rng.unit() < 0.5;
    if structured {
        text.push_str("t,q0,q1,v0\n");
        for row in 0..pick(rng, 8) {
            let time = if rng.unit() < 0.9 {
                row.to_string()
            } else {
                "0".into()
            };
            let count = 3 + pick(rng, 2) - usize::from(rng.unit() < 0.1);
            let mut fields = Vec::new();
            for _ in 0..count {
                // Mostly numbers; now and then an empty or malformed field.
                let n = if rng.unit() < 0.9 {
                    NUMBERS.len() - 2
                } else {
                    NUMBERS.len()
                };
                fields.push(NUMBERS[pick(rng, n)]);
            }
            text.push_str(&format!("{time},{}\n", fields.join(",")));
        }
    }
    let garbage = if structured && rng.unit() < 0.5 {
        0
    } else {
        pick(rng, 40)
    };
    for _ in 0..garbage {
        if rng.unit() < 0.85 {
            text.push_str(TOKENS[pick(rng, TOKENS.len())]);
        } else if let Some(c) = char::from_u32((rng.next_u64() % 0x11_0000) as u32) {
            text.push(c);
        }
    }
    text
}

#[test]
fn no_input_panics() {
    // Never a panic, whatever the text; what is accepted is consistent.
    let mut rng = Rng::new(17);
    let mut accepted = 0;
    for _ in 0..50_000 {
        let text = random_text(&mut rng);
        let nq = (rng.next_u64() % 3) as usize;
        if let Ok(s) = Samples::parse_csv(&text, nq) {
            accepted += 1;
            assert_eq!(s.positions().len(), s.len() * nq, "{text:?}");
            assert!(s.times().windows(2).all(|w| w[0] < w[1]), "{text:?}");
            assert!(s.positions().iter().all(|x| x.is_finite()), "{text:?}");
        }
    }
    println!("{accepted} of 50000 random texts accepted");
    assert!(accepted > 0);
}

// ---- Inverse plant ----

const AMP: [f64; 6] = [0.12, 0.2, 0.15, 0.25, 0.3, 0.1];
const FREQ: [f64; 6] = [1.1, 1.7, 0.9, 2.3, 1.3, 0.7];
const PHASE: [f64; 6] = [0.3, 1.1, -0.4, 2.0, 0.7, -1.3];

/// The prescribed motion `q_j = A_j·sin(ω_j t + φ_j)` and its exact rates.
fn motion(t: f64) -> [SVector<f64, 6>; 3] {
    let q = SVector::from_fn(|j, _| AMP[j] * (FREQ[j] * t + PHASE[j]).sin());
    let v = SVector::from_fn(|j, _| AMP[j] * FREQ[j] * (FREQ[j] * t + PHASE[j]).cos());
    let a = SVector::from_fn(|j, _| -AMP[j] * FREQ[j] * FREQ[j] * (FREQ[j] * t + PHASE[j]).sin());
    [q, v, a]
}

/// Samples of the motion over `[0, 3 s]` at `rate` Hz with Gaussian noise `sigma` on `q`.
fn sampled(rate: f64, sigma: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let n = (3.0 * rate) as usize + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / rate).collect();
    let mut gauss = move || {
        let u = 1.0 - rng.unit();
        let v = rng.unit();
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    };
    let q = t
        .iter()
        .flat_map(|&t| motion(t)[0].iter().copied().collect::<Vec<_>>())
        .map(|x| x + sigma * gauss())
        .collect();
    (t, q)
}

/// `(max, rms)` of the couple error, relative to the largest and the rms couple.
fn couple_error(sg: &SavitzkyGolay, t: &[f64], q: &[f64]) -> (f64, f64) {
    let c = couples::<6, 6, _>(TwoLink::COORDINATES, t, q, sg, |q, v, a| {
        TwoLink::inverse_dynamics(q, v, a)
    })
    .unwrap();
    assert_eq!(c.t.len(), t.len() - 2 * sg.half_window());
    assert_eq!(c.t[0], t[sg.half_window()]);
    let (mut err_max, mut tau_max, mut err_sq, mut tau_sq) = (0.0f64, 0.0f64, 0.0, 0.0);
    for (row, &time) in c.t.iter().enumerate() {
        let [q, v, a] = motion(time);
        let exact = TwoLink::inverse_dynamics(&q, &v, &a);
        let got = SVector::<f64, 6>::from_column_slice(c.row(row).unwrap());
        err_max = err_max.max((got - exact).amax());
        tau_max = tau_max.max(exact.amax());
        err_sq += (got - exact).norm_squared();
        tau_sq += exact.norm_squared();
    }
    (err_max / tau_max, (err_sq / tau_sq).sqrt())
}

#[test]
fn noise_free_couples_match_to_1e_6() {
    // 1 kHz, 11-sample windows, quartic fits: q̈ to O(Δ⁴).
    let sg = SavitzkyGolay::new(5, 4).unwrap();
    let (t, q) = sampled(1000.0, 0.0, 1);
    let (max, rms) = couple_error(&sg, &t, &q);
    println!("1 kHz, k = 5, p = 4: max relative couple error {max:.2e}, rms {rms:.2e}");
    assert!(max < 1e-6, "max relative error {max}");
    // The same through the run-time-sized entry point, with the reference's signature.
    let c = couples_dyn(TwoLink::COORDINATES, 6, 6, &t, &q, &sg, |q, v, a, tau| {
        let f = |x: &[f64]| SVector::<f64, 6>::from_column_slice(x);
        tau.copy_from_slice(TwoLink::inverse_dynamics(&f(q), &f(v), &f(a)).as_slice());
        Ok::<(), std::convert::Infallible>(())
    })
    .unwrap();
    let c2 = couples::<6, 6, _>(TwoLink::COORDINATES, &t, &q, &sg, |q, v, a| {
        TwoLink::inverse_dynamics(q, v, a)
    })
    .unwrap();
    assert_eq!(c, c2);
}

#[test]
fn inversion_errors() {
    let sg = SavitzkyGolay::new(5, 4).unwrap();
    let (t, mut q) = sampled(100.0, 0.0, 1);
    let id = |q: &SVector<f64, 6>, v: &SVector<f64, 6>, a: &SVector<f64, 6>| {
        TwoLink::inverse_dynamics(q, v, a)
    };
    assert_eq!(
        couples(TwoLink::COORDINATES, &t[..10], &q[..60], &sg, id),
        Err(InvertError::Differentiate(
            DifferentiateError::TooFewSamples {
                samples: 10,
                window: 11
            }
        ))
    );
    q[6 * 40 + 2] = f64::NAN;
    assert_eq!(
        couples(TwoLink::COORDINATES, &t, &q, &sg, id),
        Err(InvertError::Differentiate(
            DifferentiateError::SampleNotFinite {
                index: 40,
                column: 2
            }
        ))
    );
    // Wrong sizes for the chain's coordinates.
    let r = couples::<5, 5, _>(
        TwoLink::COORDINATES,
        &t,
        &q[..t.len() * 5],
        &sg,
        |_, _, _| SVector::zeros(),
    );
    assert!(matches!(r, Err(InvertError::Coordinates(_))));
    // A failing closure names the sample.
    let (t, q) = sampled(100.0, 0.0, 1);
    let r = couples_dyn(TwoLink::COORDINATES, 6, 6, &t, &q, &sg, |_, _, _, _| {
        Err("no")
    });
    assert_eq!(
        r,
        Err(InvertError::Dynamics {
            index: 5,
            error: "no"
        })
    );
    let r = couples_dyn(TwoLink::COORDINATES, 6, 6, &t, &q, &sg, |_, _, _, tau| {
        tau[0] = f64::NAN;
        Ok::<(), ()>(())
    });
    assert_eq!(r, Err(InvertError::NotFinite { index: 5 }));
}

#[test]
fn noise_table() {
    // Fixed windows: ±5 samples quartic; ±0.05 s and ±0.15 s cubic. "Best": the smallest rms
    // error over half windows of 0.01, 0.025, 0.05, 0.1, 0.15, 0.2, 0.3 s and degrees 3, 5.
    println!("couple error on Hemami's two-link system along sines (3 s), relative rms");
    println!("(rms of τ error / rms of τ; in brackets the max error / max |τ|)");
    println!(
        "| rate | σ (rad) | ±5 samples, p = 4 | ±0.05 s, p = 3 | ±0.15 s, p = 3 | best (half window, p) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    for rate in [100.0, 250.0, 1000.0] {
        let samples = |sec: f64| ((sec * rate).round() as usize).max(1);
        let fixed = [(5, 4), (samples(0.05), 3), (samples(0.15), 3)];
        let mut previous = [0.0; 3];
        for (s, sigma) in [0.0, 1e-6, 1e-4, 1e-3].into_iter().enumerate() {
            let (t, q) = sampled(rate, sigma, 100 + s as u64);
            let mut row = format!("| {rate} Hz | {sigma:e} |");
            for (i, &(k, p)) in fixed.iter().enumerate() {
                let (max, rms) = couple_error(&SavitzkyGolay::new(k, p).unwrap(), &t, &q);
                write!(row, " {rms:.1e} ({max:.1e}) |").unwrap();
                // More noise never helps once it dominates (from 1e-4 rad on).
                if sigma >= 1e-4 {
                    assert!(
                        rms > previous[i],
                        "rate {rate}, k {k}: {rms} after {}",
                        previous[i]
                    );
                }
                previous[i] = rms;
            }
            let mut best = (f64::INFINITY, 0.0, 0);
            for sec in [0.01, 0.025, 0.05, 0.1, 0.15, 0.2, 0.3] {
                for p in [3, 5] {
                    let k = samples(sec);
                    if let Ok(sg) = SavitzkyGolay::new(k, p) {
                        let (_, rms) = couple_error(&sg, &t, &q);
                        if rms < best.0 {
                            best = (rms, sec, p);
                        }
                    }
                }
            }
            write!(row, " {:.1e} (±{} s, {}) |", best.0, best.1, best.2).unwrap();
            println!("{row}");
        }
    }
}
