//! Tracing: each output's recursion run on the symbolic scalar ([`crate::sym`]) into an
//! expression graph, several ways, and the way with the fewest operations kept.
//!
//! The recursions traced are the reference's own generic code
//! (`articulated_dynamics::reference`: RNEA, CRBA, ABA, the sparse `LᵀDL`), instantiated on
//! [`Sym`]: what the reference computes in `f64` at run time, the generator records once, folds
//! and emits. Beside them, formulations written for the generator compute the same values in
//! fewer operations:
//! - [`regroup`]: the inertial parameters regrouped first (Khalil's base parameters);
//! - [`newton_euler`]: Newton–Euler on classical accelerations, for bias, gravity and inverse
//!   dynamics;
//! - [`crba`]: a CRBA that carries composite inertias by their upper triangle and through
//!   coordinate-axis revolute joints by double angles, for `M`;
//! - [`forward`]: forward dynamics by ABA or by CRBA + `LᵀDL`.
//!
//! The quantities of the whole system (centre of mass, momenta, energies, the Coriolis matrix)
//! are the reference's `articulated_dynamics::reference::centroidal`; the centroidal momentum
//! matrix and the Coriolis matrix are also traced with their composite inertias carried as
//! [`crba`] carries them. Regrouping moves mass between bodies, so only the kinetic energy and
//! the Coriolis matrix, which depend on `M(q)` alone, are traced on regrouped inertias too.
//!
//! Every [`Variant`] of an output is traced; [`trace`] keeps the one with the fewest operations
//! (the first of equals; each counted after its divisions by a shared divisor became products by
//! one reciprocal, [`crate::optimize::reciprocals()`]), then regroups its sums by arrival time
//! ([`crate::optimize::reassociate()`]). All
//! variants compute the same values (each formulation's tests hold it to the reference); they
//! round differently.

pub mod condensed;
pub mod constrained;
pub mod crba;
pub mod derivatives;
pub mod forward;
pub mod frames;
pub mod newton_euler;
pub mod regroup;
pub(crate) mod turns;

use std::fmt;

use articulated_dynamics::model::{Coupling, JointKind, Model};
use articulated_dynamics::reference::{self, centroidal, Tree};
use articulated_dynamics::spatial::{Force, Transform, Vec3};
use articulated_dynamics::Scalar;

use crate::optimize::{reassociate, reciprocals};
use crate::options::{Accuracy, Output};
use crate::sym::{self, Graph, OpCounts, Sym, Var};
pub use forward::FdMethod;
use turns::Turn;

/// The recursion traced for an output: the reference's, or the one written for the generator
/// that computes the same values in fewer operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// The reference's own recursion (spatial RNEA, CRBA, ABA).
    Reference,
    /// For `M`: [`crba`] (symmetric composite inertias, double angles); for bias, gravity and
    /// inverse dynamics (and `h` in forward dynamics): [`newton_euler`] (classical
    /// accelerations).
    Specialized,
    /// As [`Formulation::Specialized`], with `M`'s entries between a joint and its ancestors
    /// taken in the root body's frame ([`crba::crba_in_root_frame`]): fewer operations on long
    /// chains. Traced only where `M` is.
    SpecializedRootFrame,
}

impl Formulation {
    /// Whether bias, gravity and inverse dynamics use [`newton_euler`].
    pub fn specialized(self) -> bool {
        self != Formulation::Reference
    }
}

/// One way of tracing an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// Whether the inertias were regrouped first ([`regroup`]).
    pub regrouped: bool,
    /// The recursion for `M` and the Newton–Euler terms.
    pub formulation: Formulation,
    /// Forward dynamics only: ABA or CRBA + `LᵀDL`.
    pub method: Option<FdMethod>,
    /// Derivatives only: `∂τ` by the analytical recursion of Carpentier & Mansard (world frame)
    /// instead of forward-mode duals through the Newton–Euler `formulation`.
    pub analytic: bool,
    /// Derivatives only: `∂τ/∂v` as `2·N(q, v)`, twice the Coriolis matrix (the Christoffel
    /// one, exact wherever `v = q̇`: traced only for chains without quaternion joints).
    pub coriolis: bool,
    /// Quasi-static: traced with `v = 0`, so every velocity-product term folds away.
    pub quasi_static: bool,
}

impl fmt::Display for Variant {
    /// A short description for docs and reports: "ABA, regrouped inertias".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut parts: Vec<&str> = Vec::new();
        if let Some(m) = self.method {
            parts.push(m.name());
        }
        if self.method != Some(FdMethod::Aba) {
            parts.push(match self.formulation {
                Formulation::Reference => "reference recursions",
                Formulation::Specialized => "specialized recursions",
                Formulation::SpecializedRootFrame => {
                    "specialized recursions, M's off-diagonal entries in the root frame"
                }
            });
        }
        if self.analytic {
            parts.push("analytical derivatives");
        }
        if self.coriolis {
            parts.push("∂τ/∂v = 2·N");
        }
        if self.regrouped {
            parts.push("regrouped inertias");
        }
        if self.quasi_static {
            parts.push("quasi-static (v = 0)");
        }
        write!(f, "{}", parts.join(", "))
    }
}

/// The checks of forward dynamics' factorization: each pivot with the unreduced value it is
/// compared to, and the sum of the unreduced values, which every pivot is compared to as well.
#[derive(Clone, Debug)]
pub struct Pivots {
    /// `(pivot, unreduced)` per velocity coordinate.
    pub pairs: Vec<(Sym, Sym)>,
    /// Per velocity coordinate, whether nothing was eliminated from the pivot, so that it carries
    /// no rounding noise from the rest of the tree and only needs to be positive against its
    /// unreduced value, not against the scale: for `LᵀDL`, a pivot that is its own unreduced
    /// value `M_kk` (the first of the factorization); for ABA, whose unreduced values are already
    /// articulated, the pivots of a leaf body's joint. A body 1e12 lighter than the rest, or a
    /// slender one, at the leaves then passes in `f32` too.
    pub exact: Vec<bool>,
    /// Whether these are ABA's pivots (held to [`PIVOT_TOL_GLOBAL_ABA_F64`]) rather than an
    /// `LᵀDL`'s.
    pub aba: bool,
    /// The sum of the unreduced values.
    pub scale: Sym,
    /// A velocity coordinate at whose pivot `M(q)` is singular at every configuration
    /// ([`singular_everywhere`]): the generated function refuses every state there, in every
    /// scalar, rather than trust its rounding noise to fail the comparisons.
    pub singular: Option<usize>,
}

impl Pivots {
    /// The pivots of an `LᵀDL` with the sum of their unreduced values (inside the trace); a
    /// pivot that is its own unreduced value is exact ([`Pivots::exact`]).
    pub(crate) fn with_scale(pairs: Vec<(Sym, Sym)>) -> Pivots {
        let exact = pairs.iter().map(|&(p, d)| p == d).collect();
        Pivots::with_exact(pairs, exact, false)
    }

    /// The pivots with the sum of their unreduced values, which are exact, and whether they
    /// are ABA's.
    pub(crate) fn with_exact(pairs: Vec<(Sym, Sym)>, exact: Vec<bool>, aba: bool) -> Pivots {
        let scale = pairs
            .iter()
            .map(|p| p.1)
            .reduce(|a, b| a + b)
            .unwrap_or_else(Sym::zero)
            .label(format_args!("pivot_scale"));
        Pivots {
            pairs,
            scale,
            exact,
            aba,
            singular: None,
        }
    }
}

/// The velocity coordinate of the first pivot (in elimination order) at which `M(q)` of
/// `model` is singular at every configuration, if it is: a massless body whose motion another
/// coordinate duplicates (a free base over a massless root, whose rotation about the first
/// joint's axis moves nothing that the joint does not), joints that move no mass.
///
/// Such a pivot is rounding noise in every state, and noise is not small enough to be told
/// from a pivot by comparing it with anything: `arm6_mixed` on a free base over its massless
/// root gives pivots up to 8e-12 of their unreduced values in `f64` and 6e-4 in `f32` (tens of
/// thousands of ulps), above the 1e-6 to 1e-2 at which light limbs of regular trees stand. So
/// the generator decides it once: `M` is factored in double-double (about 32 digits) at three
/// fixed, generic configurations, and a coordinate whose pivot is below 1e-20 of the trace at
/// all three is singular everywhere (a regular configuration of any model this project
/// generates stands many orders of magnitude above that; exact singularity at 1e-30).
pub fn singular_everywhere(model: &Model) -> Option<usize> {
    use articulated_dynamics::extended::Dd;
    use articulated_dynamics::reference::{crba, ltdl_factor};
    let params: Vec<Dd> = model
        .param_defaults()
        .iter()
        .map(|&p| Dd::from_f64(p))
        .collect();
    let tree = Tree::new(model, &params);
    let (c, nv) = (model.coupling(), model.nv());
    let mut found = None;
    for sample in 1..=3u32 {
        let q = generic_configuration(model, sample);
        let q: Vec<Dd> = c.expand_q(&q).iter().map(|&x| Dd::from_f64(x)).collect();
        let m = c.reduce_matrix(&crba(&tree, &q));
        let (_, pivots) = ltdl_factor(m, nv);
        let trace = pivots.iter().fold(0.0, |s, p| s + p.1.to_f64().abs());
        // In elimination order: from the last coordinate to the first.
        let k = (0..nv)
            .rev()
            .find(|&k| pivots[k].0.to_f64() <= 1e-20 * trace)?;
        if found.is_some_and(|f| f != k) {
            return None;
        }
        found = Some(k);
    }
    found
}

/// A configuration of `model` with every coordinate away from zero and from the others
/// (`sample` picks one of several), each quaternion normalized: generic, so that no singularity
/// of a particular configuration (gimbal lock, a straight arm) shows.
fn generic_configuration(model: &Model, sample: u32) -> Vec<f64> {
    let mut q = model.neutral();
    for (i, x) in q.iter_mut().enumerate() {
        // Irrational steps: no two coordinates alike, none at a multiple of π/2.
        let t = (i as f64 + 1.0) * 0.618_033_988_749_895 + f64::from(sample) * 0.414_213_562_373;
        *x += 0.3 + 0.9 * (t - t.floor());
    }
    for (j, joint) in model.joints.iter().enumerate() {
        let at = match joint.kind {
            JointKind::SphericalQuaternion if joint.mimic.is_none() => model.q_offset(j),
            JointKind::FreeQuaternion => model.q_offset(j) + 3,
            _ => continue,
        };
        let n = q[at..at + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[at..at + 4].iter_mut().for_each(|x| *x /= n);
    }
    q
}

/// Relative pivot tolerance of generated forward dynamics: a pivot must exceed this fraction of
/// its unreduced value (the same test as the reference's ABA). The unreduced value bounds what
/// elimination subtracted from the pivot, so a pivot below it is rounding noise: what is
/// singular for the scalar (gimbal lock, about `δ²` for an Euler angle `δ` from it).
pub const PIVOT_TOL_F64: f64 = 1e-13;
/// The same for `f32` (its epsilon is 1.2e-7): 84 ε, where `f64`'s is 450 ε. Since an `f32`
/// `LᵀDL` has no test against the trace (below), this one alone refuses a state near gimbal
/// lock: at 1e-6 the two-link 1e-3 rad from it was solved with `q̈` 12 % off (`cond(M)`
/// 7.4e6); at 1e-5 it is refused, as `accuracy = robust` refuses it. Regular trees stand far
/// above it (the humanoid's lowest, 7e-3).
pub const PIVOT_TOL_F32: f64 = 1e-5;
/// Every pivot of an `LᵀDL` must also exceed this fraction of the sum of all unreduced pivots
/// (the trace of `M`). A pivot of an exactly singular `M` comes out as rounding noise, about
/// ε·trace(M) times some growth, which can pass the test against its own unreduced value (a
/// massless root under a free base: the pivot of 1e-16 against `M_kk` of 1e-3, and Pinocchio's
/// `arm6_mixed` on a free base, where 1e-15 let 1e14 through); against the trace it cannot.
/// Legitimate pivots of ill-conditioned chains (κ up to 1e11) pass; a pivot nothing was
/// eliminated from is exempt ([`Pivots::exact`]).
///
/// `f32` has no such test for an `LᵀDL`: a limb joint's pivot is a small fraction of a trace
/// that a heavy base dominates (the humanoid's wrists stand at 2.5e-6 of it, against `f32`'s
/// 1.2e-7 epsilon), while the noise of an exactly singular `M` reaches 7e-5 of it, so no
/// threshold separates the two. What the test was for, an `M` singular at every configuration,
/// the generator finds itself ([`singular_everywhere`]); an `f32` pivot is held to its own
/// unreduced value ([`PIVOT_TOL_F32`]).
pub const PIVOT_TOL_GLOBAL_F64: f64 = 1e-12;
/// The same for ABA's pivots, as the reference's (1e-15 of the largest): ABA keeps its digits
/// where `M` is ill-conditioned, so what the reference solves passes too (a body 1e12 times
/// lighter than the rest, a slender body with an axial moment 1e-12 of the others').
pub const PIVOT_TOL_GLOBAL_ABA_F64: f64 = 1e-15;
/// The same for `f32`: a few times its epsilon.
pub const PIVOT_TOL_GLOBAL_ABA_F32: f64 = 1e-6;

/// One output traced into its own graph.
#[derive(Debug)]
pub struct Traced {
    /// Which output.
    pub output: Output,
    /// The expression graph.
    pub graph: Graph,
    /// The values, in order: `M` row-major for the mass matrix (its lower triangle, row by row,
    /// for `mass_matrix_lower`), one per velocity otherwise.
    pub values: Vec<Sym>,
    /// Forward dynamics only: the factorization's checks.
    pub pivots: Option<Pivots>,
    /// The variant kept.
    pub variant: Variant,
    /// Every variant traced, with its operation count, in the order traced.
    pub candidates: Vec<(Variant, OpCounts)>,
}

impl Traced {
    /// Operations the emitted function performs (values and pivot checks).
    pub fn ops(&self) -> OpCounts {
        self.graph.op_counts(&self.all_outputs())
    }

    /// The values, then each pivot and its unreduced value, then the scale.
    pub fn all_outputs(&self) -> Vec<Sym> {
        let mut all = self.values.clone();
        if let Some(p) = &self.pivots {
            all.extend(p.pairs.iter().flat_map(|&(p, d)| [p, d]));
            all.push(p.scale);
        }
        all
    }

    /// The same values with every sum regrouped so that late terms are added last
    /// ([`crate::optimize::reassociate()`]): no more operations, a shorter critical path.
    fn reassociated(self) -> Traced {
        self.rebuilt(reassociate)
    }

    /// The same values with one division per divisor and products by its reciprocal for the
    /// rest ([`crate::optimize::reciprocals()`]).
    fn with_reciprocals(self) -> Traced {
        self.rebuilt(reciprocals)
    }

    /// The values, pivots and scale rebuilt by `pass`, which returns its new graph and the
    /// outputs it was given, in order.
    fn rebuilt(self, pass: impl FnOnce(&Graph, &[Sym]) -> (Graph, Vec<Sym>)) -> Traced {
        let (graph, mut all) = pass(&self.graph, &self.all_outputs());
        let pivots = self.pivots.as_ref().map(|_| {
            let scale = all
                .pop()
                .unwrap_or_else(|| unreachable!("the scale is last"));
            let pairs = all.split_off(self.values.len());
            Pivots {
                pairs: pairs.chunks(2).map(|pd| (pd[0], pd[1])).collect(),
                scale,
                exact: self
                    .pivots
                    .as_ref()
                    .map_or_else(Vec::new, |p| p.exact.clone()),
                aba: self.pivots.as_ref().is_some_and(|p| p.aba),
                singular: self.pivots.as_ref().and_then(|p| p.singular),
            }
        });
        Traced {
            graph,
            values: all,
            pivots,
            ..self
        }
    }

    /// Evaluates the graph in `f64` (the CLI's `--engine symbolic`): the values, then, for
    /// forward dynamics, whether every pivot passed the generated code's checks.
    pub fn eval(&self, input: impl Fn(Var) -> f64) -> (Vec<f64>, bool) {
        let all = self.graph.eval(&self.all_outputs(), input);
        let (values, rest) = all.split_at(self.values.len());
        let ok = match rest.split_last() {
            None => true,
            Some(_) if self.pivots.as_ref().is_some_and(|p| p.singular.is_some()) => false,
            Some((&scale, values)) => {
                let exact = self.pivots.as_ref().map_or(&[][..], |p| &p.exact[..]);
                let tol_global = match self.pivots.as_ref().is_some_and(|p| p.aba) {
                    true => PIVOT_TOL_GLOBAL_ABA_F64,
                    false => PIVOT_TOL_GLOBAL_F64,
                };
                values.chunks(2).zip(exact).all(|(pd, &exact)| {
                    // As the generated checks: an exact pivot is not held to the scale.
                    let global = exact || pd[0] > tol_global * scale;
                    pd[0] > PIVOT_TOL_F64 * pd[1] && global && pd[0].is_finite()
                })
            }
        };
        (values.to_vec(), ok)
    }
}

/// Traces `output` of `model` every way there is and keeps the fewest operations (see the
/// [module docs](self)).
pub fn trace(model: &Model, output: Output) -> Traced {
    trace_with(model, output, Accuracy::Fastest, false)
}

/// Traces `output` of `model` every way `accuracy` allows and keeps the fewest operations:
/// [`Accuracy::Robust`] keeps forward dynamics to ABA. `quasi_static` traces every variant with
/// `v = 0` ([`Variant::quasi_static`]).
pub fn trace_with(model: &Model, output: Output, accuracy: Accuracy, quasi_static: bool) -> Traced {
    // The frames' outputs, for no frame: the generator traces them with its frames
    // (`frames::trace`).
    if output.spec().uses_nf() {
        return frames::trace(model, output, &[], quasi_static);
    }
    // The updates into a kept matrix are `M`, stored elsewhere (the lower one storing half).
    if output.is_kept() {
        let mut traced = trace_with(model, Output::MassMatrix, accuracy, quasi_static);
        traced.output = output;
        if output == Output::MassMatrixLower {
            // Only the entries it stores: an entry above the diagonal left among the values
            // would be one the function returns, kept live to its end.
            let nv = model.nv();
            traced.values = lower_triangle(nv)
                .filter_map(|(r, c)| traced.values.get(r * nv + c).copied())
                .collect();
        }
        return traced;
    }
    let scene = |mut v: Variant| {
        v.quasi_static = quasi_static;
        v
    };
    // Regrouping moves inertia between bodies: the joint wrenches change, so they never use it.
    // So do the centre of mass, the momenta and the potential energy; the kinetic energy and
    // the Coriolis matrix depend on `M(q)` only, which regrouping keeps.
    let regroupings: &[bool] = match output {
        Output::JointWrenches
        | Output::JointWrenchesBottomUp
        | Output::CenterOfMass
        | Output::CenterOfMassVelocity
        | Output::CenterOfMassJacobian
        | Output::CentroidalMomentum
        | Output::CentroidalMomentumMatrix
        | Output::CentroidalMomentumRate
        | Output::CentroidalMomentumDrift
        | Output::PotentialEnergy => &[false],
        _ => &[false, true],
    };
    let traced: Vec<Traced> = match output {
        Output::ForwardDynamics => forward::variants(model)
            .filter(|v| accuracy == Accuracy::Fastest || v.method == Some(FdMethod::Aba))
            .map(|variant| forward::trace_variant(model, scene(variant)))
            .collect(),
        Output::InverseDynamicsDerivatives
        | Output::ForwardDynamicsDerivatives
        | Output::MassMatrixInverse => derivatives::variants(model, output)
            .into_iter()
            .map(|variant| derivatives::trace_variant(model, output, scene(variant)))
            .collect(),
        _ => regroupings
            .iter()
            .copied()
            .flat_map(|regrouped| {
                let with_m = matches!(
                    output,
                    Output::MassMatrix | Output::MassMatrixAndNonlinearEffects
                );
                let formulations: &[Formulation] = if with_m {
                    &[
                        Formulation::Reference,
                        Formulation::Specialized,
                        Formulation::SpecializedRootFrame,
                    ]
                } else if output.whole_body()
                    && !matches!(
                        output,
                        Output::CentroidalMomentumMatrix | Output::CoriolisMatrix
                    )
                {
                    // One recursion only (`reference::centroidal`).
                    &[Formulation::Reference]
                } else {
                    &[Formulation::Reference, Formulation::Specialized]
                };
                formulations.iter().map(move |&formulation| Variant {
                    regrouped,
                    formulation,
                    method: None,
                    analytic: false,
                    coriolis: false,
                    quasi_static: false,
                })
            })
            .map(|variant| trace_variant(model, output, scene(variant)))
            .collect(),
    };
    // Reciprocals before counting, so that variants are compared on what would be emitted.
    let traced: Vec<Traced> = traced.into_iter().map(Traced::with_reciprocals).collect();
    let candidates: Vec<(Variant, OpCounts)> =
        traced.iter().map(|t| (t.variant, t.ops())).collect();
    let mut best = fewest(traced, |t| t.ops().total());
    best.candidates = candidates;
    let mut best = best.reassociated();
    if let Some(p) = &mut best.pivots {
        p.singular = singular_everywhere(model);
    }
    best
}

/// The traced variant with the fewest operations (`ops`), the first of equals.
///
/// # Panics
/// With no variant: every output has at least one.
pub(crate) fn fewest<T>(variants: Vec<T>, ops: impl Fn(&T) -> usize) -> T {
    variants
        .into_iter()
        .reduce(|best, t| if ops(&t) < ops(&best) { t } else { best })
        .unwrap_or_else(|| unreachable!("every output has variants"))
}

/// The (row, column) of each entry of an `nv × nv` matrix on and below its diagonal, row by
/// row: the order of `mass_matrix_lower`'s values.
pub(crate) fn lower_triangle(nv: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..nv).flat_map(|r| (0..=r).map(move |c| (r, c)))
}

/// `M`, bias, gravity or inverse dynamics traced one way.
fn trace_variant(model: &Model, output: Output, variant: Variant) -> Traced {
    let (graph, values) = sym::trace(|| {
        let (tree, turns) = symbolic_tree(model, variant.regrouped);
        let (c, nv) = (model.coupling(), model.nv());
        let (q, v, a) = tree_inputs(model, &c, &turns, variant);
        let zero = vec![Sym::zero(); tree.nv];
        let form = variant.formulation;
        let values = match output {
            Output::MassMatrix | Output::MassMatrixUpdate | Output::MassMatrixLower => {
                c.reduce_matrix(&mass_matrix(form, &tree, &q))
            }
            Output::Bias => c.reduce(&rnea(form, &tree, &q, &v, &zero, false)),
            Output::Gravity => c.reduce(&rnea(form, &tree, &q, &zero, &zero, true)),
            Output::InverseDynamics => c.reduce(&rnea(form, &tree, &q, &v, &a, true)),
            Output::NonlinearEffects => c.reduce(&rnea(form, &tree, &q, &v, &zero, true)),
            Output::MassMatrixAndNonlinearEffects => {
                let m = c.reduce_matrix(&mass_matrix(form, &tree, &q));
                let m = label_outputs(Output::MassMatrix, m, nv);
                let nle = c.reduce(&rnea(form, &tree, &q, &v, &zero, true));
                m.into_iter()
                    .chain(label_outputs(Output::NonlinearEffects, nle, nv))
                    .collect()
            }
            Output::JointWrenches => wrench_entries(&joint_wrenches(form, &tree, &q, &v, &a)),
            Output::JointWrenchesBottomUp => {
                let (x_up, h) = inertial_forces(form, &tree, &q, &v, &a);
                let b = inputs(6, Var::Base);
                let base = Force::new(Vec3([b[0], b[1], b[2]]), Vec3([b[3], b[4], b[5]]));
                wrench_entries(&reference::bottom_up(&tree, &x_up, &h, base))
            }
            Output::CenterOfMass => centroidal::center_of_mass(&tree, &q).0.to_vec(),
            Output::CenterOfMassVelocity => centroidal::center_of_mass_velocity(&tree, &q, &v)
                .0
                .to_vec(),
            Output::CenterOfMassJacobian => {
                c.reduce_columns(&centroidal::center_of_mass_jacobian(&tree, &q), 3)
            }
            Output::CentroidalMomentum => centroidal::centroidal_momentum(&tree, &q, &v)
                .to_array()
                .to_vec(),
            Output::CentroidalMomentumMatrix => c.reduce_columns(
                &match form {
                    Formulation::Reference => centroidal::centroidal_momentum_matrix(&tree, &q),
                    _ => crba::centroidal_momentum_matrix(&tree, &q, regroup::coordinate_axis),
                },
                6,
            ),
            Output::CentroidalMomentumRate => {
                centroidal::centroidal_momentum_rate(&tree, &q, &v, &a)
                    .to_array()
                    .to_vec()
            }
            Output::CentroidalMomentumDrift => centroidal::centroidal_momentum_drift(&tree, &q, &v)
                .to_array()
                .to_vec(),
            Output::KineticEnergy => vec![centroidal::kinetic_energy(&tree, &q, &v)],
            Output::PotentialEnergy => vec![centroidal::potential_energy(&tree, &q)],
            Output::CoriolisMatrix => c.reduce_matrix(&match form {
                Formulation::Reference => centroidal::coriolis_matrix(&tree, &q, &v),
                _ => crba::coriolis_matrix(&tree, &q, &v, regroup::coordinate_axis),
            }),
            Output::ForwardDynamics => unreachable!("traced by `forward`"),
            Output::InverseDynamicsDerivatives
            | Output::ForwardDynamicsDerivatives
            | Output::MassMatrixInverse => unreachable!("traced by `derivatives`"),
            _ => unreachable!("the frames' outputs are traced by `frames`"),
        };
        label_outputs(output, values, nv)
    });
    Traced {
        output,
        graph,
        values,
        pivots: None,
        variant,
        candidates: Vec::new(),
    }
}

/// Names the outputs after what they are (`tau_3`, `m_1_2`), where the recursion left them
/// unnamed; the first name a value gets wins.
fn label_outputs(output: Output, values: Vec<Sym>, nv: usize) -> Vec<Sym> {
    let stem = match output {
        Output::MassMatrix | Output::MassMatrixUpdate | Output::MassMatrixLower => "m",
        Output::Bias => "bias",
        Output::Gravity => "g",
        Output::InverseDynamics => "tau",
        Output::ForwardDynamics => "qdd",
        Output::NonlinearEffects => "nle",
        // Labelled part by part where they are traced.
        Output::MassMatrixAndNonlinearEffects => return values,
        // The recursions label every wrench; nothing is left unnamed.
        Output::JointWrenches | Output::JointWrenchesBottomUp => return values,
        Output::CenterOfMass => "com",
        Output::CenterOfMassVelocity => "com_v",
        Output::CenterOfMassJacobian => "com_j",
        Output::CentroidalMomentum => "h_g",
        Output::CentroidalMomentumMatrix => "a_g",
        Output::CentroidalMomentumRate => "dh_g",
        Output::CentroidalMomentumDrift => "drift_h_g",
        Output::KineticEnergy => "kinetic_energy",
        Output::PotentialEnergy => "potential_energy",
        Output::CoriolisMatrix => "n",
        // Labelled where they are traced.
        Output::InverseDynamicsDerivatives
        | Output::ForwardDynamicsDerivatives
        | Output::MassMatrixInverse
        | Output::FramePlacements
        | Output::FrameVelocities
        | Output::FrameVelocityDerivatives
        | Output::FrameAccelerationDerivatives
        | Output::FrameAccelerations
        | Output::FrameJacobiansLocal
        | Output::FrameJacobiansWorld
        | Output::FrameJacobiansLocalWorldAligned
        | Output::FrameJacobianTimeVariationsLocal
        | Output::FrameJacobianTimeVariationsWorld
        | Output::FrameJacobianTimeVariationsLocalWorldAligned => return values,
    };
    const AXES: [&str; 3] = ["x", "y", "z"];
    values
        .into_iter()
        .enumerate()
        .map(|(k, x)| match output {
            Output::MassMatrix | Output::CoriolisMatrix | Output::CenterOfMassJacobian => {
                x.label(format_args!("{stem}_{}_{}", k / nv, k % nv))
            }
            Output::CentroidalMomentumMatrix => {
                let part = if k / nv < 3 { "k" } else { "p" };
                x.label(format_args!(
                    "{stem}_{part}{}_{}",
                    AXES[(k / nv) % 3],
                    k % nv
                ))
            }
            Output::CenterOfMass | Output::CenterOfMassVelocity => {
                x.label(format_args!("{stem}_{}", AXES[k]))
            }
            Output::CentroidalMomentum => {
                let part = if k < 3 { "k_g" } else { "p" };
                x.label(format_args!("{part}_{}", AXES[k % 3]))
            }
            Output::CentroidalMomentumRate | Output::CentroidalMomentumDrift => {
                let part = if k < 3 { "k_g" } else { "p" };
                x.label(format_args!("{stem}_{part}_{}", AXES[k % 3]))
            }
            Output::KineticEnergy | Output::PotentialEnergy => x.label(format_args!("{stem}")),
            _ => x.label(format_args!("{stem}_{k}")),
        })
        .collect()
}

/// The model's tree on the symbolic scalar, its parameters as inputs, regrouped if asked, with
/// each revolute placement's turn about the joint's axis folded into the angle
/// ([`turns`]): the turns are to be passed to [`model_inputs`], which adds them to the angles.
///
/// # Panics
/// Outside [`sym::trace`].
pub(crate) fn symbolic_tree(model: &Model, regrouped: bool) -> (Tree<Sym>, Vec<Turn>) {
    let params = inputs(model.params.len(), Var::Param);
    let mut tree = Tree::new(model, &params);
    if regrouped {
        regroup::regroup(&mut tree);
    }
    let turns = turns::fold(&mut tree);
    (tree, turns)
}

/// The tree's `q` and `v` from the model's inputs through the model's coupling `c`
/// ([`Model::coupling`]: the inputs themselves but for mimic joints, whose coordinates are
/// `multiplier·q_j + offset`), and a third input vector (`τ`, input `third`) in the model's
/// coordinates, not expanded.
pub(crate) fn model_inputs(
    model: &Model,
    c: &Coupling,
    turns: &[Turn],
    variant: Variant,
    third: fn(usize) -> Var,
) -> (Vec<Sym>, Vec<Sym>, Vec<Sym>) {
    (
        tree_angles(model, c, turns),
        c.expand_v(&velocities(model.nv(), variant)),
        inputs(model.nv(), third),
    )
}

/// The tree's `q`, `v` and `a` ([`model_inputs`] with `a` expanded too).
pub(crate) fn tree_inputs(
    model: &Model,
    c: &Coupling,
    turns: &[Turn],
    variant: Variant,
) -> (Vec<Sym>, Vec<Sym>, Vec<Sym>) {
    let (q, v, a) = model_inputs(model, c, turns, variant, Var::A);
    (q, v, c.expand_v(&a))
}

/// The tree's `q`: the model's inputs through the coupling, with the `turns` of
/// [`symbolic_tree`] added.
pub(crate) fn tree_angles(model: &Model, c: &Coupling, turns: &[Turn]) -> Vec<Sym> {
    turns::turned(c.expand_q(&inputs(model.nq(), Var::Q)), turns)
}

/// The velocities a variant is traced with: the inputs `v`, or zeros when quasi-static.
pub(crate) fn velocities(n: usize, variant: Variant) -> Vec<Sym> {
    if variant.quasi_static {
        vec![Sym::zero(); n]
    } else {
        inputs(n, Var::V)
    }
}

/// The inputs `var(0), …, var(n − 1)`.
pub(crate) fn inputs(n: usize, var: fn(usize) -> Var) -> Vec<Sym> {
    (0..n).map(|i| Sym::input(var(i))).collect()
}

/// Inverse dynamics by `form` (`with_gravity`: add `g(q)`).
pub(crate) fn rnea(
    form: Formulation,
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
    with_gravity: bool,
) -> Vec<Sym> {
    match form {
        Formulation::Specialized | Formulation::SpecializedRootFrame => {
            newton_euler::classical_rnea(tree, q, v, a, with_gravity)
        }
        Formulation::Reference => reference::rnea(tree, q, v, a, with_gravity),
    }
}

/// The wrench each model joint transmits by `form`, with gravity.
fn joint_wrenches(
    form: Formulation,
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
) -> Vec<Force<Sym>> {
    let f = match form {
        Formulation::Specialized | Formulation::SpecializedRootFrame => {
            newton_euler::classical_node_forces(tree, q, v, a, true)
        }
        Formulation::Reference => reference::node_forces(tree, q, v, a, true),
    };
    tree.body_node.iter().map(|&n| f[n]).collect()
}

/// `X_up` and each body's own force by `form`, with gravity.
fn inertial_forces(
    form: Formulation,
    tree: &Tree<Sym>,
    q: &[Sym],
    v: &[Sym],
    a: &[Sym],
) -> (Vec<Transform<Sym>>, Vec<Force<Sym>>) {
    match form {
        Formulation::Specialized | Formulation::SpecializedRootFrame => {
            newton_euler::classical_inertial_forces(tree, q, v, a, true)
        }
        Formulation::Reference => reference::inertial_forces(tree, q, v, a, true),
    }
}

/// Wrenches as their entries, each `[n; f]` in turn (the columns of a `6 × NB` matrix).
fn wrench_entries(wrenches: &[Force<Sym>]) -> Vec<Sym> {
    wrenches.iter().flat_map(|w| w.to_array()).collect()
}

/// `M(q)` by `form`, row-major.
pub(crate) fn mass_matrix(form: Formulation, tree: &Tree<Sym>, q: &[Sym]) -> Vec<Sym> {
    match form {
        Formulation::Specialized => crba::crba(tree, q, regroup::coordinate_axis),
        Formulation::SpecializedRootFrame => {
            crba::crba_in_root_frame(tree, q, regroup::coordinate_axis)
        }
        Formulation::Reference => reference::crba(tree, q),
    }
}
