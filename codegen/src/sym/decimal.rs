//! Exact decimal arithmetic for folding constants.
//!
//! A description's numbers are decimals (`3.2`, `2.8`), and the graph folds arithmetic between
//! them while it is traced (`3.2 − 2.8` when inertial parameters are regrouped). Folded in
//! binary floating point, that difference is `0.40000000000000036`: the exact difference of the
//! two nearest doubles, which carries both representation errors and reads as noise in the
//! emitted code. Folded here, in exact decimal arithmetic and rounded once, it is `0.4`: the
//! correctly rounded value of what the description states.
//!
//! A constant is a decimal when it is a number as written (it entered the graph through
//! `Scalar::from_f64`) and its shortest digits, what `{:?}` prints, number at most
//! [`DECIMAL_DIGITS`], f64's `DBL_DIG`: every such decimal survives the trip through a double,
//! so they are the digits as written. Sums, differences and products of decimals are exact and
//! decimals too. Anything else (a quotient, a sine, a square root, a result past [`MAX_DIGITS`]
//! digits, a constant with more digits) is a binary value and is folded in `f64` as before.

/// A decimal `mantissa · 10^exponent`, normalized (the mantissa has no trailing zero digit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Decimal {
    mantissa: i128,
    exponent: i32,
}

/// The most significant digits a folded decimal keeps exactly (an `i128` holds 38).
const MAX_DIGITS: u32 = 34;

/// A constant whose shortest digits number at most this many is taken as a decimal: 15 is
/// f64's `DBL_DIG`, the digits every decimal keeps through a double and back.
const DECIMAL_DIGITS: usize = 15;

impl Decimal {
    /// The shortest decimal that reads back as `x`, if it has at most [`DECIMAL_DIGITS`]
    /// significant digits; `None` otherwise and for a non-finite `x`.
    pub(super) fn from_f64(x: f64) -> Option<Decimal> {
        if !x.is_finite() {
            return None;
        }
        // `{:e}` prints the shortest round-trip digits: `-3.2e0`, `1e-7`, `0e0`.
        let text = format!("{x:e}");
        let (digits, exponent) = text.split_once('e')?;
        let exponent: i32 = exponent.parse().ok()?;
        let (int, frac) = digits.split_once('.').unwrap_or((digits, ""));
        if int.trim_start_matches('-').len() + frac.len() > DECIMAL_DIGITS {
            return None;
        }
        let mantissa: i128 = format!("{int}{frac}").parse().ok()?;
        Decimal::new(
            mantissa,
            exponent.checked_sub(i32::try_from(frac.len()).ok()?)?,
        )
    }

    /// `mantissa · 10^exponent` normalized, or `None` past [`MAX_DIGITS`] digits.
    fn new(mut mantissa: i128, mut exponent: i32) -> Option<Decimal> {
        if mantissa == 0 {
            return Some(Decimal {
                mantissa: 0,
                exponent: 0,
            });
        }
        while mantissa % 10 == 0 {
            mantissa /= 10;
            exponent = exponent.checked_add(1)?;
        }
        (mantissa.unsigned_abs() < 10u128.pow(MAX_DIGITS)).then_some(Decimal { mantissa, exponent })
    }

    /// The double nearest to this decimal (Rust's parser rounds correctly); `None` if it is not
    /// finite.
    pub(super) fn to_f64(self) -> Option<f64> {
        let x: f64 = format!("{}e{}", self.mantissa, self.exponent)
            .parse()
            .ok()?;
        x.is_finite().then_some(x)
    }

    /// `self + other`, exactly.
    pub(super) fn add(self, other: Decimal) -> Option<Decimal> {
        let exponent = self.exponent.min(other.exponent);
        let scaled = |d: Decimal| -> Option<i128> {
            let shift = u32::try_from(d.exponent - exponent).ok()?;
            d.mantissa.checked_mul(10i128.checked_pow(shift)?)
        };
        Decimal::new(scaled(self)?.checked_add(scaled(other)?)?, exponent)
    }

    /// `−self`.
    pub(super) fn neg(self) -> Decimal {
        Decimal {
            mantissa: -self.mantissa,
            exponent: self.exponent,
        }
    }

    /// `self · other`, exactly.
    pub(super) fn mul(self, other: Decimal) -> Option<Decimal> {
        Decimal::new(
            self.mantissa.checked_mul(other.mantissa)?,
            self.exponent.checked_add(other.exponent)?,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::Decimal;

    fn d(x: f64) -> Decimal {
        Decimal::from_f64(x).unwrap()
    }

    #[test]
    fn sums_and_products_of_decimals_are_exact() {
        // In binary these are 0.40000000000000036, 0.30000000000000004 and 0.7200000000000001.
        assert_eq!(d(3.2).add(d(-2.8)).unwrap().to_f64(), Some(0.4));
        assert_eq!(d(0.1).add(d(0.2)).unwrap().to_f64(), Some(0.3));
        assert_eq!(d(1.2).mul(d(0.6)).unwrap().to_f64(), Some(0.72));
        // And a difference that is zero in decimal is exactly zero.
        let x = d(0.1).add(d(0.2)).unwrap().add(d(-0.3)).unwrap();
        assert_eq!(x.to_f64(), Some(0.0));
        assert_eq!(d(-7.5e-12).neg().to_f64(), Some(7.5e-12));
        assert_eq!(d(0.0).to_f64(), Some(0.0));
    }

    #[test]
    fn short_decimals_read_back_and_binary_values_are_not_decimals() {
        for x in [1.0, -2.5, 1e-300, 1.5e308, 5e-324, 0.1, 123456789.012345] {
            assert_eq!(d(x).to_f64(), Some(x), "{x:e}");
        }
        // 16 and 17 digits: binary values (a third, π, what binary folding leaves).
        for x in [
            1.0 / 3.0,
            std::f64::consts::PI,
            0.1 + 0.2,
            f64::NAN,
            f64::INFINITY,
        ] {
            assert_eq!(Decimal::from_f64(x), None, "{x:e}");
        }
        // 15 × 15 digits fit exactly; a third factor does not.
        let x = d(0.123456789012345);
        let square = x.mul(x).unwrap();
        assert!(square.mul(x).is_none());
        // Far-apart exponents cannot be aligned in 34 digits.
        assert!(d(1e300).add(d(1e-300)).is_none());
    }
}
