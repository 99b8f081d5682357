//! The scalar the recursions are written over.
//!
//! The reference evaluates them in `f64`; the generator (issue 3) traces the very same code over a
//! symbolic scalar that records an expression graph. That is why the recursions never branch on a
//! value and never compare scalars: every operation they need is in this trait.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// A number the dynamics recursions can be evaluated on (`f64`, `f32`, or a symbolic scalar).
///
/// `Copy` is required so that the spatial algebra reads like the math; a symbolic scalar is a
/// handle into its expression graph, so it is `Copy` too.
pub trait Scalar:
    Copy
    + core::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `x` in this scalar.
    fn from_f64(x: f64) -> Self;
    /// `0`.
    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    /// `1`.
    fn one() -> Self {
        Self::from_f64(1.0)
    }
    /// Sine and cosine of the same angle, computed together.
    fn sin_cos(self) -> (Self, Self);
    /// Square root.
    fn sqrt(self) -> Self;
    /// Names this value for a reader of generated code and returns it unchanged. The symbolic
    /// scalar records the name, and the emitter binds the value to a local of that name (the
    /// recursions label what they compute per body: `trunk_w_x`, the angular velocity of `trunk`
    /// about x); numbers ignore it. The first name given to a value wins.
    #[inline(always)]
    fn label(self, _name: core::fmt::Arguments<'_>) -> Self {
        self
    }
}

impl Scalar for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
    fn sin_cos(self) -> (Self, Self) {
        (libm::sin(self), libm::cos(self))
    }
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
}

impl Scalar for f32 {
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn sin_cos(self) -> (Self, Self) {
        (libm::sinf(self), libm::cosf(self))
    }
    fn sqrt(self) -> Self {
        libm::sqrtf(self)
    }
}
