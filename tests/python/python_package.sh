#!/usr/bin/env bash
# The Python package (crates/python, `import fdem`): builds and installs it into .venv with
# `pip install ./crates/python` (maturin), but only when its sources or the solver's changed
# (a hash of them is kept in .venv: a warm run does not build), then runs its pytest suite
# tests/python/package: fdem.run's arrays and files against `fdem run`'s bit for bit, the
# scene errors with their JSON paths, threads, Ctrl-C, stop and resume, the readers, sweeps and
# examples; and the package's type hints and stubs with mypy --strict.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/python/lib/venv.sh
cargo build --release --locked --quiet --bin fdem
hash="$(find Cargo.toml Cargo.lock crates -type f \
  \( -path 'crates/*/src/*' -o -name Cargo.toml -o -path 'crates/python/python/*' -o -name pyproject.toml \) \
  -not -path '*/__pycache__/*' -print0 | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)"
if [ "$(cat .venv/fdem-package.hash 2>/dev/null)" != "$hash" ] || ! .venv/bin/python -c "import fdem" 2>/dev/null; then
  start=$SECONDS
  # maturin from .venv (no isolated build environment to download): its bin on PATH
  PATH="$PWD/.venv/bin:$PATH" .venv/bin/pip install -q --no-build-isolation ./crates/python
  echo "built and installed the Python package in $((SECONDS - start)) s"
  echo "$hash" > .venv/fdem-package.hash
fi
FDEM_BIN="$PWD/target/release/fdem" .venv/bin/python -m pytest -q -p no:cacheprovider tests/python/package
.venv/bin/python -m mypy --strict --no-error-summary crates/python/python/fdem
echo "mypy --strict: the package's types check"
