//! Mass properties: a mass is never negative, and positive on a body that moves (only bodies
//! fixed to the world may be massless); an inertia is symmetric, positive definite (positive
//! semi-definite on a body that does not move, or where rounding is forgiven), and its principal
//! moments obey the triangle inequality, each at most the sum of the other two, as in every
//! rigid body. The principal moments of a full matrix are its eigenvalues, from nalgebra's
//! symmetric eigen-solver; those of `diag(…)` its elements.
//!
//! How strictly: [`Strictness`]. A `.chain` body is judged on its own, to the rounding of its
//! own elements; a URDF body, once the links welded to it are merged, against the model's
//! largest principal moment ([`INERTIA_ROUNDING`]), where rounding noise written as a tensor
//! passes.

use nalgebra::{Matrix3, SymmetricEigen};

use super::num;
use crate::model::Value;

/// A principal moment may be negative by this fraction of the model's largest principal moment
/// and pass as rounding (16 ε), under [`Strictness::Model`].
pub const INERTIA_ROUNDING: f64 = 16.0 * f64::EPSILON;

/// A full matrix written in a description is rounded to this fraction of its largest element:
/// elements across the diagonal that differ by less are equal, a smallest principal moment
/// below it is zero.
const WRITTEN_ROUNDING: f64 = 1e-12;

/// The triangle inequality holds to this fraction of the largest principal moment (a thin
/// plate, `Izz = Ixx + Iyy`, is on its edge).
const TRIANGLE_SLACK: f64 = 1e-9;

/// The names of an inertia's elements, for messages.
const NAMES: [[&str; 3]; 3] = [
    ["ixx", "ixy", "ixz"],
    ["iyx", "iyy", "iyz"],
    ["izx", "izy", "izz"],
];

/// What is wrong with the mass `m` of the `noun` (`body`, `link`) called `name`, shown as
/// `shown` (the number, or a parameter and its default): negative, or zero where `moving` says
/// the body moves (`None`: not known, only a negative mass is wrong).
pub fn mass(noun: &str, name: &str, shown: &str, m: f64, moving: Option<bool>) -> Option<String> {
    let moves = moving == Some(true);
    if m < 0.0 {
        let expected = if moves {
            "a positive number"
        } else {
            "zero or a positive number"
        };
        Some(format!(
            "mass of {noun} `{name}` is {shown}: expected {expected}"
        ))
    } else if m == 0.0 && moves {
        Some(format!(
            "mass of {noun} `{name}` is {shown}: expected a positive number, since `{name}` \
             moves (only bodies fixed to the world may be massless)"
        ))
    } else {
        None
    }
}

/// An inertia as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Inertia {
    /// `diag(ixx, iyy, izz)`: its elements are its principal moments.
    Diag([f64; 3]),
    /// A full symmetric matrix.
    Full([[f64; 3]; 3]),
}

/// How strictly an inertia is judged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Strictness {
    /// As written in a description for this project (`.chain`): positive definite on a body
    /// that moves, semi-definite on one that does not, to the rounding of the matrix's own
    /// elements (`WRITTEN_ROUNDING` of the largest; none for `diag(…)`).
    Written {
        /// Whether the body moves.
        moving: bool,
    },
    /// As found in real robot files (URDF): positive semi-definite, a principal moment negative
    /// by at most [`INERTIA_ROUNDING`] of `largest`, the model's largest principal moment,
    /// passing as rounding, and the triangle inequality to the same rounding.
    Model {
        /// The model's largest principal moment.
        largest: f64,
    },
}

/// What is wrong with an inertia.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InertiaProblem {
    /// A principal moment is not positive (negative, where only semi-definite is asked for).
    NotPositive {
        /// The principal moments, ascending.
        moments: [f64; 3],
        /// Whether positive definite was asked for (else semi-definite).
        definite: bool,
        /// For `diag(…)`, the first element (0, 1, 2 as written) that is not.
        element: Option<usize>,
    },
    /// The principal moments break the triangle inequality.
    Triangle {
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
}

impl InertiaProblem {
    /// The message, for the inertia of `subject` (`body \`a\``, `link \`a\` (with \`b\` welded
    /// to it)`).
    pub fn message(&self, subject: &str) -> String {
        match *self {
            InertiaProblem::NotPositive {
                moments: [a, b, c],
                definite,
                ..
            } => {
                let (what, expected) = if definite {
                    ("definite", "all positive")
                } else {
                    ("semi-definite", "none negative")
                };
                format!(
                    "inertia of {subject} is not positive {what}: its principal moments are {}, \
                     {}, {}; expected {expected}",
                    num(a),
                    num(b),
                    num(c)
                )
            }
            InertiaProblem::Triangle { moments: [a, b, c] } => format!(
                "inertia of {subject} breaks the triangle inequality: principal moments {} + {} \
                 < {}; expected each moment to be at most the sum of the other two",
                num(a),
                num(b),
                num(c)
            ),
        }
    }

    /// The principal moments, ascending.
    pub fn moments(&self) -> [f64; 3] {
        match *self {
            InertiaProblem::NotPositive { moments, .. } | InertiaProblem::Triangle { moments } => {
                moments
            }
        }
    }
}

/// What is wrong with the inertia `i`, judged as `strictness` says (`None` also where the
/// eigen-solver does not converge, which 3×3 matrices do not do).
pub fn inertia(i: &Inertia, strictness: Strictness) -> Option<InertiaProblem> {
    let (definite, rounding) = match (strictness, i) {
        (Strictness::Written { moving }, Inertia::Diag(_)) => (moving, 0.0),
        (Strictness::Written { moving }, Inertia::Full(m)) => (moving, WRITTEN_ROUNDING * scale(m)),
        (Strictness::Model { largest }, _) => (false, INERTIA_ROUNDING * largest),
    };
    let not_positive = |x: f64| {
        if definite {
            x <= rounding
        } else {
            x < -rounding
        }
    };
    let (moments, element) = match i {
        Inertia::Diag(d) => {
            let mut e = *d;
            e.sort_by(f64::total_cmp);
            (e, d.iter().position(|&x| not_positive(x)))
        }
        Inertia::Full(m) => (principal_moments(m)?, None),
    };
    if not_positive(moments[0]) {
        return Some(InertiaProblem::NotPositive {
            moments,
            definite,
            element,
        });
    }
    let [a, b, c] = moments;
    let slack = rounding.max(TRIANGLE_SLACK * c.abs());
    (a + b < c - slack).then_some(InertiaProblem::Triangle { moments })
}

/// The largest element of `m` in magnitude.
fn scale(m: &[[f64; 3]; 3]) -> f64 {
    m.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// The pairs `(i, j)`, `i < j`, whose elements across the diagonal differ: constants by more than
/// the rounding of the matrix's elements (`at_default`, the values at the parameters' defaults),
/// parameters by being different parameters or a parameter and a constant.
pub fn asymmetric(value: &[[Value; 3]; 3], at_default: &[[f64; 3]; 3]) -> Vec<(usize, usize)> {
    let tolerance = WRITTEN_ROUNDING * scale(at_default);
    [(0, 1), (0, 2), (1, 2)]
        .into_iter()
        .filter(|&(i, j)| {
            let (upper, lower) = (value[i][j], value[j][i]);
            let same = match (upper, lower) {
                (Value::Const(a), Value::Const(b)) => (a - b).abs() <= tolerance,
                _ => upper == lower,
            };
            !same
        })
        .collect()
}

/// The message for the pair `(i, j)` of [`asymmetric`] in the inertia of `subject`, with the
/// elements as written: `lower` below the diagonal, `upper` above.
pub fn asymmetry(subject: &str, (i, j): (usize, usize), lower: &str, upper: &str) -> String {
    let name = |r: usize, c: usize| NAMES.get(r).and_then(|row| row.get(c)).unwrap_or(&"");
    format!(
        "inertia of {subject} is not symmetric: `{}` is `{lower}` but `{}` is `{upper}`; \
         expected equal elements across the diagonal",
        name(j, i),
        name(i, j)
    )
}

/// The eigenvalues of the symmetric matrix whose upper triangle is that of `m`, in ascending
/// order; `None` if nalgebra's solver has not converged after 1000 iterations (3×3 matrices take
/// a few: the cap only keeps a macro expansion from hanging, which `symmetric_eigenvalues`,
/// without one, would not).
pub fn principal_moments(m: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let upper = Matrix3::from_fn(|i, j| {
        m.get(i.min(j))
            .and_then(|row| row.get(i.max(j)))
            .copied()
            .unwrap_or(0.0)
    });
    let e = SymmetricEigen::try_new(upper, f64::EPSILON, 1000)?.eigenvalues;
    let mut e = [e[0], e[1], e[2]];
    e.sort_by(f64::total_cmp);
    Some(e)
}
