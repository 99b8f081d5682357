//! The contact forces that produce a motion with the least effort, within each contact's
//! friction cone and, for a flat foot, its sole (issue 34, item 4; Wieber 2005 eq. 16's
//! unilaterality and limited friction): with `h = M·q̈ + nle`, the forces `f` that minimise
//!
//! ```text
//! ‖τ‖² + w·‖f‖²,   τ = (h − Jᵀ·f) on the actuated velocities,
//! ```
//!
//! subject to the unactuated rows `(Jᵀ·f)_b = h_b` (the free base's six equations: the contacts
//! alone can push the whole body), each contact's force in its friction cone
//! `‖f_t‖ ≤ μ·f_n` (the normal is the world's `z` for a point contact, whose force is in world
//! axes, and the frame's `z` for a six-dimensional one, whose wrench `[n; f]` is in the frame),
//! and each sole's centre of pressure inside its rectangle in the frame's `z = 0` plane:
//! `x₀ ≤ −n_y/f_z ≤ x₁`, `y₀ ≤ n_x/f_z ≤ y₁`. No rotation about the normal is limited (no
//! torsional friction). A second-order cone program, solved by `clarabel` (an interior-point
//! solver: the constraints hold to its tolerance, about 1e-8 relative).
//!
//! Where the contacts cannot produce the motion within their limits (a foot that would have to
//! pull, slide, or push beyond its toes) it is [`OptimalError::Infeasible`], naming how many
//! contacts were asked.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{SMatrix, SVector};

use super::{Contact, ContactWrenches, Kind, System};

/// A sole's rectangle in its contact frame's `z = 0` plane (m): where the centre of pressure
/// may be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sole {
    /// `[heel, toes]` along the frame's `x`.
    pub x: [f64; 2],
    /// `[right, left]` along the frame's `y`.
    pub y: [f64; 2],
}

/// A contact's limits: its friction coefficient and, for a six-dimensional contact, its sole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// `μ`: the tangential force at most `μ` times the normal one.
    pub friction: f64,
    /// The sole of a six-dimensional contact; `None` leaves its centre of pressure free (and
    /// must be `None` for a point contact).
    pub sole: Option<Sole>,
}

/// Why no optimal forces came back.
#[derive(Clone, Debug, PartialEq)]
pub enum OptimalError {
    /// An input is not finite, or the weight is negative.
    NonFinite,
    /// Contact `contact`'s limits make no sense: a negative or non-finite friction
    /// coefficient, an empty sole, a sole on a point contact, or not one limit per contact
    /// (`contact` is then the number of limits), or rows the contacts do not account for.
    Limits {
        /// The contact.
        contact: usize,
    },
    /// No forces within the contacts' friction cones and soles produce the motion.
    Infeasible {
        /// How many contacts were asked.
        contacts: usize,
    },
    /// The solver stopped without a solution, with its status.
    Solver(String),
}

impl fmt::Display for OptimalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OptimalError::NonFinite => {
                write!(f, "an input is not finite (or the weight is negative)")
            }
            OptimalError::Limits { contact } => write!(
                f,
                "the limits of contact {contact} make no sense (friction ≥ 0, a sole with \
                 x₀ < x₁ and y₀ < y₁ on six-dimensional contacts only, one limit per contact)"
            ),
            OptimalError::Infeasible { contacts } => write!(
                f,
                "no forces within the friction cones and soles of the {contacts} contacts \
                 produce this motion (a contact would have to pull, slide or push past its sole)"
            ),
            OptimalError::Solver(status) => write!(f, "the conic solver stopped: {status}"),
        }
    }
}

impl core::error::Error for OptimalError {}

/// The optimal forces of `contacts` (the rows of `system`, in that order) that produce `q̈`
/// (module docs), with `force_weight` the weight `w` of `‖f‖²` and `unactuated` the velocities
/// without an actuator (6 under a free base: [`super::unactuated`]). Allocates (the solver's
/// matrices).
///
/// # Errors
/// [`OptimalError`].
#[allow(clippy::too_many_arguments)]
pub fn contact_forces<const NV: usize, const R: usize>(
    m: &SMatrix<f64, NV, NV>,
    nle: &SVector<f64, NV>,
    qdd: &SVector<f64, NV>,
    system: &System<NV, R>,
    contacts: &[Contact],
    limits: &[Limits],
    unactuated: usize,
    force_weight: f64,
) -> Result<ContactWrenches<NV, R>, OptimalError> {
    let values = [
        m.as_slice(),
        nle.as_slice(),
        qdd.as_slice(),
        system.jacobian.as_slice(),
    ];
    if !(values.iter().all(|x| x.iter().all(|x| x.is_finite()))
        && force_weight.is_finite()
        && force_weight >= 0.0
        && unactuated <= NV)
    {
        return Err(OptimalError::NonFinite);
    }
    check_limits(system.rows, contacts, limits)?;
    let k = system.rows;
    let h = m * qdd + nle;
    let j = &system.jacobian;
    let (p, q) = objective(j, &h, k, unactuated, force_weight);
    let (a, b, cones) = cone_rows(j, &h, k, unactuated, contacts, limits);
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .map_err(|e| OptimalError::Solver(e.to_string()))?;
    let p = csc(&p, k);
    let a = csc(&a, k);
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
        .map_err(|e| OptimalError::Solver(format!("{e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            return Err(OptimalError::Infeasible {
                contacts: contacts.len(),
            });
        }
        other => return Err(OptimalError::Solver(format!("{other:?}"))),
    }
    let mut forces = SVector::<f64, R>::zeros();
    for (r, x) in solver.solution.x.iter().enumerate().take(k) {
        forces[r] = *x;
    }
    let tau = h - j.tr_mul(&forces);
    let residual = tau
        .iter()
        .take(unactuated)
        .fold(0.0f64, |m, x| m.max(x.abs()));
    Ok(ContactWrenches {
        tau,
        forces,
        rows: k,
        residual,
    })
}

/// One limit per contact, the contacts covering the system's `rows`, each friction coefficient
/// finite and not negative and each sole (of a six-dimensional contact only) a rectangle.
fn check_limits(rows: usize, contacts: &[Contact], limits: &[Limits]) -> Result<(), OptimalError> {
    let finite = |x: &[f64]| x.iter().all(|x| x.is_finite());
    if limits.len() != contacts.len() {
        return Err(OptimalError::Limits {
            contact: limits.len(),
        });
    }
    if contacts.iter().map(|c| c.kind.rows()).sum::<usize>() != rows {
        return Err(OptimalError::Limits {
            contact: contacts.len(),
        });
    }
    for (i, (c, l)) in contacts.iter().zip(limits).enumerate() {
        let sole_ok = match (c.kind, l.sole) {
            (_, None) => true,
            (Kind::Point, Some(_)) => false,
            (Kind::SixD, Some(s)) => {
                finite(&[s.x[0], s.x[1], s.y[0], s.y[1]]) && s.x[0] < s.x[1] && s.y[0] < s.y[1]
            }
        };
        if !(l.friction.is_finite() && l.friction >= 0.0 && sole_ok) {
            return Err(OptimalError::Limits { contact: i });
        }
    }
    Ok(())
}

/// The objective `½·fᵀ·P·f + qᵀ·f` (upper triangle of `P`, by rows) with `P = 2·(B·Bᵀ + w·I)`,
/// `q = −2·B·h_a`, where the actuated joint forces are `τ_a = h_a − Bᵀ·f` (`B`: the actuated
/// columns of `J`, `k × (NV − u)`).
fn objective<const NV: usize, const R: usize>(
    j: &SMatrix<f64, R, NV>,
    h: &SVector<f64, NV>,
    k: usize,
    u: usize,
    force_weight: f64,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut p = vec![vec![0.0; k]; k];
    let mut q = vec![0.0; k];
    for r in 0..k {
        for c in r..k {
            let bb: f64 = (u..NV).map(|a| j[(r, a)] * j[(c, a)]).sum();
            p[r][c] = 2.0 * (bb + if r == c { force_weight } else { 0.0 });
        }
        q[r] = -2.0 * (u..NV).map(|a| j[(r, a)] * h[a]).sum::<f64>();
    }
    (p, q)
}

/// The constraints `A·f + s = b`, `s` in the cones, in their order: the unactuated rows (zero
/// cone), then each contact's friction cone (second-order: `s = (μ·f_n, f_t1, f_t2)`), then the
/// soles' four inequalities each (non-negative: `s = −(row·f) ≥ 0`).
fn cone_rows<const NV: usize, const R: usize>(
    j: &SMatrix<f64, R, NV>,
    h: &SVector<f64, NV>,
    k: usize,
    u: usize,
    contacts: &[Contact],
    limits: &[Limits],
) -> (Vec<Vec<f64>>, Vec<f64>, Vec<SupportedConeT<f64>>) {
    let mut a: Vec<Vec<f64>> = Vec::new();
    let mut b = Vec::new();
    let mut cones = Vec::new();
    for base in 0..u {
        a.push((0..k).map(|r| j[(r, base)]).collect());
        b.push(h[base]);
    }
    if u > 0 {
        cones.push(SupportedConeT::ZeroConeT(u));
    }
    let mut start = 0;
    let mut starts = Vec::with_capacity(contacts.len());
    for c in contacts {
        starts.push(start);
        // The force's components: in world axes for a point, in the frame for six_d.
        let force = match c.kind {
            Kind::Point => start,
            Kind::SixD => start + 3,
        };
        let unit = |at: usize, scale: f64| {
            let mut row = vec![0.0; k];
            row[at] = -scale;
            row
        };
        let mu = limits[starts.len() - 1].friction;
        a.push(unit(force + 2, mu));
        a.push(unit(force, 1.0));
        a.push(unit(force + 1, 1.0));
        b.extend([0.0; 3]);
        cones.push(SupportedConeT::SecondOrderConeT(3));
        start += c.kind.rows();
    }
    let mut soles = 0;
    for ((c, l), &s) in contacts.iter().zip(limits).zip(&starts) {
        if let (Kind::SixD, Some(sole)) = (c.kind, l.sole) {
            // n = f[s..s+3], f = f[s+3..s+6]; each row·f ≤ 0.
            let (nx, ny, fz) = (s, s + 1, s + 5);
            // x ≤ x₁, x ≥ x₀, y ≤ y₁, y ≥ y₀ of the centre of pressure, times f_z.
            for pairs in [
                [(ny, -1.0), (fz, -sole.x[1])],
                [(ny, 1.0), (fz, sole.x[0])],
                [(nx, 1.0), (fz, -sole.y[1])],
                [(nx, -1.0), (fz, sole.y[0])],
            ] {
                let mut row = vec![0.0; k];
                for (at, value) in pairs {
                    row[at] = value;
                }
                a.push(row);
                b.push(0.0);
                soles += 1;
            }
        }
    }
    if soles > 0 {
        cones.push(SupportedConeT::NonnegativeConeT(soles));
    }
    (a, b, cones)
}

/// A dense matrix of `cols` columns (by rows) in compressed sparse columns, zeros left out.
fn csc(rows: &[Vec<f64>], cols: usize) -> CscMatrix<f64> {
    let mut colptr = vec![0];
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    for c in 0..cols {
        for (r, row) in rows.iter().enumerate() {
            let x = row[c];
            if x != 0.0 {
                rowval.push(r);
                nzval.push(x);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows.len(), cols, colptr, rowval, nzval)
}
