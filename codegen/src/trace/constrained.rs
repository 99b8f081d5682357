//! Constrained forward dynamics for the constraints a description declares, traced in one pass:
//! `q̈` and the constraint forces `f` with `M·q̈ + h = τ + Jᵀ·f` and `J·q̈ + γ = 0` (`h = N·q̇ + g`,
//! `J` the constraints' stacked rows, `γ` their drift), for the generated
//! `constrained_forward_dynamics`.
//!
//! `M`, `h`, the frames' Jacobians and drifts come from one kinematic pass (the graph shares the
//! transforms they have in common), then, with `M = LᵀDL` factored from the last coordinate to
//! the first (RBDA §6.5, the tree's sparsity kept):
//! - `Z = L⁻ᵀ·Jᵀ` and `y = L⁻ᵀ·(τ − h)`. A constraint's row is non-zero only on the coordinates
//!   of its frames' ancestors, a set closed towards the root, and solving with `Lᵀ` from the last
//!   coordinate to the first only carries a coordinate's entry to its ancestors: each column of
//!   `Z` keeps the sparsity of its row of `J` (Featherstone 2005, "Efficient factorization of
//!   the joint-space inertia matrix…"). The structural zeros are exact zeros of the graph, so
//!   every product with them folds away;
//! - the operational-space (Delassus) matrix `G = J·M⁻¹·Jᵀ = Zᵀ·D⁻¹·Z` and the right side
//!   `−γ − J·M⁻¹·(τ − h) = −γ − Zᵀ·D⁻¹·y`: sparse dot products, `M⁻¹·(τ − h)` never formed;
//! - `G·f = b` by `LᵀDL` of `G` with its rows in reverse, so that its elimination runs from the
//!   first row to the last, as the runtime's Cholesky does (the row a redundancy is reported at
//!   is the same);
//! - `q̈ = L⁻¹·D⁻¹·(y + Z·f)`: one more sparse solve, for the free and the constrained motion
//!   together.
//!
//! The rows are the runtime's (`articulated::constraint::Frames::system`) but for the axes of a
//! six-dimensional contact: a point contact's three linear rows of its LOCAL_WORLD_ALIGNED
//! Jacobian with the classical acceleration of its origin as drift; a loop the difference of its
//! two frames' point rows; a six-dimensional contact, which the runtime holds in LOCAL (the
//! Jacobian `J_local = Wᵀ·J_lwa` block by block, `W = world_R_frame`, the spatial drift
//! `[Wᵀ·ω̇; Wᵀ·p̈ − ω_l × v_l]`), held here in world axes: `W·(J_local·q̈ + γ_local) = 0` is
//! `J_lwa·q̈ + [ω̇; p̈ − ω × ṗ] = 0` (a rotation keeps the cross product), which spares turning
//! every column of the Jacobian into the frame; the wrench solved for, in world axes, is turned
//! into the frame's at the end (`Wᵀ·n`, `Wᵀ·f`), what the runtime returns. `G` is the runtime's
//! turned by `W` (the same rank); a redundancy names the contact and its row in world axes.

use articulated_dynamics::model::{Coupling, Model};
use articulated_dynamics::reference::Ltdl;
use articulated_dynamics::spatial::Vec3;
use articulated_dynamics::Scalar;

use super::frames::{Frame, FrameAt, In, Kinematics};
use super::{fewest, inputs, mass_matrix, model_inputs, rnea, symbolic_tree};
use super::{Formulation, Variant};
use crate::optimize::{reassociate, reciprocals};
use crate::sym::{self, Graph, OpCounts, Sym, Var};

/// One declared constraint, by the index of its frames in the frames traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Constraint {
    /// A point contact: 3 rows.
    Point(usize),
    /// A six-dimensional contact: 6 rows.
    SixD(usize),
    /// A point loop holding frame `a`'s origin on frame `b`'s: 3 rows.
    Loop(usize, usize),
    /// A six-dimensional loop holding frame `a` on frame `b`: 6 rows.
    LoopSixD(usize, usize),
}

impl Constraint {
    /// Its rows.
    pub fn rows(self) -> usize {
        match self {
            Constraint::SixD(_) | Constraint::LoopSixD(..) => 6,
            Constraint::Point(_) | Constraint::Loop(..) => 3,
        }
    }
}

/// The traced function: `q̈` (`nv` values) then the forces (one per row), and the checks of its
/// two factorizations.
#[derive(Debug)]
pub struct ConstrainedTraced {
    /// The expression graph.
    pub graph: Graph,
    /// `q̈`, then the forces.
    pub values: Vec<Sym>,
    /// `M`'s pivots with their unreduced values, by velocity coordinate.
    pub mass: Vec<(Sym, Sym)>,
    /// `G`'s pivots with their unreduced values (its diagonal), by row.
    pub delassus: Vec<(Sym, Sym)>,
    /// The variant kept (the recursions of `M` and `h`, the inertias regrouped or not).
    pub variant: Variant,
    /// Every variant traced, with its operations.
    pub candidates: Vec<(Variant, OpCounts)>,
}

impl ConstrainedTraced {
    /// The values, then each pivot of `M` and its unreduced value, then each of `G`'s.
    pub fn all_outputs(&self) -> Vec<Sym> {
        let mut all = self.values.clone();
        for &(p, d) in self.mass.iter().chain(&self.delassus) {
            all.extend([p, d]);
        }
        all
    }

    /// Operations the emitted function performs.
    pub fn ops(&self) -> OpCounts {
        self.graph.op_counts(&self.all_outputs())
    }

    /// The same outputs rebuilt by `pass` (which returns its graph and the outputs, in order).
    fn rebuilt(self, pass: impl FnOnce(&Graph, &[Sym]) -> (Graph, Vec<Sym>)) -> Self {
        let (graph, mut all) = pass(&self.graph, &self.all_outputs());
        let mut pairs = all.split_off(self.values.len());
        let delassus = pairs.split_off(2 * self.mass.len());
        let to_pairs = |v: Vec<Sym>| v.chunks(2).map(|pd| (pd[0], pd[1])).collect();
        ConstrainedTraced {
            graph,
            values: all,
            mass: to_pairs(pairs),
            delassus: to_pairs(delassus),
            ..self
        }
    }

    /// Evaluates the graph in `f64`: the values, and whether every pivot passed the checks the
    /// generated function makes (`tolerance` of its unreduced value).
    pub fn eval(&self, input: impl Fn(Var) -> f64, tolerance: f64) -> (Vec<f64>, bool) {
        let all = self.graph.eval(&self.all_outputs(), input);
        let (values, pivots) = all.split_at(self.values.len());
        let ok = pivots.chunks(2).all(|pd| pd[0] > tolerance * pd[1]);
        (values.to_vec(), ok)
    }
}

/// Traces the constrained forward dynamics of `model` with `constraints` on `frames`, every
/// way `M` and `h` can be formed (specialized recursions, `M`'s off-diagonal entries in the root
/// frame or not, regrouped inertias or not), and keeps the fewest operations.
pub fn trace(model: &Model, frames: &[FrameAt], constraints: &[Constraint]) -> ConstrainedTraced {
    let variants = [false, true].into_iter().flat_map(|regrouped| {
        [Formulation::Specialized, Formulation::SpecializedRootFrame].map(|formulation| Variant {
            regrouped,
            formulation,
            method: None,
            analytic: false,
            coriolis: false,
            quasi_static: false,
        })
    });
    let traced: Vec<ConstrainedTraced> = variants
        .map(|v| trace_variant(model, frames, constraints, v).rebuilt(reciprocals))
        .collect();
    let candidates = traced.iter().map(|t| (t.variant, t.ops())).collect();
    let mut best = fewest(traced, |t| t.ops().total());
    best.candidates = candidates;
    best.rebuilt(reassociate)
}

fn trace_variant(
    model: &Model,
    frames: &[FrameAt],
    constraints: &[Constraint],
    variant: Variant,
) -> ConstrainedTraced {
    let (graph, (values, mass, delassus)) = sym::trace(|| {
        let (tree, turns) = symbolic_tree(model, variant.regrouped);
        let (c, nv) = (model.coupling(), model.nv());
        let (q, v, tau) = model_inputs(model, &c, &turns, variant, Var::Tau);
        let zero = vec![Sym::zero(); tree.nv];
        let m = c.reduce_matrix(&mass_matrix(variant.formulation, &tree, &q));
        let h = c.reduce(&rnea(variant.formulation, &tree, &q, &v, &zero, true));

        // The rows and drifts, on the tree's kinematics (regrouping moves no frame).
        let params = inputs(model.params.len(), Var::Param);
        let k = Kinematics::new(&tree, &q, &v);
        let placed: Vec<_> = frames.iter().map(|f| k.frame(f, &params)).collect();
        let (mut rows, mut drift) = rows_and_drift(&k, &c, &placed, constraints, &zero, nv);
        for (r, row) in rows.iter_mut().enumerate() {
            for (col, x) in row.iter_mut().enumerate() {
                *x = x.label(format_args!("j_{r}_{col}"));
            }
            drift[r] = drift[r].label(format_args!("gamma_{r}"));
        }
        let (mut values, mass, delassus) = solve(m, &h, &tau, &rows, &drift, nv);
        // Each six-dimensional contact's wrench from world axes into its frame's.
        let mut at = nv;
        for &constraint in constraints {
            if let Constraint::SixD(i) | Constraint::LoopSixD(i, _) = constraint {
                let w = placed[i].rotation;
                for part in 0..2 {
                    let s = at + 3 * part;
                    let x = w.tr_mul_vec(Vec3([values[s], values[s + 1], values[s + 2]]));
                    for (r, x) in x.0.into_iter().enumerate() {
                        values[s + r] = x.label(format_args!("force_{}", s + r - nv));
                    }
                }
            }
            at += constraint.rows();
        }
        (values, mass, delassus)
    });
    ConstrainedTraced {
        graph,
        values,
        mass,
        delassus,
        variant,
        candidates: Vec::new(),
    }
}

/// The constraints' rows (`nv` columns each) and drifts, stacked in order (module docs), from
/// the tree's kinematics with the frames placed on it; `zero` is `q̈ = 0` on the tree.
fn rows_and_drift(
    k: &Kinematics<'_, Sym>,
    c: &Coupling,
    placed: &[Frame<Sym>],
    constraints: &[Constraint],
    zero: &[Sym],
    nv: usize,
) -> (Vec<Vec<Sym>>, Vec<Sym>) {
    let point = |i: usize| -> (Vec<Vec<Sym>>, [Sym; 3]) {
        let j = c.reduce_columns(&k.jacobian(&placed[i], In::LocalWorldAligned), 6);
        let rows = (3..6).map(|r| j[r * nv..(r + 1) * nv].to_vec()).collect();
        let (_, ddp) = k.classical_acceleration(&placed[i], zero);
        (rows, ddp.0)
    };
    let mut rows: Vec<Vec<Sym>> = Vec::new();
    let mut drift: Vec<Sym> = Vec::new();
    for &constraint in constraints {
        match constraint {
            Constraint::Point(i) => {
                let (r, d) = point(i);
                rows.extend(r);
                drift.extend(d);
            }
            Constraint::SixD(i) => {
                // In world axes (module docs): the LOCAL_WORLD_ALIGNED Jacobian, the drift
                // `[ω̇; p̈ − ω × ṗ]`.
                let f = &placed[i];
                let j = c.reduce_columns(&k.jacobian(f, In::LocalWorldAligned), 6);
                rows.extend((0..6).map(|r| j[r * nv..(r + 1) * nv].to_vec()));
                let (dw, ddp) = k.classical_acceleration(f, zero);
                let (w, dp) = k.aligned_velocity(f);
                drift.extend(dw.0);
                drift.extend((ddp - w.cross(dp)).0);
            }
            Constraint::Loop(a, b) => {
                let ((ra, da), (rb, db)) = (point(a), point(b));
                for (x, y) in ra.into_iter().zip(rb) {
                    rows.push(x.iter().zip(&y).map(|(&x, &y)| x - y).collect());
                }
                drift.extend((Vec3(da) - Vec3(db)).0);
            }
            Constraint::LoopSixD(a, b) => {
                // In world axes at `a`'s origin (module docs): `b`'s motion moved to
                // `p_a` (`r = p_a − p_b`) subtracted from `a`'s.
                let (fa, fb) = (&placed[a], &placed[b]);
                let ja = c.reduce_columns(&k.jacobian(fa, In::LocalWorldAligned), 6);
                let jb = c.reduce_columns(&k.jacobian(fb, In::LocalWorldAligned), 6);
                let r = fa.origin - fb.origin;
                let at = |j: &[Sym], row: usize, col: usize| j[row * nv + col];
                let moved: Vec<Vec3<Sym>> = (0..nv)
                    .map(|col| r.cross(Vec3([at(&jb, 0, col), at(&jb, 1, col), at(&jb, 2, col)])))
                    .collect();
                let block = (0..6).map(|i| {
                    (0..nv)
                        .map(|col| {
                            let d = at(&ja, i, col) - at(&jb, i, col);
                            if i < 3 {
                                d
                            } else {
                                d + moved[col].0[i - 3]
                            }
                        })
                        .collect::<Vec<Sym>>()
                });
                rows.extend(block);
                let spatial = |f: &Frame<Sym>| {
                    let (dw, ddp) = k.classical_acceleration(f, zero);
                    let (w, dp) = k.aligned_velocity(f);
                    (dw, ddp - w.cross(dp), w, dp)
                };
                let (dwa, dva, wa, pa) = spatial(fa);
                let (dwb, dvb, wb, pb) = spatial(fb);
                // `b`'s velocity and drift at `p_a`; the drift is `W_a·(γ_a − ᵃX_b·γ_b +
                // v_a × ᵃX_b·v_b)`, the runtime's turned into world axes.
                let pb = pb + wb.cross(r);
                let dvb = dvb + dwb.cross(r);
                drift.extend((dwa - dwb + wa.cross(wb)).0);
                drift.extend((dva - dvb + wa.cross(pb) + pa.cross(wb)).0);
            }
        }
    }
    (rows, drift)
}

/// `(q̈ then f, M's pivots, G's pivots)` from `M` (row-major), `h`, `τ`, the rows and their
/// drift (module docs).
#[allow(clippy::type_complexity)]
fn solve(
    m: Vec<Sym>,
    h: &[Sym],
    tau: &[Sym],
    rows: &[Vec<Sym>],
    drift: &[Sym],
    n: usize,
) -> (Vec<Sym>, Vec<(Sym, Sym)>, Vec<(Sym, Sym)>) {
    let (ltdl, mass) = Ltdl::new(m, n);
    // `Lᵀ·x = b`, from the last coordinate up (the first half of `Ltdl::solve`).
    let upper = |mut x: Vec<Sym>| {
        for k in (0..n).rev() {
            for i in 0..k {
                x[i] = x[i] - ltdl.l[k * n + i] * x[k];
            }
        }
        x
    };
    let y: Vec<Sym> = upper(tau.iter().zip(h).map(|(&t, &h)| t - h).collect());
    let z: Vec<Vec<Sym>> = rows.iter().map(|r| upper(r.clone())).collect();
    // `D⁻¹·z` per row.
    let scaled: Vec<Vec<Sym>> = z
        .iter()
        .map(|z| z.iter().zip(&ltdl.inv_d).map(|(&z, &d)| z * d).collect())
        .collect();
    let dot = |a: &[Sym], b: &[Sym]| a.iter().zip(b).fold(Sym::zero(), |s, (&a, &b)| s + a * b);
    let r = rows.len();
    // `G` and `b` with their rows in reverse (module docs).
    let mut g = vec![Sym::zero(); r * r];
    let mut b = vec![Sym::zero(); r];
    for i in 0..r {
        for j in 0..=i {
            let x = dot(&scaled[i], &z[j]).label(format_args!("g_{i}_{j}"));
            g[(r - 1 - i) * r + (r - 1 - j)] = x;
            g[(r - 1 - j) * r + (r - 1 - i)] = x;
        }
        b[r - 1 - i] = (-drift[i] - dot(&scaled[i], &y)).label(format_args!("b_{i}"));
    }
    let (g_ltdl, g_pivots) = Ltdl::new(g, r);
    let reversed = g_ltdl.solve(b);
    let forces: Vec<Sym> = (0..r)
        .map(|i| reversed[r - 1 - i].label(format_args!("f_{i}")))
        .collect();
    let delassus = (0..r).map(|i| g_pivots[r - 1 - i]).collect();
    // `q̈ = L⁻¹·D⁻¹·(y + Z·f)`: `L·x = D⁻¹·(…)` from the first coordinate down.
    let mut x: Vec<Sym> = (0..n)
        .map(|k| {
            let s = z.iter().zip(&forces).fold(y[k], |s, (z, &f)| s + z[k] * f);
            s * ltdl.inv_d[k]
        })
        .collect();
    for k in 0..n {
        for i in 0..k {
            x[k] = x[k] - ltdl.l[k * n + i] * x[i];
        }
    }
    let values = x
        .into_iter()
        .enumerate()
        .map(|(k, x)| x.label(format_args!("qdd_{k}")))
        .chain(forces)
        .collect();
    (values, mass, delassus)
}
