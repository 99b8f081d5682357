//! `libm::sincos`, std's `f64::sin_cos` (glibc) and `articulated::math::sincos` side by side:
//! each group `"sincos/<case>"` holds `libm`, `std` and `articulated`.
//!
//! - `one_fixed`: one call per iteration on the same angle through `black_box` (every branch
//!   predicted; successive iterations overlap, so this is between latency and throughput);
//! - `one_random`: one call per iteration, cycling through 1024 seeded angles in [−π, π]
//!   (libm's and glibc's branches on the size and quadrant see no pattern they could learn);
//! - `one_chained`: the next angle is `sin + cos` of the previous one, so calls cannot overlap:
//!   the latency of one call;
//! - `seven_fixed`, `seven_random`: seven independent angles per iteration, summed, as the
//!   seven joints of an arm (throughput: what the generated inverse dynamics pays); these two
//!   also have `articulated_array`, one `articulated::math::sincos_array` call for the seven.
//!
//! `"sincosf/seven_random"` does the same for `f32` (`libm::sincosf`, `f32::sin_cos`,
//! `articulated::math::sincosf`).
//!
//! `cargo bench -p articulated-bench --bench math` runs it all in about 70 s. Figures are per
//! iteration: divide the `seven_*` ones by 7 for one angle.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};

const ANGLES: usize = 1024;

/// 1024 angles in [−π, π), the same on every run.
fn angles() -> Vec<f64> {
    articulated_bench::angles(ANGLES)
}

/// Calls `$body(name, f, args…)` for the three implementations. Each `f` is a function item
/// (not a `fn` pointer), so `articulated::math::sincos` is inlined as in generated code, while
/// `libm::sincos` and glibc stay out-of-line calls, as they are there.
macro_rules! each_sincos {
    ($body:ident, $($arg:expr),*) => {{
        $body("libm", articulated::libm::sincos, $($arg),*);
        $body("std", f64::sin_cos, $($arg),*);
        $body("articulated", articulated::math::sincos, $($arg),*);
    }};
}

fn sincos(c: &mut Criterion) {
    let table = angles();

    fn fixed<F: Fn(f64) -> (f64, f64)>(
        name: &str,
        f: F,
        g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    ) {
        g.bench_function(name, |b| {
            b.iter(|| {
                let (s, c) = f(black_box(1.0));
                s + c
            })
        });
    }
    let mut group = c.benchmark_group("sincos/one_fixed");
    each_sincos!(fixed, &mut group);
    group.finish();

    fn random<F: Fn(f64) -> (f64, f64)>(
        name: &str,
        f: F,
        g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
        table: &[f64],
    ) {
        g.bench_function(name, |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) % ANGLES;
                let (s, c) = f(black_box(table[i]));
                s + c
            })
        });
    }
    let mut group = c.benchmark_group("sincos/one_random");
    each_sincos!(random, &mut group, &table);
    group.finish();

    fn chained<F: Fn(f64) -> (f64, f64)>(
        name: &str,
        f: F,
        g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    ) {
        g.bench_function(name, |b| {
            let mut x = 0.5;
            b.iter(|| {
                let (s, c) = f(x);
                x = black_box(s + c);
            })
        });
    }
    let mut group = c.benchmark_group("sincos/one_chained");
    each_sincos!(chained, &mut group);
    group.finish();

    fn seven_fixed<F: Fn(f64) -> (f64, f64)>(
        name: &str,
        f: F,
        g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
        table: &[f64],
    ) {
        let q: [f64; 7] = table[..7].try_into().unwrap();
        g.bench_function(name, |b| {
            b.iter(|| {
                let q = black_box(&q);
                let mut sum = 0.0;
                for &x in q {
                    let (s, c) = f(x);
                    sum += s + c;
                }
                sum
            })
        });
    }
    let mut group = c.benchmark_group("sincos/seven_fixed");
    each_sincos!(seven_fixed, &mut group, &table);
    let q: [f64; 7] = table[..7].try_into().unwrap();
    group.bench_function("articulated_array", |b| {
        b.iter(|| {
            let (s, c) = articulated::math::sincos_array(*black_box(&q));
            s.iter().zip(&c).map(|(s, c)| s + c).sum::<f64>()
        })
    });
    group.finish();

    /// Seven consecutive angles of `table` per iteration (a different seven each time), each
    /// through `f`, summed; for `f64` and `f32` alike.
    fn seven_random<T, F>(
        name: &str,
        f: F,
        g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
        table: &[T],
    ) where
        T: Copy + Default + core::ops::Add<Output = T>,
        F: Fn(T) -> (T, T),
    {
        g.bench_function(name, |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 7) % (ANGLES - 7);
                let q: &[T; 7] = black_box(table[i..i + 7].try_into().unwrap());
                let mut sum = T::default();
                for &x in q {
                    let (s, c) = f(x);
                    sum = sum + (s + c);
                }
                sum
            })
        });
    }
    let mut group = c.benchmark_group("sincos/seven_random");
    each_sincos!(seven_random, &mut group, &table);
    group.bench_function("articulated_array", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 7) % (ANGLES - 7);
            let q: &[f64; 7] = black_box(table[i..i + 7].try_into().unwrap());
            let (s, c) = articulated::math::sincos_array(*q);
            s.iter().zip(&c).map(|(s, c)| s + c).sum::<f64>()
        })
    });
    group.finish();

    // f32.
    let table32: Vec<f32> = table.iter().map(|&x| x as f32).collect();
    let mut group = c.benchmark_group("sincosf/seven_random");
    seven_random("libm", articulated::libm::sincosf, &mut group, &table32);
    seven_random("std", f32::sin_cos, &mut group, &table32);
    seven_random(
        "articulated",
        articulated::math::sincosf,
        &mut group,
        &table32,
    );
    group.finish();
}

/// Private, so the `pub fn benches` that `criterion_group!` writes needs no docs.
mod group {
    use super::*;

    criterion_group! {
        name = benches;
        config = Criterion::default()
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_millis(2000))
            .sample_size(40);
        targets = sincos
    }
}
criterion_main!(group::benches);
