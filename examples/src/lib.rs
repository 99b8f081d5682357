//! Runnable examples of `articulated` live in `examples/`; what they share with the tests
//! (`tests/tests/falling_cat.rs`) lives here.
//!
//! - [`free_floating`]: a free-floating chain moved by its joints alone (hybrid dynamics with the
//!   generated `M` and `nle`), and its momenta from body Jacobians as an independent check;
//!   the examples `falling_cat` and `walking_rotation` both run on it.
//! - [`falling_cat`]: the falling cat of Wieber (2005, §4.2): the cone cycles, one simulated
//!   fall, and the planner that turns the cat over.
//! - [`drift`]: the energy and momentum drift of every integrator over long horizons, on the
//!   two-link and the falling cat; the example `drift` writes `docs/drift.md` from it.
//! - [`trade`]: the speed–accuracy trade (scalar, accuracy choice, integrator and step, full or
//!   pruned model) against the ground truth; the example `trade` writes `docs/trade.md`.
//! - [`extremes`]: the accuracy study's extremes (gimbal lock, mass ratios, slender bodies,
//!   lengths, spin), generated code against the double-double ground truth; the example
//!   `extremes` writes `docs/accuracy.md` from it.
//! - [`hemami`]: the LQR design about upright that Hemami's two-link examples share.
//! - [`output`]: where the examples write their pages and figures: a folder the user names
//!   (default `target/docs/`); `scripts/figures.sh` regenerates the committed ones in `docs/`.

pub mod drift;
pub mod extremes;
pub mod falling_cat;
pub mod free_floating;
pub mod hemami;
pub mod output;
pub mod trade;
