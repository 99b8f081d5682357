//! Constants as Rust literals a person would write, and clippy would accept in the user's
//! crate: the shortest digits that read back exactly (`{:?}`), a constant equal to one of
//! `core::f64::consts` by its name, and a literal that clippy's `approx_constant` would mistake
//! for one (say `3.14`) as an exact quotient (`314.0_f64 / 100.0_f64`), which is the same
//! number.

use std::str::FromStr;

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote, ToTokens};

use super::EmitError;
use crate::options::ScalarKind;

/// `core::f64::consts` (and `f32`) written by name when a constant equals one exactly, and
/// clippy's `approx_constant` table: (value, name, fewest significant characters it checks).
const KNOWN: &[(f64, f32, &str, usize)] = {
    use std::f32::consts as s;
    use std::f64::consts as d;
    &[
        (d::E, s::E, "E", 4),
        (d::FRAC_1_PI, s::FRAC_1_PI, "FRAC_1_PI", 4),
        (d::FRAC_1_SQRT_2, s::FRAC_1_SQRT_2, "FRAC_1_SQRT_2", 5),
        (d::FRAC_2_PI, s::FRAC_2_PI, "FRAC_2_PI", 5),
        (d::FRAC_2_SQRT_PI, s::FRAC_2_SQRT_PI, "FRAC_2_SQRT_PI", 5),
        (d::FRAC_PI_2, s::FRAC_PI_2, "FRAC_PI_2", 5),
        (d::FRAC_PI_3, s::FRAC_PI_3, "FRAC_PI_3", 5),
        (d::FRAC_PI_4, s::FRAC_PI_4, "FRAC_PI_4", 5),
        (d::FRAC_PI_6, s::FRAC_PI_6, "FRAC_PI_6", 5),
        (d::FRAC_PI_8, s::FRAC_PI_8, "FRAC_PI_8", 5),
        (d::LN_2, s::LN_2, "LN_2", 5),
        (d::LN_10, s::LN_10, "LN_10", 5),
        (d::LOG2_10, s::LOG2_10, "LOG2_10", 5),
        (d::LOG2_E, s::LOG2_E, "LOG2_E", 5),
        (d::LOG10_2, s::LOG10_2, "LOG10_2", 5),
        (d::LOG10_E, s::LOG10_E, "LOG10_E", 5),
        (d::PI, s::PI, "PI", 3),
        (d::SQRT_2, s::SQRT_2, "SQRT_2", 5),
        (d::TAU, s::TAU, "TAU", 3),
    ]
};

/// Whether clippy's `approx_constant` would flag a float literal written `text` (its
/// `is_approx_const`, as of clippy 1.95 and as before, applied to the table above).
fn looks_like_known_constant(text: &str) -> bool {
    let Ok(value) = text.parse::<f64>() else {
        return false;
    };
    let shortest = value.to_string();
    let after_dot = text.split_once('.').map_or(0, |(_, frac)| frac.len());
    KNOWN.iter().any(|&(known, _, _, min_digits)| {
        let known_text = known.to_string();
        text.len() > min_digits
            && (known_text.starts_with(text)
                || (shortest.len() > min_digits && known_text.starts_with(&shortest))
                || format!("{known:.*}", text.len() - 2) == text
                || format!("{known:0width$.after_dot$}", width = text.len()) == text)
    })
}

/// A positive constant in `scalar` that is not exactly one of [`KNOWN`], and whether it is a
/// quotient (which needs parentheses as an operand of `+ − · /`).
///
/// Normally the shortest literal that reads back as the same number (`{:?}`). If clippy's
/// `approx_constant` would take that literal for a known constant (a model with a length of
/// `3.14` m), the same number is written as a quotient of two exactly representable integers,
/// `314.0_f64 / 100.0_f64`, which IEEE division rounds to exactly the number `3.14` reads as; if
/// the integers are not exact, as `f64::from_bits(…)`.
fn positive_constant(a: f64, scalar: ScalarKind) -> (TokenStream, bool) {
    let (text, suffix) = match scalar {
        ScalarKind::F32 => (format!("{:?}", a as f32), "_f32"),
        ScalarKind::F64 => (format!("{a:?}"), "_f64"),
        ScalarKind::Generic => (format!("{a:?}"), ""),
    };
    if !looks_like_known_constant(&text) {
        return (
            literal(&format!("{text}{suffix}")).into_token_stream(),
            false,
        );
    }
    if let Some((int, frac)) = text.split_once('.').filter(|_| !text.contains('e')) {
        let numerator = format!("{int}{frac}").trim_start_matches('0').to_owned();
        let denominator = format!("1{}", "0".repeat(frac.len()));
        let exact = match (numerator.parse::<u64>(), denominator.parse::<u64>()) {
            (Ok(n), Ok(d)) => match scalar {
                ScalarKind::F32 => {
                    n < 1 << 24 && d < 1 << 24 && (n as f32) / (d as f32) == a as f32
                }
                _ => n < 1 << 53 && d < 1 << 53 && (n as f64) / (d as f64) == a,
            },
            _ => false,
        };
        let (n, d) = (
            format!("{numerator}.0{suffix}"),
            format!("{denominator}.0{suffix}"),
        );
        if exact && !looks_like_known_constant(&n) && !looks_like_known_constant(&d) {
            let (n, d) = (literal(&n), literal(&d));
            return (quote!(#n / #d), true);
        }
    }
    let tokens = match scalar {
        ScalarKind::F32 => {
            let bits = Literal::u32_unsuffixed((a as f32).to_bits());
            quote!(::core::primitive::f32::from_bits(#bits))
        }
        _ => {
            let bits = Literal::u64_unsuffixed(a.to_bits());
            quote!(::core::primitive::f64::from_bits(#bits))
        }
    };
    (tokens, false)
}

/// A constant as an operand in `scalar`, and whether it is a quotient (see
/// [`positive_constant`]).
pub(super) fn constant(x: f64, scalar: ScalarKind) -> Result<(TokenStream, bool), EmitError> {
    let error = EmitError::NonFiniteConstant { value: x, scalar };
    let in_scalar_finite = match scalar {
        ScalarKind::F32 => (x as f32).is_finite(),
        _ => x.is_finite(),
    };
    if !in_scalar_finite {
        return Err(error);
    }
    let minus = if x < 0.0 { quote!(-) } else { quote!() };
    let a = x.abs();
    let known = KNOWN.iter().find(|k| match scalar {
        ScalarKind::F32 => a as f32 == k.1,
        _ => a == k.0,
    });
    let module = match scalar {
        ScalarKind::F32 => quote!(f32),
        _ => quote!(f64),
    };
    let (value, compound) = match known {
        Some(k) => {
            let name = format_ident!("{}", k.2);
            (quote!(#minus ::core::#module::consts::#name), false)
        }
        None => {
            let (c, compound) = positive_constant(a, scalar);
            (quote!(#minus #c), compound)
        }
    };
    Ok(match scalar {
        ScalarKind::Generic => (
            quote!(::articulated::nalgebra::convert::<f64, T>(#value)),
            false,
        ),
        _ => (value, compound),
    })
}

/// A float literal token from its text.
fn literal(text: &str) -> Literal {
    match Literal::from_str(text) {
        Ok(lit) => lit,
        // `digits` only produces `{:?}` output of a finite float or its exponent form, plus a
        // suffix: always a valid literal.
        Err(_) => unreachable!("not a float literal: {text}"),
    }
}
