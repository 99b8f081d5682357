//! `articulated::math::sincos`, `sincosf` and `sincosf_array`, and the `f32` lanes' sines, against `libm`, against std's `sin_cos` (glibc)
//! and against an independent reference: exact reduction by a 256-bit π/2 in integer
//! arithmetic, then Taylor series in double-double.
//!
//! `cargo test -p articulated --test math -- --nocapture` prints, per range, the largest
//! difference in ulps and the fraction of arguments where the result is bit-identical to libm.

use std::f64::consts::FRAC_PI_2;

use articulated::lanes::{F32x8, Simd};
use articulated::math::{sincos, sincos_array, sincosf, sincosf_array, SINCOS_FAST_LIMIT};
use articulated_dynamics::random::Rng;

/// Distance in ulps between two `f64`: the difference of their bit patterns mapped to a
/// monotonic integer line (±0 are the same point). Two NaN are 0 apart, NaN and a number
/// `u64::MAX`.
fn ulps(a: f64, b: f64) -> u64 {
    ulp_distance(a.to_bits(), b.to_bits(), 1 << 63, a.is_nan(), b.is_nan())
}

/// [`ulps`] for `f32`.
fn ulps32(a: f32, b: f32) -> u64 {
    let bits = |x: f32| u64::from(x.to_bits());
    ulp_distance(bits(a), bits(b), 1 << 31, a.is_nan(), b.is_nan())
}

/// The distance of two floats' bit patterns (`sign`: the sign bit) on the monotonic line.
fn ulp_distance(a: u64, b: u64, sign: u64, a_nan: bool, b_nan: bool) -> u64 {
    if a_nan || b_nan {
        return if a_nan && b_nan { 0 } else { u64::MAX };
    }
    let key = |bits: u64| {
        let mag = i128::from(bits & !sign);
        if bits & sign != 0 {
            -mag
        } else {
            mag
        }
    };
    (key(a) - key(b)).unsigned_abs() as u64
}

fn same_bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Per-range comparison of `sincos` with libm and std.
struct Stats {
    name: &'static str,
    points: u64,
    identical: u64,
    max_libm: u64,
    max_std: u64,
}

impl Stats {
    fn new(name: &'static str) -> Self {
        Stats {
            name,
            points: 0,
            identical: 0,
            max_libm: 0,
            max_std: 0,
        }
    }

    /// Checks `sincos(x)` against `libm::sincos(x)` and `x.sin_cos()`: at most 1 ulp apart.
    fn check(&mut self, x: f64) {
        let (s, c) = sincos(x);
        let (ls, lc) = libm::sincos(x);
        let (gs, gc) = x.sin_cos();
        let d_libm = ulps(s, ls).max(ulps(c, lc));
        let d_std = ulps(s, gs).max(ulps(c, gc));
        assert!(
            d_libm <= 1,
            "{}: sincos({x:e} = {:#x}) = ({s:e}, {c:e}), libm ({ls:e}, {lc:e}): {d_libm} ulp",
            self.name,
            x.to_bits()
        );
        assert!(
            d_std <= 1,
            "{}: sincos({x:e} = {:#x}) = ({s:e}, {c:e}), std ({gs:e}, {gc:e}): {d_std} ulp",
            self.name,
            x.to_bits()
        );
        self.points += 1;
        self.identical += u64::from(same_bits(s, ls) && same_bits(c, lc));
        self.max_libm = self.max_libm.max(d_libm);
        self.max_std = self.max_std.max(d_std);
    }

    /// Prints the figures; fails if fewer than `min_identical` of the points are bit-identical
    /// to libm (the same kernels: a sloppy reduction shows up here before it reaches 2 ulps).
    fn report(&self, min_identical: f64) {
        assert!(self.points > 0);
        let identical = self.identical as f64 / self.points as f64;
        assert!(
            identical >= min_identical,
            "{}: only {identical} identical to libm",
            self.name
        );
        println!(
            "sincos  {:<28} {:>8} points: max {} ulp vs libm, {} ulp vs std; {:.4} % identical to libm",
            self.name,
            self.points,
            self.max_libm,
            self.max_std,
            100.0 * identical
        );
    }
}

/// A random finite `f64` with a biased exponent in `exp_lo..=exp_hi` and a random sign.
fn random_with_exponent(rng: &mut Rng, exp_lo: u64, exp_hi: u64) -> f64 {
    let bits = rng.next_u64();
    let exp = exp_lo + bits % (exp_hi - exp_lo + 1);
    f64::from_bits((bits & (1 << 63)) | (exp << 52) | (rng.next_u64() >> 12))
}

const RANDOM_POINTS: usize = 200_000;

#[test]
fn random_points_agree_with_libm_and_std() {
    let mut rng = Rng::new(0x5EED_0001);
    for (name, r) in [
        ("|x| < 1", 1.0),
        ("|x| < 10", 10.0),
        ("|x| < 1e3", 1e3),
        ("|x| < 1e5", 1e5),
        ("|x| < LIMIT", SINCOS_FAST_LIMIT),
    ] {
        let mut stats = Stats::new(name);
        for _ in 0..RANDOM_POINTS {
            stats.check(rng.symmetric(r));
        }
        stats.report(0.95);
    }

    // Beyond the limit (the libm fallback): every exponent from the limit's to the largest.
    let limit_exp = SINCOS_FAST_LIMIT.to_bits() >> 52;
    let mut stats = Stats::new("LIMIT <= |x| < inf");
    for _ in 0..RANDOM_POINTS / 4 {
        let x = random_with_exponent(&mut rng, limit_exp, 0x7FE);
        if x.abs() >= SINCOS_FAST_LIMIT {
            stats.check(x);
        }
    }
    stats.report(1.0);

    // Tiny arguments down to the subnormals.
    let mut stats = Stats::new("|x| < 2^-20 incl. subnormal");
    for _ in 0..RANDOM_POINTS / 4 {
        stats.check(random_with_exponent(&mut rng, 0, 0x3FF - 21));
    }
    stats.report(1.0);

    // Any bit pattern (mostly huge or tiny numbers, a few infinities and NaN).
    let mut stats = Stats::new("random bit patterns");
    for _ in 0..RANDOM_POINTS / 4 {
        stats.check(f64::from_bits(rng.next_u64()));
    }
    stats.report(0.995);
}

/// Steps `x` by `k` ulps (`k` may be negative); stays finite for the arguments used here.
fn ulp_step(x: f64, k: i64) -> f64 {
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

/// The double nearest to `k·π/2` (for `|k| ≤ 2^21`): `FRAC_PI_2` plus its 53-bit tail.
fn nearest_k_pio2(k: f64) -> f64 {
    const PIO2_TAIL: f64 = 6.123_233_995_736_766e-17; // π/2 − FRAC_PI_2
    k.mul_add(FRAC_PI_2, k * PIO2_TAIL)
}

#[test]
fn near_multiples_of_pi_over_2_agree_with_libm_and_std() {
    // `k as f64 * FRAC_PI_2` exactly, and a few ulps either side, for every |k| ≤ 1e5.
    let mut stats = Stats::new("k*FRAC_PI_2 +-3ulp, k<=1e5");
    for k in -100_000i64..=100_000 {
        let x = k as f64 * FRAC_PI_2;
        for d in -3..=3 {
            stats.check(ulp_step(x, d));
        }
    }
    stats.report(0.995);

    // The double nearest to k·π/2 (the hardest cancellation), ± 2 ulps, for every k up to
    // 2^20 (the fast range ends near k = 2^15; beyond, this checks the switch to libm).
    let mut stats = Stats::new("nearest k*pi/2 +-2ulp, k<=2^20");
    for k in 1i64..=1 << 20 {
        let x = nearest_k_pio2(k as f64);
        for d in -2..=2 {
            let y = ulp_step(x, d);
            stats.check(y);
            stats.check(-y);
        }
    }
    stats.report(0.995);

    // Around the limit itself, both sides.
    let mut stats = Stats::new("around LIMIT");
    for d in -1000..=1000 {
        stats.check(ulp_step(SINCOS_FAST_LIMIT, d));
        stats.check(-ulp_step(SINCOS_FAST_LIMIT, d));
    }
    stats.report(0.995);
}

#[test]
fn special_values() {
    // The sign of zero.
    let (s, c) = sincos(0.0);
    assert_eq!((s.to_bits(), c), (0.0f64.to_bits(), 1.0));
    let (s, c) = sincos(-0.0);
    assert_eq!((s.to_bits(), c), ((-0.0f64).to_bits(), 1.0));
    let (s, c) = sincosf(-0.0);
    assert_eq!((s.to_bits(), c), ((-0.0f32).to_bits(), 1.0));

    // Subnormals and the smallest normals: sin x = x, cos x = 1, exactly.
    for x in [
        f64::from_bits(1),
        f64::from_bits(0x000F_FFFF_FFFF_FFFF),
        f64::MIN_POSITIVE,
        1e-300,
        1e-20,
    ] {
        for x in [x, -x] {
            assert_eq!(sincos(x), (x, 1.0), "sincos({x:e})");
        }
    }

    // NaN for NaN and the infinities.
    for x in [
        f64::NAN,
        -f64::NAN,
        f64::from_bits(0x7FF0_0000_0000_0001),
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        let (s, c) = sincos(x);
        assert!(s.is_nan() && c.is_nan(), "sincos({x}) = ({s}, {c})");
        let (s, c) = sincosf(x as f32);
        assert!(s.is_nan() && c.is_nan(), "sincosf({x}) = ({s}, {c})");
    }

    let mut stats = Stats::new("special values");
    for x in [
        0.0,
        f64::MIN_POSITIVE,
        f64::from_bits(1),
        f64::EPSILON,
        f64::MAX,
        f64::MIN,
        1.0,
        FRAC_PI_2,
        std::f64::consts::FRAC_PI_4,
        std::f64::consts::PI,
        std::f64::consts::TAU,
        1e22,
        f64::INFINITY,
        f64::NAN,
    ] {
        for x in [x, -x, x.next_up(), x.next_down()] {
            stats.check(x);
        }
    }
    stats.report(0.95);
}

#[test]
fn sin_squared_plus_cos_squared_is_one() {
    // s² + c² − 1 is evaluated exactly enough (double-double), so only the errors δ of s and c
    // show: |2s·δs + 2c·δc| ≤ 2·0.73·2^-53·(|s| + |c|) ≤ 2.3e-16 for |δ| ≤ 0.73 ulp (the
    // kernels' worst case, libm's too), so the bound is 2.5e-16, not 2e-16: libm exceeds
    // 2e-16 on these points as well.
    let defect = |(s, c): (f64, f64)| {
        let (s, c) = (Dd::from(s), Dd::from(c));
        let e = s.mul(s).add(c.mul(c)).add(Dd::from(-1.0));
        (e.hi + e.lo).abs()
    };
    let mut rng = Rng::new(0x5EED_0002);
    let (mut worst, mut worst_libm) = (0.0f64, 0.0f64);
    for _ in 0..100_000 {
        let x = rng.symmetric(1e3);
        worst = worst.max(defect(sincos(x)));
        worst_libm = worst_libm.max(defect(libm::sincos(x)));
    }
    println!("sincos  max |sin^2 + cos^2 - 1| = {worst:e} (libm {worst_libm:e})");
    assert!(worst <= 2.5e-16, "{worst:e}");
}

// --- sincosf -------------------------------------------------------------------------------

struct Stats32 {
    name: &'static str,
    points: u64,
    identical: u64,
    max_libm: u64,
    /// Arguments where the result differs from glibc's `f64` result rounded to `f32` (which is
    /// itself correctly rounded except in rare double-rounding cases).
    not_glibc_rounded: u64,
}

impl Stats32 {
    fn new(name: &'static str) -> Self {
        Stats32 {
            name,
            points: 0,
            identical: 0,
            max_libm: 0,
            not_glibc_rounded: 0,
        }
    }

    fn check(&mut self, x: f32) {
        self.check_result(x, sincosf(x));
    }

    /// `(s, c)`, computed for `x`, within an ulp of libm's and of glibc's `f64` rounded.
    fn check_result(&mut self, x: f32, (s, c): (f32, f32)) {
        let (ls, lc) = libm::sincosf(x);
        let (gs, gc) = f64::from(x).sin_cos();
        let d = ulps32(s, ls).max(ulps32(c, lc));
        assert!(
            d <= 1,
            "{}: sincosf({x:e} = {:#x}) = ({s:e}, {c:e}), libm ({ls:e}, {lc:e}): {d} ulp",
            self.name,
            x.to_bits()
        );
        let d_glibc = ulps32(s, gs as f32).max(ulps32(c, gc as f32));
        assert!(d_glibc <= 1, "{}: sincosf({x:e}) vs glibc", self.name);
        self.points += 1;
        self.identical += u64::from(ulps32(s, ls) == 0 && ulps32(c, lc) == 0);
        self.not_glibc_rounded += u64::from(d_glibc != 0);
        self.max_libm = self.max_libm.max(d);
    }

    fn report(&self) {
        println!(
            "sincosf {:<28} {:>8} points: max {} ulp vs libm; {:.4} % identical to libm; \
             {} differ from glibc's f64 rounded to f32",
            self.name,
            self.points,
            self.max_libm,
            100.0 * self.identical as f64 / self.points as f64,
            self.not_glibc_rounded
        );
    }
}

#[test]
fn sincosf_agrees_with_libm() {
    let mut rng = Rng::new(0x5EED_0003);
    for (name, r) in [
        ("|x| < 1", 1.0),
        ("|x| < 10", 10.0),
        ("|x| < 1e3", 1e3),
        ("|x| < 1e5", 1e5),
        ("|x| < LIMIT", SINCOS_FAST_LIMIT),
        ("|x| < 1e30", 1e30),
    ] {
        let mut stats = Stats32::new(name);
        for _ in 0..RANDOM_POINTS {
            stats.check(rng.symmetric(r) as f32);
        }
        stats.report();
    }
    let mut stats = Stats32::new("random bit patterns");
    for _ in 0..RANDOM_POINTS {
        stats.check(f32::from_bits(rng.next_u64() as u32));
    }
    stats.report();
    let mut stats = Stats32::new("near k*pi/2 +-4ulp, k<=1e4");
    for k in -10_000i32..=10_000 {
        let x = (f64::from(k) * FRAC_PI_2) as f32;
        let mut y = x;
        for _ in 0..4 {
            y = y.next_down();
        }
        for _ in 0..9 {
            stats.check(y);
            y = y.next_up();
        }
    }
    stats.report();
    let mut stats = Stats32::new("specials");
    for x in [
        0.0,
        -0.0,
        f32::from_bits(1),
        f32::MIN_POSITIVE,
        f32::MAX,
        f32::MIN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ] {
        stats.check(x);
    }
    stats.report();
}

/// The `f32` lanes' sines and cosines ([`F32x8`], the scalar of `f32` batch code) against
/// `libm::sincosf`, the scalar `f32` code's: within an ulp everywhere (as [`sincosf`]), and
/// identical but for a rare argument (the reduction subtracts π/2 in two parts where libm
/// rounds a multiple of it first, see `lanes::sincosf_x4`). Eight arguments per call, the ranges
/// of [`sincosf_agrees_with_libm`], a group that mixes the fallback's arguments with ordinary
/// ones, and the sign of zero.
#[test]
fn f32_lanes_agree_with_libm() {
    let lanes = |x: [f32; 8]| {
        let (s, c) = F32x8::from_fn(|l| x[l]).sincos();
        std::array::from_fn::<_, 8, _>(|l| (s.lane(l), c.lane(l)))
    };
    let mut rng = Rng::new(0x5EED_0006);
    let mut check = |name, x: &mut dyn FnMut(&mut Rng) -> f32| {
        let mut stats = Stats32::new(name);
        for _ in 0..RANDOM_POINTS / 8 {
            let group: [f32; 8] = std::array::from_fn(|_| x(&mut rng));
            for (x, r) in group.into_iter().zip(lanes(group)) {
                stats.check_result(x, r);
            }
        }
        stats.report();
        assert!(
            stats.identical * 1000 >= stats.points * 999,
            "{name}: {} of {} identical to libm",
            stats.identical,
            stats.points
        );
    };
    for (name, r) in [
        ("lanes |x| < 1", 1.0),
        ("lanes |x| < 10", 10.0),
        ("lanes |x| < 1e4", 1e4),
        ("lanes |x| < 4e8 (reduced)", 4e8),
        ("lanes |x| < 1e30 (libm)", 1e30),
    ] {
        check(name, &mut |rng| rng.symmetric(r) as f32);
    }
    check("lanes, random bit patterns", &mut |rng| {
        f32::from_bits(rng.next_u64() as u32)
    });
    let mut k = -10_000i32;
    check("lanes, near k*pi/2 +-1ulp", &mut |rng| {
        k += 1;
        let x = (f64::from(k) * FRAC_PI_2) as f32;
        [x.next_down(), x, x.next_up()][(rng.next_u64() % 3) as usize]
    });
    // A lane beyond the reduction among ordinary ones, infinities, NaN and both zeros: each lane
    // its own value.
    let x = [
        0.5,
        1e9,
        -0.0,
        0.0,
        f32::INFINITY,
        3.0,
        f32::NAN,
        f32::from_bits(1),
    ];
    for (l, (x, (s, c))) in x.into_iter().zip(lanes(x)).enumerate() {
        let (ls, lc) = libm::sincosf(x);
        assert!(
            s.to_bits() == ls.to_bits() && c.to_bits() == lc.to_bits()
                || s.is_nan() && ls.is_nan() && c.is_nan() && lc.is_nan(),
            "lane {l}: sincos({x:e}) = ({s:e}, {c:e}), libm ({ls:e}, {lc:e})"
        );
    }
    let r = lanes([-0.0, 1.0, -0.0, 0.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(
        (r[0].0.to_bits(), r[2].0.to_bits()),
        ((-0.0f32).to_bits(), (-0.0f32).to_bits())
    );
}

/// [`sincosf_array`], the scalar `f32` code's sines, gives each angle what the `f32` lanes give
/// it, bit for bit, whatever its neighbours (so that a state's values in an `f32` batch are the
/// scalar function's), and within an ulp of libm: groups of six (a partial last group of four,
/// or three pairs), with an angle beyond the reduction (which `libm` takes) beside ordinary
/// ones, infinities, NaN and both zeros, then random angles of every range of
/// [`sincosf_agrees_with_libm`]. [`sincosf`] in its place (`f64`'s sines rounded) fails it.
#[test]
fn f32_scalar_sines_are_the_lanes_bit_for_bit() {
    let lanes = |x: f32| {
        let (s, c) = F32x8::splat(x).sincos();
        (s.lane(0), c.lane(0))
    };
    let mut stats = Stats32::new("sincosf_array");
    let mut check = |x: [f32; 6]| {
        let (s, c) = sincosf_array(x);
        for (i, &x) in x.iter().enumerate() {
            let (ls, lc) = lanes(x);
            assert!(
                ulps32(s[i], ls) == 0 && ulps32(c[i], lc) == 0,
                "angle {i}, {x:e}: ({:e}, {:e}), the lanes ({ls:e}, {lc:e})",
                s[i],
                c[i]
            );
            stats.check_result(x, (s[i], c[i]));
        }
    };
    check([0.5, 1e9, -0.0, f32::NAN, 0.0, f32::INFINITY]);
    check([1.0, 2.0, 3.0, 4.0, 5.0, -1e30]);
    let mut rng = Rng::new(0x5EED_0007);
    for r in [1.0, 10.0, 1e4, 4e8] {
        for _ in 0..RANDOM_POINTS / 6 {
            check(std::array::from_fn(|_| rng.symmetric(r) as f32));
        }
    }
    stats.report();
}

// --- the double-double reference -----------------------------------------------------------

/// An unevaluated sum `hi + lo`, `|lo| ≤ ulp(hi)/2` (about 106 bits).
#[derive(Clone, Copy, Debug)]
struct Dd {
    hi: f64,
    lo: f64,
}

fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    Dd {
        hi: s,
        lo: (a - (s - bb)) + (b - bb),
    }
}

fn fast_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

impl Dd {
    fn from(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    fn add(self, b: Dd) -> Dd {
        let s = two_sum(self.hi, b.hi);
        let t = two_sum(self.lo, b.lo);
        let u = fast_two_sum(s.hi, s.lo + t.hi);
        fast_two_sum(u.hi, u.lo + t.lo)
    }

    fn mul(self, b: Dd) -> Dd {
        let p = self.hi * b.hi;
        let e = self.hi.mul_add(b.hi, -p);
        fast_two_sum(p, e + (self.hi * b.lo + self.lo * b.hi))
    }

    fn div(self, d: f64) -> Dd {
        let q1 = self.hi / d;
        let p = q1 * d;
        let e = q1.mul_add(d, -p);
        let r = two_sum(self.hi, -p);
        let q2 = (r.hi + ((r.lo - e) + self.lo)) / d;
        fast_two_sum(q1, q2)
    }
}

/// `floor(π/2 · 2^256)`, little-endian 64-bit limbs (computed with Machin's formula in
/// integer arithmetic; its top 53 bits are `FRAC_PI_2`'s, checked below).
const PIO2_2P256: [u64; 5] = [
    0x0417_7d4c_7627_3644,
    0x5204_9c11_14cf_98e8,
    0x898c_c517_01b8_39a2,
    0x921f_b544_42d1_8469,
    0x1,
];

/// A 384-bit two's-complement integer, little-endian limbs.
type Big = [u64; 6];

fn big_sub(a: &Big, b: &Big) -> Big {
    let mut out = [0; 6];
    let mut borrow = false;
    for i in 0..6 {
        let (d, b1) = a[i].overflowing_sub(b[i]);
        let (d, b2) = d.overflowing_sub(u64::from(borrow));
        out[i] = d;
        borrow = b1 || b2;
    }
    out
}

fn big_neg(a: &Big) -> Big {
    big_sub(&[0; 6], a)
}

/// `m · 2^shift`.
fn big_shl(m: u64, shift: u32) -> Big {
    let mut out = [0; 6];
    let (limb, bit) = ((shift / 64) as usize, shift % 64);
    let wide = u128::from(m) << bit;
    out[limb] = wide as u64;
    if limb + 1 < 6 {
        out[limb + 1] = (wide >> 64) as u64;
    }
    out
}

/// `n · π/2 · 2^256`, truncated (n < 2^64).
fn big_n_pio2(n: u64) -> Big {
    let mut out = [0; 6];
    let mut carry = 0u128;
    for i in 0..6 {
        let limb = if i < 5 { PIO2_2P256[i] } else { 0 };
        let t = u128::from(limb) * u128::from(n) + carry;
        out[i] = t as u64;
        carry = t >> 64;
    }
    out
}

/// A non-negative `Big` times `2^-256` as a double-double (106 bits, truncated).
fn big_to_dd(a: &Big) -> Dd {
    let Some(top) = (0..6).rev().find(|&i| a[i] != 0) else {
        return Dd::from(0.0);
    };
    let h = top as i32 * 64 + 63 - a[top].leading_zeros() as i32; // highest set bit
                                                                  // Bits from..from + 53 (those below bit 0 are zero).
    let bits53 = |from: i32| -> u64 {
        let limb = |i: i32| if i < 0 { 0 } else { u128::from(a[i as usize]) };
        let (l, sh) = (from.div_euclid(64), from.rem_euclid(64));
        let window = limb(l) | limb(l + 1) << 64;
        (window >> sh) as u64 & ((1 << 53) - 1)
    };
    let hi = bits53(h - 52) as f64 * 2f64.powi(h - 52 - 256);
    let lo = bits53(h - 105) as f64 * 2f64.powi(h - 105 - 256);
    fast_two_sum(hi, lo)
}

/// `n = round(|x|·2/π)` and `|x| − n·π/2`, exact to 2^-256 before its rounding to 106 bits,
/// for `|x| ≤ 2^21`.
fn reduce_exactly(x: f64) -> (u64, Dd) {
    let ax = x.abs();
    let n = (ax * std::f64::consts::FRAC_2_PI).round();
    assert!(n < (1u64 << 22) as f64);
    if n == 0.0 {
        return (0, Dd::from(ax));
    }
    // ax = m · 2^e exactly, e ≥ -53 here.
    let bits = ax.to_bits();
    let e = (bits >> 52) as i32 - 1075;
    let m = (bits & ((1 << 52) - 1)) | (1 << 52);
    let d = big_sub(&big_shl(m, (e + 256) as u32), &big_n_pio2(n as u64));
    let y = if d[5] >> 63 == 1 {
        big_to_dd(&big_neg(&d)).neg()
    } else {
        big_to_dd(&d)
    };
    (n as u64, y)
}

/// `(sin x, cos x)` in double-double for `|x| ≤ 2^21`: [`reduce_exactly`], then Taylor series.
fn reference_sincos(x: f64) -> (Dd, Dd) {
    let (n, y) = reduce_exactly(x);
    let y2 = y.mul(y);
    let (mut s, mut c) = (y, Dd::from(1.0));
    let (mut ts, mut tc) = (y, Dd::from(1.0));
    for i in 1..40 {
        let i = f64::from(i);
        ts = ts.mul(y2).div(-(2.0 * i) * (2.0 * i + 1.0));
        tc = tc.mul(y2).div(-(2.0 * i - 1.0) * (2.0 * i));
        s = s.add(ts);
        c = c.add(tc);
    }
    let (s, c) = match n & 3 {
        0 => (s, c),
        1 => (c, s.neg()),
        2 => (s.neg(), c.neg()),
        _ => (c.neg(), s),
    };
    (if x < 0.0 { s.neg() } else { s }, c)
}

/// `(v − r) / ulp(r)`, in ulps of the double nearest to `r`.
fn ulp_error(v: f64, r: Dd) -> f64 {
    let exp = (r.hi.abs().to_bits() >> 52) as i32;
    let ulp = 2f64.powi(exp.max(1) - 1075);
    ((v - r.hi) - r.lo).abs() / ulp
}

struct RefStats {
    name: &'static str,
    points: u64,
    worst: f64,
    worst_x: f64,
    worst_libm: f64,
    worst_int: u64,
}

impl RefStats {
    fn check(&mut self, x: f64) {
        let (rs, rc) = reference_sincos(x);
        let (s, c) = sincos(x);
        let (ls, lc) = libm::sincos(x);
        let e = ulp_error(s, rs).max(ulp_error(c, rc));
        let rounded = |r: Dd| r.hi + r.lo;
        let e_int = ulps(s, rounded(rs)).max(ulps(c, rounded(rc)));
        assert!(
            e < 1.0 && e_int <= 1,
            "{}: sincos({x:e} = {:#x}) = ({s:e}, {c:e}), reference ({:e}, {:e}): {e} ulp",
            self.name,
            x.to_bits(),
            rounded(rs),
            rounded(rc)
        );
        if e > self.worst {
            self.worst = e;
            self.worst_x = x;
        }
        self.worst_int = self.worst_int.max(e_int);
        self.worst_libm = self
            .worst_libm
            .max(ulp_error(ls, rs).max(ulp_error(lc, rc)));
        self.points += 1;
    }

    fn report(&self) {
        println!(
            "sincos  {:<28} {:>8} points: max {:.3} ulp ({} ulp from the rounded value) from the \
             double-double reference (at x = {:e}); libm {:.3} ulp",
            self.name, self.points, self.worst, self.worst_int, self.worst_x, self.worst_libm
        );
    }
}

#[test]
fn reference_constant_is_pi_over_2() {
    // Top 53 bits of the 257-bit integer: FRAC_PI_2's significand (its next bit is 0).
    let top = (PIO2_2P256[4] << 52) | (PIO2_2P256[3] >> 12);
    assert_eq!(top, FRAC_PI_2.to_bits() & ((1 << 52) - 1) | (1 << 52));
    // The reference itself at points with known values.
    let (s, c) = reference_sincos(std::f64::consts::FRAC_PI_6);
    assert!((s.hi - 0.5).abs() < 1e-16 && (c.hi - 0.75f64.sqrt()).abs() < 1e-16);
    let (s, c) = reference_sincos(std::f64::consts::PI);
    // sin(fl(π)) = π − fl(π) to first order.
    assert!((s.hi - 1.224_646_799_147_353_2e-16).abs() < 1e-31 && c.hi == -1.0);
}

#[test]
fn within_one_ulp_of_a_double_double_reference() {
    let mut rng = Rng::new(0x5EED_0004);
    let new = |name| RefStats {
        name,
        points: 0,
        worst: 0.0,
        worst_x: 0.0,
        worst_libm: 0.0,
        worst_int: 0,
    };
    for (name, r) in [
        ("|x| < 1", 1.0),
        ("|x| < 10", 10.0),
        ("|x| < 1e3", 1e3),
        ("|x| < 1e5", 1e5),
        ("|x| < LIMIT", SINCOS_FAST_LIMIT),
    ] {
        let mut stats = new(name);
        for _ in 0..20_000 {
            stats.check(rng.symmetric(r));
        }
        stats.report();
    }

    // The hardest arguments of the fast range, among the doubles nearest to k·π/2 and their
    // neighbours for every k below the limit (k ≤ 2^15): the 500 closest to their multiple of
    // π/2 (the most cancellation in the reduction, the smallest results), and the 500 with the
    // least |x − k·π/2| / k (the error of the reduction's last part grows with k: these have
    // the least margin).
    let k_max = (SINCOS_FAST_LIMIT / FRAC_PI_2) as u32 + 1;
    let mut closest: Vec<(f64, f64)> = Vec::new();
    let mut least_ratio: Vec<(f64, f64)> = Vec::new();
    for k in 1..=k_max {
        let x = nearest_k_pio2(f64::from(k));
        for x in [x.next_down(), x, x.next_up()] {
            if x < SINCOS_FAST_LIMIT {
                let (n, y) = reduce_exactly(x);
                closest.push((y.hi.abs(), x));
                least_ratio.push((y.hi.abs() / n as f64, x));
            }
        }
    }
    closest.sort_by(|a, b| a.0.total_cmp(&b.0));
    closest.truncate(500);
    least_ratio.sort_by(|a, b| a.0.total_cmp(&b.0));
    least_ratio.truncate(500);
    println!(
        "sincos  closest double below LIMIT to a multiple of pi/2: x = {:e}, |x - n*pi/2| = {:e} = 2^{:.1}",
        closest[0].1,
        closest[0].0,
        closest[0].0.log2()
    );
    println!(
        "sincos  least |x - n*pi/2| / n below LIMIT: x = {:e}, 2^{:.1}",
        least_ratio[0].1,
        least_ratio[0].0.log2()
    );
    for (name, set) in [
        ("500 closest to k*pi/2", &closest),
        ("500 least |x - k*pi/2| / k", &least_ratio),
    ] {
        let mut stats = new(name);
        for &(_, x) in set {
            stats.check(x);
            stats.check(-x);
        }
        stats.report();
    }

    let mut stats = new("nearest k*pi/2 +-2ulp");
    for i in 0..2_000 {
        let k = if i < 200 {
            f64::from(i + 1)
        } else {
            f64::from(rng.next_u64() as u32 % k_max + 1)
        };
        let x = nearest_k_pio2(k);
        for d in -2..=2 {
            let y = ulp_step(x, d);
            if y.abs() < SINCOS_FAST_LIMIT {
                stats.check(y);
            }
        }
    }
    stats.report();

    // The top of the fast range (the largest n, the largest parts of the reduction).
    let mut stats = new("2000 ulps below LIMIT");
    let mut x = SINCOS_FAST_LIMIT;
    for _ in 0..2_000 {
        x = x.next_down();
        stats.check(x);
        stats.check(-x);
    }
    stats.report();
}

// --- the array versions ------------------------------------------------------------------

/// `sincos_array::<N>` against `sincos` of each lane, bit for bit, on `rounds` random arrays
/// whose lanes mix ordinary angles with the fallback's cases.
fn check_array<const N: usize>(rng: &mut Rng, rounds: usize) {
    let specials = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        SINCOS_FAST_LIMIT,
        -SINCOS_FAST_LIMIT.next_down(),
        1e300,
        f64::from_bits(1),
    ];
    for round in 0..rounds {
        let x: [f64; N] = std::array::from_fn(|_| {
            // Every eighth array gets a special lane now and then.
            if round.is_multiple_of(8) && rng.next_u64().is_multiple_of(4) {
                specials[(rng.next_u64() % specials.len() as u64) as usize]
            } else {
                let r = if rng.next_u64().is_multiple_of(2) {
                    4.0
                } else {
                    1e4
                };
                rng.symmetric(r)
            }
        });
        let (s, c) = sincos_array(x);
        for i in 0..N {
            let (si, ci) = sincos(x[i]);
            assert!(
                same_bits(s[i], si) && same_bits(c[i], ci),
                "sincos_array::<{N}> lane {i} of {x:?}: ({}, {}) vs sincos ({si}, {ci})",
                s[i],
                c[i]
            );
        }
    }
}

#[test]
fn arrays_equal_the_scalar_function_lane_by_lane() {
    let mut rng = Rng::new(0x5EED_0005);
    assert_eq!(sincos_array([]), ([], []));
    check_array::<1>(&mut rng, 2_000);
    check_array::<2>(&mut rng, 2_000);
    check_array::<3>(&mut rng, 2_000);
    check_array::<6>(&mut rng, 2_000);
    check_array::<7>(&mut rng, 2_000);
    check_array::<8>(&mut rng, 2_000);
    check_array::<13>(&mut rng, 500);
    // The sign of zero in every lane position.
    let (s, c) = sincos_array([-0.0, 1.0, -0.0]);
    assert_eq!(s.map(f64::to_bits)[0], (-0.0f64).to_bits());
    assert_eq!(s.map(f64::to_bits)[2], (-0.0f64).to_bits());
    assert_eq!((c[0], c[2]), (1.0, 1.0));
}
