//! Sine and cosine of an angle together, inlinable, without branches on the argument, as
//! accurate as [`libm::sincos`]: for several angles at once ([`sincos_array`], faster than
//! libm) or for one ([`sincos`], **slower** than libm; see below).
//!
//! # Why hand-written
//!
//! [`libm::sincos`] (FreeBSD/musl) is accurate but is an out-of-line call whose reduction
//! branches on the argument: five size classes of `|x|`, one to three rounds of reduction
//! depending on the cancellation, a `match` on the quadrant. On the 2-core Zen 4 VM it costs
//! about 7 ns per angle (97 instructions for angles in [−π, π]), a large part of the 7-DOF
//! inverse dynamics, which needs six.
//!
//! This module computes the same thing as straight-line code: the same reduction constants and
//! polynomial coefficients, a reduction that does all its rounds every time (exact for every
//! argument below [`SINCOS_FAST_LIMIT`], so no branch on the amount of cancellation), and the
//! quadrant applied with bit masks instead of a `match`. The one branch left sends
//! `|x| ≥` [`SINCOS_FAST_LIMIT`], infinities and NaN to [`libm::sincos`]; joint angles always
//! take it the same way.
//!
//! What that buys, measured on that VM (`cargo bench -p articulated-bench --bench math`;
//! `cargo run --release -p articulated-bench --bin sincos_table [-- --instructions]`; the VM's
//! speed drifts by up to 1.5× over minutes, so only figures from one run compare):
//!
//! - several angles, [`sincos_array`]: faster. With no branch per angle the compiler runs the
//!   angles two by two in SSE2 instructions, with one shared check for the fallback: about 64
//!   instructions per angle instead of libm's 97. Seven angles per iteration: 0.74 to 0.90 of
//!   libm's time over several criterion runs (e.g. 39 ns against 53), 5.5 ns per angle
//!   against 6.4 in `sincos_table`. In the generated 7-DOF inverse dynamics (`arm7`), its six
//!   `libm::sincos` calls replaced by one `sincos_array` call: 112 ns instead of 120.
//! - one angle, [`sincos`]: **not** faster than libm: 1.3 to 1.8 times slower depending on the
//!   loop around it (one call per iteration: 10.8 ns against 7.2 in `sincos_table`; the
//!   latency of a chain of calls: 24 ns against 18.5), and the same `arm7` with six inlined
//!   [`sincos`] takes 143 ns instead of 120. Doing the whole reduction every time costs more
//!   than libm's branches, which the processor predicts or recovers from cheaply even on
//!   random angles, and inlining saves only the call. It is kept for single angles where a
//!   branch-free, inlined path matters more than speed, and it is what [`sincos_array`]
//!   computes for each angle.
//!
//! # The algorithm
//!
//! - `n = round(x·2/π)` by the `x·(2/π) + 1.5·2^52 − 1.5·2^52` trick (valid for
//!   `|x| <` [`SINCOS_FAST_LIMIT`]); `n mod 4` is the low two bits of the sum's representation;
//! - `y = x − n·π/2` as a head and tail `y0 + y1` by Cody–Waite with the π/2 split of FreeBSD
//!   `__rem_pio2`: `y0 = (x − n·pio2_1) − n·pio2_1t` is its first round (few operations, so
//!   the kernels start early), and beside it `y1`, the exact rest, from the three-part split
//!   `pio2_2`, `pio2_3`, `pio2_3t`, every step exact but the last (see the comments in the
//!   code): `y0 + y1` is good to about 2^-120 absolute for every argument in the range, where
//!   the closest a double comes to a multiple of π/2 is 2^-60.5 (x = 45.553…);
//! - the FreeBSD/musl kernels `__sin(y0, y1, 1)` and `__cos(y0, y1)`: the same polynomials
//!   with the same coefficients S1..S6, C1..C6 and the same first-order corrections for `y1`,
//!   evaluated in Estrin's order (`z = y0²`, `z²`, `z⁴` side by side) rather than musl's
//!   nested one: a shorter dependency chain, the same accuracy;
//! - the quadrant: swap sine and cosine if `n` is odd, flip their signs per `n mod 4`, with bit
//!   masks on their representations (no branch, no table).
//!
//! # Accuracy
//!
//! `runtime/tests/math.rs` (`-- --nocapture` prints the figures per range): within 1 ulp of
//! [`libm::sincos`] and of glibc's `f64::sin_cos` everywhere tested (random arguments in
//! `|x| < 1, 10, 10³, 10⁵`, the limit and beyond, every double nearest to `k·π/2` for
//! `k ≤ 2^20` and its neighbours, zeros, subnormals, the extremes), and bit-identical to libm
//! for 98–99 % of random arguments below the limit (100 % near the multiples of π/2 and
//! beyond the limit). Against a double-double reference (exact reduction by a 256-bit π/2,
//! Taylor series): at most 0.73 ulp, the same worst cases and the same figures as libm,
//! 0.50 ulp on the 500 arguments closest to a multiple of π/2. `sincos(−0.0) = (−0.0, 1.0)`;
//! subnormal `x` gives `(x, 1.0)`; infinities and NaN give `(NaN, NaN)`.
//!
//! [`sincos`]: crate::math::sincos
//! [`sincos_array`]: crate::math::sincos_array
//! [`SINCOS_FAST_LIMIT`]: crate::math::SINCOS_FAST_LIMIT

// The reduction constants and the polynomial coefficients S1..S6, C1..C6 are those of FreeBSD
// msun `e_rem_pio2.c`, `k_sin.c` and `k_cos.c` (also musl's and the `libm` crate's), under
// this notice:
//
// ====================================================
// Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
//
// Developed at SunSoft, a Sun Microsystems, Inc. business.
// Permission to use, copy, modify, and distribute this
// software is freely granted, provided that this notice
// is preserved.
// ====================================================
//
// (e_rem_pio2.c optimized by Bruce D. Evans.) The branch-free arrangement around them (the
// always-complete compensated reduction, the Estrin evaluation, the quadrant by masks, the
// lane-parallel form) is this crate's.

/// The fast path covers `|x| <` this bound (`f64::from_bits(0x413921fb00000000)`,
/// `≈ 1647099.3 ≈ 2^20·π/2`); beyond it, and for infinities and NaN, [`libm::sincos`] is
/// called.
///
/// Below it `n = round(x·2/π) ≤ 2^20`, so `n` times each 33-bit part of π/2 is exact and the
/// reduction is exact but for roundings far below an ulp of the result: this is the bound of
/// the "medium" case of FreeBSD/musl `__rem_pio2`. Joint angles are far below it.
pub const SINCOS_FAST_LIMIT: f64 = f64::from_bits(0x4139_21fb_0000_0000);

/// `1.5·2^52`: adding and subtracting it rounds to the nearest integer (for `|v| < 2^51`), and
/// the low bits of the sum are that integer in two's complement.
const TOINT: f64 = 6_755_399_441_055_744.0;
/// 53 bits of 2/π.
const INV_PIO2: f64 = f64::from_bits(0x3FE4_5F30_6DC9_C883); // 6.36619772367581382433e-01
/// First 33 bits of π/2.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000); // 1.57079632673412561417e+00
/// π/2 − PIO2_1, to 53 bits.
const PIO2_1T: f64 = f64::from_bits(0x3DD0_B461_1A62_6331); // 6.07710050650619224932e-11
/// Second 33 bits of π/2.
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000); // 6.07710050630396597660e-11
/// Third 33 bits of π/2.
const PIO2_3: f64 = f64::from_bits(0x3BA3_198A_2E00_0000); // 2.02226624871116645580e-21
/// π/2 − (PIO2_1 + PIO2_2 + PIO2_3), to 53 bits.
const PIO2_3T: f64 = f64::from_bits(0x397B_839A_2520_49C1); // 8.47842766036889956997e-32

// __sin: sin(x) ≈ x + S1·x³ + … + S6·x¹³ on [−π/4, π/4], |error/x| ≤ 2^-58.
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549); // -1.66666666666666324348e-01
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6); // 8.33333333332248946124e-03
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5); // -1.98412698298579493134e-04
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D); // 2.75573137070700676789e-06
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB); // -2.50507602534068634195e-08
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C); // 1.58969099521155010221e-10

// __cos: cos(x) ≈ 1 − x²/2 + C1·x⁴ + … + C6·x¹⁴ on [−π/4, π/4], |error| ≤ 2^-58.
const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C); // 4.16666666666666019037e-02
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177); // -1.38888888888741095749e-03
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590); // 2.48015872894767294178e-05
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD); // -2.75573143513906633035e-07
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4); // 2.08757232129817482790e-09
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4); // -1.13596475577881948265e-11

/// `(sin x, cos x)`, within 1 ulp of [`libm::sincos`]; see the [module](self) documentation.
///
/// Straight-line code for `|x| <` [`SINCOS_FAST_LIMIT`]; beyond it, and for infinities and NaN
/// (which give `(NaN, NaN)`), it calls [`libm::sincos`]. `sincos(-0.0)` is `(-0.0, 1.0)`.
/// Slower than [`libm::sincos`] on its own (see the [module](self) documentation); for several
/// angles, [`sincos_array`] is faster than both.
#[inline]
pub fn sincos(x: f64) -> (f64, f64) {
    if !in_fast_range(x) {
        return sincos_libm(x);
    }
    let ([s], [c]) = lanes([x]);
    (s, c)
}

/// `(sin x[i], cos x[i])` for every `i`, as `([sin x[0], …], [cos x[0], …])`: the same values
/// as [`sincos`] of each, bit for bit.
///
/// The angles go through the fast path two by two (the compiler computes each pair with
/// two-lane SSE2 instructions), and one check at the end sends any `|x[i]| ≥`
/// [`SINCOS_FAST_LIMIT`], infinity or NaN to [`libm::sincos`]. For the angles of a chain,
/// cheaper than `N` calls to [`libm::sincos`] (see the [module](self) documentation).
///
/// Always inlined: out of line, the arrays go through memory and the stores of the caller's
/// copy stall the two-lane loads (it then measured slower than libm).
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

/// `(sin x, cos x)` in `f32`: [`sincos`] of `x as f64`, rounded to `f32`.
///
/// The `f64` values are within 1 ulp of `f64`, so rounding them gives the correctly rounded
/// `f32` unless the exact value lies within about `2^-29` `f32`-ulp of a rounding boundary
/// (none among the tests' 1.4 million random arguments: all equal glibc's `f64` rounded);
/// always within 1 ulp of [`libm::sincosf`], which it matches in 99.9 % of cases. It is more
/// accurate than [`libm::sincosf`] but about 2.5 times slower (that one works in `f64` on an
/// `f32`-sized reduction). Infinities and NaN give `(NaN, NaN)`.
#[inline]
pub fn sincosf(x: f32) -> (f32, f32) {
    let (s, c) = sincos(f64::from(x));
    (s as f32, c as f32)
}

/// `|x| <` [`SINCOS_FAST_LIMIT`]: false for infinities and NaN.
#[inline(always)]
fn in_fast_range(x: f64) -> bool {
    x.abs() < SINCOS_FAST_LIMIT
}

/// The out-of-line fallback of [`sincos`].
#[cold]
#[inline(never)]
fn sincos_libm(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// The out-of-line fallback of [`sincos_array`]: redoes the angles the fast path cannot take.
#[cold]
#[inline(never)]
fn sincos_array_libm(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    for ((&x, s), c) in x.iter().zip(sin).zip(cos) {
        if !in_fast_range(x) {
            (*s, *c) = libm::sincos(x);
        }
    }
}

/// The fast path for `N` (1 or 2) angles, lane by lane, with no branch: correct for
/// `|x| <` [`SINCOS_FAST_LIMIT`], meaningless (but harmless) beyond.
#[inline(always)]
fn lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    for i in 0..N {
        let x = x[i];

        // n = round(x·2/π), |n| ≤ 2^20; n mod 4 is in the low bits of `t`'s representation.
        let t = x * INV_PIO2 + TOINT;
        let quadrant = t.to_bits();
        let n = t - TOINT;

        // y = x − n·π/2 = x − n·(PIO2_1 + PIO2_2 + PIO2_3 + PIO2_3T) as y0 + y1.
        //
        // y0 is musl's first round, r1 − fl(n·PIO2_1T). y1 = y − y0 is computed beside it,
        // every step exact but the last:
        // - n·PIO2_1, n·PIO2_2, n·PIO2_3 are exact (20 + 33 bits ≤ 53), and so is
        //   r1 = x − n·PIO2_1 (Sterbenz: x is within a factor 2 of n·π/2 when n ≠ 0);
        // - e1 = (r1 − y0) − p is the exact error of y0 = r1 − p (Fast2Sum: r1 is a multiple
        //   of 2^-53, as x is, or n = 0, and |p| < 2^-13, so r1's exponent is at least p's);
        // - p − n·PIO2_2 is exact (Sterbenz: PIO2_1T ≈ PIO2_2), and so is subtracting
        //   n·PIO2_3: the result, n·(PIO2_1T − PIO2_2 − PIO2_3) plus p's rounding error, is
        //   below 2^-66 and a multiple of 2^-96 (PIO2_3's last bit);
        // - so y = y0 + e1 + q − n·PIO2_3T exactly but for n·PIO2_3T's rounding, and the last
        //   two roundings are 2^-53 of |y1| ≤ ulp(y0)/2 + n·2^-87, at most 2^-59 of |y| since
        //   |y| ≥ 2^-60.5 (the closest case below the limit, x = 45.553…, n = 29, has
        //   |y1| ≈ 2^-82): below 1/50 ulp.
        // y1 enters the kernels only in their first-order corrections, late.
        let r1 = x - n * PIO2_1;
        let p = n * PIO2_1T;
        let y0 = r1 - p;
        let e1 = (r1 - y0) - p;
        let q = (p - n * PIO2_2) - n * PIO2_3;
        let y1 = e1 + (q - n * PIO2_3T);

        let (s, c) = kernels(y0, y1);

        // Quadrant 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
        let swap = 0u64.wrapping_sub(quadrant & 1);
        let (sb, cb) = (s.to_bits(), c.to_bits());
        let sin_sign = (quadrant & 2) << 62;
        let cos_sign = (quadrant.wrapping_add(1) & 2) << 62;
        sin[i] = f64::from_bits(((sb & !swap) | (cb & swap)) ^ sin_sign);
        cos[i] = f64::from_bits(((cb & !swap) | (sb & swap)) ^ cos_sign);
    }
    (sin, cos)
}

/// FreeBSD `__sin(x, y, 1)` and `__cos(x, y)`: (sin(x + y), cos(x + y)) for |x| ≲ π/4 and
/// |y| ≪ |x| (or y = 0).
///
/// The polynomials and the corrections for `y` are musl's:
/// `sin = x − ((z·(y/2 − v·r) − y) − v·S1)` with `z = x²`, `v = z·x`,
/// `r = S2 + S3·z + … + S6·z⁴`, and `cos = w + (((1 − w) − z/2) + (z·r' − x·y))` with
/// `w = 1 − z/2`, `r' = C1·z + … + C6·z⁶`; only the order of the additions differs (Estrin:
/// pairs of coefficients combined with `z²` and `z⁴`). The sine keeps its final subtraction,
/// so `sin(−0) = −0`.
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
