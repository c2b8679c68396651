#!/usr/bin/env bash
# meshio cross-check of the meshes in meshes/: node, triangle and group counts equal those
# recorded in crates/mesh/tests/meshes.rs (which the Rust reader is tested against).
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/python/lib/venv.sh
.venv/bin/python tests/python/mesh_counts.py
