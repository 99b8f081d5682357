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
//!
//! With a derivative output asked for, [`trace_derivatives`] adds the derivatives with respect
//! to `q`, `v` and `τ` (`constrained_forward_dynamics_derivatives`; Pinocchio's
//! `computeConstraintDynamicsDerivatives`). At the solution the residuals
//! `r₁ = ID(q, v, q̈) − Jᵀ·f − τ` and `r₂ = J·q̈ + γ` vanish for every `(q, v, τ)`, so at fixed
//! `(q̈, f)` (the runtime's `articulated::constraint::derivatives` derives the same)
//!
//! ```text
//! [M  −Jᵀ] [∂q̈]     [∂r₁]
//! [J   0 ] [∂f ] = − [∂r₂]
//! ```
//!
//! - `∂r₁` and `∂r₂` along each tangent direction by forward mode ([`Dual`]) through one
//!   Newton–Euler pass (`residuals`): the constraint forces enter it as external forces on
//!   their bodies (a six-dimensional wrench, fixed in its frame, is a constant of its body's
//!   frame: only the backward pass's transforms carry its derivative), and the constraints'
//!   accelerations come from the same pass's spatial accelerations. The structure folds away:
//!   a body's motion does not depend on the joints below it;
//! - each column solved with the factorizations of the solve above (`Kkt::solve`): `L⁻ᵀ`,
//!   the `Z` dot products, `G`'s `LᵀDL`, `L⁻¹`; for `τ`, `∂r₁ = −e_j`. Held in world axes as
//!   the solve is: a six-dimensional constraint's `∂r₂` turned by `W` (at the solution
//!   `r₂ = 0`, so `∂(W·r₂) = W·∂r₂`) and its `∂f` turned back by `Wᵀ`, with `f` held fixed in
//!   its frame.

use articulated_dynamics::model::{Coupling, Model};
use articulated_dynamics::reference::derivatives::{configuration_tangent, map_tree, Dual, Wrt};
use articulated_dynamics::reference::{project, transmit, Ltdl, Tree};
use articulated_dynamics::spatial::{Force, Inertia, Mat3, Motion, Vec3};
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
    trace_with(model, frames, constraints, false)
}

/// [`trace`] with the residuals `J·q̈ + γ` (one per row, world axes) and the derivatives after
/// the forces: `∂q̈/∂q`, `∂q̈/∂v`, `∂q̈/∂τ` (`nv × nv` each), then `∂f/∂q`, `∂f/∂v`, `∂f/∂τ`
/// (`rows × nv` each), row-major, `∂/∂q` along the configuration's tangent (module docs).
pub fn trace_derivatives(
    model: &Model,
    frames: &[FrameAt],
    constraints: &[Constraint],
) -> ConstrainedTraced {
    trace_with(model, frames, constraints, true)
}

/// [`trace`] with the derivatives ([`trace_derivatives`]'s values) or without.
fn trace_with(
    model: &Model,
    frames: &[FrameAt],
    constraints: &[Constraint],
    derivatives: bool,
) -> ConstrainedTraced {
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
        .map(|v| trace_variant(model, frames, constraints, v, derivatives).rebuilt(reciprocals))
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
    derivatives: bool,
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
        let (l, m_pivots) = Ltdl::new(m, nv);
        let solver = Kkt::new(l, &rows);
        let rhs: Vec<Sym> = tau.iter().zip(&h).map(|(&t, &h)| t - h).collect();
        let (qdd, world) = solver.solve(rhs, &drift);
        let qdd: Vec<Sym> = qdd
            .into_iter()
            .enumerate()
            .map(|(k, x)| x.label(format_args!("qdd_{k}")))
            .collect();
        let world: Vec<Sym> = world
            .into_iter()
            .enumerate()
            .map(|(i, x)| x.label(format_args!("f_{i}")))
            .collect();
        let forces: Vec<Sym> = to_frames(&placed, constraints, world)
            .into_iter()
            .enumerate()
            .map(|(i, x)| x.label(format_args!("force_{i}")))
            .collect();
        let mut values = qdd.clone();
        values.extend(&forces);
        if derivatives {
            // `max |J·q̈ + γ|` for the solution's report, then the derivatives.
            values.extend(rows.iter().zip(&drift).enumerate().map(|(r, (row, &d))| {
                let x = row.iter().zip(&qdd).fold(d, |s, (&j, &a)| s + j * a);
                x.label(format_args!("residual_{r}"))
            }));
            let at = Point {
                tree: &tree,
                coupling: &c,
                frames,
                constraints,
                params: &params,
                q: &q,
                v: &v,
            };
            values.extend(derivative_values(&at, &solver, &placed, &qdd, &forces));
        }
        (values, m_pivots, solver.pivots())
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

/// The constraint forces turned from world axes into each six-dimensional constraint's frame
/// (`Wᵀ·n`, `Wᵀ·f`), what the runtime returns; the others as they are.
fn to_frames<T: Scalar>(
    placed: &[Frame<T>],
    constraints: &[Constraint],
    mut forces: Vec<T>,
) -> Vec<T> {
    turn(placed, constraints, &mut forces, |w, x| w.tr_mul_vec(x));
    forces
}

/// Applies `by(W, part)` to each three-vector of each six-dimensional constraint's force, `W`
/// its frame's `world_R_frame`.
fn turn<T: Scalar>(
    placed: &[Frame<T>],
    constraints: &[Constraint],
    forces: &mut [T],
    by: impl Fn(&Mat3<T>, Vec3<T>) -> Vec3<T>,
) {
    let mut at = 0;
    for &constraint in constraints {
        if let Constraint::SixD(i) | Constraint::LoopSixD(i, _) = constraint {
            for part in 0..2 {
                let s = at + 3 * part;
                let x = by(
                    &placed[i].rotation,
                    Vec3([forces[s], forces[s + 1], forces[s + 2]]),
                );
                forces[s..s + 3].copy_from_slice(&x.0);
            }
        }
        at += constraint.rows();
    }
}

/// Where the derivatives are taken: the tree, its inputs and the constraints.
struct Point<'a> {
    tree: &'a Tree<Sym>,
    coupling: &'a Coupling,
    frames: &'a [FrameAt],
    constraints: &'a [Constraint],
    params: &'a [Sym],
    /// The tree's `q` and `v`.
    q: &'a [Sym],
    v: &'a [Sym],
}

/// The residuals at `(q, v)` on `tree` (a dual tree, for their derivatives), with `q̈` (the
/// model's) and `f` (the runtime's: six-dimensional wrenches in their frames) held fixed, both
/// from one Newton–Euler pass:
/// - `r₁ = ID(q, v, q̈) − Jᵀ·f` (`nv`): the constraint forces enter as external forces on their
///   bodies before the backward pass (a wrench fixed in a body's frame is a constant there);
/// - `r₂ = J·q̈ + γ`, the constraints' accelerations (one per row, in the solve's world axes),
///   from the pass's spatial accelerations. A six-dimensional contact's is its frame's spatial
///   acceleration in LOCAL (the runtime's row) turned by `w`, the value of its `world_R_frame`
///   as a constant: at the solution that acceleration is zero, so `∂(W·r₂) = W·∂r₂`, the
///   derivative the world-axes solve needs.
#[allow(clippy::too_many_arguments)]
fn residuals<T: Scalar>(
    tree: &Tree<T>,
    c: &Coupling,
    frames: &[FrameAt],
    constraints: &[Constraint],
    params: &[T],
    (q, v): (&[T], &[T]),
    (qdd, forces): (&[T], &[T]),
    w: &[Mat3<T>],
) -> Vec<T> {
    let a = c.expand_v(qdd);
    let k = Kinematics::new(tree, q, v);
    let placed: Vec<Frame<T>> = frames.iter().map(|f| k.frame(f, params)).collect();
    // Forward pass (RBDA Table 5.1), gravity as the base's acceleration.
    let a0 = tree.base_acceleration(true);
    let n = tree.nodes.len();
    let mut acc: Vec<Motion<T>> = Vec::with_capacity(n);
    let mut f: Vec<Force<T>> = Vec::with_capacity(n);
    for (i, node) in tree.nodes.iter().enumerate() {
        let v_i = k.vel[i];
        let a_i = match node.parent {
            None => k.x_up[i].apply_motion(a0) + node.s_mul(&a),
            Some(p) => {
                k.x_up[i].apply_motion(acc[p]) + node.s_mul(&a) + v_i.cross_motion(node.s_mul(v))
            }
        };
        let inertia = &node.inertia;
        f.push(inertia.mul_motion(a_i) + v_i.cross_force(inertia.mul_motion(v_i)));
        acc.push(a_i);
    }
    // A frame's motion in its body's axes: `(ω̇, a)` the spatial acceleration at its origin
    // (gravity's part taken out: `X_0·a₀ = [0; E·a₀]`) and `(ω, ṗ)` its velocity there.
    let motion = |fr: &Frame<T>| -> Option<[Vec3<T>; 4]> {
        let n = fr.node?;
        let (ac, ve) = (acc[n], k.vel[n]);
        let lin = ac.lin - k.x0[n].e.mul_vec(a0.lin);
        let p = fr.offset;
        Some([
            ac.ang,
            lin + ac.ang.cross(p),
            ve.ang,
            ve.lin + ve.ang.cross(p),
        ])
    };
    // `[ω̇; p̈]` and `[ω; ṗ]` of a frame's origin in world axes (classical).
    let classical = |fr: &Frame<T>| -> [Vec3<T>; 4] {
        let Some([dw, a, om, dp]) = motion(fr) else {
            return [Vec3::zero(); 4];
        };
        let to_world = |x: Vec3<T>| fr.node.map_or(x, |n| k.x0[n].e.tr_mul_vec(x));
        [
            to_world(dw),
            to_world(a + om.cross(dp)),
            to_world(om),
            to_world(dp),
        ]
    };
    // `wrench` (about the frame's origin, in its body's axes) on the frame's body.
    let mut push = |fr: &Frame<T>, n_b: Vec3<T>, f_b: Vec3<T>| {
        if let Some(n) = fr.node {
            f[n] = f[n] - Force::new(n_b + fr.offset.cross(f_b), f_b);
        }
    };
    let three = |at: usize| Vec3([forces[at], forces[at + 1], forces[at + 2]]);
    let body = |fr: &Frame<T>, x: Vec3<T>| fr.node.map_or(x, |n| k.x0[n].e.mul_vec(x));
    let mut r2: Vec<T> = Vec::with_capacity(forces.len());
    let mut at = 0;
    for &constraint in constraints {
        match constraint {
            Constraint::Point(i) => {
                let fr = &placed[i];
                push(fr, Vec3::zero(), body(fr, three(at)));
                r2.extend(classical(fr)[1].0);
            }
            Constraint::SixD(i) => {
                let fr = &placed[i];
                let (n_l, f_l) = (three(at), three(at + 3));
                push(fr, fr.in_body.mul_vec(n_l), fr.in_body.mul_vec(f_l));
                let [dw, a, ..] = motion(fr).unwrap_or([Vec3::zero(); 4]);
                let local = [fr.in_body.tr_mul_vec(dw), fr.in_body.tr_mul_vec(a)];
                r2.extend(local.into_iter().flat_map(|x| w[i].mul_vec(x).0));
            }
            Constraint::Loop(a, b) => {
                let f_w = three(at);
                push(&placed[a], Vec3::zero(), body(&placed[a], f_w));
                push(&placed[b], Vec3::zero(), body(&placed[b], -f_w));
                r2.extend((classical(&placed[a])[1] - classical(&placed[b])[1]).0);
            }
            Constraint::LoopSixD(a, b) => {
                let (fa, fb) = (&placed[a], &placed[b]);
                let (n_l, f_l) = (three(at), three(at + 3));
                push(fa, fa.in_body.mul_vec(n_l), fa.in_body.mul_vec(f_l));
                // The opposite wrench on `b`, at `a`'s origin: about `b`'s origin in `b`'s axes.
                let r = fa.origin - fb.origin;
                let (n_w, f_w) = (fa.rotation.mul_vec(n_l), fa.rotation.mul_vec(f_l));
                push(fb, -body(fb, n_w + r.cross(f_w)), -body(fb, f_w));
                // The world-axes rows of `rows_and_drift` at the pass's accelerations.
                r2.extend(six_d_loop_acceleration(classical(fa), classical(fb), r));
            }
        }
        at += constraint.rows();
    }
    transmit(tree, &k.x_up, &mut f);
    let mut tau = project(tree, &f);
    for node in &tree.nodes {
        node.add_armature(&a, &mut tau);
    }
    let mut out = c.reduce(&tau);
    out.extend(r2);
    out
}

/// The residuals' derivatives at `(q, v)` with `(q̈, f)` held fixed: `∂r/∂q` and `∂r/∂v`,
/// `r = (r₁, r₂)` (`(nv + rows) × nv` each, row-major, `∂/∂q` along the configuration's
/// tangent), by forward mode ([`residuals`] on duals, one pass per tangent direction); and
/// `r₂ = J·q̈ + γ` itself. `r₂` in world axes (`world`: the solve's), or in the runtime's
/// (a six-dimensional constraint's rows in its frame: the composed derivatives').
fn residual_jacobians(
    at: &Point<'_>,
    placed: &[Frame<Sym>],
    qdd: &[Sym],
    forces: &[Sym],
    world: bool,
) -> (Vec<Sym>, Vec<Sym>, Vec<Sym>) {
    let (tree, c) = (at.tree, at.coupling);
    let (nv, rows, nt) = (qdd.len(), forces.len(), tree.nv);
    let dual_tree = map_tree(tree, Dual::constant);
    let constant = |x: &[Sym]| -> Vec<Dual<Sym>> { x.iter().map(|&x| Dual::constant(x)).collect() };
    let (qc, vc, params) = (constant(at.q), constant(at.v), constant(at.params));
    let (qdd_c, forces_c) = (constant(qdd), constant(forces));
    // Each frame's `world_R_frame` as a constant: at the solution `r₂ = 0`, so a turned
    // residual's derivative is the turned derivative.
    let w: Vec<Mat3<Dual<Sym>>> = placed
        .iter()
        .map(|f| Mat3(f.rotation.0.map(|r| r.map(Dual::constant))))
        .collect();
    let identity = vec![Mat3::identity(); placed.len()];
    let run = |q: &[Dual<Sym>], v: &[Dual<Sym>]| -> Vec<Dual<Sym>> {
        let mut r = residuals(
            &dual_tree,
            c,
            at.frames,
            at.constraints,
            &params,
            (q, v),
            (&qdd_c, &forces_c),
            if world { &w } else { &identity },
        );
        if !world {
            // A six-dimensional loop's rows, in world axes at `a`'s origin, into `a`'s frame.
            let mut start = nv;
            for &constraint in at.constraints {
                if let Constraint::LoopSixD(a, _) = constraint {
                    for s in [start, start + 3] {
                        let x = w[a].tr_mul_vec(Vec3([r[s], r[s + 1], r[s + 2]]));
                        r[s..s + 3].copy_from_slice(&x.0);
                    }
                }
                start += constraint.rows();
            }
        }
        r
    };
    // Columns by tree velocity, `(nv + rows) × nt` row-major, then through the coupling.
    let n = nv + rows;
    let mut by_q = vec![Sym::zero(); n * nt];
    let mut by_v = vec![Sym::zero(); n * nt];
    let mut r2 = Vec::new();
    for k in 0..nt {
        let tangent = configuration_tangent(tree, at.q, k);
        let qk: Vec<Dual<Sym>> =
            at.q.iter()
                .zip(tangent)
                .map(|(&x, d)| Dual::seeded(x, d, Wrt::Q(k)))
                .collect();
        let r = run(&qk, &vc);
        if k == 0 {
            r2 = r[nv..].iter().map(|x| x.re).collect();
        }
        for (i, x) in r.into_iter().enumerate() {
            by_q[i * nt + k] = x.du;
        }
        let vk: Vec<Dual<Sym>> = at
            .v
            .iter()
            .enumerate()
            .map(|(i, &x)| Dual::seeded(x, Sym::from_f64(f64::from(u8::from(i == k))), Wrt::V(k)))
            .collect();
        for (i, x) in run(&qc, &vk).into_iter().enumerate() {
            by_v[i * nt + k] = x.du;
        }
    }
    (c.reduce_columns(&by_q, n), c.reduce_columns(&by_v, n), r2)
}

/// `∂q̈/∂q`, `∂q̈/∂v`, `∂q̈/∂τ` (`nv × nv` each), then `∂f/∂q`, `∂f/∂v`, `∂f/∂τ` (`rows × nv`
/// each), row-major (module docs): the residuals' derivatives along each tangent direction by
/// forward mode ([`residual_jacobians`]), each column solved with the solve's factorizations.
fn derivative_values(
    at: &Point<'_>,
    solver: &Kkt,
    placed: &[Frame<Sym>],
    qdd: &[Sym],
    forces: &[Sym],
) -> Vec<Sym> {
    let (nv, rows) = (qdd.len(), forces.len());
    let n = nv + rows;
    let (by_q, by_v, _) = residual_jacobians(at, placed, qdd, forces, true);
    // Each column solved: `(∂q̈, ∂f)` for `(∂r₁, ∂r₂)`; for `τ`, `∂r₁ = −e_j`, `∂r₂ = 0`.
    let column = |m: &[Sym], j: usize| -> (Vec<Sym>, Vec<Sym>) {
        let dr1: Vec<Sym> = (0..nv).map(|i| -m[i * nv + j]).collect();
        let dr2: Vec<Sym> = (nv..n).map(|i| m[i * nv + j]).collect();
        let (x, f) = solver.solve(dr1, &dr2);
        (x, to_frames(placed, at.constraints, f))
    };
    let zeros = vec![Sym::zero(); rows];
    let by_tau = |j: usize| -> (Vec<Sym>, Vec<Sym>) {
        let e: Vec<Sym> = (0..nv)
            .map(|i| Sym::from_f64(f64::from(u8::from(i == j))))
            .collect();
        let (x, f) = solver.solve(e, &zeros);
        (x, to_frames(placed, at.constraints, f))
    };
    let solved: [Vec<(Vec<Sym>, Vec<Sym>)>; 3] = [
        (0..nv).map(|j| column(&by_q, j)).collect(),
        (0..nv).map(|j| column(&by_v, j)).collect(),
        (0..nv).map(by_tau).collect(),
    ];
    let mut values = Vec::with_capacity(3 * n * nv);
    for (stem, columns) in ["dqdd_dq", "dqdd_dv", "dqdd_dtau"].iter().zip(&solved) {
        for i in 0..nv {
            values.extend((0..nv).map(|j| columns[j].0[i].label(format_args!("{stem}_{i}_{j}"))));
        }
    }
    for (stem, columns) in ["dforce_dq", "dforce_dv", "dforce_dtau"]
        .iter()
        .zip(&solved)
    {
        for i in 0..rows {
            values.extend((0..nv).map(|j| columns[j].1[i].label(format_args!("{stem}_{i}_{j}"))));
        }
    }
    values
}

/// The constraints' part of the residuals' derivatives, for the composed
/// `constrained_forward_dynamics_derivatives`: a graph of `q`, `v`, `q̈` (inputs `A`) and the
/// forces (inputs `Force`) whose values are `∂c/∂q`, `∂c/∂v` (`(nv + rows) × nv` each,
/// row-major) with `c = r − (ID(q, v, q̈), 0) = (−Jᵀ·f, J·q̈ + γ)`, `r = (r₁, r₂)`
/// ([`residuals`]); then the rows `J` (`rows × nv`, row-major) and `r₂` itself; all in the
/// runtime's axes (a six-dimensional constraint's rows and wrench in its frame, as
/// `constrained_forward_dynamics` returns the wrench). Inverse dynamics' share, the larger,
/// is `inverse_dynamics_derivatives` at `(q, v, q̈)`: here the bodies are massless, and the
/// forces alone load the backward pass.
pub fn trace_constraint_terms(
    model: &Model,
    frames: &[FrameAt],
    constraints: &[Constraint],
) -> (Graph, Vec<Sym>) {
    let rows: usize = constraints.iter().map(|c| c.rows()).sum();
    let nv = model.nv();
    let variant = Variant {
        regrouped: false,
        formulation: Formulation::Specialized,
        method: None,
        analytic: false,
        coriolis: false,
        quasi_static: false,
    };
    let (graph, values) = sym::trace(|| {
        let (mut tree, turns) = symbolic_tree(model, false);
        for node in &mut tree.nodes {
            node.inertia = Inertia::zero();
        }
        let c = model.coupling();
        let (q, v, qdd) = model_inputs(model, &c, &turns, variant, Var::A);
        let forces = inputs(rows, Var::Force);
        let params = inputs(model.params.len(), Var::Param);
        let k = Kinematics::new(&tree, &q, &v);
        let placed: Vec<_> = frames.iter().map(|f| k.frame(f, &params)).collect();
        let at = Point {
            tree: &tree,
            coupling: &c,
            frames,
            constraints,
            params: &params,
            q: &q,
            v: &v,
        };
        let (by_q, by_v, r2) = residual_jacobians(&at, &placed, &qdd, &forces, false);
        let zero = vec![Sym::zero(); tree.nv];
        let (world_rows, _) = rows_and_drift(&k, &c, &placed, constraints, &zero, nv);
        // Each column's six-dimensional rows turned into their frames (`Wᵀ`).
        let mut rows_j = vec![Sym::zero(); rows * nv];
        for col in 0..nv {
            let mut x: Vec<Sym> = world_rows.iter().map(|r| r[col]).collect();
            turn(&placed, constraints, &mut x, |w, x| w.tr_mul_vec(x));
            for (r, x) in x.into_iter().enumerate() {
                rows_j[r * nv + col] = x;
            }
        }
        let label = |stem: &'static str, x: Vec<Sym>| {
            x.into_iter()
                .enumerate()
                .map(move |(i, x)| x.label(format_args!("{stem}_{}_{}", i / nv, i % nv)))
        };
        let mut values: Vec<Sym> = label("dc_dq", by_q).chain(label("dc_dv", by_v)).collect();
        values.extend(label("j", rows_j));
        values.extend(
            r2.into_iter()
                .enumerate()
                .map(|(i, x)| x.label(format_args!("residual_{i}"))),
        );
        values
    });
    let (graph, values) = reciprocals(&graph, &values);
    reassociate(&graph, &values)
}

/// The constraints' rows (`nv` columns each) and drifts, stacked in order (module docs), from
/// the tree's kinematics with the frames placed on it; `zero` is `q̈ = 0` on the tree.
fn rows_and_drift<T: Scalar>(
    k: &Kinematics<'_, T>,
    c: &Coupling,
    placed: &[Frame<T>],
    constraints: &[Constraint],
    zero: &[T],
    nv: usize,
) -> (Vec<Vec<T>>, Vec<T>) {
    let point = |i: usize| -> (Vec<Vec<T>>, [T; 3]) {
        let j = c.reduce_columns(&k.jacobian(&placed[i], In::LocalWorldAligned), 6);
        let rows = (3..6).map(|r| j[r * nv..(r + 1) * nv].to_vec()).collect();
        let (_, ddp) = k.classical_acceleration(&placed[i], zero);
        (rows, ddp.0)
    };
    let mut rows: Vec<Vec<T>> = Vec::new();
    let mut drift: Vec<T> = Vec::new();
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
                let at = |j: &[T], row: usize, col: usize| j[row * nv + col];
                let moved: Vec<Vec3<T>> = (0..nv)
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
                        .collect::<Vec<T>>()
                });
                rows.extend(block);
                let classical = |f: &Frame<T>| {
                    let (dw, ddp) = k.classical_acceleration(f, zero);
                    let (w, dp) = k.aligned_velocity(f);
                    [dw, ddp, w, dp]
                };
                drift.extend(six_d_loop_acceleration(classical(fa), classical(fb), r));
            }
        }
    }
    (rows, drift)
}

/// A six-dimensional loop's acceleration in world axes at `a`'s origin, `W_a·(a_a − ᵃX_b·a_b +
/// v_a × ᵃX_b·v_b)` (the runtime's, LOCAL of `a`, turned into world axes), from each frame's
/// classical `[ω̇, p̈, ω, ṗ]` in world axes and `r = p_a − p_b`: `b`'s velocity and spatial
/// acceleration moved to `p_a`. Six values, angular first.
fn six_d_loop_acceleration<T: Scalar>(a: [Vec3<T>; 4], b: [Vec3<T>; 4], r: Vec3<T>) -> Vec<T> {
    let [dwa, ddpa, wa, pa] = a;
    let [dwb, ddpb, wb, pb] = b;
    let dva = ddpa - wa.cross(pa);
    let dvb = ddpb - wb.cross(pb) + dwb.cross(r);
    let pb = pb + wb.cross(r);
    let mut out = (dwa - dwb + wa.cross(wb)).0.to_vec();
    out.extend((dva - dvb + wa.cross(pb) + pa.cross(wb)).0);
    out
}

/// The constrained system factored (module docs): `M = LᵀDL`, `Z = L⁻ᵀ·Jᵀ` by row of `J`,
/// `D⁻¹·Z`, and `G = Zᵀ·D⁻¹·Z = LᵀDL` with its rows in reverse.
struct Kkt {
    l: Ltdl<Sym>,
    z: Vec<Vec<Sym>>,
    scaled: Vec<Vec<Sym>>,
    g: Ltdl<Sym>,
    g_pivots: Vec<(Sym, Sym)>,
}

impl Kkt {
    fn new(l: Ltdl<Sym>, rows: &[Vec<Sym>]) -> Self {
        let z: Vec<Vec<Sym>> = rows
            .iter()
            .map(|r| l_transpose_solve(&l, r.clone()))
            .collect();
        // `D⁻¹·z` per row.
        let scaled: Vec<Vec<Sym>> = z
            .iter()
            .map(|z| z.iter().zip(&l.inv_d).map(|(&z, &d)| z * d).collect())
            .collect();
        let r = rows.len();
        // `G` with its rows in reverse (module docs).
        let mut g = vec![Sym::zero(); r * r];
        for i in 0..r {
            for j in 0..=i {
                let x = dot(&scaled[i], &z[j]).label(format_args!("g_{i}_{j}"));
                g[(r - 1 - i) * r + (r - 1 - j)] = x;
                g[(r - 1 - j) * r + (r - 1 - i)] = x;
            }
        }
        let (g, g_pivots) = Ltdl::new(g, r);
        Kkt {
            l,
            z,
            scaled,
            g,
            g_pivots,
        }
    }

    /// `G`'s pivots with their unreduced values, by row.
    fn pivots(&self) -> Vec<(Sym, Sym)> {
        self.g_pivots.iter().rev().copied().collect()
    }

    /// `(x, f)` with `M·x = b + Jᵀ·f` and `J·x + c = 0`: `y = L⁻ᵀ·b`, `G·f = −c − Zᵀ·D⁻¹·y`,
    /// `x = L⁻¹·D⁻¹·(y + Z·f)`. `f` in the rows' axes.
    fn solve(&self, b: Vec<Sym>, c: &[Sym]) -> (Vec<Sym>, Vec<Sym>) {
        let (l, n, r) = (&self.l, self.l.n, self.z.len());
        let y = l_transpose_solve(l, b);
        let mut rhs = vec![Sym::zero(); r];
        for i in 0..r {
            rhs[r - 1 - i] = (-c[i] - dot(&self.scaled[i], &y)).label(format_args!("b_{i}"));
        }
        let reversed = self.g.solve(rhs);
        let f: Vec<Sym> = (0..r).map(|i| reversed[r - 1 - i]).collect();
        // `L·x = D⁻¹·(…)` from the first coordinate down.
        let mut x: Vec<Sym> = (0..n)
            .map(|k| {
                let s = self.z.iter().zip(&f).fold(y[k], |s, (z, &f)| s + z[k] * f);
                s * l.inv_d[k]
            })
            .collect();
        for k in 0..n {
            for i in 0..k {
                x[k] = x[k] - l.l[k * n + i] * x[i];
            }
        }
        (x, f)
    }
}

/// `L⁻ᵀ·b`: `Lᵀ·x = b` from the last coordinate up (the first half of `Ltdl::solve`).
fn l_transpose_solve(l: &Ltdl<Sym>, mut x: Vec<Sym>) -> Vec<Sym> {
    let n = l.n;
    for k in (0..n).rev() {
        for i in 0..k {
            x[i] = x[i] - l.l[k * n + i] * x[k];
        }
    }
    x
}

fn dot(a: &[Sym], b: &[Sym]) -> Sym {
    a.iter().zip(b).fold(Sym::zero(), |s, (&a, &b)| s + a * b)
}
