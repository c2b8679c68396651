#!/usr/bin/env bash
# Reads fdem's ParaView output (.pvd + .vtu, raw appended zlib blocks) with meshio and with VTK's own
# XML reader, and compares every array with the raw JSON dump the solver wrote beside each
# frame (fdem run --raw): values must be equal bit for bit; the fracturing notched beam adds
# the joint series (joints.pvd, line cells) and its agreement with fractures.csv.
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/python/lib/venv.sh
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cargo run --release --quiet -- run examples/bar-pulse.json --out "$out/bar" --raw >/dev/null 2>&1
cargo run --release --quiet -- run examples/brazilian-disc-elastic.json --out "$out/disc" --raw >/dev/null 2>&1
cargo run --release --quiet -- run examples/disc-collision.json --out "$out/contact" --raw >/dev/null 2>&1
cargo run --release --quiet -- run examples/notched-beam-fracture.json --out "$out/fracture" --raw >/dev/null 2>&1
.venv/bin/python tests/python/vtu_readback.py "$out/bar" "$out/disc" "$out/contact" "$out/fracture"
