//! Long horizons (issue 12): the energy and momentum drift of every integrator over 1e5 and 1e6
//! steps, on Hemami's two-link (Euler-angle joints, gravity) and on the falling cat without
//! gravity (`data/drift/floating_cat.chain`: a free quaternion base and an Euler waist), both
//! left to themselves (`τ = 0`) with generated `f64` code.
//!
//! What is conserved, and so what drift means: the total energy `T + V` on both; on the floating
//! cat, on which no external force acts, also the angular momentum about the centre of mass
//! `k_G` and the linear momentum `p` (Wieber 2005, §4). Each [`Run`] records, every
//! `record_every` steps, the relative error of the energy and of each momentum against their
//! initial values. The example `drift`
//! writes `docs/drift.md` and `docs/figures/drift.svg`; `tests/drift.rs` asserts what each
//! method guarantees over a shorter horizon.

use std::time::Instant;

use articulated::integrate::{ControlledChain, Integrator, Method, State, Stepper};
use articulated::nalgebra::{Const, SVector};
use articulated::prelude::*;

/// Hemami's two-link with what the study reads.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [forward_dynamics, kinetic_energy, potential_energy]
)]
pub struct DriftTwoLink;

/// The falling cat without gravity, with what the study reads.
#[derive(articulated::Chain)]
#[chain(
    file = "data/drift/floating_cat.chain",
    outputs = [forward_dynamics, kinetic_energy, potential_energy, centroidal_momentum]
)]
pub struct DriftCat;

/// The two models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// [`DriftTwoLink`], swinging from `q0 = [3.0, 0.2, 0, 0, −0.3, 0]` (hanging, tilted).
    TwoLink,
    /// [`DriftCat`], tumbling: spun about two axes and twisting at the waist, no gravity.
    Cat,
}

impl Model {
    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Model::TwoLink => "two-link",
            Model::Cat => "floating cat",
        }
    }
}

/// One integration, recorded.
#[derive(Clone, Debug)]
pub struct Run {
    /// The model.
    pub model: Model,
    /// The method.
    pub method: Method,
    /// The step (for Dopri5: the output interval; it steps to its tolerance within).
    pub dt: f64,
    /// Steps taken (output intervals for Dopri5).
    pub steps: usize,
    /// `(t, |E − E₀|/|E₀|)` every `record_every` steps.
    pub energy: Vec<(f64, f64)>,
    /// `(t, |k_G − k₀|/|k₀|)` (the cat only).
    pub angular_momentum: Vec<(f64, f64)>,
    /// `(t, |p − p₀| / |p₀|)` (the cat only).
    pub linear_momentum: Vec<(f64, f64)>,
    /// Wall time of the integration (s), recording included.
    pub seconds: f64,
    /// The fault that stopped it early, if any.
    pub fault: Option<String>,
}

impl Run {
    /// The largest energy error over the run.
    pub fn max_energy(&self) -> f64 {
        self.energy.iter().fold(0.0, |m, &(_, e)| m.max(e))
    }

    /// The largest energy error over the first and over the second half of the run.
    pub fn halves(&self) -> (f64, f64) {
        let mid = self.energy.len() / 2;
        let max = |s: &[(f64, f64)]| s.iter().fold(0.0f64, |m, &(_, e)| m.max(e));
        (max(&self.energy[..mid]), max(&self.energy[mid..]))
    }

    /// The largest angular-momentum error (zero for the two-link).
    pub fn max_angular_momentum(&self) -> f64 {
        self.angular_momentum
            .iter()
            .fold(0.0, |m, &(_, e)| m.max(e))
    }
}

/// The cat's initial state: upright-ish, spinning and twisting.
fn cat_start() -> (SVector<f64, 10>, SVector<f64, 9>) {
    let q =
        SVector::<f64, 10>::from_column_slice(&[0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.3, -0.4, 0.2]);
    let v = SVector::<f64, 9>::from_column_slice(&[0.2, -0.1, 0.5, 1.5, -0.8, 2.0, 1.0, -0.7, 0.9]);
    (q, v)
}

const TWO_LINK_Q0: [f64; 6] = [3.0, 0.2, 0.0, 0.0, -0.3, 0.0];
const TWO_LINK_V0: [f64; 6] = [0.0, 0.5, 0.0, 0.0, -0.5, 0.0];

/// `steps` steps of `dt` of `method` on `model`, recording every `record_every` steps.
pub fn run(model: Model, method: Method, dt: f64, steps: usize, record_every: usize) -> Run {
    match model {
        Model::TwoLink => {
            let q0 = SVector::<f64, 6>::from_column_slice(&TWO_LINK_Q0);
            let v0 = SVector::<f64, 6>::from_column_slice(&TWO_LINK_V0);
            integrate::<DriftTwoLink, 6, 6>(
                model,
                method,
                dt,
                steps,
                record_every,
                q0,
                v0,
                |_, _| None,
            )
        }
        Model::Cat => {
            let (q0, v0) = cat_start();
            let h0 = DriftCat::centroidal_momentum(&q0, &v0);
            let (k0, p0) = (h0.fixed_rows::<3>(0).norm(), h0.fixed_rows::<3>(3).norm());
            integrate::<DriftCat, 10, 9>(
                model,
                method,
                dt,
                steps,
                record_every,
                q0,
                v0,
                move |s, _| {
                    let h = DriftCat::centroidal_momentum(&s.q, &s.v);
                    let dk = (h.fixed_rows::<3>(0) - h0.fixed_rows::<3>(0)).norm() / k0;
                    let dp = (h.fixed_rows::<3>(3) - h0.fixed_rows::<3>(3)).norm() / p0;
                    Some((dk, dp))
                },
            )
        }
    }
}

/// The integration loop shared by both models; `momenta` gives the cat's momentum errors.
#[allow(clippy::too_many_arguments)]
fn integrate<C, const NQ: usize, const NV: usize>(
    model: Model,
    method: Method,
    dt: f64,
    steps: usize,
    record_every: usize,
    q0: SVector<f64, NQ>,
    v0: SVector<f64, NV>,
    momenta: impl Fn(&State<f64, Const<NQ>, Const<NV>>, f64) -> Option<(f64, f64)>,
) -> Run
where
    C: ForwardDynamics<f64, NQ, NV>
        + KineticEnergy<f64, NQ, NV>
        + PotentialEnergy<f64, NQ, NV>
        + Chain<f64, Params = ()>,
{
    let energy = |s: &State<f64, Const<NQ>, Const<NV>>| {
        C::kinetic_energy(&s.q, &s.v) + C::potential_energy(&s.q)
    };
    let mut system = ControlledChain::<f64, C, _>::unforced();
    let mut stepper = Stepper::<f64, Const<NQ>, Const<NV>>::new(method, 1e-10, 1e-12);
    let mut state = State::new(0.0, q0, v0);
    let e0 = energy(&state);
    let mut out = Run {
        model,
        method,
        dt,
        steps,
        energy: vec![(0.0, 0.0)],
        angular_momentum: Vec::new(),
        linear_momentum: Vec::new(),
        seconds: 0.0,
        fault: None,
    };
    let start = Instant::now();
    for k in 1..=steps {
        let t = k as f64 * dt;
        if let Err(e) = stepper.advance(&mut system, &mut state, t, k) {
            out.fault = Some(e.to_string());
            break;
        }
        if k % record_every == 0 || k == steps {
            out.energy.push((t, ((energy(&state) - e0) / e0).abs()));
            if let Some((dk, dp)) = momenta(&state, t) {
                out.angular_momentum.push((t, dk));
                out.linear_momentum.push((t, dp));
            }
        }
    }
    out.seconds = start.elapsed().as_secs_f64();
    out
}

/// The methods the study compares: every fixed-step method, and Dopri5 to a tolerance.
pub const METHODS: [Method; 5] = Method::ALL;
