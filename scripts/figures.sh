#!/bin/sh
# Regenerates the committed pages and figures in docs/ that the examples write: each example
# named (all of them by default) runs in release with docs/ as its output folder (its page in
# docs/, its figures in docs/figures/). Without that argument an example writes into
# target/docs/ instead, which git ignores (articulated_examples::output).
#
#   scripts/figures.sh                        # every one (trade and drift take minutes)
#   scripts/figures.sh hemami_two_link drives # just these
#
# `trade` and `drift` put wall-clock times in their pages: run them with nothing else running.
# The examples are built with every function aligned to 64 bytes (their own target folder,
# target/figures): the time of a generated function then does not depend on where the linker
# put it. Without it, the two-link's forward dynamics in the trade study, the same machine code,
# ran twice as long at a 32-byte boundary as at a 64-byte one (commit ed9a878 has the figures).
set -eu
cd "$(dirname "$0")/.."
examples="${*:-hemami_two_link hemami_standing ground_contact drives operational_space four_bar falling_cat walking_rotation drift extremes trade}"
for example in $examples; do
    echo "== $example" >&2
    RUSTFLAGS="${RUSTFLAGS:-} -C llvm-args=-align-all-functions=6" CARGO_TARGET_DIR=target/figures \
        cargo run --release -q -p articulated-examples --example "$example" -- docs
done
