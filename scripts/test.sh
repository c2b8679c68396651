#!/usr/bin/env bash
# Runs every test of fdem: the Rust unit, integration and validation tests of the whole
# workspace, then the checks that read fdem's output with independent Python readers
# (they make their own virtual environment in .venv on first use).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --locked
if compgen -G "tests/python/*.sh" >/dev/null; then
  for t in tests/python/*.sh; do
    echo "== $t"
    bash "$t"
  done
fi
