//! Generated code of seeded random trees (`articulated_dynamics::random::random_model`, written by
//! `tests/build.rs` through `articulated_codegen::Builder`) against the reference on random
//! states from `random_state`, to the tolerances of `generated_common`.
//!
//! The trees are included below in a module with no `#[allow]`: rustc's and clippy's warnings on
//! the emitted code are errors under `cargo clippy --workspace --all-targets -- -D warnings`.
//!
//! Sizes: 2 to 4 bodies only, for now. rustc 1.95 overflows its stack in LLVM's DWARF emission
//! (`DwarfCompileUnit::createAndAddScopeChildren`, one nested lexical scope per `let`) on a
//! function of roughly 2,600 or more `let` statements compiled with debug info, as the test
//! profile does; macro output escapes it (its statements share the call site's span), a
//! Builder file does not. A 5-body tree's forward dynamics is already ~3,300 statements and a
//! 30-body tree's ~31,000, so larger trees wait for the generator to emit fewer nested scopes.

mod common;

use std::collections::BTreeSet;

use articulated::model::JointKind;
use articulated::reference::Reference;
use articulated_dynamics::random::{random_model, random_state};
use common::check_chain;

/// The generated trees, exactly as the Builder wrote them.
mod trees {
    include!(concat!(env!("OUT_DIR"), "/random_trees.rs"));
}

include!(concat!(env!("OUT_DIR"), "/random_trees_list.rs"));

/// Random states per tree.
const CASES: u32 = 32;

#[test]
fn random_trees_match_the_reference() {
    let mut kinds = BTreeSet::new();
    let mut largest = 0;
    macro_rules! check {
        ($name:ident, $seed:expr, $n:expr, $nq:expr, $nv:expr) => {{
            let model = random_model($seed, $n);
            for j in &model.joints {
                kinds.insert(match j.kind {
                    JointKind::Revolute { .. } => "revolute",
                    JointKind::Prismatic { .. } => "prismatic",
                    JointKind::SphericalEuler { .. } => "spherical Euler",
                    JointKind::SphericalQuaternion => "spherical quaternion",
                    JointKind::FreeEuler { .. } => "free Euler",
                    JointKind::FreeQuaternion => "free quaternion",
                    JointKind::Fixed => "fixed",
                });
            }
            largest = largest.max($n);
            assert_eq!((trees::$name::NQ, trees::$name::NV), ($nq, $nv));
            let r = Reference::new(&model).unwrap();
            let label = format!("{} (seed {}, {} bodies)", stringify!($name), $seed, $n);
            let w = check_chain::<trees::$name, $nq, $nv>(&label, &r, &(), CASES, |s| {
                random_state(&model, s)
            });
            assert_eq!(w.states, CASES as usize);
            println!(
                "    ops: mass_matrix {} | bias {} | gravity {} | inverse_dynamics {} | forward_dynamics {}",
                trees::$name::MASS_MATRIX_OPS.total(),
                trees::$name::BIAS_OPS.total(),
                trees::$name::GRAVITY_OPS.total(),
                trees::$name::INVERSE_DYNAMICS_OPS.total(),
                trees::$name::FORWARD_DYNAMICS_OPS.total(),
            );
        }};
    }
    for_each_random_tree!(check);
    assert_eq!(
        kinds.len(),
        7,
        "every joint kind must appear among the trees, found {kinds:?}"
    );
    assert!(largest >= 3);
}
