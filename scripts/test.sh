#!/usr/bin/env bash
# Every test: the Rust workspace's (`cargo test --workspace`), then the Python package's
# (pytest, python/tests): built into a virtual environment of its own with maturin, checked
# against Pinocchio's Python bindings, its generated models built with cargo, its Ray example
# run on a local two-worker instance. The README's test command and CI's (`.ci/run`).
#
#   scripts/test.sh              # both
#   scripts/test.sh --python     # the Python package's only
#
# The first run creates target/python-venv and installs python/requirements-test.txt there
# (pinned: maturin, pytest, numpy, pin, ray; about 400 MB); later runs reuse it. PYTHON picks the
# interpreter (default: python3, 3.9 or newer).
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${1:-}" != "--python" ]]; then
  cargo test --workspace
fi

venv=target/python-venv
if [[ ! -x "$venv/bin/python" ]]; then
  "${PYTHON:-python3}" -m venv "$venv"
fi
# Installs only what is missing (pip checks the pins against what is there).
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
# The package in release, into the environment (its own target directory under target/).
(cd python && VIRTUAL_ENV="$PWD/../$venv" "../$venv/bin/maturin" develop --release --quiet)
# generate() builds its crates into the workspace's target directory, where the release
# dependencies maturin just built are reused.
export ARTICULATED_TARGET_DIR="$PWD/target"
"$venv/bin/python" -m pytest -q python/tests
