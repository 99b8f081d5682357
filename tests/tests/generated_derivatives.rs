//! The generated derivative outputs (`inverse_dynamics_derivatives`,
//! `forward_dynamics_derivatives`, `mass_matrix_inverse`) of every small shipped model, of a
//! free-floating quaternion chain, of a chain with a quaternion ball joint (`data/ball.chain`) and
//! of the humanoid's legs on its free base (`data/legs.chain`, whose `forward_dynamics_derivatives`
//! the generator composes of smaller functions), each checked
//! three ways on random states:
//! - against central finite differences of the generated values (`inverse_dynamics`,
//!   `forward_dynamics`), the configuration moved along the runtime's own retraction
//!   (`control::tangent::retract`: the body-frame increment for quaternions), the step chosen per
//!   scalar, to 1e-6 relative to the largest entry;
//! - against the reference evaluated with dual numbers through its `Scalar` trait (1e-12 for
//!   `∂τ`; κ(M)-aware for forward dynamics, as for `q̈`), and `M⁻¹` against nalgebra's inverse
//!   of the reference's `M`;
//! - the identities `M⁻¹·M = I` and `∂q̈/∂q = −M⁻¹·∂τ/∂q`, `∂q̈/∂v = −M⁻¹·∂τ/∂v` at `a = q̈`,
//!   with `M` and `∂τ` from the other generated functions.
//!
//! Pinocchio's `computeRNEADerivatives` / `computeABADerivatives` are the last check
//! (`tests/data/pinocchio-derivatives.json`, from `tests/data/make_derivatives_reference.py`),
//! to 1e-10: generated code on the 7-DOF arm (fixed and on its Euler floating base), the
//! reference on the 37-DOF humanoid's free-flyer base.
//!
//! `cargo test -p articulated-tests --test generated_derivatives -- --nocapture` prints the
//! worst errors.

mod common;

use std::path::Path;

use articulated::control::tangent::retract;
use articulated::nalgebra::{DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::{condition, fd_tol, read_json, rel_err, rows_of, vec_of};

/// What a chain with every derivative output and the values they differentiate implements.
trait Derivatives<const NQ: usize, const NV: usize>:
    InverseDynamics<f64, NQ, NV>
    + ForwardDynamics<f64, NQ, NV>
    + MassMatrix<f64, NQ, NV>
    + InverseDynamicsDerivatives<f64, NQ, NV>
    + ForwardDynamicsDerivatives<f64, NQ, NV>
    + MassMatrixInverse<f64, NQ, NV>
{
}

impl<C, const NQ: usize, const NV: usize> Derivatives<NQ, NV> for C where
    C: InverseDynamics<f64, NQ, NV>
        + ForwardDynamics<f64, NQ, NV>
        + MassMatrix<f64, NQ, NV>
        + InverseDynamicsDerivatives<f64, NQ, NV>
        + ForwardDynamicsDerivatives<f64, NQ, NV>
        + MassMatrixInverse<f64, NQ, NV>
{
}

macro_rules! with_derivatives {
    ($name:ident, $file:literal) => {
        #[derive(articulated::Chain)]
        #[chain(
            file = $file,
            outputs = [
                inverse_dynamics, forward_dynamics, mass_matrix, inverse_dynamics_derivatives,
                forward_dynamics_derivatives, mass_matrix_inverse
            ]
        )]
        struct $name;
    };
}

with_derivatives!(TwoLink, "../models/two_link.chain");
with_derivatives!(InvertedPendulum, "../models/inverted_pendulum.chain");
with_derivatives!(DoublePendulum, "../models/double_pendulum.chain");
with_derivatives!(Arm7, "../models/arm7.chain");
with_derivatives!(TreeModel, "../models/tree.chain");
with_derivatives!(FallingCat, "../models/falling_cat.chain");

with_derivatives!(Ball, "data/ball.chain");
with_derivatives!(Legs, "data/legs.chain");

/// The step of a central difference at `x`: `ε^(1/3)·max(1, |x|)`, rounded so that `x ± h`
/// are exact.
fn step(x: f64) -> f64 {
    let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
    (x + h) - x
}

/// `∂f/∂x` by central differences, one column per coordinate of `x` (`n` of them), moving `x`
/// by `±h` along coordinate `k` with `along(k, h)`.
fn central(
    n: usize,
    x: &[f64],
    f: impl Fn(Vec<f64>) -> Vec<f64>,
    along: impl Fn(usize, f64) -> Vec<f64>,
) -> DMatrix<f64> {
    let cols: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let h = step(x.get(k).copied().unwrap_or(0.0));
            let (p, m) = (f(along(k, h)), f(along(k, -h)));
            p.iter().zip(&m).map(|(p, m)| (p - m) / (2.0 * h)).collect()
        })
        .collect();
    DMatrix::from_fn(cols[0].len(), n, |i, j| cols[j][i])
}

fn matrix<const N: usize>(m: &SMatrix<f64, N, N>) -> DMatrix<f64> {
    DMatrix::from_column_slice(N, N, m.as_slice())
}

fn err(ours: &DMatrix<f64>, theirs: &DMatrix<f64>) -> f64 {
    rel_err(ours.as_slice(), theirs.as_slice())
}

/// The worst errors of one chain: `[finite differences, reference (∂τ), reference (forward,
/// over its κ-aware tolerance), identities]`.
fn check<C: Derivatives<NQ, NV>, const NQ: usize, const NV: usize>(
    file: &str,
    states: u64,
) -> [f64; 4] {
    let model = load_model(Path::new(file), false).unwrap_or_else(|e| panic!("{e}"));
    let r = Reference::new(&model).unwrap();
    let coords = C::COORDINATES;
    let mut worst = [0.0f64; 4];
    for seed in 0..states {
        let (q, v, a) = random_state(&model, seed);
        let (qs, vs, as_) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NV>::from_column_slice(&v),
            SVector::<f64, NV>::from_column_slice(&a),
        );
        let tau = C::inverse_dynamics(&qs, &vs, &as_).add_scalar(0.5);
        let (dtau_dq, dtau_dv) = C::inverse_dynamics_derivatives(&qs, &vs, &as_);
        let (ddq_dq, ddq_dv, minv) = C::forward_dynamics_derivatives(&qs, &vs, &tau)
            .unwrap_or_else(|e| panic!("{file}, seed {seed}: {e}"));
        let (dtau_dq, dtau_dv, ddq_dq, ddq_dv, minv) = (
            matrix(&dtau_dq),
            matrix(&dtau_dv),
            matrix(&ddq_dq),
            matrix(&ddq_dv),
            matrix(&minv),
        );

        // Finite differences of the generated values.
        let moved = |k: usize, h: f64| {
            let mut delta = vec![0.0; NV];
            delta[k] = h;
            let mut out = vec![0.0; NQ];
            assert!(retract(coords, &q, &delta, &mut out));
            out
        };
        let plus_v = |k: usize, h: f64| {
            let mut out = v.clone();
            out[k] += h;
            out
        };
        let id = |q: &[f64], v: &[f64]| {
            C::inverse_dynamics(
                &SVector::from_column_slice(q),
                &SVector::from_column_slice(v),
                &as_,
            )
            .as_slice()
            .to_vec()
        };
        let fd = |q: &[f64], v: &[f64], tau: &SVector<f64, NV>| {
            C::forward_dynamics(
                &SVector::from_column_slice(q),
                &SVector::from_column_slice(v),
                tau,
            )
            .unwrap()
            .as_slice()
            .to_vec()
        };
        let zeros = vec![0.0; NV];
        let differences = [
            (
                err(&dtau_dq, &central(NV, &zeros, |q| id(&q, &v), moved)),
                "dtau/dq",
            ),
            (
                err(&dtau_dv, &central(NV, &v, |v| id(&q, &v), plus_v)),
                "dtau/dv",
            ),
            (
                err(&ddq_dq, &central(NV, &zeros, |q| fd(&q, &v, &tau), moved)),
                "dqdd/dq",
            ),
            (
                err(&ddq_dv, &central(NV, &v, |v| fd(&q, &v, &tau), plus_v)),
                "dqdd/dv",
            ),
            (
                err(
                    &minv,
                    &central(
                        NV,
                        tau.as_slice(),
                        |t| fd(&q, &v, &SVector::from_column_slice(&t)),
                        |k, h| {
                            let mut t = tau.as_slice().to_vec();
                            t[k] += h;
                            t
                        },
                    ),
                ),
                "dqdd/dtau",
            ),
        ];
        for (e, what) in differences {
            assert!(
                e < 1e-6,
                "{file}, seed {seed}: {what} against central differences: {e:e}"
            );
            worst[0] = worst[0].max(e);
        }

        // The reference on dual numbers.
        let (rq, rv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
        let e = err(&dtau_dq, &rq).max(err(&dtau_dv, &rv));
        assert!(
            e < 1e-12,
            "{file}, seed {seed}: dtau against the reference: {e:e}"
        );
        worst[1] = worst[1].max(e);
        let m_ref = r.mass_matrix(&q).unwrap();
        let tol = fd_tol(condition(&m_ref));
        let [rdq, rdv, rminv] = r
            .forward_dynamics_derivatives(&q, &v, tau.as_slice())
            .unwrap();
        let inverse = m_ref.clone().try_inverse().unwrap();
        let e = [
            err(&ddq_dq, &rdq),
            err(&ddq_dv, &rdv),
            err(&minv, &rminv),
            err(&minv, &inverse),
        ]
        .into_iter()
        .fold(0.0, f64::max)
            / tol;
        assert!(
            e < 1.0,
            "{file}, seed {seed}: forward derivatives against the reference: {e:e} of {tol:e}"
        );
        worst[2] = worst[2].max(e);

        // Identities, with the other generated functions.
        let m = matrix(&C::mass_matrix(&qs));
        let qdd = C::forward_dynamics(&qs, &vs, &tau).unwrap();
        let (at_q, at_v) = C::inverse_dynamics_derivatives(&qs, &vs, &qdd);
        let identity = DMatrix::<f64>::identity(NV, NV);
        let generated_minv = matrix(&C::mass_matrix_inverse(&qs).unwrap());
        let e = [
            err(&(&minv * &m), &identity),
            err(&generated_minv, &minv),
            err(&ddq_dq, &(-&minv * matrix(&at_q))),
            err(&ddq_dv, &(-&minv * matrix(&at_v))),
        ]
        .into_iter()
        .fold(0.0, f64::max)
            / tol;
        assert!(e < 1.0, "{file}, seed {seed}: identities: {e:e} of {tol:e}");
        worst[3] = worst[3].max(e);
    }
    println!(
        "{file}: finite differences {:.1e}, reference ∂τ {:.1e}, reference forward {:.2} of tolerance, identities {:.2} of tolerance",
        worst[0], worst[1], worst[2], worst[3]
    );
    worst
}

#[test]
fn shipped_models() {
    check::<TwoLink, { TwoLink::NQ }, { TwoLink::NV }>("../models/two_link.chain", 16);
    check::<InvertedPendulum, { InvertedPendulum::NQ }, { InvertedPendulum::NV }>(
        "../models/inverted_pendulum.chain",
        16,
    );
    check::<DoublePendulum, { DoublePendulum::NQ }, { DoublePendulum::NV }>(
        "../models/double_pendulum.chain",
        16,
    );
    check::<Arm7, { Arm7::NQ }, { Arm7::NV }>("../models/arm7.chain", 16);
    check::<TreeModel, { TreeModel::NQ }, { TreeModel::NV }>("../models/tree.chain", 16);
}

#[test]
fn quaternion_joints() {
    check::<FallingCat, { FallingCat::NQ }, { FallingCat::NV }>("../models/falling_cat.chain", 16);
    check::<Ball, { Ball::NQ }, { Ball::NV }>("data/ball.chain", 16);
}

/// A chain large enough that its `forward_dynamics_derivatives` is composed of
/// `forward_dynamics`, `inverse_dynamics_derivatives` and `mass_matrix_inverse` and two
/// products (`codegen/src/generate/composed.rs`): the humanoid's legs on its free quaternion
/// base, 18 velocities. The same three checks; the finite differences and the reference do not
/// go through the composition.
#[test]
fn composed_forward_dynamics_derivatives() {
    check::<Legs, { Legs::NQ }, { Legs::NV }>("data/legs.chain", 8);
}

/// Pinocchio's derivatives: the generated arm on its fixed and floating (Euler) bases.
#[derive(articulated::Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    outputs = [inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse]
)]
struct Arm7Urdf;
#[derive(articulated::Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    floating,
    outputs = [inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse]
)]
struct Arm7Floating;

/// Relative to the largest entry of Pinocchio's value.
const PINOCCHIO_TOL: f64 = 1e-10;

/// The worst error of a chain's derivatives against one configuration of the JSON; `eval`
/// gives ours as `[∂τ/∂q, ∂τ/∂v, ∂q̈/∂q, ∂q̈/∂v, M⁻¹]`, each row-major.
fn against_pinocchio(
    config: &serde_json::Value,
    eval: impl Fn(&[f64], &[f64], &[f64], &[f64]) -> [Vec<f64>; 5],
) -> f64 {
    let states = config["states"].as_array().unwrap();
    assert!(!states.is_empty());
    let mut worst = 0.0f64;
    for s in states {
        let (q, v, a, tau) = (
            vec_of(&s["q"]),
            vec_of(&s["v"]),
            vec_of(&s["a"]),
            vec_of(&s["tau"]),
        );
        let ours = eval(&q, &v, &a, &tau);
        let theirs = ["dtau_dq", "dtau_dv", "ddq_dq", "ddq_dv", "minv"].map(|k| rows_of(&s[k]));
        for (o, t) in ours.iter().zip(&theirs) {
            worst = worst.max(rel_err(o, t));
        }
        worst = worst.max(rel_err(&ours[4], &rows_of(&s["mass_matrix_inverse"])));
    }
    worst
}

/// Row-major entries of a generated (column-major) square matrix.
fn rows<const N: usize>(m: &SMatrix<f64, N, N>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

fn generated<C, const NQ: usize, const NV: usize>(
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tau: &[f64],
) -> [Vec<f64>; 5]
where
    C: InverseDynamicsDerivatives<f64, NQ, NV> + ForwardDynamicsDerivatives<f64, NQ, NV>,
{
    let (q, v) = (SVector::from_column_slice(q), SVector::from_column_slice(v));
    let (dq, dv) = C::inverse_dynamics_derivatives(&q, &v, &SVector::from_column_slice(a));
    let (fq, fv, minv) =
        C::forward_dynamics_derivatives(&q, &v, &SVector::from_column_slice(tau)).unwrap();
    [rows(&dq), rows(&dv), rows(&fq), rows(&fv), rows(&minv)]
}

#[test]
fn generated_arm_matches_pinocchio() {
    let json = read_json("data/pinocchio-derivatives.json");
    let arm = &json["models"]["arm7"];
    let fixed = against_pinocchio(&arm["fixed"], generated::<Arm7Urdf, 7, 7>);
    let floating = against_pinocchio(&arm["floating"], generated::<Arm7Floating, 13, 13>);
    println!("arm7 against Pinocchio: fixed {fixed:.1e}, floating {floating:.1e}");
    assert!(fixed < PINOCCHIO_TOL, "arm7 (fixed): {fixed:e}");
    assert!(floating < PINOCCHIO_TOL, "arm7 (floating): {floating:e}");
}

#[test]
fn reference_humanoid_matches_pinocchio() {
    let json = read_json("data/pinocchio-derivatives.json");
    let model = load_model(Path::new(articulated_models::HUMANOID.chain), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let rows = |m: DMatrix<f64>| m.transpose().as_slice().to_vec();
    let worst = against_pinocchio(&json["models"]["humanoid"]["free_flyer"], |q, v, a, tau| {
        let (dq, dv) = r.inverse_dynamics_derivatives(q, v, a).unwrap();
        let [fq, fv, minv] = r.forward_dynamics_derivatives(q, v, tau).unwrap();
        [rows(dq), rows(dv), rows(fq), rows(fv), rows(minv)]
    });
    println!("humanoid (free flyer), reference against Pinocchio: {worst:.1e}");
    assert!(worst < PINOCCHIO_TOL, "humanoid: {worst:e}");
}

/// The two-link's derivatives in `f32`.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = f32,
    outputs = [inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse]
)]
struct TwoLinkF32;

/// The two-link's derivatives for any scalar.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    scalar = generic,
    outputs = [inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse]
)]
struct TwoLinkGeneric;

/// `f32` (to 1e-5 for `∂τ`, 1e-4 for forward dynamics' derivatives, relative to the largest
/// entry) and generic over `f64` (1e-12) against the `f64` reference, on inputs exactly
/// representable in `f32`.
#[test]
fn derivatives_in_every_scalar() {
    let model = load_model(Path::new(articulated_models::TWO_LINK.chain), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let to32 = |x: &[f64]| SVector::<f32, 6>::from_iterator(x.iter().map(|&v| v as f32));
    let to64 = |x: &[f32]| x.iter().map(|&v| f64::from(v)).collect::<Vec<f64>>();
    let (mut worst_tau32, mut worst_fd32, mut worst64) = (0.0f64, 0.0f64, 0.0f64);
    for seed in 0..32 {
        let (q, v, a) = random_state(&model, seed);
        let (q32, v32, a32) = (to32(&q), to32(&v), to32(&a));
        let tau32 = to32(r.inverse_dynamics(&q, &v, &a).unwrap().as_slice()).add_scalar(0.5);
        let (q, v, a, tau) = (
            to64(q32.as_slice()),
            to64(v32.as_slice()),
            to64(a32.as_slice()),
            to64(tau32.as_slice()),
        );
        let (rq, rv) = r.inverse_dynamics_derivatives(&q, &v, &a).unwrap();
        let [fq, fv, minv] = r.forward_dynamics_derivatives(&q, &v, &tau).unwrap();
        let want = [rq, rv, fq, fv, minv].map(|m| m.as_slice().to_vec());

        let (dq, dv) = TwoLinkF32::inverse_dynamics_derivatives(&q32, &v32, &a32);
        let (gq, gv, gminv) = TwoLinkF32::forward_dynamics_derivatives(&q32, &v32, &tau32).unwrap();
        let ours32 = [dq, dv, gq, gv, gminv].map(|m| to64(m.as_slice()));
        for (k, (o, w)) in ours32.iter().zip(&want).enumerate() {
            let e = rel_err(o, w);
            if k < 2 {
                worst_tau32 = worst_tau32.max(e);
            } else {
                worst_fd32 = worst_fd32.max(e);
            }
        }
        let minv32 = TwoLinkF32::mass_matrix_inverse(&q32).unwrap();
        worst_fd32 = worst_fd32.max(rel_err(&to64(minv32.as_slice()), &want[4]));

        let (q64, v64) = (
            SVector::<f64, 6>::from_column_slice(&q),
            SVector::<f64, 6>::from_column_slice(&v),
        );
        let (a64, tau64) = (
            SVector::<f64, 6>::from_column_slice(&a),
            SVector::<f64, 6>::from_column_slice(&tau),
        );
        let (dq, dv) =
            <TwoLinkGeneric as InverseDynamicsDerivatives<f64, 6, 6>>::inverse_dynamics_derivatives(
                &q64, &v64, &a64,
            );
        let (gq, gv, gminv) = <TwoLinkGeneric as ForwardDynamicsDerivatives<f64, 6, 6>>::forward_dynamics_derivatives(&q64, &v64, &tau64).unwrap();
        let minv64 =
            <TwoLinkGeneric as MassMatrixInverse<f64, 6, 6>>::mass_matrix_inverse(&q64).unwrap();
        for (o, w) in [dq, dv, gq, gv, gminv, minv64]
            .iter()
            .zip(want.iter().chain([&want[4]]))
        {
            worst64 = worst64.max(rel_err(o.as_slice(), w));
        }
    }
    println!("two-link derivatives: f32 ∂τ {worst_tau32:.1e}, f32 forward {worst_fd32:.1e}, generic f64 {worst64:.1e}");
    assert!(worst_tau32 < 1e-5, "f32 ∂τ: {worst_tau32:e}");
    assert!(worst_fd32 < 1e-4, "f32 forward derivatives: {worst_fd32:e}");
    assert!(worst64 < 1e-12, "generic f64: {worst64:e}");
}
