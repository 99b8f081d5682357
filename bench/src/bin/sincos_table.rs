//! `libm::sincos`, std's `f64::sin_cos` (glibc) and `articulated::math::sincos` side by side,
//! on 1024 seeded angles in [−π, π]: ns per angle (plain loop timing) and instructions per
//! angle (callgrind, independent of the machine's load).
//!
//! ```text
//! cargo run --release -p articulated-bench --bin sincos_table                 # ns per angle
//! cargo run --release -p articulated-bench --bin sincos_table -- --instructions  # callgrind
//! sincos_table --calls K IMPL CASE   # exactly K iterations, then exit
//! ```
//!
//! Cases: `one`, one angle per iteration (independent iterations: the processor overlaps
//! them); `chained`, the next angle is `sin + cos` of the previous one (the latency of one
//! call); `seven`, seven angles per iteration, summed (the joints of an arm). IMPL is `libm`,
//! `std`, `articulated` (`articulated::math::sincos` inlined into the loop, as in generated
//! code), `articulated-call` (through the `#[inline(never)]` [`one_sincos`]),
//! `articulated-array` (`seven` only: one `sincos_array` call for the seven angles) or
//! `baseline-array` (`seven` only: the same with the previous `sincos_array`, of commit
//! a7ea426, kept in this file as [`mod@baseline`] to compare the two in one run).
//!
//! Timing: batches of about 0.2 ms, the implementations alternating, 101 batches each; the
//! fastest batch is reported, which stays reproducible on a loaded machine. Instructions:
//! (Ir(K) − Ir(0)) / K / angles per iteration, so both include the loop and the table load
//! (a few instructions per angle). `objdump -d target/release/sincos_table` shows
//! `articulated::math::sincos` on its own (what `one_sincos` calls).

use std::f64::consts::PI;
use std::hint::black_box;
use std::process::{Command, ExitCode};
use std::time::Instant;

const USAGE: &str = "usage: sincos_table [--instructions]
       sincos_table --calls K IMPL CASE   (IMPL: libm, std, articulated, articulated-call,
                                           articulated-array, baseline-array;
                                           CASE: one, chained, seven)";

const ANGLES: usize = 1024;
const IMPLS: [&str; 6] = [
    "libm",
    "std",
    "articulated",
    "articulated-call",
    "articulated-array",
    "baseline-array",
];
const CASES: [(&str, f64); 3] = [("one", 1.0), ("chained", 1.0), ("seven", 7.0)];

fn angles() -> Vec<f64> {
    let mut state = 0x5EED_u64;
    (0..ANGLES)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            ((z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * PI
        })
        .collect()
}

/// `articulated::math::sincos`, out of line.
#[inline(never)]
pub fn one_sincos(x: f64) -> (f64, f64) {
    articulated::math::sincos(x)
}

fn run<F: Fn(f64) -> (f64, f64)>(f: F, case: &str, calls: usize, table: &[f64]) -> f64 {
    let mut sum = 0.0;
    let mut i = 0;
    match case {
        "one" => {
            for _ in 0..calls {
                i = (i + 1) % ANGLES;
                let (s, c) = f(black_box(table[i]));
                sum += s + c;
            }
        }
        "chained" => {
            let mut x = 0.5;
            for _ in 0..calls {
                let (s, c) = f(x);
                // Stays in [−π, π], but each angle depends on the previous result.
                x = black_box(s * 2.0 + c);
            }
            sum = x;
        }
        _ => {
            for _ in 0..calls {
                i = (i + 7) % (ANGLES - 7);
                let q: &[f64; 7] = black_box(table[i..i + 7].try_into().unwrap());
                for &x in q {
                    let (s, c) = f(x);
                    sum += s + c;
                }
            }
        }
    }
    sum
}

/// `f` (`articulated::math::sincos_array` or [`baseline::sincos_array`]): the seven angles
/// of an iteration in one call (`seven` only).
fn run_array<F: Fn([f64; 7]) -> ([f64; 7], [f64; 7])>(
    f: F,
    case: &str,
    calls: usize,
    table: &[f64],
) -> Option<f64> {
    if case != "seven" {
        return None;
    }
    let mut sum = 0.0;
    let mut i = 0;
    for _ in 0..calls {
        i = (i + 7) % (ANGLES - 7);
        let q: &[f64; 7] = black_box(table[i..i + 7].try_into().unwrap());
        let (s, c) = f(*q);
        for k in 0..7 {
            sum += s[k] + c[k];
        }
    }
    Some(sum)
}

fn run_impl(imp: &str, case: &str, calls: usize, table: &[f64]) -> Option<f64> {
    Some(match imp {
        "libm" => run(articulated::libm::sincos, case, calls, table),
        "std" => run(f64::sin_cos, case, calls, table),
        "articulated" => run(articulated::math::sincos, case, calls, table),
        "articulated-call" => run(one_sincos, case, calls, table),
        "articulated-array" => run_array(articulated::math::sincos_array, case, calls, table)?,
        "baseline-array" => run_array(baseline::sincos_array, case, calls, table)?,
        _ => return None,
    })
}

fn callgrind(calls: usize, imp: &str, case: &str) -> Result<u64, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new("valgrind")
        .args(["--tool=callgrind", "--callgrind-out-file=/dev/null"])
        .arg(exe)
        .args(["--calls", &calls.to_string(), imp, case])
        .output()
        .map_err(|e| format!("cannot run valgrind: {e}"))?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!("valgrind failed: {stderr}"));
    }
    stderr
        .lines()
        .find_map(|l| l.split("Collected :").nth(1))
        .and_then(|n| n.trim().parse().ok())
        .ok_or_else(|| format!("no instruction count in valgrind's output: {stderr}"))
}

fn instructions() -> Result<(), String> {
    let calls = 100_000;
    println!("instructions per angle (loop included)");
    println!("| impl | one | chained | seven |");
    println!("|---|---:|---:|---:|");
    for imp in IMPLS {
        let mut row = format!("| {imp} |");
        for (case, per) in CASES {
            if imp.ends_with("-array") && case != "seven" {
                row.push_str(" – |");
                continue;
            }
            let base = callgrind(0, imp, case)?;
            let full = callgrind(calls, imp, case)?;
            let per_angle = full.saturating_sub(base) as f64 / calls as f64 / per;
            row.push_str(&format!(" {per_angle:.1} |"));
        }
        println!("{row}");
    }
    Ok(())
}

fn timing(table: &[f64]) {
    println!("ns per angle (fastest of 101 batches)");
    println!("| impl | one | chained | seven |");
    println!("|---|---:|---:|---:|");
    let mut best = [[f64::INFINITY; 3]; IMPLS.len()];
    for (k, (case, per)) in CASES.into_iter().enumerate() {
        // About 0.2 ms per batch.
        let calls = (20_000.0 / per) as usize;
        for _ in 0..101 {
            for (j, imp) in IMPLS.into_iter().enumerate() {
                if imp.ends_with("-array") && case != "seven" {
                    continue;
                }
                let start = Instant::now();
                black_box(run_impl(imp, case, calls, table));
                let ns = start.elapsed().as_nanos() as f64 / calls as f64 / per;
                best[j][k] = best[j][k].min(ns);
            }
        }
    }
    let cell = |ns: f64| {
        if ns.is_finite() {
            format!("{ns:.2}")
        } else {
            "–".to_string()
        }
    };
    for (j, imp) in IMPLS.into_iter().enumerate() {
        println!(
            "| {imp} | {} | {} | {} |",
            cell(best[j][0]),
            cell(best[j][1]),
            cell(best[j][2])
        );
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let table = angles();
    match args[..] {
        ["--calls", k, imp, case] if CASES.iter().any(|c| c.0 == case) => {
            let Ok(calls) = k.parse() else {
                eprintln!("{USAGE}");
                return ExitCode::FAILURE;
            };
            match run_impl(imp, case, calls, &table) {
                Some(sum) => {
                    black_box(sum);
                    ExitCode::SUCCESS
                }
                None => {
                    eprintln!("{USAGE}");
                    ExitCode::FAILURE
                }
            }
        }
        ["--instructions"] => match instructions() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        },
        [] => {
            timing(&table);
            ExitCode::SUCCESS
        }
        _ => {
            eprintln!("{USAGE}");
            ExitCode::FAILURE
        }
    }
}

/// `articulated::math::sincos_array` as it was in commit a7ea426 (reduction by π/2 in five
/// parts, FreeBSD's kernels in Estrin's order, the quadrant by masks, not inlined), kept
/// verbatim without its comments to time the current one against it in the same run.
///
/// Its reduction constants and polynomial coefficients are FreeBSD msun's (`e_rem_pio2.c`,
/// `k_sin.c`, `k_cos.c`): Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
/// Developed at SunSoft, a Sun Microsystems, Inc. business. Permission to use, copy, modify,
/// and distribute this software is freely granted, provided that this notice is preserved.
mod baseline {
    const SINCOS_FAST_LIMIT: f64 = f64::from_bits(0x4139_21fb_0000_0000);

    const TOINT: f64 = 6_755_399_441_055_744.0;
    const INV_PIO2: f64 = f64::from_bits(0x3FE4_5F30_6DC9_C883); // 6.36619772367581382433e-01
    const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000); // 1.57079632673412561417e+00
    const PIO2_1T: f64 = f64::from_bits(0x3DD0_B461_1A62_6331); // 6.07710050650619224932e-11
    const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000); // 6.07710050630396597660e-11
    const PIO2_3: f64 = f64::from_bits(0x3BA3_198A_2E00_0000); // 2.02226624871116645580e-21
    const PIO2_3T: f64 = f64::from_bits(0x397B_839A_2520_49C1); // 8.47842766036889956997e-32

    const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549); // -1.66666666666666324348e-01
    const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6); // 8.33333333332248946124e-03
    const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5); // -1.98412698298579493134e-04
    const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D); // 2.75573137070700676789e-06
    const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB); // -2.50507602534068634195e-08
    const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C); // 1.58969099521155010221e-10

    const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C); // 4.16666666666666019037e-02
    const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177); // -1.38888888888741095749e-03
    const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590); // 2.48015872894767294178e-05
    const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD); // -2.75573143513906633035e-07
    const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4); // 2.08757232129817482790e-09
    const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4); // -1.13596475577881948265e-11

    pub fn sincos_array<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
        let mut sin = [0.0; N];
        let mut cos = [0.0; N];
        let mut i = 0;
        while i + 2 <= N {
            let (s, c) = lanes([x[i], x[i + 1]]);
            sin[i..i + 2].copy_from_slice(&s);
            cos[i..i + 2].copy_from_slice(&c);
            i += 2;
        }
        if N % 2 == 1 {
            let ([s], [c]) = lanes([x[N - 1]]);
            sin[N - 1] = s;
            cos[N - 1] = c;
        }
        let mut slow = false;
        for x in x {
            slow |= !in_fast_range(x);
        }
        if slow {
            sincos_array_libm(&x, &mut sin, &mut cos);
        }
        (sin, cos)
    }

    #[inline(always)]
    fn in_fast_range(x: f64) -> bool {
        x.abs() < SINCOS_FAST_LIMIT
    }

    #[cold]
    #[inline(never)]
    fn sincos_array_libm(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
        for ((&x, s), c) in x.iter().zip(sin).zip(cos) {
            if !in_fast_range(x) {
                (*s, *c) = articulated::libm::sincos(x);
            }
        }
    }

    #[inline(always)]
    fn lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
        let mut sin = [0.0; N];
        let mut cos = [0.0; N];
        for i in 0..N {
            let x = x[i];

            let t = x * INV_PIO2 + TOINT;
            let quadrant = t.to_bits();
            let n = t - TOINT;

            let r1 = x - n * PIO2_1;
            let p = n * PIO2_1T;
            let y0 = r1 - p;
            let e1 = (r1 - y0) - p;
            let q = (p - n * PIO2_2) - n * PIO2_3;
            let y1 = e1 + (q - n * PIO2_3T);

            let (s, c) = kernels(y0, y1);

            let swap = 0u64.wrapping_sub(quadrant & 1);
            let (sb, cb) = (s.to_bits(), c.to_bits());
            let sin_sign = (quadrant & 2) << 62;
            let cos_sign = (quadrant.wrapping_add(1) & 2) << 62;
            sin[i] = f64::from_bits(((sb & !swap) | (cb & swap)) ^ sin_sign);
            cos[i] = f64::from_bits(((cb & !swap) | (sb & swap)) ^ cos_sign);
        }
        (sin, cos)
    }

    #[inline(always)]
    fn kernels(x: f64, y: f64) -> (f64, f64) {
        let z = x * x;
        let z2 = z * z;
        let z4 = z2 * z2;
        let v = z * x;
        let hz = 0.5 * z;

        let r = (S2 + z * S3) + z2 * (S4 + z * S5) + z4 * S6;
        let sin = x - (((hz * y - y) - v * S1) - (v * z) * r);

        let rc = (C1 + z * C2) + z2 * (C3 + z * C4) + z4 * (C5 + z * C6);
        let w = 1.0 - hz;
        let cos = w + ((((1.0 - w) - hz) - x * y) + z2 * rc);
        (sin, cos)
    }
}
