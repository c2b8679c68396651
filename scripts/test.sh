#!/usr/bin/env bash
# Runs every test of fdem: the Rust unit, integration and validation tests of the whole
# workspace, then the checks that read fdem's output with independent Python readers
# (they make their own virtual environment in .venv on first use). Everything is built in
# the release profile, the one `cargo run --release` (the main job) uses: after the main
# job only the test binaries are left to compile. docs/testing.md says what runs where.
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests record the measured figures of docs/validation.md (its "today" column); the
# check after them fails when the committed table differs (docs/testing.md).
python3 scripts/validation_figures.py clear
cargo test --workspace --locked --release
python3 scripts/validation_figures.py --check
if compgen -G "tests/python/*.sh" >/dev/null || compgen -G "tests/mpi/*.sh" >/dev/null; then
  for t in tests/python/*.sh tests/mpi/*.sh; do
    echo "== $t"
    bash "$t"
  done
fi
