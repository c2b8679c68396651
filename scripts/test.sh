#!/usr/bin/env bash
# Runs every test of fdem: the Rust unit, integration and validation tests of the whole
# workspace, then the checks that read fdem's output with independent Python readers
# (they use the virtual environment .venv, made here on first use while cargo compiles),
# then the distributed runs through MPI. Everything is built in the release profile, the one
# `cargo run --release` (the main job) uses: after the main job only the test binaries are
# left to compile. docs/testing.md says what runs where.
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests record the measured figures of docs/validation.md (its "today" column); the
# check after them fails when the committed table differs (docs/testing.md).
python3 scripts/validation_figures.py clear
# .venv is mostly a download (VTK, numpy, pandas, ...): made beside the compiling, not after
venv_log=$(mktemp)
trap 'rm -f "$venv_log"' EXIT
(source tests/python/lib/venv.sh) >"$venv_log" 2>&1 &
venv=$!
rust=0
cargo test --workspace --locked --release || rust=$?
if ! wait "$venv"; then
  cat "$venv_log" >&2
  echo "error: making the Python virtual environment .venv failed (above)" >&2
  exit 1
fi
[ "$rust" = 0 ] || exit "$rust"
python3 scripts/validation_figures.py --check
if compgen -G "tests/python/*.sh" >/dev/null || compgen -G "tests/mpi/*.sh" >/dev/null; then
  for t in tests/python/*.sh tests/mpi/*.sh; do
    echo "== $t"
    bash "$t"
  done
fi
