//! Many states per call: the scalars of [`Simd`], which carry `N` states' values of one quantity,
//! and what the generated batch functions (`C::inverse_dynamics_batch`, …) are made of.
//!
//! # How a batch is computed
//!
//! A chain that asks for lanes (`lanes: 4` in its description, `lanes = 4` in `#[chain(…)]`)
//! gets, for each output, the same straight-line statements as its scalar function, typed in
//! [`F64x4`] instead of `f64`: one statement then computes the same quantity for four states,
//! in one vector instruction (`x86-64-v3`: four `f64` in a 256-bit register; the default
//! target: two 128-bit instructions). The statements are the
//! scalar function's, operand for operand, with the same fused multiply–adds, divisions and
//! sines (the lanes' sines and cosines are [`crate::math::sincos_array`]'s in `f64`,
//! [`crate::math::sincosf_array`]'s in `f32`), so a state's result in a batch is the scalar
//! function's, bit for bit, whichever lane it sits in.
//!
//! The batch function ([`crate::InverseDynamics::inverse_dynamics_batch`] and its kind) takes
//! the slices a user holds (`&[SVector<f64, NQ>]`), gathers `N` states at a time into lanes
//! ([`gather`]), runs the statements and scatters the results ([`Split`]); the last, partial
//! group is padded with copies of its first state, whose results are dropped. Forward dynamics
//! checks its pivots lane by lane ([`positive_pivot`] gives a [`Mask`]): a singular state gets
//! its error, its neighbours their values ([`refuse`]).
//!
//! The lane types: [`F64x2`], [`F64x4`], [`F64x8`] (`lanes: 2 | 4 | 8` in `f64`) and [`F32x4`],
//! [`F32x8`], [`F32x16`] (`lanes: 4 | 8 | 16` in `f32`), each one vector of the `wide` crate,
//! which picks the target's instructions at compile time (SSE2, AVX, AVX-512, NEON, or plain
//! arrays). The large outputs (a thousand operations or more) take instead the lane type of
//! [`fit`]: at most the lanes asked for, as many as one of the target's registers holds.
//!
//! Every chain has the batch functions: without `lanes`, they call the scalar function state by
//! state (the traits' provided methods); with it, the generator overrides them with the lane
//! code, at the price of compiling each output twice.
//!
//! # What lanes speed up, and what they cannot
//!
//! The lanes carry every operation of the scalar code for `N` states at once, with one exception
//! that bounds what they gain: the sines and cosines. The scalar functions already compute
//! theirs four angles per instruction where the target has AVX2 ([`crate::math::sincos_array`],
//! [`crate::math::sincosf_array`]),
//! so in lanes a state's sines cost what they cost it alone, less only the padding of the scalar
//! code's last group of four (a chain of 6 angles: 8 computed alone, 6 in lanes; the humanoid's
//! 31: 32 and 31). The outputs whose work is mostly sines and cosines, such as a short chain's
//! mass matrix, gain least. Gathering the states into lanes and scattering the results, entry by
//! entry of the inputs and outputs, take their share too. `BENCHMARKS.md` ("Many states per
//! call") has the ratios.
//!
//! # Why wrappers of `wide`'s vectors
//!
//! The generated code is written in `+ − · /` and a few calls: it needs a type whose operators
//! also take an `f64` constant on either side (`0.25_f64 * x`), so that the lane statements are
//! the scalar ones unchanged; a type of another crate cannot be given those operators (`f64 *
//! wide::f64x4` is a foreign impl on foreign types), so each lane type wraps one. The first
//! version was an array `[f64; N]` with each operation a loop over its lanes, left to the
//! compiler to vectorize: it did for arm7's forward dynamics in four lanes, not for its inverse
//! dynamics (nine in ten operations stayed scalar, no faster than the scalar loop). A vector type
//! leaves the compiler nothing to find. The sines and cosines are computed on the lanes as an
//! array by [`crate::math::sincos_array`], which the compiler does vectorize (four angles per
//! instruction with AVX2), so that they are the scalar code's, bit for bit.

use core::fmt::Debug;
use core::ops::{Add, BitAnd, Div, Mul, Neg, Sub};

use nalgebra::{SMatrix, SVector};

use crate::{FramePlacement, SingularMassMatrix};

/// The element types of the lanes: `f64` and `f32`, with what the lane code computes on them.
pub trait Element: nalgebra::Scalar + Copy + PartialOrd + Mul<Output = Self> {
    /// Neither infinite nor NaN.
    fn is_finite(x: Self) -> bool;
    /// Zero.
    const ZERO: Self;
}

impl Element for f64 {
    #[inline(always)]
    fn is_finite(x: f64) -> bool {
        x.is_finite()
    }
    const ZERO: f64 = 0.0;
}

impl Element for f32 {
    #[inline(always)]
    fn is_finite(x: f32) -> bool {
        x.is_finite()
    }
    const ZERO: f32 = 0.0;
}

/// A lane type: `LANES` values of one quantity, one per state, the scalar of the generated lane
/// code. Arithmetic is lane by lane, also with a plain element on either side (the same value in
/// every lane).
pub trait Simd:
    Copy
    + Debug
    + PartialEq
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// One state's value: `f64` or `f32`.
    type Element: Element;
    /// States per value.
    const LANES: usize;
    /// Zero in every lane.
    const ZERO: Self;
    /// The same value in every lane.
    fn splat(x: Self::Element) -> Self;
    /// Lane `i`'s value computed by `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> Self::Element) -> Self;
    /// Lane `i`'s value (`i < LANES`).
    fn lane(&self, i: usize) -> Self::Element;
    /// `a·b + c` lane by lane, as the scalar code's [`crate::math::mul_add`]: fused where the
    /// target has FMA, `a * b + c` otherwise.
    fn mul_add(a: Self, b: Self, c: Self) -> Self;
    /// `(sin x, cos x)` lane by lane, as the scalar code computes them.
    fn sincos(self) -> (Self, Self);
    /// `√x` lane by lane (correctly rounded, as the scalar code's `libm::sqrt`).
    fn sqrt(self) -> Self;
    /// Up to `LANES` states' vectors (at least one) as one vector of lanes: entry `k` of state
    /// `l` in lane `l` of entry `k`; missing lanes repeat the first state.
    fn gather<const K: usize>(states: &[SVector<Self::Element, K>]) -> SVector<Self, K>;
    /// The lanes where `a > b` (false for NaN), lane `l` in bit `l`.
    fn gt(a: Self, b: Self) -> Mask;
    /// The lanes that are neither infinite nor NaN.
    fn finite(self) -> Mask;
    /// `out[l][e] = values[e].lane(l)` for each lane `l` whose `out[l]` is `Some`: the inverse
    /// of [`Simd::gather`], by `LANES × LANES` transposes of blocks of entries where the target
    /// transposes in registers, lane by lane otherwise.
    fn scatter_entries(values: &[Self], out: &mut [Option<&mut [Self::Element]>]);
}

/// One lane type and its operators, over a vector of `wide`.
macro_rules! lane_type {
    ($(#[$doc:meta])* $name:ident($wide:ty, $t:ty, $n:literal), transpose: $transpose:expr,
     by $transposed:path, |$x:ident| $sincos:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[repr(transparent)]
        pub struct $name(pub $wide);

        impl $name {
            /// The same value in every lane: how generated code writes a constant it stores.
            #[inline(always)]
            pub fn splat(x: $t) -> Self {
                $name(<$wide>::splat(x))
            }
        }

        impl Simd for $name {
            type Element = $t;
            const LANES: usize = $n;
            const ZERO: Self = $name(<$wide>::splat(0.0));
            #[inline(always)]
            fn splat(x: $t) -> Self {
                $name::splat(x)
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> $t) -> Self {
                $name(<$wide>::new(core::array::from_fn(f)))
            }
            #[inline(always)]
            fn lane(&self, i: usize) -> $t {
                self.0.as_array()[i]
            }
            #[inline(always)]
            fn mul_add(a: Self, b: Self, c: Self) -> Self {
                // `wide` fuses where the target has FMA, as `math::mul_add` does; elsewhere it
                // rounds twice, like `a * b + c`.
                $name(a.0.mul_add(b.0, c.0))
            }
            #[inline(always)]
            fn sincos(self) -> (Self, Self) {
                let $x = self.0;
                let (s, c) = $sincos;
                ($name(s), $name(c))
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $name(self.0.sqrt())
            }
            #[inline(always)]
            fn gt(a: Self, b: Self) -> Mask {
                Mask(a.0.simd_gt(b.0).to_bitmask())
            }
            #[inline(always)]
            fn finite(self) -> Mask {
                Mask(self.0.is_finite().to_bitmask())
            }
            #[inline(always)]
            fn gather<const K: usize>(states: &[SVector<$t, K>]) -> SVector<Self, K> {
                let Ok(full) = <&[SVector<$t, K>; $n]>::try_from(states) else {
                    return gather_padded(states);
                };
                // Blocks of `LANES` entries by transposes in registers where the target has
                // them (one load per state and block), the rest entry by entry, each lane's
                // value loaded into its place. The transposes of `wide` for `F64x4` measured
                // slower than entry by entry (through memory); `transpose_f64x4`'s are faster.
                let mut values: [Self; K] = [Self::ZERO; K];
                let whole = if $transpose { K / $n * $n } else { 0 };
                let mut rows: [_; $n] =
                    core::array::from_fn(|l| full[l].as_slice().chunks_exact($n));
                for dst in values[..whole].chunks_exact_mut($n) {
                    let block: [$wide; $n] = core::array::from_fn(|l| {
                        rows[l]
                            .next()
                            .and_then(|c| <[$t; $n]>::try_from(c).ok())
                            .map_or(<$wide>::ZERO, <$wide>::new)
                    });
                    for (d, t) in dst.iter_mut().zip($transposed(block)) {
                        *d = $name(t);
                    }
                }
                for (k, d) in values.iter_mut().enumerate().skip(whole) {
                    *d = $name(<$wide>::new(core::array::from_fn(|l| full[l].data.0[0][k])));
                }
                SVector::from_array_storage(nalgebra::ArrayStorage([values]))
            }
            #[inline(always)]
            fn scatter_entries(values: &[Self], out: &mut [Option<&mut [$t]>]) {
                // Where `wide` has no transpose in registers for this target, its transpose
                // builds each vector from scalars through memory, and the vector loads that
                // follow the scalar stores stall (commit 633ba16 has the figures): each lane's
                // entries are stored straight into its state's result instead.
                let blocks = if $transpose {
                    values.chunks_exact($n)
                } else {
                    values[..0].chunks_exact($n)
                };
                let whole = blocks.len() * $n;
                for (b, block) in blocks.enumerate() {
                    let at = b * $n;
                    let rows: [$wide; $n] = core::array::from_fn(|e| block[e].0);
                    for (o, t) in out.iter_mut().zip($transposed(rows)) {
                        if let Some(dst) = o.as_deref_mut().and_then(|o| o.get_mut(at..at + $n)) {
                            dst.copy_from_slice(t.as_array());
                        }
                    }
                }
                let rest = &values[whole..];
                for (l, o) in out.iter_mut().enumerate().take($n) {
                    if let Some(o) = o.as_deref_mut() {
                        for (d, v) in o.iter_mut().skip(whole).zip(rest) {
                            *d = v.lane(l);
                        }
                    }
                }
            }
        }

        impl Operand<$name> for $t {
            #[inline(always)]
            fn lanes(self) -> $name {
                $name::splat(self)
            }
        }

        impl Split for $name {
            type State = $t;
            #[inline(always)]
            fn zero() -> $t {
                0.0
            }
            #[inline(always)]
            fn scatter_with<O>(&self, out: &mut [O], place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut $t>) {
                for (l, o) in out.iter_mut().enumerate().take($n) {
                    if let Some(o) = place(o) {
                        *o = self.lane(l);
                    }
                }
            }
        }

        lane_type!(@ops $name, $t: Add add +, Sub sub -, Mul mul *, Div div /);

        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                $name(-self.0)
            }
        }
    };
    (@ops $name:ident, $t:ty: $($tr:ident $f:ident $op:tt),*) => {$(
        impl $tr for $name {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                $name(self.0 $op o.0)
            }
        }
        impl $tr<$t> for $name {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: $t) -> Self {
                self $op $name::splat(o)
            }
        }
        impl $tr<$name> for $t {
            type Output = $name;
            #[inline(always)]
            fn $f(self, o: $name) -> $name {
                $name::splat(self) $op o
            }
        }
    )*};
}

/// `math::fast` on `f64` vectors: the scalar code's algorithm ([`crate::math::sincos_array`])
/// on every lane at once.
macro_rules! angles {
    ($wide:ty, $bits:ty) => {
        impl crate::math::Angles for $wide {
            type Bits = $bits;
            #[inline(always)]
            fn splat(x: f64) -> Self {
                <$wide>::splat(x)
            }
            #[inline(always)]
            fn fma(a: Self, b: Self, c: Self) -> Self {
                a.mul_add(b, c)
            }
            #[inline(always)]
            fn to_bits(self) -> $bits {
                wide::bytemuck::cast(self)
            }
            #[inline(always)]
            fn from_bits(b: $bits) -> Self {
                wide::bytemuck::cast(b)
            }
            #[inline(always)]
            fn bits(b: u64) -> $bits {
                <$bits>::splat(b)
            }
            #[inline(always)]
            fn shl(b: $bits, n: u32) -> $bits {
                b << n
            }
            #[inline(always)]
            fn wrapping_neg(b: $bits) -> $bits {
                <$bits>::splat(0) - b
            }
        }
    };
}
angles!(wide::f64x2, wide::u64x2);
angles!(wide::f64x4, wide::u64x4);
angles!(wide::f64x8, wide::u64x8);

/// `(sin x, cos x)` of every lane of an `f64` vector: [`crate::math::fast`] on the vector, the
/// scalar code's algorithm and so its values, bit for bit; any lane at or beyond
/// [`crate::math::SINCOS_FAST_LIMIT`] (or not finite) redone by `libm`, as the scalar code does.
#[inline(always)]
fn sincos_f64<W: crate::math::Angles + Copy, const N: usize>(
    x: W,
    to_array: impl Fn(W) -> [f64; N],
    from_array: impl Fn([f64; N]) -> W,
) -> (W, W) {
    let (s, c) = crate::math::fast(x);
    let xs = to_array(x);
    if xs.iter().all(|&x| crate::math::in_fast_range(x)) {
        return (s, c);
    }
    let (mut s, mut c) = (to_array(s), to_array(c));
    crate::math::sincos_array_libm(&xs, &mut s, &mut c);
    (from_array(s), from_array(c))
}

/// The sines and cosines of `N` `f32` values (lanes, or a scalar function's angles):
/// [`libm::sincosf`]'s algorithm, `W` at a time in `f64` (4 or 2: [`sincosf_kernel`]), so
/// `libm`'s values for nearly every argument and within an ulp of them for every one. A value
/// at or beyond the reduction's range (`|x| ≥ 2^28·π/2`), infinite or NaN, takes
/// `libm::sincosf`, and only that one: each value's sine depends on it alone, so the scalar
/// code ([`crate::math::sincosf_array`]) and the lanes give the same, bit for bit.
///
/// The lanes' sines were first `f64`'s ([`crate::math::sincos_array`]) rounded: its kernels
/// carry twice the coefficients `f32` needs, so a lane of `f32` paid what a lane of `f64` does.
#[inline(always)]
pub(crate) fn sincos_f32<const N: usize, const W: usize>(x: [f32; N]) -> ([f32; N], [f32; N]) {
    if !x.iter().all(|&x| in_f32_range(x)) {
        return sincos_f32_libm::<N, W>(x);
    }
    let (mut sin, mut cos) = ([0.0; N], [0.0; N]);
    for ((x, s), c) in x
        .chunks_exact(W)
        .zip(sin.chunks_exact_mut(W))
        .zip(cos.chunks_exact_mut(W))
    {
        sincosf_group::<W>(x, s, c);
    }
    if !N.is_multiple_of(W) {
        let whole = N / W * W;
        sincosf_group::<W>(&x[whole..], &mut sin[whole..], &mut cos[whole..]);
    }
    (sin, cos)
}

/// [`sincosf_x4`] (`W = 4`) or [`sincosf_x2`] (`W = 2`) of up to `W` values into `sin` and
/// `cos` (as long as `x`), the missing lanes zero.
#[inline(always)]
fn sincosf_group<const W: usize>(x: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    const { assert!(W == 2 || W == 4, "the kernels are four or two lanes wide") };
    let lane = |l: usize| x.get(l).map_or(0.0, |&x| f64::from(x));
    let mut put = |vs: &[f64], vc: &[f64]| {
        for ((s, c), (&vs, &vc)) in sin.iter_mut().zip(&mut *cos).zip(vs.iter().zip(vc)) {
            (*s, *c) = (vs as f32, vc as f32);
        }
    };
    if W == 4 {
        let (vs, vc) = sincosf_x4(wide::f64x4::new(core::array::from_fn(lane)));
        put(vs.as_array(), vc.as_array());
    } else {
        let (vs, vc) = sincosf_x2(wide::f64x2::new(core::array::from_fn(lane)));
        put(vs.as_array(), vc.as_array());
    }
}

/// Below libm's `rem_pio2f` medium bound (`|x| < 2^28·π/2`, its one-step reduction, what
/// [`sincosf_kernel`] computes): false for infinities and NaN.
#[inline(always)]
fn in_f32_range(x: f32) -> bool {
    x.to_bits() & 0x7fff_ffff < 0x4dc9_0fdb
}

/// [`sincos_f32`] where a value is out of range: those by [`libm::sincosf`], the others as in
/// range (in groups with the out-of-range values as zero: a group's lanes do not mix). Out of
/// line, so that the usual path stays as short as without it.
#[cold]
#[inline(never)]
fn sincos_f32_libm<const N: usize, const W: usize>(x: [f32; N]) -> ([f32; N], [f32; N]) {
    let (mut sin, mut cos) = sincos_f32::<N, W>(x.map(|x| if in_f32_range(x) { x } else { 0.0 }));
    for ((&x, s), c) in x.iter().zip(&mut sin).zip(&mut cos) {
        if !in_f32_range(x) {
            (*s, *c) = libm::sincosf(x);
        }
    }
    (sin, cos)
}

/// What [`crate::math::sincosf_array`] computes a scalar function's angles with: groups of four
/// where the target has AVX (one register), pairs where it has 128-bit `f64` vectors (SSE2,
/// NEON: a group of four would be two registers, and the last group's padding whole
/// instructions); elsewhere (no `f64` vectors: the `f64` of a Cortex-M is soft float)
/// [`libm::sincosf`] angle by angle, shared code rather than a kernel inlined in every function.
#[inline(always)]
pub(crate) fn sincos_f32_scalar<const N: usize>(x: [f32; N]) -> ([f32; N], [f32; N]) {
    #[cfg(target_feature = "avx")]
    {
        sincos_f32::<N, 4>(x)
    }
    #[cfg(all(
        not(target_feature = "avx"),
        any(
            target_feature = "sse2",
            all(target_arch = "aarch64", target_feature = "neon")
        )
    ))]
    {
        sincos_f32::<N, 2>(x)
    }
    #[cfg(not(any(
        target_feature = "avx",
        target_feature = "sse2",
        all(target_arch = "aarch64", target_feature = "neon")
    )))]
    {
        let (mut sin, mut cos) = ([0.0; N], [0.0; N]);
        for ((x, s), c) in x.iter().zip(&mut sin).zip(&mut cos) {
            (*s, *c) = libm::sincosf(*x);
        }
        (sin, cos)
    }
}

/// [`libm::sincosf`] of `f32` arguments held exactly in `f64`, `|x| < 2^28·π/2`, a vector of
/// them at once, before the final rounding to `f32`: `n = rint(x·2/π)`, `y = x − n·p1 − n·p1t`
/// (`rem_pio2f`), then `k_sinf`/`k_cosf` on `y` and the quadrant `n mod 4`: libm's operations,
/// fused in pairs where the target has FMA (half the instructions; libm rounds each product),
/// the same in every lane whatever the vector's width.
///
/// libm itself skips the reduction below `π/4` (the same `y`) and, up to `9π/4`, subtracts a
/// multiple of π/2 rounded to one `f64` where this subtracts it in two parts; with the fused
/// operations, the `f64` result is within a few `f64` ulps of libm's, so the `f32` results
/// differ from libm's only where the exact value lies within about `2^-26` `f32`-ulp of a
/// rounding boundary (`runtime/tests/math.rs` counts them).
macro_rules! sincosf_kernel {
    ($(#[$doc:meta])* $name:ident($f64s:ident, $u64s:ident)) => {
        $(#[$doc])*
        #[inline(always)]
        fn $name(x: wide::$f64s) -> (wide::$f64s, wide::$f64s) {
            use wide::{$f64s, $u64s};
            // libm's `rem_pio2f` constants (2/π; π/2 as 33 bits and the rest) and `k_sinf`'s and
            // `k_cosf`'s coefficients, by their bits (their comments give them so).
            const TOINT: f64 = 1.5 / f64::EPSILON;
            const INV_PIO2: f64 = core::f64::consts::FRAC_2_PI;
            const PIO2_1: f64 = f64::from_bits(0x3ff9_21fb_5000_0000);
            const PIO2_1T: f64 = f64::from_bits(0x3e51_10b4_611a_6263);
            const S: [f64; 4] = [
                f64::from_bits(0xbfc5_5555_54cb_ac77),
                f64::from_bits(0x3f81_1110_896e_fbb2),
                f64::from_bits(0xbf2a_00f9_e2ca_e774),
                f64::from_bits(0x3ec6_cd87_8c3b_46a7),
            ];
            const C: [f64; 4] = [
                f64::from_bits(0xbfdf_ffff_fd0c_5e81),
                f64::from_bits(0x3fa5_5553_e105_3a42),
                f64::from_bits(0xbf56_c087_e80f_1e27),
                f64::from_bits(0x3ef9_9342_e0ee_5069),
            ];
            let splat = $f64s::splat;
            let t = x.mul_add(splat(INV_PIO2), splat(TOINT));
            let n = t - splat(TOINT);
            let y = n.mul_neg_add(splat(PIO2_1T), n.mul_neg_add(splat(PIO2_1), x));
            let z = y * y;
            let w = z * z;
            // k_sinf: (y + s·(S1 + z·S2)) + s·w·(S3 + z·S4), s = z·y.
            let sy = z * y;
            let sin_head = sy.mul_add(z.mul_add(splat(S[1]), splat(S[0])), y);
            let sin = (sy * w).mul_add(z.mul_add(splat(S[3]), splat(S[2])), sin_head);
            // k_cosf: ((1 + z·C0) + w·C1) + (w·z)·(C2 + z·C3).
            let cos_head = w.mul_add(splat(C[1]), z.mul_add(splat(C[0]), splat(1.0)));
            let cos = (w * z).mul_add(z.mul_add(splat(C[3]), splat(C[2])), cos_head);
            // The quadrant, from the low bits of `t` (`n` in its last place): odd swaps sine and cosine;
            // the sine is negated in quadrants 2 and 3, the cosine in 1 and 2.
            let bits: $u64s = wide::bytemuck::cast(t);
            let odd: $f64s = wide::bytemuck::cast($u64s::splat(0) - (bits & $u64s::splat(1)));
            let (s, c) = (odd.bitselect(cos, sin), odd.bitselect(sin, cos));
            let sign_s: $f64s = wide::bytemuck::cast((bits & $u64s::splat(2)) << 62);
            let sign_c: $f64s = wide::bytemuck::cast(((bits + $u64s::splat(1)) & $u64s::splat(2)) << 62);
            // `sin(±0) = ±0`, as libm returns its tiny arguments (the kernel would give `+0` for `−0`).
            let zero = x.simd_eq(splat(0.0));
            (zero.bitselect(x, s ^ sign_s), c ^ sign_c)
        }
    };
}
sincosf_kernel!(
    /// [`sincosf_kernel`] on four arguments: the `f32` lanes' four at a time, and the scalar
    /// code's angles where the target has AVX.
    sincosf_x4(f64x4, u64x4)
);
sincosf_kernel!(
    /// [`sincosf_kernel`] on two arguments: the scalar code's angles two at a time where the
    /// target has no AVX (one SSE2 register).
    sincosf_x2(f64x2, u64x2)
);

/// Four vectors of four `f64` transposed: `out[j].lane(i) == rows[i].lane(j)`.
///
/// `wide`'s own transpose builds each row from cross-lane unpacks, each several shuffles after
/// the compiler lowers it; with AVX this is the textbook eight: four in-lane unpacks and four
/// 128-bit permutes.
#[inline(always)]
#[allow(unsafe_code)] // As `math::mul_add`: see the SAFETY note.
fn transpose_f64x4(rows: [wide::f64x4; 4]) -> [wide::f64x4; 4] {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
    {
        use core::arch::x86_64::{
            __m256d, _mm256_permute2f128_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd,
        };
        let [a, b, c, d]: [__m256d; 4] = rows.map(wide::bytemuck::cast);
        // `t0 = [a0 b0 a2 b2]`, `t1 = [a1 b1 a3 b3]`, `t2 = [c0 d0 c2 d2]`, `t3 = [c1 d1 c3 d3]`.
        // SAFETY: the intrinsics need AVX, and this block is compiled only when the build
        // enables it for every function, the guarantee under which `wide` emits AVX itself.
        let t: [__m256d; 4] = unsafe {
            let (t0, t1) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
            let (t2, t3) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
            [
                _mm256_permute2f128_pd::<0x20>(t0, t2),
                _mm256_permute2f128_pd::<0x20>(t1, t3),
                _mm256_permute2f128_pd::<0x31>(t0, t2),
                _mm256_permute2f128_pd::<0x31>(t1, t3),
            ]
        };
        t.map(wide::bytemuck::cast)
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
    {
        wide::f64x4::transpose(rows)
    }
}

lane_type!(
    /// Two `f64` states (`lanes: 2`): one 128-bit vector.
    F64x2(wide::f64x2, f64, 2),
    transpose: cfg!(any(
        target_feature = "sse2",
        all(target_feature = "neon", target_arch = "aarch64"),
        target_feature = "simd128"
    )),
    by wide::f64x2::transpose,
    |x| sincos_f64(x, |v| v.to_array(), wide::f64x2::new)
);
lane_type!(
    /// Four `f64` states (`lanes: 4`): one 256-bit vector with AVX, two 128-bit ones without.
    F64x4(wide::f64x4, f64, 4),
    transpose: cfg!(target_feature = "avx"),
    by transpose_f64x4,
    |x| sincos_f64(x, |v| v.to_array(), wide::f64x4::new)
);
lane_type!(
    /// Eight `f64` states (`lanes: 8`): one 512-bit vector with AVX-512, two 256-bit ones with
    /// AVX.
    F64x8(wide::f64x8, f64, 8),
    transpose: false,
    by wide::f64x8::transpose,
    |x| sincos_f64(x, |v| v.to_array(), wide::f64x8::new)
);
lane_type!(
    /// Four `f32` states (`lanes: 4` in `f32`): one 128-bit vector.
    F32x4(wide::f32x4, f32, 4),
    transpose: cfg!(target_feature = "sse"),
    by wide::f32x4::transpose,
    |x| {
        let (s, c) = sincos_f32::<_, 4>(x.to_array());
        (wide::f32x4::new(s), wide::f32x4::new(c))
    }
);
lane_type!(
    /// Eight `f32` states (`lanes: 8` in `f32`): one 256-bit vector with AVX.
    F32x8(wide::f32x8, f32, 8),
    transpose: cfg!(target_feature = "avx"),
    by wide::f32x8::transpose,
    |x| {
        let (s, c) = sincos_f32::<_, 4>(x.to_array());
        (wide::f32x8::new(s), wide::f32x8::new(c))
    }
);
lane_type!(
    /// Sixteen `f32` states (`lanes: 16` in `f32`): one 512-bit vector with AVX-512, two
    /// 256-bit ones with AVX.
    F32x16(wide::f32x16, f32, 16),
    transpose: false,
    by wide::f32x16::transpose,
    |x| {
        let (s, c) = sincos_f32::<_, 4>(x.to_array());
        (wide::f32x16::new(s), wide::f32x16::new(c))
    }
);

/// The lane types of the large batch functions (a thousand operations or more: arm7's forward
/// dynamics, the derivatives, the humanoid's every output), under the names of the lane types
/// asked for: each is the widest lane type no wider than the one it is named after that fits
/// one of the target's vector registers. `fit::F64x4` is [`F64x4`] with AVX, [`F64x2`] without.
///
/// Why: a lane type wider than the registers is carried in halves (`F64x4` in two 128-bit
/// registers on the default target), so the statements need twice the registers, and a large
/// function's statements then spill: arm7's forward dynamics on the default target ran no faster
/// in four lanes than state by state (its two lanes against the scalar loop: `BENCHMARKS.md`,
/// "Many states per call", "By target"). Its mass matrix, a few hundred independent products,
/// gained from the halves' extra instruction-level parallelism: the small functions keep the
/// lanes asked for (the commit that set this has the figures).
pub mod fit {
    #[cfg(target_feature = "avx512f")]
    pub use super::{F32x16, F64x8};
    pub use super::{F32x4, F64x2};
    #[cfg(target_feature = "avx")]
    pub use super::{F32x8, F64x4};

    /// [`super::F64x4`] where the target has 256-bit registers (AVX), else [`super::F64x2`].
    #[cfg(not(target_feature = "avx"))]
    pub type F64x4 = super::F64x2;
    /// [`super::F32x8`] where the target has 256-bit registers (AVX), else [`super::F32x4`].
    #[cfg(not(target_feature = "avx"))]
    pub type F32x8 = super::F32x4;
    /// [`super::F64x8`] where the target has 512-bit registers (AVX-512), else [`F64x4`].
    #[cfg(not(target_feature = "avx512f"))]
    pub type F64x8 = F64x4;
    /// [`super::F32x16`] where the target has 512-bit registers (AVX-512), else [`F32x8`].
    #[cfg(not(target_feature = "avx512f"))]
    pub type F32x16 = F32x8;
}

/// A value the lane code reads: lanes, or a constant of their element, the same in every lane.
pub trait Operand<L: Simd>: Copy {
    /// As lanes.
    fn lanes(self) -> L;
}

impl<L: Simd> Operand<L> for L {
    #[inline(always)]
    fn lanes(self) -> L {
        self
    }
}

/// `a·b + c` lane by lane ([`Simd::mul_add`]): what generated lane code computes its sums of
/// products with. Any operand may be a constant.
#[inline(always)]
pub fn mul_add<L: Simd>(a: impl Operand<L>, b: impl Operand<L>, c: impl Operand<L>) -> L {
    L::mul_add(a.lanes(), b.lanes(), c.lanes())
}

/// The sines and cosines of `K` angles in lanes, as the scalar code's
/// [`crate::math::sincos_array`] computes each (the same values, bit for bit, in `f64`).
#[inline(always)]
pub fn sincos_array<L: Simd, const K: usize>(x: [L; K]) -> ([L; K], [L; K]) {
    let mut sin = [L::ZERO; K];
    let mut cos = [L::ZERO; K];
    for ((x, s), c) in x.iter().zip(&mut sin).zip(&mut cos) {
        (*s, *c) = x.sincos();
    }
    (sin, cos)
}

/// `(sin x, cos x)` lane by lane.
#[inline(always)]
pub fn sincos<L: Simd>(x: L) -> (L, L) {
    x.sincos()
}

/// `sin x` lane by lane.
#[inline(always)]
pub fn sin<L: Simd>(x: L) -> L {
    x.sincos().0
}

/// `cos x` lane by lane.
#[inline(always)]
pub fn cos<L: Simd>(x: L) -> L {
    x.sincos().1
}

/// `√x` lane by lane.
#[inline(always)]
pub fn sqrt<L: Simd>(x: L) -> L {
    x.sqrt()
}

/// One truth value per lane, lane `i` in bit `i`: the outcome of a check (a pivot, a finite
/// value) state by state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mask(pub u32);

impl BitAnd for Mask {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        Mask(self.0 & o.0)
    }
}

impl Mask {
    /// No lane: a check that fails for every state.
    pub const NONE: Mask = Mask(0);
}

/// `pivot > tol·scale` lane by lane, false for NaN: the scalar code's pivot check
/// (`__private::positive_pivot`) state by state.
#[inline(always)]
pub fn positive_pivot<L: Simd>(
    pivot: impl Operand<L>,
    scale: impl Operand<L>,
    tol: L::Element,
) -> Mask {
    L::gt(pivot.lanes(), L::splat(tol) * scale.lanes())
}

/// `x > 0` lane by lane, false for NaN.
#[inline(always)]
pub fn positive<L: Simd>(x: impl Operand<L>) -> Mask {
    L::gt(x.lanes(), L::ZERO)
}

/// Neither infinite nor NaN, lane by lane.
#[inline(always)]
pub fn is_finite<L: Simd>(x: impl Operand<L>) -> Mask {
    x.lanes().finite()
}

/// Records `SingularMassMatrix { velocity }` for each lane where `ok` is false and no earlier
/// check failed: the first failure per state, as the scalar code returns it.
#[inline(always)]
pub fn refuse<const N: usize>(
    status: &mut [Option<SingularMassMatrix>; N],
    ok: Mask,
    velocity: usize,
) {
    let all = (1u32 << N) - 1;
    if ok.0 & all == all {
        return;
    }
    for (i, s) in status.iter_mut().enumerate() {
        if ok.0 >> i & 1 == 0 && s.is_none() {
            *s = Some(SingularMassMatrix { velocity });
        }
    }
}

/// Up to `LANES` states' vectors (at least one) as one vector of lanes ([`Simd::gather`]).
#[inline(always)]
pub fn gather<L: Simd, const K: usize>(states: &[SVector<L::Element, K>]) -> SVector<L, K> {
    L::gather(states)
}

/// [`Simd::gather`] of a group of fewer than `LANES` states (the last of a batch): entry by
/// entry, the missing lanes repeating the first state.
#[cold]
fn gather_padded<L: Simd, const K: usize>(states: &[SVector<L::Element, K>]) -> SVector<L, K> {
    let first = states.first();
    SVector::from_fn(|k, _| {
        L::from_fn(|l| states.get(l).or(first).map_or(L::Element::ZERO, |s| s[k]))
    })
}

/// The most lanes of any lane type ([`F32x16`]).
const MAX_LANES: usize = 16;

/// A result in lanes that splits into one result per state.
pub trait Split {
    /// One state's result.
    type State: 'static;
    /// A state's result of zeros, to be written over.
    fn zero() -> Self::State;
    /// Lane `l`'s result into `place(&mut out[l])` for each `l` where it is `Some` (the lanes
    /// past `out`'s length, padding, are dropped).
    fn scatter_with<O>(
        &self,
        out: &mut [O],
        place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut Self::State>,
    );
    /// Each state's result into `out`, in order.
    #[inline(always)]
    fn scatter(&self, out: &mut [Self::State]) {
        self.scatter_with(out, |o| Some(o));
    }
}

impl<L: Simd, const R: usize, const C: usize> Split for SMatrix<L, R, C> {
    type State = SMatrix<L::Element, R, C>;
    #[inline(always)]
    fn zero() -> Self::State {
        SMatrix::from_element(L::Element::ZERO)
    }
    #[inline(always)]
    fn scatter_with<O>(
        &self,
        out: &mut [O],
        place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut Self::State>,
    ) {
        let mut it = out.iter_mut().map(|o| place(o).map(|m| m.as_mut_slice()));
        let mut slots: [Option<&mut [L::Element]>; MAX_LANES] =
            core::array::from_fn(|_| it.next().flatten());
        L::scatter_entries(self.as_slice(), &mut slots);
    }
}

impl<L: Simd> Split for FramePlacement<L> {
    type State = FramePlacement<L::Element>;
    #[inline(always)]
    fn zero() -> Self::State {
        FramePlacement {
            rotation: SMatrix::<L, 3, 3>::zero(),
            translation: SMatrix::<L, 3, 1>::zero(),
        }
    }
    #[inline(always)]
    fn scatter_with<O>(
        &self,
        out: &mut [O],
        place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut Self::State>,
    ) {
        self.rotation
            .scatter_with(out, |o| place(o).map(|p| &mut p.rotation));
        self.translation
            .scatter_with(out, |o| place(o).map(|p| &mut p.translation));
    }
}

impl<S: Split, const K: usize> Split for [S; K] {
    type State = [S::State; K];
    #[inline(always)]
    fn zero() -> Self::State {
        core::array::from_fn(|_| S::zero())
    }
    #[inline(always)]
    fn scatter_with<O>(
        &self,
        out: &mut [O],
        place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut Self::State>,
    ) {
        for (k, s) in self.iter().enumerate() {
            s.scatter_with(out, |o| place(o).and_then(|a| a.get_mut(k)));
        }
    }
}

/// [`Split`] for the tuples results are made of: part by part.
macro_rules! tuples {
    ($(($($part:ident $index:tt),+)),+) => {$(
        impl<$($part: Split),+> Split for ($($part,)+) {
            type State = ($($part::State,)+);
            #[inline(always)]
            fn zero() -> Self::State {
                ($($part::zero(),)+)
            }
            #[inline(always)]
            fn scatter_with<O>(
                &self,
                out: &mut [O],
                place: impl for<'a> Fn(&'a mut O) -> Option<&'a mut Self::State>,
            ) {
                $(self.$index.scatter_with(out, |o| place(o).map(|t| &mut t.$index));)+
            }
        }
    )+};
}
tuples!((A 0, B 1), (A 0, B 1, C 2));

/// The results of a fallible output in lanes (forward dynamics): the values, and per lane the
/// first check that failed, into one `Result` per state.
#[inline(always)]
pub fn scatter_results<S: Split, const N: usize>(
    values: &S,
    status: &[Option<SingularMassMatrix>; N],
    out: &mut [Result<S::State, SingularMassMatrix>],
) {
    for (o, s) in out.iter_mut().zip(status) {
        *o = match s {
            Some(e) => Err(*e),
            None => Ok(S::zero()),
        };
    }
    values.scatter_with(out, |o| o.as_mut().ok());
}

/// A batch call whose arguments are not as long as its `out` slice: which argument, and the
/// lengths. Nothing was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchLengths {
    /// The argument's name in the signature (`q`, `v`, `a`, `tau`, `base`).
    pub argument: &'static str,
    /// `out`'s length: one result per state.
    pub expected: usize,
    /// The argument's length.
    pub found: usize,
}

impl core::fmt::Display for BatchLengths {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.argument == "p" {
            return write!(
                f,
                "batch argument `p` holds {} parameter sets, but `out` has room for {} states: \
                 give one set for all of them or one for each",
                self.found, self.expected
            );
        }
        write!(
            f,
            "batch argument `{}` holds {} states, but `out` has room for {}: they must be equal",
            self.argument, self.found, self.expected
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for BatchLengths {}

/// `Ok` where every argument is `out`'s length (`expected`), else the first that is not.
///
/// # Errors
/// [`BatchLengths`] for the first argument of another length.
#[inline]
pub fn check_lengths(expected: usize, args: &[(&'static str, usize)]) -> Result<(), BatchLengths> {
    match args.iter().find(|(_, n)| *n != expected) {
        Some(&(argument, found)) => Err(BatchLengths {
            argument,
            expected,
            found,
        }),
        None => Ok(()),
    }
}

/// [`check_lengths`], and `params` (the number of parameter sets) either 1 (one set for every
/// state) or `expected` (one per state).
///
/// # Errors
/// [`BatchLengths`] for the first argument of another length, then for `p`.
#[inline]
pub fn check_batch(
    expected: usize,
    args: &[(&'static str, usize)],
    params: usize,
) -> Result<(), BatchLengths> {
    check_lengths(expected, args)?;
    if params == 1 || params == expected {
        Ok(())
    } else {
        Err(BatchLengths {
            argument: "p",
            expected,
            found: params,
        })
    }
}

/// State `i`'s parameters: `p[i]`, or `p[0]` where `p` holds one set for all.
#[inline(always)]
pub fn params_of<P>(p: &[P], i: usize) -> &P {
    if p.len() == 1 {
        &p[0]
    } else {
        &p[i]
    }
}

/// The parameters of the `len` states from `start` of a batch of `n` ([`check_batch`]'s
/// lengths): `p` itself where it holds one set for all.
#[inline]
pub fn params_chunk<P>(p: &[P], n: usize, start: usize, len: usize) -> &[P] {
    if p.len() == 1 && n != 1 {
        p
    } else {
        &p[start..start + len]
    }
}

/// The runtime parameters of up to `L::LANES` states in lanes: entry `k` of lane `l` is
/// `fields(&params[l])[k]`, the last set repeated in the lanes past its end (whose results are
/// dropped). One set gives the same parameters in every lane.
#[inline(always)]
pub fn gather_params<L: Simd, P, const K: usize>(
    params: &[P],
    fields: impl Fn(&P) -> [L::Element; K],
) -> [L; K] {
    let last = params.len() - 1;
    core::array::from_fn(|k| L::from_fn(|l| fields(&params[l.min(last)])[k]))
}

/// The fewest states one thread takes at a time in the `_par_batch` functions
/// (`par_chunk`, with the `rayon` feature): a multiple of every lane count.
pub const PAR_CHUNK: usize = 64;

/// The states one thread takes at a time in a `_par_batch` function over `n` states: about four
/// groups per thread of the current rayon pool, a multiple of 16 (every lane count), at least
/// [`PAR_CHUNK`].
///
/// Why not a fixed size: 64 states of the arm's inverse dynamics in lanes take about as long as
/// handing a group to a thread, so on 16 threads fixed groups of 64 spent most of the time
/// handing them out (`docs/throughput.md` has the scaling since). A state's result does not depend on its group (each
/// lane is computed on its own), so neither do the results on the number of threads.
#[cfg(feature = "rayon")]
pub fn par_chunk(n: usize) -> usize {
    let groups = 4 * rayon::current_num_threads();
    n.div_ceil(groups.max(1))
        .next_multiple_of(16)
        .max(PAR_CHUNK)
}
