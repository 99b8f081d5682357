//! Operation counts of generated functions: counted by the generator on its expression graph,
//! exposed by generated code as constants (`C::MASS_MATRIX_OPS`). Here because both the
//! generator and the runtime need the type and neither can depend on the other.

use core::fmt;

/// How many operations a function performs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OpCounts {
    /// Additions and subtractions.
    pub adds: usize,
    /// Multiplications.
    pub muls: usize,
    /// Divisions.
    pub divs: usize,
    /// Negations.
    pub negs: usize,
    /// Sine/cosine evaluations, counted once per argument (a sine and a cosine of the same angle
    /// are computed together).
    pub sin_cos: usize,
    /// Square roots.
    pub sqrts: usize,
}

impl OpCounts {
    /// All operations together.
    pub const fn total(&self) -> usize {
        self.adds + self.muls + self.divs + self.negs + self.sin_cos + self.sqrts
    }
}

/// The operations of two functions together (a composed one and its parts).
impl core::ops::Add for OpCounts {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        OpCounts {
            adds: self.adds + other.adds,
            muls: self.muls + other.muls,
            divs: self.divs + other.divs,
            negs: self.negs + other.negs,
            sin_cos: self.sin_cos + other.sin_cos,
            sqrts: self.sqrts + other.sqrts,
        }
    }
}

impl fmt::Display for OpCounts {
    /// `12 add/sub, 20 mul, 0 div, 1 neg, 2 sin/cos, 0 sqrt (35 total)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} add/sub, {} mul, {} div, {} neg, {} sin/cos, {} sqrt ({} total)",
            self.adds,
            self.muls,
            self.divs,
            self.negs,
            self.sin_cos,
            self.sqrts,
            self.total()
        )
    }
}
