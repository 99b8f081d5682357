#!/usr/bin/env bash
# `cargo publish --dry-run` for every crate that is published: articulated-dynamics,
# articulated-codegen, articulated-macros, articulated (the one users depend on) and
# articulated-cli (the `articulated` command). The others say `publish = false`.
#
#   scripts/publish_dry_run.sh               # package and verify: about 2 minutes on 2 cores
#   scripts/publish_dry_run.sh --no-verify   # package only: seconds
#
# `cargo publish --workspace` (cargo 1.90 or newer) packages them together in dependency order
# and verifies each one against the others' packages through a local registry, so none needs to
# be on crates.io first. Packaging fails on missing metadata (license, description, a version on
# a dependency between them); verifying builds each crate from its package alone, so it fails
# where a crate reads a file outside its directory at build time (`include_str!("../…")`). It
# needs crates.io's index. Nothing is uploaded; to publish, run the same without `--dry-run`.
#
# The verification builds in its own target directory (target/publish unless CARGO_TARGET_DIR
# is set) without debug info: the packages are built once, to see that they build, and a
# package's build ignores the workspace's profiles.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each run packages into a fresh directory below that target directory. Cargo keys the copies it
# unpacks from the local registry (in $CARGO_HOME/registry/src) by the registry's path and
# reuses a copy it finds there: at a fixed path, a run verified against the packages of an
# earlier run (a CI machine that keeps $CARGO_HOME and clones to the same folder failed so).
# The copies this run unpacked are removed at the end.
base="${CARGO_TARGET_DIR:-target/publish}"
mkdir -p "$base"
export CARGO_TARGET_DIR
CARGO_TARGET_DIR="$(mktemp -d "$base/run.XXXXXX")"
export CARGO_PROFILE_DEV_DEBUG="${CARGO_PROFILE_DEV_DEBUG:-false}"
stamp="$CARGO_TARGET_DIR/started"
touch "$stamp"
cleanup() {
  find "${CARGO_HOME:-$HOME/.cargo}/registry/src" -mindepth 2 -maxdepth 2 -name 'articulated*' \
    -newer "$stamp" -exec rm -rf {} + 2>/dev/null || true
  rm -rf "$CARGO_TARGET_DIR"
}
trap cleanup EXIT
cargo publish --workspace --dry-run "$@"
