//! `nonlinear_effects` (bias and gravity in one pass) and `mass_matrix_and_nonlinear_effects`
//! (both with the kinematics shared) against the reference's `bias + gravity` and `M`, on the
//! shipped serial and branching models, fixed and floating; and their operation counts against
//! the separate functions': one pass costs less than two.

mod common;

use std::path::Path;

use articulated::nalgebra::SVector;
use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::random_state;
use common::rel_err;

macro_rules! chain {
    ($name:ident, $attr:meta) => {
        #[derive(Chain)]
        #[$attr]
        struct $name;
    };
}

chain!(
    TwoLink,
    chain(
        file = "../models/two_link.chain",
        outputs = [
            mass_matrix,
            bias,
            gravity,
            inverse_dynamics,
            nonlinear_effects,
            mass_matrix_and_nonlinear_effects
        ]
    )
);
chain!(
    Arm7,
    chain(
        urdf = "../models/arm7.urdf",
        outputs = [
            mass_matrix,
            bias,
            gravity,
            inverse_dynamics,
            nonlinear_effects,
            mass_matrix_and_nonlinear_effects
        ]
    )
);
chain!(
    Arm7Floating,
    chain(
        urdf = "../models/arm7.urdf",
        floating,
        outputs = [nonlinear_effects, mass_matrix_and_nonlinear_effects]
    )
);
chain!(
    Tree,
    chain(
        file = "../models/tree.chain",
        outputs = [nonlinear_effects, mass_matrix_and_nonlinear_effects]
    )
);

/// Both outputs of `C` against the reference at random states.
fn check<C, const NQ: usize, const NV: usize>(path: &str, floating: bool)
where
    C: NonlinearEffects<f64, NQ, NV> + MassMatrixAndNonlinearEffects<f64, NQ, NV>,
{
    let model = load_model(Path::new(path), floating).unwrap_or_else(|e| panic!("{e}"));
    let r = Reference::new(&model).unwrap();
    for seed in 0..40 {
        let (q, v, _) = random_state(&model, seed);
        let want = r.bias(&q, &v).unwrap() + r.gravity(&q).unwrap();
        let m_want = r.mass_matrix(&q).unwrap();
        let (qs, vs) = (
            SVector::<f64, NQ>::from_column_slice(&q),
            SVector::<f64, NV>::from_column_slice(&v),
        );
        let nle = C::nonlinear_effects(&qs, &vs);
        assert!(
            rel_err(nle.as_slice(), want.as_slice()) < 1e-12,
            "{path} seed {seed}: nle"
        );
        let (m, nle2) = C::mass_matrix_and_nonlinear_effects(&qs, &vs);
        assert!(
            rel_err(nle2.as_slice(), want.as_slice()) < 1e-12,
            "{path} seed {seed}"
        );
        assert!(
            rel_err(m.as_slice(), m_want.as_slice()) < 1e-12,
            "{path} seed {seed}: M"
        );
    }
}

#[test]
fn nonlinear_effects_and_with_the_mass_matrix_match_the_reference() {
    check::<TwoLink, 6, 6>("../models/two_link.chain", false);
    check::<Arm7, 7, 7>("../models/arm7.urdf", false);
    check::<Arm7Floating, 13, 13>("../models/arm7.urdf", true);
    check::<Tree, 7, 7>("../models/tree.chain", false);
}

#[test]
fn one_pass_costs_less_than_two() {
    for (name, nle, bias, gravity, id, both, m) in [
        (
            "two-link",
            TwoLink::NONLINEAR_EFFECTS_OPS,
            TwoLink::BIAS_OPS,
            TwoLink::GRAVITY_OPS,
            TwoLink::INVERSE_DYNAMICS_OPS,
            TwoLink::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS,
            TwoLink::MASS_MATRIX_OPS,
        ),
        (
            "arm7",
            Arm7::NONLINEAR_EFFECTS_OPS,
            Arm7::BIAS_OPS,
            Arm7::GRAVITY_OPS,
            Arm7::INVERSE_DYNAMICS_OPS,
            Arm7::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS,
            Arm7::MASS_MATRIX_OPS,
        ),
    ] {
        println!(
            "{name}: nle {} (bias {} + gravity {}, inverse dynamics {}); M with nle {} (M {})",
            nle.total(),
            bias.total(),
            gravity.total(),
            id.total(),
            both.total(),
            m.total()
        );
        assert!(nle.total() < bias.total() + gravity.total(), "{name}");
        assert!(
            nle.total() <= id.total(),
            "{name}: nle costs more than inverse dynamics"
        );
        assert!(
            both.total() < m.total() + nle.total(),
            "{name}: nothing shared"
        );
    }
}
