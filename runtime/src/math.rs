//! Sine and cosine of an angle together, inlinable, without branches on the argument, as
//! accurate as [`libm::sincos`]: for several angles at once ([`sincos_array`], faster than
//! libm) or for one ([`sincos`], **slower** than libm; see below).
//!
//! # Why hand-written
//!
//! [`libm::sincos`] (FreeBSD/musl) is accurate but is an out-of-line call whose reduction
//! branches on the argument: five size classes of `|x|`, one to three rounds of reduction
//! depending on the cancellation, a `match` on the quadrant. Measured, it was a large part of
//! the 7-DOF inverse dynamics, which needs six angles.
//!
//! This module computes the same thing as straight-line code: the same polynomial coefficients,
//! a reduction that does all its steps every time (exact for every argument below
//! [`SINCOS_FAST_LIMIT`], so no branch on the amount of cancellation), and the quadrant applied
//! with bit masks instead of a `match`. The one branch left sends `|x| ≥`
//! [`SINCOS_FAST_LIMIT`], infinities and NaN to [`libm::sincos`]; joint angles always take it
//! the same way.
//!
//! What that buys: for several angles ([`sincos_array`]) far fewer instructions per angle than
//! libm, and the generated dynamics that call it faster; for one angle ([`sincos`]) fewer
//! instructions but **more time** than libm, whose branches the processor predicts cheaply.
//! `cargo run --release -p articulated-bench --bin sincos_table [-- --instructions]` and
//! `cargo bench -p articulated-bench --bench math` measure both against libm and std; the
//! figures of the session that wrote this module are in the history of `bench/README.md`
//! ("Sine and cosine", last at commit 4b955c8).
//!
//! # The algorithm
//!
//! - `n = round(x·2/π)` by the `x·(2/π) + 1.5·2^52 − 1.5·2^52` trick (valid for
//!   `|x| <` [`SINCOS_FAST_LIMIT`], where `|n| ≤ 2^15`); `n mod 4` is the low two bits of the
//!   sum's representation;
//! - `y = x − n·π/2` as a head and tail `y0 − yn` by Cody–Waite with π/2 in three parts, two
//!   of 35 bits (`n` times each is exact) and a rounded third: `y0 = (x − n·p1) − n·p2`,
//!   `yn` its exact rounding error (Fast2Sum) plus `n·p3`, four operations after `y0` (see the
//!   comments in the code). `y0 − yn` is within `n·2^-128` of `y`, under 1/100 ulp of the
//!   result for every argument in the range: the least `|y|/n` below the limit is 2^-67.5
//!   (x = 46066.74…), the closest a double comes to a multiple of π/2 is 2^-60.5
//!   (x = 45.553…);
//! - the FreeBSD/musl kernels `__sin(y0, −yn, 1)` and `__cos(y0, −yn)`: the same polynomials
//!   with the same coefficients S1..S6, C1..C6 and the same first-order corrections for the
//!   tail, regrouped (see `kernels` in the code), the sine's polynomial in Horner's order (in
//!   two-operand SSE2, two instructions per coefficient, no register copies), the cosine's, on
//!   the critical path, in pairs of coefficients;
//! - the quadrant: negate the sine if `n` is odd, swap sine and cosine if `n` is odd, negate
//!   both if `n mod 4 ≥ 2`, with bit masks on their representations (no branch, no table).
//!
//! Tried and dropped (same harnesses): a table-driven reduction to `x = k·π/64 + r` with 128
//! entries (sine and cosine of `k·π/64` as head and tail, the head of the product by `r` kept
//! exact), degree-7/8 polynomials in `r`: the polynomials shrink, but the exact recombination
//! and the table loads cost more than they save. Both polynomials in Horner's order: slightly
//! fewer instructions, but slower in `arm7` and a longer latency. Estrin's order for both (this
//! module's before): more instructions, no faster. A fallback that returns new arrays (see
//! [`sincos_array`]).
//!
//! # Accuracy
//!
//! `runtime/tests/math.rs` (`-- --nocapture` prints the figures per range): within 1 ulp of
//! [`libm::sincos`] and of glibc's `f64::sin_cos` everywhere tested (random arguments in
//! `|x| < 1, 10, 10³, 10⁵`, the limit and beyond, every double nearest to `k·π/2` for
//! `k ≤ 2^20` and its neighbours, zeros, subnormals, the extremes), and bit-identical to libm
//! for 98–99 % of random arguments below the limit (100 % near the multiples of π/2 and
//! beyond the limit). Against a double-double reference (exact reduction by a 256-bit π/2,
//! Taylor series), 20 000 random arguments per range: at most 0.79 ulp for `|x| < 1` (libm
//! 0.75; the previous version 0.79 too, at the same argument), 0.73–0.74 ulp in the other
//! ranges (libm the same); 0.50 ulp on the 500 arguments closest to a multiple of π/2, on
//! the 500 with the least `|y|/n`, and just below the limit. `sincos(−0.0) = (−0.0, 1.0)`;
//! subnormal `x` gives `(x, 1.0)`; infinities and NaN give `(NaN, NaN)`.
//!
//! [`sincos`]: crate::math::sincos
//! [`sincos_array`]: crate::math::sincos_array
//! [`SINCOS_FAST_LIMIT`]: crate::math::SINCOS_FAST_LIMIT

// The polynomial coefficients S1..S6, C1..C6 and the kernels' corrections are those of FreeBSD
// msun `k_sin.c` and `k_cos.c` (also musl's and the `libm` crate's), and the reduction follows
// the Cody–Waite scheme of its `e_rem_pio2.c`, under this notice:
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
// (e_rem_pio2.c optimized by Bruce D. Evans.) The reduction's three-part π/2 and the
// branch-free arrangement around the kernels (the always-complete compensated reduction, the
// regrouped corrections, the quadrant by masks, the lane-parallel form) are this crate's.

/// The fast path covers `|x| <` this bound (`f64::from_bits(0x40e921fb00000000)`,
/// `= 51471.84375`, just below `2^15·π/2`); beyond it, and for infinities and NaN,
/// [`libm::sincos`] is called.
///
/// Below it `n = round(x·2/π) ≤ 2^15`, so `n` times each 35-bit part of π/2 is exact, and the
/// reduction is exact but for roundings far below an ulp of the result (see the
/// [module](self) documentation). Joint angles are far below it: 8192 turns.
///
/// It was `≈ 1647099.3 ≈ 2^20·π/2` in commit a7ea426, with a reduction that cost five more
/// operations per angle; between the two bounds the results now come from [`libm::sincos`]
/// (within 1 ulp of the former ones, like everywhere else).
pub const SINCOS_FAST_LIMIT: f64 = f64::from_bits(0x40E9_21FB_0000_0000);

/// `1.5·2^52`: adding and subtracting it rounds to the nearest integer (for `|v| < 2^51`), and
/// the low bits of the sum are that integer in two's complement.
const TOINT: f64 = 6_755_399_441_055_744.0;
/// 53 bits of 2/π.
const INV_PIO2: f64 = f64::from_bits(0x3FE4_5F30_6DC9_C883); // 6.36619772367581382433e-01
/// π/2 truncated to 38 bits (35 significant: its last three are zero).
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5444_0000); // 1.57079632679233327508e+00
/// π/2 − PIO2_1 truncated to 38 bits (35 significant).
const PIO2_2: f64 = f64::from_bits(0x3D86_8C23_4C4C_0000); // 2.56334415158395578912e-12
/// π/2 − PIO2_1 − PIO2_2 rounded to 53 bits; the sum of the three is π/2 within 2^-130.
const PIO2_3: f64 = f64::from_bits(0x3B29_8A2E_0370_7345); // 1.05629990669874276403e-23

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
/// copy stall the two-lane loads (in commit a7ea426 it had no attribute and was not inlined
/// into the generated code; inlining alone made `arm7`'s inverse dynamics faster).
/// The fallback writes into the arrays, so they stay in memory even inlined: a fallback that
/// returns new arrays instead saves a few instructions per angle but measured slower in
/// `arm7`'s inverse dynamics (the results then stay in registers through the caller's code).
#[inline(always)]
pub fn sincos_array<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    let mut i = 0;
    // With AVX2 (`-C target-cpu=x86-64-v3` or newer) the compiler runs four lanes in one ymm
    // register: four angles at a time, then pairs.
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    while i + 4 <= N {
        let (s, c) = lanes([x[i], x[i + 1], x[i + 2], x[i + 3]]);
        sin[i..i + 4].copy_from_slice(&s);
        cos[i..i + 4].copy_from_slice(&c);
        i += 4;
    }
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    if N - i == 3 {
        let (s, c) = lanes([x[i], x[i + 1], x[i + 2], 0.0]);
        sin[i..].copy_from_slice(&s[..3]);
        cos[i..].copy_from_slice(&c[..3]);
        i += 3;
    }
    while i + 2 <= N {
        let (s, c) = lanes([x[i], x[i + 1]]);
        sin[i..i + 2].copy_from_slice(&s);
        cos[i..i + 2].copy_from_slice(&c);
        i += 2;
    }
    if i < N {
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

/// A cut in a generated function's straight-line code: a branch that is never taken but that
/// the optimizer cannot remove (its condition is [`core::hint::black_box`]`(false)`), so that the
/// statements before it and after it are separate basic blocks. Inlined, it costs three
/// instructions (a byte stored, compared in memory, and the jump).
///
/// Why: the generated mass matrix is one long basic block, and LLVM schedules a basic block as
/// one region; what it made of the humanoid's `mass_matrix_update` (thousands of statements)
/// kept more values live than 16 vector registers hold, and a large share of its instructions
/// moved spilled values to and from the stack. Cut into blocks of about 200 statements, it
/// compiles to fewer instructions, fewer spill moves and fewer bytes, and runs faster
/// (`x86-64-v3`). Only a branch does it: a compiler fence or a `black_box` without a branch at
/// the same places left the function as slow. The generator cuts only the mass matrix, where it
/// measured faster (`articulated_codegen`'s `emit::with_boundaries` says how the spacing was
/// chosen).
#[inline(always)]
pub fn block_boundary() {
    if core::hint::black_box(false) {
        never_taken();
    }
}

/// The branch of [`block_boundary`] that is never taken. It must not return: a call that returns
/// and does nothing would be removed, and the branch with it.
#[cold]
#[inline(never)]
fn never_taken() -> ! {
    loop {
        core::hint::spin_loop();
    }
}

/// `a·b + c`, rounded once (a fused multiply–add) when the build targets a processor with FMA,
/// and as `a * b + c` (rounded twice) otherwise; what generated `f64` code computes its sums of
/// products with.
///
/// "Targets a processor with FMA" means `cfg(target_feature = "fma")` on x86-64: built with
/// `-C target-cpu=x86-64-v3` (Haswell, Zen and later), `-C target-cpu=native` on such a
/// processor, or `-C target-feature=+fma`. The instruction then replaces a product and a sum,
/// and its latency (4 cycles on Zen 4) is shorter than theirs (3 + 3). Elsewhere (the default
/// x86-64 target, other architectures) it is exactly `a * b + c`: no call to a software `fma`,
/// which would be far slower than the two operations it replaces.
///
/// Rust does not contract `a * b + c` into an FMA by itself (that would change results from
/// one target to another), so the generated code asks for it here, where both roundings are
/// acceptable: the generated dynamics are held to the reference at 1e-12, the difference is
/// a few units in the last place.
///
/// With the `std` feature (the default) the FMA is `f64::mul_add`, which the compiler sees as
/// one scalar operation (`llvm.fma`). Without `std` it is `core::arch`'s `_mm_fmadd_sd`, which
/// goes through vector registers: the same machine code in the end (arm7's inverse dynamics
/// compiles to the same 847 instructions either way), but LLVM's optimizer spends far longer on
/// large functions written with it (a release build of the tests' 30-body random tree for
/// `x86-64-v3`: 14.5 s with `f64::mul_add`, not done after 20 minutes with the intrinsic).
#[inline(always)]
#[allow(unsafe_code)] // The one `unsafe` of the workspace: see the SAFETY note.
pub fn mul_add(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(all(feature = "std", target_arch = "x86_64", target_feature = "fma"))]
    {
        a.mul_add(b, c)
    }
    #[cfg(all(not(feature = "std"), target_arch = "x86_64", target_feature = "fma"))]
    {
        use core::arch::x86_64::{_mm_cvtsd_f64, _mm_fmadd_sd, _mm_set_sd};
        // SAFETY: the intrinsics need SSE2 and FMA, and this block is compiled only when the
        // build enables both for every function (`target_feature = "fma"` implies SSE2 on
        // x86-64), the same guarantee under which the compiler emits FMA instructions itself.
        unsafe { _mm_cvtsd_f64(_mm_fmadd_sd(_mm_set_sd(a), _mm_set_sd(b), _mm_set_sd(c))) }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "fma")))]
    {
        a * b + c
    }
}

/// [`mul_add`] in `f32`.
#[inline(always)]
#[allow(unsafe_code)] // As in `mul_add`.
pub fn mul_addf(a: f32, b: f32, c: f32) -> f32 {
    #[cfg(all(feature = "std", target_arch = "x86_64", target_feature = "fma"))]
    {
        a.mul_add(b, c)
    }
    #[cfg(all(not(feature = "std"), target_arch = "x86_64", target_feature = "fma"))]
    {
        use core::arch::x86_64::{_mm_cvtss_f32, _mm_fmadd_ss, _mm_set_ss};
        // SAFETY: as in `mul_add`.
        unsafe { _mm_cvtss_f32(_mm_fmadd_ss(_mm_set_ss(a), _mm_set_ss(b), _mm_set_ss(c))) }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "fma")))]
    {
        a * b + c
    }
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

/// `(sin x[i], cos x[i])` in `f32` for every `i`, as `([sin x[0], …], [cos x[0], …])`: what
/// generated `f32` code computes its angles' sines with. On x86-64 and AArch64, four at a time
/// with AVX, two without, by [`libm::sincosf`]'s algorithm in `f64` vectors, the one of the `f32`
/// batch functions ([`crate::lanes`]), so that a state's values in a batch are the scalar
/// function's, bit for bit; equal to [`libm::sincosf`] but where the exact value lies within
/// about `2^-26` ulp of a rounding boundary, within an ulp of it there (`runtime/tests/math.rs`
/// counts them); angles at or beyond `2^28·π/2`, infinities and NaN are [`libm::sincosf`]'s.
/// Elsewhere (no `f64` vectors, as on a Cortex-M) it is [`libm::sincosf`] angle by angle.
///
/// Why not [`libm::sincosf`] angle by angle everywhere: the generated functions measured run
/// fewer instructions with the angles in vectors (all but one), and the humanoid's `f32` inverse
/// dynamics on the default target ran much faster without its 31 calls (the commit that made
/// this the generated code's has the figures).
#[inline(always)]
pub fn sincosf_array<const N: usize>(x: [f32; N]) -> ([f32; N], [f32; N]) {
    crate::lanes::sincos_f32_scalar(x)
}

/// `|x| <` [`SINCOS_FAST_LIMIT`]: false for infinities and NaN.
#[inline(always)]
pub(crate) fn in_fast_range(x: f64) -> bool {
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
pub(crate) fn sincos_array_libm(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    for ((&x, s), c) in x.iter().zip(sin).zip(cos) {
        if !in_fast_range(x) {
            (*s, *c) = libm::sincos(x);
        }
    }
}

/// The fast path for `N` (1, 2 or 4) angles, lane by lane, with no branch: correct for
/// `|x| <` [`SINCOS_FAST_LIMIT`], meaningless (but harmless) beyond.
#[inline(always)]
fn lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    for i in 0..N {
        (sin[i], cos[i]) = fast(x[i]);
    }
    (sin, cos)
}

/// What the fast path computes with: `f64`, or a vector of them (`articulated::lanes`, whose
/// lane types run the same algorithm on several states at once).
pub(crate) trait Angles:
    Copy
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
    + core::ops::Neg<Output = Self>
{
    /// The representations: `u64`, or a vector of them.
    type Bits: Copy
        + core::ops::BitXor<Output = Self::Bits>
        + core::ops::BitAnd<Output = Self::Bits>;
    /// A constant in every lane.
    fn splat(x: f64) -> Self;
    /// [`mul_add`] in every lane.
    fn fma(a: Self, b: Self, c: Self) -> Self;
    /// The representation.
    fn to_bits(self) -> Self::Bits;
    /// The value of a representation.
    fn from_bits(b: Self::Bits) -> Self;
    /// A representation in every lane.
    fn bits(b: u64) -> Self::Bits;
    /// Shifted left by `n`.
    fn shl(b: Self::Bits, n: u32) -> Self::Bits;
    /// `0 − b`, wrapping.
    fn wrapping_neg(b: Self::Bits) -> Self::Bits;
}

impl Angles for f64 {
    type Bits = u64;
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn fma(a: f64, b: f64, c: f64) -> f64 {
        mul_add(a, b, c)
    }
    #[inline(always)]
    fn to_bits(self) -> u64 {
        f64::to_bits(self)
    }
    #[inline(always)]
    fn from_bits(b: u64) -> f64 {
        f64::from_bits(b)
    }
    #[inline(always)]
    fn bits(b: u64) -> u64 {
        b
    }
    #[inline(always)]
    fn shl(b: u64, n: u32) -> u64 {
        b << n
    }
    #[inline(always)]
    fn wrapping_neg(b: u64) -> u64 {
        b.wrapping_neg()
    }
}

/// The fast path for one angle (or one vector of them): `(sin x, cos x)` with no branch,
/// correct for `|x| <` [`SINCOS_FAST_LIMIT`], meaningless (but harmless) beyond.
#[inline(always)]
pub(crate) fn fast<V: Angles>(x: V) -> (V, V) {
    let c = V::splat;
    let mul_add = V::fma;

    // n = round(x·2/π), |n| ≤ 2^15; n mod 4 is in the low bits of `t`'s representation.
    // Fused where the target has FMA (`mul_add`): one rounding instead of two, which can
    // only move `n` by one where x·2/π lies within an ulp of a half-integer (|y| then ≈ π/4,
    // inside the kernels' range either way), and a shorter latency before the kernels.
    let t = mul_add(x, c(INV_PIO2), c(TOINT));
    let quadrant = t.to_bits();
    let n = t - c(TOINT);

    // y = x − n·π/2 = x − n·(PIO2_1 + PIO2_2 + PIO2_3) as y0 − yn, |yn| ≪ |y0|:
    // - n·PIO2_1 and n·PIO2_2 are exact (15 + 35 bits ≤ 53, or n = 2^15), and so is
    //   r1 = x − n·PIO2_1 (Sterbenz: x is within a factor 2 of n·PIO2_1 when n ≠ 0);
    // - y0 = r1 − p2 rounded, and p2 − (r1 − y0) is its exact error: r1 is a multiple of
    //   2^-53 (|x| > 1/2 when n ≠ 0, and PIO2_1's last bit is 2^-34), hence of p2's ulp
    //   (|p2| < 2^-23), which makes Fast2Sum exact whichever of r1 and p2 is larger;
    // - yn adds n·PIO2_3 (< n·2^-76): y = y0 − yn but for the roundings of n·PIO2_3 and
    //   of that sum (2^-53 of n·2^-76 each, plus 2^-106 of |y0|) and for
    //   π/2 − (PIO2_1 + PIO2_2 + PIO2_3) < 2^-130: below n·2^-128 + 2^-106·|y0| in all.
    //   Below the limit |y| ≥ n·2^-67.5 (the least ratio, at x = 46066.74…, n = 29327), so
    //   the error is below 2^-60 of |y|, 1/100 of an ulp; the closest x to a multiple of
    //   π/2, x = 45.553…, n = 29, has |y| = 2^-60.5 and |yn| ≈ 2^-71.5.
    // yn enters the kernels only in their first-order corrections, late.
    let r1 = mul_add(-n, c(PIO2_1), x);
    let p2 = n * c(PIO2_2);
    let y0 = r1 - p2;
    let yn = mul_add(n, c(PIO2_3), p2 - (r1 - y0));

    let (s, co) = kernels(y0, yn);

    // Quadrant 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s). That is: negate s if n is
    // odd, swap the two if n is odd (xor-swap under a mask), negate both if n mod 4 ≥ 2.
    let s = s.to_bits() ^ V::shl(quadrant, 63);
    let co = co.to_bits();
    let swap = (s ^ co) & V::wrapping_neg(quadrant & V::bits(1));
    let sign = V::shl(quadrant, 62) & V::bits(1 << 63);
    (
        V::from_bits(s ^ swap ^ sign),
        V::from_bits(co ^ swap ^ sign),
    )
}

/// FreeBSD `__sin(x, −yn, 1)` and `__cos(x, −yn)`: (sin(x − yn), cos(x − yn)) for
/// |x| ≲ π/4 and |yn| ≪ |x| (or yn = 0).
///
/// The polynomials, with musl's coefficients, and musl's first-order corrections for the
/// tail, arranged with fewer operations: `sin = x − ((w·yn − v·S1) − (v·z)·r)` with `z = x²`,
/// `v = z·x`, `w = 1 − z/2`, `r = S2 + S3·z + … + S6·z⁴` (musl: `x − ((z·(y/2 − v·r) − y) −
/// v·S1)` with `y = −yn`; `w·yn` is its `y − z·y/2` in one product), and
/// `cos = w + ((((1 − w) − z/2) + x·yn) + z²·r')` with `r' = C1 + … + C6·z⁵`, musl's terms
/// (it adds `z²·r' + x·yn` first). The sine keeps its final subtraction of a difference, so
/// `sin(−0) = −0`.
///
/// The order of evaluation is a trade between instructions and latency. In two-operand SSE2,
/// Horner's order costs one multiplication and one addition from memory per coefficient, no
/// register copy; Estrin's (this module's before) needs copies and `z⁴`. The sine's `r` is in
/// Horner's order; the cosine's `r'`, one coefficient longer and then the critical path, is
/// Horner's order in `z²` over pairs `Ci + Ci+1·z`: slightly more instructions than Horner's
/// order for both, fewer than Estrin's for both, and as fast as the latter (`arm7`'s inverse
/// dynamics faster than with Horner's order for both, and a shorter latency of [`sincos`]).
#[inline(always)]
fn kernels<V: Angles>(x: V, yn: V) -> (V, V) {
    let c = V::splat;
    let mul_add = V::fma;
    let z = x * x;
    let z2 = z * z;
    let v = z * x;
    let hz = c(0.5) * z;
    let w = c(1.0) - hz;

    // In `mul_add`: fused where the target has FMA (shorter latency, one rounding per
    // coefficient instead of two), the same operations in the same order otherwise.
    let r = mul_add(
        z,
        mul_add(z, mul_add(z, mul_add(z, c(S6), c(S5)), c(S4)), c(S3)),
        c(S2),
    );
    let sin = x - ((w * yn - v * c(S1)) - (v * z) * r);

    let rc = mul_add(
        z2,
        mul_add(z2, mul_add(z, c(C6), c(C5)), mul_add(z, c(C4), c(C3))),
        mul_add(z, c(C2), c(C1)),
    );
    let cos = w + ((((c(1.0) - w) - hz) + x * yn) + z2 * rc);
    (sin, cos)
}
