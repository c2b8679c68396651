#!/usr/bin/env bash
# Runs every example scene with a given fdem binary and prints one SHA-256 per output file
# that holds results (frames .vtu, histories and fracture events .csv), so that two builds
# can be compared bit for bit:
#
#   bash scripts/frame_hashes.sh target/release/fdem /tmp/hashes-a > a.txt
#   bash scripts/frame_hashes.sh other/fdem /tmp/hashes-b > b.txt && diff a.txt b.txt
#
# The results do not depend on the number of threads (RAYON_NUM_THREADS), so any machine
# that runs the same binary gives the same hashes.
# Writes the runs under OUTDIR (default: a fresh temporary folder), never into the repository.
set -euo pipefail
bin=$(realpath "${1:?usage: frame_hashes.sh FDEM_BINARY [OUTDIR]}")
out=${2:-$(mktemp -d "${TMPDIR:-/tmp}/fdem-hashes.XXXXXX")}
cd "$(dirname "$0")/.."
mkdir -p "$out"
for scene in examples/*.json; do
  case "$scene" in *.study.json) continue ;; esac
  name=$(basename "$scene" .json)
  "$bin" run "$scene" --out "$out/$name" >/dev/null 2>"$out/$name.stderr" || {
    echo "$name: fdem exited with $? (see $out/$name.stderr)" >&2
    exit 1
  }
  (cd "$out" && find "$name" -type f \( -name '*.vtu' -o -name '*.csv' \) -print0 |
    sort -z | xargs -0 sha256sum)
done
