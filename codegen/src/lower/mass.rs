//! Mass properties, checked at the parameters' defaults: masses (never negative, positive on
//! every body that moves: only bodies fixed to the world may be massless) and inertias
//! (symmetric, positive definite, or positive semi-definite on a body that does not move, and
//! the triangle inequality on the principal moments). The principal moments of a full matrix are
//! its eigenvalues, from nalgebra's symmetric eigen-solver.

use nalgebra::{Matrix3, SymmetricEigen};
use proc_macro2::Ident;

use super::context::num;
use super::{BodyDecl, InertiaDecl, Lower};
use crate::model::Value;
use crate::parse::Expr;

/// The names of the inertia's elements, for messages.
const NAMES: [[&str; 3]; 3] = [
    ["ixx", "ixy", "ixz"],
    ["iyx", "iyy", "iyz"],
    ["izx", "izy", "izz"],
];

impl Lower {
    /// Checks the mass and the inertia of `b`; `moving` says whether the body moves.
    pub(super) fn mass_properties(&mut self, b: &BodyDecl, moving: bool) {
        let name = &b.def.name;
        if let Some((v, e)) = b.mass {
            self.mass(name, v, e, moving);
        }
        let Some(inertia) = &b.inertia else { return };
        let Some(m) = self.inertia_at_default(inertia) else {
            return;
        };
        let eig = match inertia.diag {
            Some(d) => self.diag_moments(name, inertia, d, &m, moving),
            None => self.full_moments(name, inertia, &m, moving),
        };
        let Some(eig) = eig else { return };
        // Triangle inequality on the sorted principal moments: e0 + e1 ≥ e2.
        if eig[0] + eig[1] < eig[2] - 1e-9 * eig[2].abs() {
            self.cx.error(
                inertia.expr,
                format!(
                    "inertia of body `{name}` breaks the triangle inequality: principal moments \
                     {} + {} < {}; expected each moment to be at most the sum of the other two",
                    num(eig[0]),
                    num(eig[1]),
                    num(eig[2])
                ),
            );
        }
    }

    /// The mass `v`, written `e`, of body `name`.
    fn mass(&mut self, name: &Ident, v: Value, e: &Expr, moving: bool) {
        let Some(m) = self.at_default(v) else { return };
        if m < 0.0 {
            let expected = if moving {
                "a positive number"
            } else {
                "zero or a positive number"
            };
            let msg = format!(
                "mass of body `{name}` is {}: expected {expected}",
                self.describe(v, e)
            );
            self.cx.error(e, msg);
        } else if m == 0.0 && moving {
            let msg = format!(
                "mass of body `{name}` is {}: expected a positive number, since \
                 `{name}` moves (only bodies fixed to the world may be massless)",
                self.describe(v, e)
            );
            self.cx.error(e, msg);
        }
    }

    /// The inertia's elements at the parameters' defaults (`None` if a default was invalid).
    fn inertia_at_default(&self, inertia: &InertiaDecl) -> Option<[[f64; 3]; 3]> {
        let mut m = [[0.0; 3]; 3];
        for (row, values) in m.iter_mut().zip(&inertia.value) {
            for (x, &v) in row.iter_mut().zip(values) {
                *x = self.at_default(v)?;
            }
        }
        Some(m)
    }

    /// The principal moments of `diag(…)` as written, sorted; reports the first that is not
    /// positive (negative, on a body that does not move).
    fn diag_moments(
        &mut self,
        name: &Ident,
        inertia: &InertiaDecl,
        d: [&Expr; 3],
        m: &[[f64; 3]; 3],
        moving: bool,
    ) -> Option<[f64; 3]> {
        let bad = (0..3).find(|&i| {
            if moving {
                m[i][i] <= 0.0
            } else {
                m[i][i] < 0.0
            }
        });
        if let Some(i) = bad {
            self.cx.error(
                d[i],
                format!(
                    "inertia of body `{name}` is not positive definite: principal moment \
                     {} must be positive",
                    self.describe(inertia.value[i][i], d[i])
                ),
            );
            return None;
        }
        let mut e = [m[0][0], m[1][1], m[2][2]];
        e.sort_by(f64::total_cmp);
        Some(e)
    }

    /// The principal moments of a full matrix, sorted; reports elements that differ across the
    /// diagonal and a matrix that is not positive definite (semi-definite, on a body that does
    /// not move).
    fn full_moments(
        &mut self,
        name: &Ident,
        inertia: &InertiaDecl,
        m: &[[f64; 3]; 3],
        moving: bool,
    ) -> Option<[f64; 3]> {
        let scale = m.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
        if !self.symmetric(name, inertia, scale) {
            return None;
        }
        let e = eigenvalues(m)?;
        let tol = 1e-12 * scale;
        let bad = if moving { e[0] <= tol } else { e[0] < -tol };
        if bad {
            self.cx.error(
                inertia.expr,
                format!(
                    "inertia of body `{name}` is not positive definite: its principal \
                     moments are {}, {}, {}; expected all positive",
                    num(e[0]),
                    num(e[1]),
                    num(e[2])
                ),
            );
            return None;
        }
        Some(e)
    }

    /// Whether the elements across the diagonal are equal (constants to `1e-12·scale`, the
    /// largest element); reports each pair that is not, at the element below the diagonal.
    fn symmetric(&mut self, name: &Ident, inertia: &InertiaDecl, scale: f64) -> bool {
        let Expr::List(_, rows) = inertia.expr else {
            return false;
        };
        let element = |i: usize, j: usize| -> Option<&Expr> {
            match rows.iter().nth(i)? {
                Expr::List(_, elems) => elems.iter().nth(j),
                _ => None,
            }
        };
        let mut symmetric = true;
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let (upper, lower) = (inertia.value[i][j], inertia.value[j][i]);
            let same = match (upper, lower) {
                (Value::Const(a), Value::Const(b)) => (a - b).abs() <= 1e-12 * scale,
                _ => upper == lower,
            };
            if !same {
                symmetric = false;
                if let (Some(eu), Some(el)) = (element(i, j), element(j, i)) {
                    self.cx.error(
                        el,
                        format!(
                            "inertia of body `{name}` is not symmetric: `{}` is `{el}` but \
                             `{}` is `{eu}`; expected equal elements across the diagonal",
                            NAMES[j][i], NAMES[i][j]
                        ),
                    );
                }
            }
        }
        symmetric
    }
}

/// The eigenvalues of the symmetric matrix whose upper triangle is that of `m`, in ascending
/// order; `None` if nalgebra's solver has not converged after 1000 iterations (3×3 matrices take
/// a few: the cap only keeps a macro expansion from hanging, which `symmetric_eigenvalues`,
/// without one, would not).
pub(crate) fn eigenvalues(m: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let upper = Matrix3::from_fn(|i, j| m[i.min(j)][i.max(j)]);
    let e = SymmetricEigen::try_new(upper, f64::EPSILON, 1000)?.eigenvalues;
    let mut e = [e[0], e[1], e[2]];
    e.sort_by(f64::total_cmp);
    Some(e)
}
