//! Shared by the tests of this crate: how generated code and imported models are compared with
//! the reference and with Pinocchio.
//!
//! Every comparison is against an independent value (the interpreted reference
//! `articulated::reference::Reference`, Pinocchio, a closed form); the only check of generated
//! code against itself is forward(inverse(a)) = a.
//!
//! Errors are relative to the largest entry of the expected value (absolute where that is 0), so
//! one tolerance fits a 2-body and a 30-body tree; a NaN on either side counts as infinite.

// Each test crate that includes this module uses part of it.
#![allow(dead_code)]

pub mod batch;

use articulated::nalgebra::{DMatrix, DVector, SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::{Error, Reference};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use serde_json::Value as Json;

/// The rows of a matrix stored as a JSON list of rows, concatenated (row-major).
pub fn rows_of(j: &Json) -> Vec<f64> {
    j.as_array().unwrap().iter().flat_map(vec_of).collect()
}

/// Reads one of this crate's JSON data files (`rel` from the crate's directory, e.g.
/// `data/pinocchio-arm7.json`). Python's `json.dump` writes NaN as a bare `NaN`, which is not
/// JSON: it is read as `null`. Pinocchio gives NaN accelerations where `M(q)` is singular.
pub fn read_json(rel: &str) -> Json {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text.replace("NaN", "null"))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The numbers of a JSON array; `null` (Pinocchio's NaN, see [`read_json`]) reads as NaN.
pub fn vec_of(j: &Json) -> Vec<f64> {
    j.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().unwrap_or(f64::NAN))
        .collect()
}

/// Tolerance of M, bias, gravity and inverse dynamics against the reference (relative to the
/// largest entry).
pub const TOL: f64 = 1e-12;

/// Largest |ours − theirs| relative to the largest |theirs| (absolute if that is 0); a NaN on
/// either side gives infinity, so it cannot hide behind `f64::max`.
pub fn rel_err(ours: &[f64], theirs: &[f64]) -> f64 {
    let scale = max_abs(theirs);
    let scale = if scale > 0.0 { scale } else { 1.0 };
    abs_err(ours, theirs) / scale
}

/// The largest entry-wise difference (infinite if any is NaN).
pub fn abs_err(ours: &[f64], theirs: &[f64]) -> f64 {
    assert_eq!(ours.len(), theirs.len(), "lengths differ");
    ours.iter().zip(theirs).fold(0.0f64, |e, (a, b)| {
        let d = (a - b).abs();
        if d.is_nan() {
            f64::INFINITY
        } else {
            e.max(d)
        }
    })
}

/// A generated `constrained_forward_dynamics`'s `(q̈, forces)` against Pinocchio's (to `tol`,
/// `q̈` relative to its largest entry, the forces of `weight = m·‖g‖`) and against the
/// runtime's solution of the same constraints (to 1e-11): prints both, panics past either.
#[allow(dead_code)]
pub fn check_constrained(
    label: &str,
    ours: (&[f64], &[f64]),
    pinocchio: (&[f64], &[f64]),
    runtime: (&[f64], &[f64]),
    weight: f64,
    tol: f64,
) {
    let e_qdd = rel_err(ours.0, pinocchio.0);
    let e_f = abs_err(ours.1, pinocchio.1) / weight;
    let r_qdd = rel_err(ours.0, runtime.0);
    let r_f = abs_err(ours.1, runtime.1) / weight;
    println!(
        "{label}: against Pinocchio q̈ {e_qdd:.1e}, forces {e_f:.1e}; against the runtime q̈ \
         {r_qdd:.1e}, forces {r_f:.1e}"
    );
    assert!(
        e_qdd < tol && e_f < tol,
        "{label}: q̈ {e_qdd:.1e}, forces {e_f:.1e} off Pinocchio's"
    );
    assert!(
        r_qdd < 1e-11 && r_f < 1e-11,
        "{label}: q̈ {r_qdd:.1e}, forces {r_f:.1e} off the runtime's"
    );
}

/// The largest |x| (infinite if any entry is NaN).
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |s, v| {
        if v.is_nan() {
            f64::INFINITY
        } else {
            s.max(v.abs())
        }
    })
}

/// The 2-norm condition number of a symmetric matrix from its eigenvalues (infinite where the
/// smallest is not positive).
pub fn condition(m: &DMatrix<f64>) -> f64 {
    let eig = m.clone().symmetric_eigenvalues();
    let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), e| {
        (lo.min(*e), hi.max(e.abs()))
    });
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// The tolerance of forward dynamics against the reference, relative to the largest |q̈|.
///
/// Why it depends on κ(M): the generated code and the reference compute `q̈ = M⁻¹(τ − h)` by
/// different operation orders (ABA or a sparse LᵀDL against the reference's ABA). Each is
/// backward stable: it solves a system within a few hundred ulps of `(M, τ − h)`. Perturbation
/// theory turns that into a forward error up to κ(M) times larger, so two correct solvers may
/// differ by ~κ·100·ε ≈ κ·2e-14 however exact each step is. With 1e-13·κ (a margin of 5) and a
/// floor of 1e-12, the two-link (κ ~ 10–100) is held to 1e-12–1e-11 and a 30-body random tree
/// (κ up to ~1e5) to what its conditioning allows. The κ-free check is [`fd_residual`].
pub fn fd_tol(kappa: f64) -> f64 {
    TOL.max(1e-13 * kappa)
}

/// `‖M·q̈ + h − τ‖∞ / (‖M‖max·‖q̈‖∞ + ‖τ − h‖∞)` with the reference's `M` and `h = bias +
/// gravity`: how far `q̈` is from solving the reference's equations of motion. A backward-stable
/// solver keeps this near ε whatever κ(M) is, so it is held to [`TOL`] without a κ factor.
pub fn fd_residual(m: &DMatrix<f64>, h: &[f64], tau: &[f64], qdd: &[f64]) -> f64 {
    let n = tau.len();
    let mut worst = 0.0f64;
    let mut rhs = 0.0f64;
    for i in 0..n {
        let mq: f64 = (0..n).map(|j| m[(i, j)] * qdd[j]).sum();
        let r = mq + h[i] - tau[i];
        worst = if r.is_nan() {
            f64::INFINITY
        } else {
            worst.max(r.abs())
        };
        rhs = rhs.max((tau[i] - h[i]).abs());
    }
    let scale = max_abs(m.as_slice()) * max_abs(qdd) + rhs;
    if scale > 0.0 {
        worst / scale
    } else {
        worst
    }
}

/// The outputs compared, in print order.
pub const OUTPUTS: [&str; 7] = [
    "mass_matrix",
    "bias",
    "gravity",
    "inverse_dynamics",
    "fd_vs_reference/tol",
    "fd_residual",
    "fd(id(a))-a/tol",
];

/// One state's errors, in [`OUTPUTS`] order. The two `/tol` entries are already divided by the
/// κ-aware [`fd_tol`] (pass when ≤ 1); the others are relative errors (pass when ≤ [`TOL`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Errors {
    /// See [`OUTPUTS`].
    pub e: [f64; 7],
    /// κ(M) at this state.
    pub kappa: f64,
    /// The reference found M singular here (forward dynamics not compared).
    pub singular: bool,
}

impl Errors {
    /// The first failing output, as a message.
    pub fn failure(&self) -> Option<String> {
        OUTPUTS.iter().zip(self.e).find_map(|(name, e)| {
            let bound = if name.ends_with("/tol") { 1.0 } else { TOL };
            // NaN fails too.
            (e.is_nan() || e > bound).then(|| format!("{name} = {e:e} (bound {bound:e})"))
        })
    }
}

/// The worst errors over many states.
#[derive(Clone, Debug, Default)]
pub struct Worst {
    /// Per output, [`OUTPUTS`] order.
    pub e: [f64; 7],
    /// The largest κ(M) met.
    pub kappa: f64,
    /// States compared.
    pub states: usize,
    /// States where the reference found M singular.
    pub singular: usize,
}

impl Worst {
    /// Takes one state's errors into account.
    pub fn note(&mut self, e: &Errors) {
        for (w, x) in self.e.iter_mut().zip(e.e) {
            *w = if x.is_nan() { f64::INFINITY } else { w.max(x) };
        }
        self.kappa = self.kappa.max(e.kappa);
        self.states += 1;
        self.singular += usize::from(e.singular);
    }

    /// One line: label, then each output's worst error.
    pub fn line(&self, label: &str) -> String {
        let mut s = format!("{label:<26} states={:<3}", self.states);
        for (name, e) in OUTPUTS.iter().zip(self.e) {
            s += &format!(" {name}={e:.1e}");
        }
        s += &format!(" max_kappa={:.1e}", self.kappa);
        if self.singular > 0 {
            s += &format!(" singular={}", self.singular);
        }
        s
    }
}

/// Compares every output of the generated chain `C` (through the `_with` functions, parameters
/// `p`) with the reference `r` (built for the same parameter values) at one state.
pub fn compare_state<C, const NQ: usize, const NV: usize>(
    r: &Reference,
    p: &C::Params,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Errors
where
    C: DefaultOutputs<f64, NQ, NV>,
{
    assert_eq!((r.nq(), r.nv()), (NQ, NV), "the reference's sizes");
    let (qs, vs, as_) = (
        SVector::<f64, NQ>::from_column_slice(q),
        SVector::<f64, NV>::from_column_slice(v),
        SVector::<f64, NV>::from_column_slice(a),
    );
    let mut out = Errors::default();
    let m_ref = r.mass_matrix(q).expect("reference mass matrix");
    let m: SMatrix<f64, NV, NV> = C::mass_matrix_with(&qs, p);
    // Both column-major.
    out.e[0] = rel_err(m.as_slice(), m_ref.as_slice());
    // Bias and τ are held relative to the size of their terms, not of the result, which the
    // terms can cancel to nothing (a bias that vanishes at some state while each of its
    // `∂M/∂q·q̇²` terms does not): bias against `max(|b|, |M|·|v|²)`, τ against that and
    // `|M|·|a|` and `|g|`. The generated code sums the terms in another order than the
    // reference (regrouped inertias, another Newton–Euler form), so its rounding is of the
    // terms' size.
    let m_size = max_abs(m_ref.as_slice());
    let v_size = max_abs(v);
    let b_ref = r.bias(q, v).expect("reference bias");
    let b_scale = max_abs(b_ref.as_slice()).max(m_size * v_size * v_size);
    out.e[1] = abs_err(C::bias_with(&qs, &vs, p).as_slice(), b_ref.as_slice())
        / b_scale.max(f64::MIN_POSITIVE);
    let g_ref = r.gravity(q).expect("reference gravity");
    out.e[2] = rel_err(C::gravity_with(&qs, p).as_slice(), g_ref.as_slice());
    let tau_ref = r
        .inverse_dynamics(q, v, a)
        .expect("reference inverse dynamics");
    let tau = C::inverse_dynamics_with(&qs, &vs, &as_, p);
    let tau_scale = max_abs(tau_ref.as_slice())
        .max(b_scale)
        .max(m_size * max_abs(a))
        .max(max_abs(g_ref.as_slice()));
    out.e[3] = abs_err(tau.as_slice(), tau_ref.as_slice()) / tau_scale.max(f64::MIN_POSITIVE);

    out.kappa = condition(&m_ref);
    let tol = fd_tol(out.kappa);
    let h: Vec<f64> = b_ref.iter().zip(g_ref.iter()).map(|(b, g)| b + g).collect();
    let taus = SVector::<f64, NV>::from_column_slice(tau_ref.as_slice());
    let fd = C::forward_dynamics_with(&qs, &vs, &taus, p);
    match (r.forward_dynamics(q, v, tau_ref.as_slice()), fd) {
        (Ok(qdd_ref), Ok(qdd)) => {
            out.e[4] = rel_err(qdd.as_slice(), qdd_ref.as_slice()) / tol;
            out.e[5] = fd_residual(&m_ref, &h, tau_ref.as_slice(), qdd.as_slice());
        }
        (Ok(_), Err(e)) => {
            // The reference solved it: generated code must not refuse.
            out.e[4] = f64::INFINITY;
            eprintln!(
                "generated forward dynamics refused a regular M (κ = {:e}): {e}",
                out.kappa
            );
        }
        (Err(Error::Singular(_)), Ok(qdd)) => {
            // Singular per the reference's eigenvalue test: the generated pivots may pass by
            // rounding; then at least the equations of motion must hold.
            out.singular = true;
            out.e[5] = fd_residual(&m_ref, &h, tau_ref.as_slice(), qdd.as_slice());
        }
        (Err(Error::Singular(_)), Err(_)) => out.singular = true,
        (Err(e), _) => panic!("reference forward dynamics: {e}"),
    }
    // Generated code alone: forward(inverse(a)) = a.
    if !out.singular {
        out.e[6] = match C::forward_dynamics_with(&qs, &vs, &tau, p) {
            Ok(back) => rel_err(back.as_slice(), a) / tol,
            Err(_) => f64::INFINITY,
        };
    }
    out
}

/// The generated `C::COORDINATES` (the generator's mapping of joint kinds) against the runtime's
/// `coordinates_of` of the same model (written apart, for chains read at run time), and their
/// sizes against the reference's.
pub fn check_coordinates<C: Chain<f64>>(label: &str, r: &Reference) {
    let expected = articulated::interpreted::coordinates_of(r.model());
    assert_eq!(C::COORDINATES, expected.as_slice(), "{label}: COORDINATES");
    let nq: usize = C::COORDINATES.iter().map(|c| c.nq()).sum();
    let nv: usize = C::COORDINATES.iter().map(|c| c.nv()).sum();
    assert_eq!((nq, nv), (r.nq(), r.nv()), "{label}: COORDINATES sizes");
}

/// Runs [`compare_state`] on `cases` random states drawn by proptest: a `u64` seed per case,
/// turned into `(q, v, a)` by `state` (typically `articulated_dynamics::random::random_state`,
/// which keeps Euler angles away from gimbal lock and quaternions unit). A failure shrinks the
/// seed and reports it; `PROPTEST_RNG_SEED` fixes the run. Returns the worst errors.
pub fn check_chain<C, const NQ: usize, const NV: usize>(
    label: &str,
    r: &Reference,
    p: &C::Params,
    cases: u32,
    state: impl Fn(u64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
) -> Worst
where
    C: DefaultOutputs<f64, NQ, NV>,
{
    check_coordinates::<C>(label, r);
    // A fixed seed: the same states on every run, so a failure reproduces.
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let worst = std::cell::RefCell::new(Worst::default());
    let result = runner.run(&any::<u64>(), |seed| {
        let (q, v, a) = state(seed);
        let e = compare_state::<C, NQ, NV>(r, p, &q, &v, &a);
        worst.borrow_mut().note(&e);
        match e.failure() {
            Some(msg) => Err(TestCaseError::fail(format!(
                "{label}: {msg} (κ = {:.1e}) at q = {q:?}, v = {v:?}, a = {a:?}",
                e.kappa
            ))),
            None => Ok(()),
        }
    });
    let worst = worst.into_inner();
    println!("{}", worst.line(label));
    if let Err(e) = result {
        panic!("{e}");
    }
    worst
}

/// The outputs [`compare_pinocchio`] checks, as it prints them.
pub const PINOCCHIO_OUTPUTS: [&str; 5] = ["mass_matrix", "bias", "gravity", "tau", "qdd"];

/// Compares the generated chain `C` with one model's Pinocchio states (M, bias, gravity,
/// inverse and forward dynamics, each to `tol` relative to Pinocchio's largest entry); prints
/// the worst errors and returns the failures. Where Pinocchio's M is singular, forward dynamics
/// must return an error.
pub fn compare_pinocchio<C, const NQ: usize, const NV: usize>(
    label: &str,
    case: &Json,
    tol: f64,
) -> Vec<String>
where
    C: DefaultOutputs<f64, NQ, NV>,
{
    assert_eq!(case["nq"].as_u64(), Some(NQ as u64), "{label}: nq");
    assert_eq!(case["nv"].as_u64(), Some(NV as u64), "{label}: nv");
    let mut worst = [0.0f64; 5];
    let mut failures = Vec::new();
    let (mut singular, mut states) = (0, 0);
    for s in case["states"].as_array().unwrap() {
        states += 1;
        let q = SVector::<f64, NQ>::from_column_slice(&vec_of(&s["q"]));
        let v = SVector::<f64, NV>::from_column_slice(&vec_of(&s["v"]));
        let a = SVector::<f64, NV>::from_column_slice(&vec_of(&s["a"]));
        let tau = SVector::<f64, NV>::from_column_slice(&vec_of(&s["tau"]));
        let m_theirs = rows_of(&s["mass_matrix"]);
        let m = C::mass_matrix(&q);
        // Row-major on both sides (M is symmetric, but compare the layout honestly).
        let m_ours: Vec<f64> = (0..NV)
            .flat_map(|i| (0..NV).map(move |j| (i, j)))
            .map(|(i, j)| m[(i, j)])
            .collect();
        let mut e = [
            rel_err(&m_ours, &m_theirs),
            rel_err(C::bias(&q, &v).as_slice(), &vec_of(&s["bias"])),
            rel_err(C::gravity(&q).as_slice(), &vec_of(&s["gravity"])),
            rel_err(
                C::inverse_dynamics(&q, &v, &a).as_slice(),
                &vec_of(&s["tau_out"]),
            ),
            0.0,
        ];
        let qdd_theirs = vec_of(&s["qdd"]);
        let eig = DMatrix::from_row_slice(NV, NV, &m_theirs).symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
            (lo.min(*x), hi.max(x.abs()))
        });
        let fd = C::forward_dynamics(&q, &v, &tau);
        if lo <= 1e-12 * hi || qdd_theirs.iter().any(|x| x.is_nan()) {
            singular += 1;
            if let Ok(qdd) = fd {
                failures.push(format!(
                    "{label}: Pinocchio's M is singular (eigenvalues {lo:e} .. {hi:e}) but \
                     generated forward dynamics returned Ok({:?})",
                    qdd.as_slice()
                ));
            }
        } else {
            e[4] = match fd {
                Ok(qdd) => rel_err(qdd.as_slice(), &qdd_theirs),
                Err(err) => {
                    failures.push(format!("{label}: forward dynamics refused: {err}"));
                    f64::INFINITY
                }
            };
        }
        for (w, x) in worst.iter_mut().zip(e) {
            *w = if x.is_nan() { f64::INFINITY } else { w.max(x) };
        }
    }
    let mut line = format!("{label:<26} states={states}");
    for (name, w) in PINOCCHIO_OUTPUTS.iter().zip(worst) {
        line += &format!(" {name}={w:.1e}");
        if w.is_nan() || w > tol {
            failures.push(format!("{label}: {name} differs from Pinocchio by {w:e}"));
        }
    }
    if singular > 0 {
        line += &format!(" (M singular at {singular} states: Err required)");
    }
    println!("{line}");
    failures
}

/// The whole-system outputs in the order of `Output::ALL`: the names of [`whole_body_errors`]'
/// entries, then `coriolis_matrix` ([`coriolis_error`]).
pub const WHOLE_BODY_OUTPUTS: [&str; 8] = [
    "center_of_mass",
    "center_of_mass_velocity",
    "center_of_mass_jacobian",
    "centroidal_momentum",
    "centroidal_momentum_matrix",
    "kinetic_energy",
    "potential_energy",
    "coriolis_matrix",
];

/// The entries of a `rows × n` matrix given column-major (nalgebra's `as_slice`), row by row.
pub fn row_major(column_major: &[f64], rows: usize) -> Vec<f64> {
    let cols = column_major.len() / rows;
    (0..rows)
        .flat_map(|r| (0..cols).map(move |c| column_major[c * rows + r]))
        .collect()
}

/// The generated whole-system outputs against the reference's at one state, each relative to
/// the largest entry of the reference's value; the energies relative to the largest of their
/// value and the state's kinetic energy plus `m·|g|` (metres: the tree's size), so that a value
/// crossing zero is still compared at its natural scale.
pub fn whole_body_errors<C, const NQ: usize, const NV: usize>(
    r: &Reference,
    q: &[f64],
    v: &[f64],
) -> [f64; 7]
where
    C: WholeBodyOutputs<f64, NQ, NV>,
{
    let (qs, vs) = (SVector::from_column_slice(q), SVector::from_column_slice(v));
    let row_major = |m: DMatrix<f64>| m.transpose().as_slice().to_vec();
    let com_v = r.center_of_mass_jacobian(q).unwrap() * DVector::from_column_slice(v);
    let kinetic = r.kinetic_energy(q, v).unwrap();
    let mass: f64 = r.tree().nodes.iter().map(|n| n.inertia.m).sum();
    let energy_scale = kinetic.abs() + mass * 9.81;
    let energy = |ours: f64, theirs: f64| (ours - theirs).abs() / energy_scale.max(theirs.abs());
    [
        rel_err(
            C::center_of_mass(&qs).as_slice(),
            r.center_of_mass(q).unwrap().as_slice(),
        ),
        rel_err(
            C::center_of_mass_velocity(&qs, &vs).as_slice(),
            com_v.as_slice(),
        ),
        rel_err(
            C::center_of_mass_jacobian(&qs).transpose().as_slice(),
            &row_major(r.center_of_mass_jacobian(q).unwrap()),
        ),
        rel_err(
            C::centroidal_momentum(&qs, &vs).as_slice(),
            r.centroidal_momentum(q, v).unwrap().as_slice(),
        ),
        rel_err(
            C::centroidal_momentum_matrix(&qs).transpose().as_slice(),
            &row_major(r.centroidal_momentum_matrix(q).unwrap()),
        ),
        energy(C::kinetic_energy(&qs, &vs), kinetic),
        energy(C::potential_energy(&qs), r.potential_energy(q).unwrap()),
    ]
}

/// The generated rate of the centroidal momentum and its drift against the reference's at one
/// state, each relative to the largest entry of the reference's value.
pub fn centroidal_rate_errors<C, const NQ: usize, const NV: usize>(
    r: &Reference,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> [f64; 2]
where
    C: CentroidalMomentumRate<f64, NQ, NV> + CentroidalMomentumDrift<f64, NQ, NV>,
{
    let (qs, vs, as_) = (
        SVector::from_column_slice(q),
        SVector::from_column_slice(v),
        SVector::from_column_slice(a),
    );
    [
        rel_err(
            C::centroidal_momentum_rate(&qs, &vs, &as_).as_slice(),
            r.centroidal_momentum_rate(q, v, a).unwrap().as_slice(),
        ),
        rel_err(
            C::centroidal_momentum_drift(&qs, &vs).as_slice(),
            r.centroidal_momentum_drift(q, v).unwrap().as_slice(),
        ),
    ]
}

/// The generated `ḣ_G` at `(q, v, a)` against the derivative of the generated `h_G` along
/// `q(t) = q ⊕ (v·t + a·t²/2)`, `v(t) = v + a·t` (`q̇(0)` is the velocity `v` and `v̇(0) = a`,
/// all that `A_G·a + Ȧ_G·v` depends on), by the five-point central difference of step `dt`,
/// whose truncation error falls as `dt⁴`. Relative to the largest entry of the differences;
/// also returns the drift's difference from the rate at `a = 0`, relative to the latter.
pub fn centroidal_rate_by_differences<C, const NQ: usize, const NV: usize>(
    q: &[f64],
    v: &[f64],
    a: &[f64],
    dt: f64,
) -> [f64; 2]
where
    C: CentroidalMomentum<f64, NQ, NV>
        + CentroidalMomentumRate<f64, NQ, NV>
        + CentroidalMomentumDrift<f64, NQ, NV>,
{
    let (qs, vs, as_) = (
        SVector::<f64, NQ>::from_column_slice(q),
        SVector::<f64, NV>::from_column_slice(v),
        SVector::<f64, NV>::from_column_slice(a),
    );
    let h = |t: f64| {
        let delta = vs * t + as_ * (0.5 * t * t);
        let mut qt = [0.0; NQ];
        assert!(articulated::control::tangent::retract(
            C::COORDINATES,
            q,
            delta.as_slice(),
            &mut qt
        ));
        C::centroidal_momentum(&SVector::from_column_slice(&qt), &(vs + as_ * t))
    };
    let by_differences = ((h(dt) - h(-dt)) * 8.0 - (h(2.0 * dt) - h(-2.0 * dt))) / (12.0 * dt);
    let rate = C::centroidal_momentum_rate(&qs, &vs, &as_);
    let drift = C::centroidal_momentum_drift(&qs, &vs);
    let at_zero = C::centroidal_momentum_rate(&qs, &vs, &SVector::zeros());
    [
        rel_err(rate.as_slice(), by_differences.as_slice()),
        rel_err(drift.as_slice(), at_zero.as_slice()),
    ]
}

/// The generated Coriolis matrix against the reference's at one state, relative to its largest
/// entry (or to `max|M|·max|v|`, its natural size, where the matrix vanishes).
pub fn coriolis_error<C, const NQ: usize, const NV: usize>(
    r: &Reference,
    q: &[f64],
    v: &[f64],
) -> f64
where
    C: CoriolisMatrix<f64, NQ, NV>,
{
    let (qs, vs) = (SVector::from_column_slice(q), SVector::from_column_slice(v));
    let want = r.coriolis_matrix(q, v).unwrap();
    let scale = want
        .amax()
        .max(r.mass_matrix(q).unwrap().amax() * max_abs(v))
        .max(1e-300);
    abs_err(C::coriolis_matrix(&qs, &vs).as_slice(), want.as_slice()) / scale
}
