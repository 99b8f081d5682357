//! The extremes of the accuracy study (issue 12): generated code in `f64` and `f32`, with each
//! accuracy choice, and the `f64` reference, measured against the double-double ground truth
//! ([`articulated_dynamics::extended`]) at the states where rigid-body dynamics loses digits.
//!
//! - **Gimbal lock**: Hemami's two-link (`models/two_link.chain`, roll-pitch-yaw joints) with the
//!   ankle's second angle `π/2 − δ`, `δ` from 0.1 down to exactly 0; the same attitudes with
//!   quaternion joints (`data/extremes/two_link_quaternion.chain`).
//! - **Mass ratios** 1e-6 … 1e12 (the links' mass over the tip's), **slender tips** (axial moment
//!   down to 1e-12 of the others), a tip on the **triangle inequality's edge** (a flat disc), and
//!   **lengths** from 0.1 mm to 1 km: `data/extremes/three_link.chain`, whose numbers are
//!   runtime parameters.
//! - **Spin** up to 1e4 rad/s on both chains.
//!
//! Each [`Row`] holds `cond(M)` and the normwise relative error of forward dynamics (and the
//! largest of `M`'s and `τ`'s) for each way of computing it, or the refusal. The example
//! `extremes` prints them as `docs/accuracy.md`; `tests/extremes.rs` asserts the bounds.

use core::f64::consts::FRAC_PI_2;
use std::path::Path;

use articulated::nalgebra::{DMatrix, SMatrix, SVector};
use articulated::prelude::*;
use articulated_dynamics::extended::{relative_error, Dd, GroundTruth};
use articulated_dynamics::model::Model;
use articulated_dynamics::reference::Reference;

macro_rules! extremes_chain {
    ($name:ident, $file:literal, $scalar:ident, $accuracy:ident) => {
        #[doc = concat!("`", $file, "` in `", stringify!($scalar), "`, `accuracy = ", stringify!($accuracy), "`.")]
        #[derive(articulated::Chain)]
        #[chain(
            file = $file,
            scalar = $scalar,
            accuracy = $accuracy,
            outputs = [mass_matrix, inverse_dynamics, forward_dynamics]
        )]
        pub struct $name;
    };
}

extremes_chain!(TwoLinkFastest, "../models/two_link.chain", f64, fastest);
extremes_chain!(TwoLinkRobust, "../models/two_link.chain", f64, robust);
extremes_chain!(TwoLinkFastestF32, "../models/two_link.chain", f32, fastest);
extremes_chain!(TwoLinkRobustF32, "../models/two_link.chain", f32, robust);
extremes_chain!(
    QuaternionFastest,
    "data/extremes/two_link_quaternion.chain",
    f64,
    fastest
);
extremes_chain!(
    QuaternionRobust,
    "data/extremes/two_link_quaternion.chain",
    f64,
    robust
);
extremes_chain!(
    QuaternionFastestF32,
    "data/extremes/two_link_quaternion.chain",
    f32,
    fastest
);
extremes_chain!(
    QuaternionRobustF32,
    "data/extremes/two_link_quaternion.chain",
    f32,
    robust
);
extremes_chain!(
    ThreeLinkFastest,
    "data/extremes/three_link.chain",
    f64,
    fastest
);
extremes_chain!(
    ThreeLinkRobust,
    "data/extremes/three_link.chain",
    f64,
    robust
);
extremes_chain!(
    ThreeLinkFastestF32,
    "data/extremes/three_link.chain",
    f32,
    fastest
);
extremes_chain!(
    ThreeLinkRobustF32,
    "data/extremes/three_link.chain",
    f32,
    robust
);

/// What one way of computing forward dynamics gave at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// The normwise relative error of `q̈` against ground truth.
    Error(f64),
    /// The function refused the state (`Err`: `M` singular for its scalar).
    Refused,
}

impl Outcome {
    /// The error, if the state was accepted.
    pub fn error(self) -> Option<f64> {
        match self {
            Outcome::Error(e) => Some(e),
            Outcome::Refused => None,
        }
    }
}

/// Forward dynamics and the other outputs of one scalar and accuracy choice at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// `q̈`.
    pub forward: Outcome,
    /// The larger of `M`'s and `τ`'s relative errors (always computed).
    pub others: f64,
}

/// One state of one scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The scenario (`gimbal lock`, `mass ratio`, …).
    pub scenario: &'static str,
    /// The case within it (`δ = 1e-6`).
    pub case: String,
    /// `cond(M)` at the `f64` state (from the ground truth's `M`).
    pub cond: f64,
    /// The `f64` reference (ABA with its own singularity checks).
    pub reference: Outcome,
    /// Generated `f64`, `accuracy = fastest`.
    pub fastest: Measured,
    /// Generated `f64`, `accuracy = robust`.
    pub robust: Measured,
    /// Generated `f32`, `accuracy = fastest`.
    pub fastest_f32: Measured,
    /// Generated `f32`, `accuracy = robust`.
    pub robust_f32: Measured,
}

/// A chain's model, read from the file the generated types were made from.
fn model(file: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    articulated_codegen::load::load_model(&path, false)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A state and the parameters it is evaluated with.
struct State<'a> {
    q: &'a [f64],
    v: &'a [f64],
    tau: &'a [f64],
    params: &'a [f64],
}

/// `M` row-major, `τ = ID(q, v, τ_as_a)` and `q̈` from one generated chain.
type Evaluated = (Vec<f64>, Vec<f64>, Option<Vec<f64>>);

/// The normwise relative errors of one generated chain's outputs at `s` (inputs rounded to the
/// chain's scalar, the ground truth taken at the rounded state).
fn measure(model: &Model, s: &State, eval: impl Fn(&State) -> Evaluated) -> Measured {
    let truth = GroundTruth::with_params(model, s.params).expect("a valid model");
    let (m, tau, qdd) = eval(s);
    let m_truth = truth.mass_matrix(s.q).expect("a valid state");
    let id_truth = truth
        .inverse_dynamics(s.q, s.v, s.tau, true)
        .expect("a valid state");
    let others = relative_error(&m, &m_truth).max(relative_error(&tau, &id_truth));
    let forward = match qdd {
        Some(qdd) => {
            let (qdd_truth, _) = truth
                .forward_dynamics(s.q, s.v, s.tau)
                .expect("a valid state");
            Outcome::Error(relative_error(&qdd, &qdd_truth))
        }
        None => Outcome::Refused,
    };
    Measured { forward, others }
}

/// `x` rounded to `f32` and widened back (exactly).
fn round32(x: &[f64]) -> Vec<f64> {
    x.iter().map(|&x| f64::from(x as f32)).collect()
}

/// One generated chain evaluated in its scalar at a state given in `f64`: `$params` builds its
/// parameters from a slice (`|_| ()` without any).
macro_rules! evaluate {
    ($chain:ty, $t:ty, $nq:literal, $nv:literal, $params:expr) => {
        |s: &State| -> Evaluated {
            let q = SVector::<$t, $nq>::from_iterator(s.q.iter().map(|&x| x as $t));
            let v = SVector::<$t, $nv>::from_iterator(s.v.iter().map(|&x| x as $t));
            let tau = SVector::<$t, $nv>::from_iterator(s.tau.iter().map(|&x| x as $t));
            let p: <$chain as Chain<$t>>::Params = ($params)(s.params);
            let m: SMatrix<$t, $nv, $nv> = <$chain>::mass_matrix_with(&q, &p);
            let id = <$chain>::inverse_dynamics_with(&q, &v, &tau, &p);
            let qdd = <$chain>::forward_dynamics_with(&q, &v, &tau, &p).ok();
            let widen = |x: &[$t]| -> Vec<f64> { x.iter().map(|&x| f64::from(x)).collect() };
            let m_rows: Vec<f64> = widen(m.transpose().as_slice());
            (
                m_rows,
                widen(id.as_slice()),
                qdd.map(|x| widen(x.as_slice())),
            )
        }
    };
}

/// `cond(M)` of the ground truth's `M` rounded to `f64` (infinite where it is singular to that
/// precision).
fn condition(truth: &GroundTruth, q: &[f64]) -> f64 {
    let n = truth.nv();
    let m: Vec<f64> = truth
        .mass_matrix(q)
        .expect("a valid state")
        .iter()
        .map(|x: &Dd| x.to_f64())
        .collect();
    let eig = DMatrix::from_row_slice(n, n, &m).symmetric_eigenvalues();
    let (lo, hi) = (eig.min(), eig.max());
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// The reference's outcome at `s`.
fn reference(model: &Model, s: &State) -> Outcome {
    let truth = GroundTruth::with_params(model, s.params).expect("a valid model");
    let (qdd_truth, _) = truth
        .forward_dynamics(s.q, s.v, s.tau)
        .expect("a valid state");
    match Reference::with_params(model, s.params)
        .expect("a valid model")
        .forward_dynamics(s.q, s.v, s.tau)
    {
        Ok(qdd) => Outcome::Error(relative_error(qdd.as_slice(), &qdd_truth)),
        Err(_) => Outcome::Refused,
    }
}

/// The quaternion `[w, x, y, z]` of `Rx(a)·Ry(b)·Rz(c)` (the two-link's `xyz` Euler angles).
fn quaternion_xyz(a: f64, b: f64, c: f64) -> [f64; 4] {
    let half = |x: f64| ((x / 2.0).cos(), (x / 2.0).sin());
    let ((ca, sa), (cb, sb), (cc, sc)) = (half(a), half(b), half(c));
    // qx·qy, then ·qz.
    let (w, x, y, z) = (ca * cb, sa * cb, ca * sb, sa * sb);
    [
        w * cc - z * sc,
        x * cc + y * sc,
        y * cc - x * sc,
        z * cc + w * sc,
    ]
}

/// Every row of the study.
pub fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    gimbal_lock(&mut rows);
    three_link(&mut rows);
    spin(&mut rows);
    rows
}

/// A row from the four generated chains (`f64` then `f32`, fastest then robust).
#[allow(clippy::too_many_arguments)]
fn row(
    scenario: &'static str,
    case: String,
    model: &Model,
    s: &State,
    fastest: impl Fn(&State) -> Evaluated,
    robust: impl Fn(&State) -> Evaluated,
    fastest_f32: impl Fn(&State) -> Evaluated,
    robust_f32: impl Fn(&State) -> Evaluated,
) -> Row {
    let truth = GroundTruth::with_params(model, s.params).expect("a valid model");
    let (q32, v32, tau32, p32) = (
        round32(s.q),
        round32(s.v),
        round32(s.tau),
        round32(s.params),
    );
    let s32 = State {
        q: &q32,
        v: &v32,
        tau: &tau32,
        params: &p32,
    };
    Row {
        scenario,
        case,
        cond: condition(&truth, s.q),
        reference: reference(model, s),
        fastest: measure(model, s, fastest),
        robust: measure(model, s, robust),
        fastest_f32: measure(model, &s32, fastest_f32),
        robust_f32: measure(model, &s32, robust_f32),
    }
}

/// A two-link row (Euler joints) from its four generated chains.
fn two_link_row(scenario: &'static str, case: String, model: &Model, s: &State) -> Row {
    row(
        scenario,
        case,
        model,
        s,
        evaluate!(TwoLinkFastest, f64, 6, 6, |_| ()),
        evaluate!(TwoLinkRobust, f64, 6, 6, |_| ()),
        evaluate!(TwoLinkFastestF32, f32, 6, 6, |_| ()),
        evaluate!(TwoLinkRobustF32, f32, 6, 6, |_| ()),
    )
}

const TWO_LINK_V: [f64; 6] = [0.5, -0.3, 0.8, 0.2, -0.1, 0.3];
const TWO_LINK_TAU: [f64; 6] = [1.0, -2.0, 0.5, 3.0, 1.0, -1.0];

/// The gimbal-lock sweep on the Euler and the quaternion two-link.
fn gimbal_lock(rows: &mut Vec<Row>) {
    let euler = model("../models/two_link.chain");
    let quaternion = model("data/extremes/two_link_quaternion.chain");
    for delta in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 0.0] {
        let q = [0.2, FRAC_PI_2 - delta, -0.3, 0.1, 0.4, 0.2];
        let s = State {
            q: &q,
            v: &TWO_LINK_V,
            tau: &TWO_LINK_TAU,
            params: &[],
        };
        rows.push(two_link_row(
            "gimbal lock, Euler angles",
            format!("δ = {delta:.0e}"),
            &euler,
            &s,
        ));
        let (a, b) = (
            quaternion_xyz(q[0], q[1], q[2]),
            quaternion_xyz(q[3], q[4], q[5]),
        );
        let qq = [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]];
        let s = State {
            q: &qq,
            v: &TWO_LINK_V,
            tau: &TWO_LINK_TAU,
            params: &[],
        };
        rows.push(row(
            "the same attitudes, quaternions",
            format!("δ = {delta:.0e}"),
            &quaternion,
            &s,
            evaluate!(QuaternionFastest, f64, 8, 6, |_| ()),
            evaluate!(QuaternionRobust, f64, 8, 6, |_| ()),
            evaluate!(QuaternionFastestF32, f32, 8, 6, |_| ()),
            evaluate!(QuaternionRobustF32, f32, 8, 6, |_| ()),
        ));
    }
}

/// The three-link's parameters: `[length, half, link_i, link_izz, tip_mass, tip_i, tip_izz]`.
type ThreeLinkParams = [f64; 7];

const THREE_LINK_DEFAULT: ThreeLinkParams = [0.5, 0.25, 0.02, 0.005, 1.0, 0.02, 0.005];

macro_rules! three_link_params {
    ($params:ident, $t:ty) => {
        |p: &[f64]| $params {
            length: p[0] as $t,
            half: p[1] as $t,
            link_i: p[2] as $t,
            link_izz: p[3] as $t,
            tip_mass: p[4] as $t,
            tip_i: p[5] as $t,
            tip_izz: p[6] as $t,
        }
    };
}

/// One three-link row.
fn three_link_row(
    scenario: &'static str,
    case: String,
    params: &ThreeLinkParams,
    v: &[f64; 3],
) -> Row {
    let model = model("data/extremes/three_link.chain");
    let (q, tau) = ([0.4, -0.7, 0.3], [1.0, -0.5, 0.2]);
    let s = State {
        q: &q,
        v,
        tau: &tau,
        params,
    };
    row(
        scenario,
        case,
        &model,
        &s,
        evaluate!(
            ThreeLinkFastest,
            f64,
            3,
            3,
            three_link_params!(ThreeLinkFastestParams, f64)
        ),
        evaluate!(
            ThreeLinkRobust,
            f64,
            3,
            3,
            three_link_params!(ThreeLinkRobustParams, f64)
        ),
        evaluate!(
            ThreeLinkFastestF32,
            f32,
            3,
            3,
            three_link_params!(ThreeLinkFastestF32Params, f32)
        ),
        evaluate!(
            ThreeLinkRobustF32,
            f32,
            3,
            3,
            three_link_params!(ThreeLinkRobustF32Params, f32)
        ),
    )
}

/// Mass ratios, slender tips, the triangle inequality's edge, lengths.
fn three_link(rows: &mut Vec<Row>) {
    let v = [0.5, -0.3, 0.8];
    for ratio in [1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9, 1e12] {
        let mut p = THREE_LINK_DEFAULT;
        // The tip's mass and inertia over the ratio.
        p[4] /= ratio;
        p[5] /= ratio;
        p[6] /= ratio;
        rows.push(three_link_row(
            "mass ratio, links : tip",
            format!("{ratio:.0e}"),
            &p,
            &v,
        ));
    }
    for izz in [5e-3, 1e-6, 1e-9, 1e-12] {
        let mut p = THREE_LINK_DEFAULT;
        p[6] = izz;
        rows.push(three_link_row(
            "slender tip, axial moment",
            format!("{izz:.0e} kg·m²"),
            &p,
            &v,
        ));
    }
    let mut p = THREE_LINK_DEFAULT;
    // A flat disc: Izz = Ixx + Iyy exactly.
    p[5] = 0.01;
    p[6] = 0.02;
    rows.push(three_link_row(
        "triangle inequality's edge",
        "Izz = Ixx + Iyy".into(),
        &p,
        &v,
    ));
    for length in [1e-4, 1e-2, 1.0, 1e2, 1e3] {
        let scale = length / THREE_LINK_DEFAULT[0];
        let mut p = THREE_LINK_DEFAULT;
        p[0] = length;
        p[1] = length / 2.0;
        for k in [2, 3, 5, 6] {
            p[k] *= scale * scale;
        }
        rows.push(three_link_row(
            "lengths (inertias scaled)",
            format!("{length:.0e} m"),
            &p,
            &v,
        ));
    }
}

/// Spin rates up to 1e4 rad/s.
fn spin(rows: &mut Vec<Row>) {
    let euler = model("../models/two_link.chain");
    for rate in [1.0, 1e2, 1e4] {
        let q = [0.2, 0.5, -0.3, 0.1, 0.4, 0.2];
        let v = TWO_LINK_V.map(|x| x * rate);
        let s = State {
            q: &q,
            v: &v,
            tau: &TWO_LINK_TAU,
            params: &[],
        };
        rows.push(two_link_row(
            "spin, two-link",
            format!("{rate:.0e} rad/s"),
            &euler,
            &s,
        ));
        let v3 = [0.5 * rate, -0.3 * rate, 0.8 * rate];
        rows.push(three_link_row(
            "spin, three-link",
            format!("{rate:.0e} rad/s"),
            &THREE_LINK_DEFAULT,
            &v3,
        ));
    }
}

/// `x` as the table prints it: `3.1e-15`, or `refused`.
fn cell(o: Outcome) -> String {
    match o {
        Outcome::Error(e) => format!("{e:.1e}"),
        Outcome::Refused => "refused".into(),
    }
}

/// The rows as a Markdown table.
pub fn table(rows: &[Row]) -> String {
    let mut out = String::from(
        "| scenario | case | cond(M) | reference f64 | fastest f64 | robust f64 | fastest f32 | \
         robust f32 | M, τ f64 | M, τ f32 |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {:.1e} | {} | {} | {} | {} | {} | {:.1e} | {:.1e} |\n",
            r.scenario,
            r.case,
            r.cond,
            cell(r.reference),
            cell(r.fastest.forward),
            cell(r.robust.forward),
            cell(r.fastest_f32.forward),
            cell(r.robust_f32.forward),
            r.fastest.others.max(r.robust.others),
            r.fastest_f32.others.max(r.robust_f32.others),
        ));
    }
    out
}
