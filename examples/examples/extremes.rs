//! The extremes table of the accuracy study (issue 12): generated forward dynamics (`f64` and
//! `f32`, each accuracy choice), `M`, `τ` and the `f64` reference against the double-double
//! ground truth, written to `accuracy.md` (whole, or not at all) in the folder given as its
//! argument (default `target/docs/`; `scripts/figures.sh` passes `docs/`) and printed.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example extremes [-- OUT]
//! ```

use articulated_examples::extremes::{rows, table};
use articulated_examples::output::Output;

const HEADER: &str = "# Accuracy at the extremes

Written by `scripts/figures.sh extremes` (the rows:
`examples/src/extremes.rs`; the bounds asserted on them: `examples/tests/extremes.rs`).

Each entry is the normwise relative error `max|x − x*| / max|x*|` against the ground truth `x*`:
the reference's recursions evaluated in double-double arithmetic (about 32 digits,
`articulated_dynamics::extended`, held to `mpmath` and to closed forms to 1e-28), at the state the
code actually saw (for `f32`, the inputs rounded to `f32`). The forward-dynamics columns are
`q̈`; *refused* means the function returned `Err(SingularMassMatrix)` (the reference: its own
singularity error). The last two columns are the larger of the errors of `M(q)` and of
`τ = ID(q, v, a)` over both accuracy choices. `cond(M)` is at the `f64` state.

- `fastest`: the fewest operations (CRBA + `LᵀDL` where that is cheaper, as on the two-link);
  its error grows as `ε·cond(M)`.
- `robust`: forward dynamics by ABA, whose error does not: within 1e-12 wherever
  `cond(M) < 1e8`, within 10× the `f64` reference's own error beyond, refused where `M` is
  singular for the scalar.
- Quaternion joints at the same attitudes keep `cond(M)` that of the bodies.

";

fn main() {
    let out = match Output::from_args() {
        Ok(out) => out,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let text = format!("{HEADER}{}", table(&rows()));
    print!("{text}");
    match out.write(&out.page("accuracy.md"), text.as_bytes()) {
        Ok(file) => eprintln!("wrote {file}"),
        Err(e) => {
            eprintln!("error: cannot write {e}");
            std::process::exit(1);
        }
    }
}
