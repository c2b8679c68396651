#!/usr/bin/env bash
# Runs every example scene and prints, per example, what its console ends with: the lines
# after the progress (the summary, the result block, the accuracy block and the files
# written: at most 25 fit one screen), the accuracy warnings, and the result block's first
# line:
#
#   bash scripts/example_consoles.sh [FDEM_BINARY] [OUTDIR]
#
# Exits with 1 when a console is longer than 25 lines after its progress.
# Writes the runs under OUTDIR (default: a fresh temporary folder), never into the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-target/release/fdem}")
out=${2:-$(mktemp -d "${TMPDIR:-/tmp}/fdem-consoles.XXXXXX")}
mkdir -p "$out"
long=0
printf '| example | lines after the progress | warnings | result |\n|---|---|---|---|\n'
for scene in examples/*.json; do
  case "$scene" in *.study.json) continue ;; esac
  name=$(basename "$scene" .json)
  "$bin" run "$scene" --out "$out/$name" >"$out/$name.stdout" 2>"$out/$name.stderr" || {
    echo "$name: fdem exited with $? (see $out/$name.stderr)" >&2
    exit 1
  }
  # stdout holds only what follows the progress (the progress and the set-up go to stderr)
  n=$(wc -l <"$out/$name.stdout")
  warned=$(grep -o '^  WARN [a-z_]*' "$out/$name.stdout" | awk '{print $2}' | paste -sd, - || true)
  result=$(grep -m1 '^result: ' "$out/$name.stdout" | sed 's/^result: //; s/ (.*)//' || true)
  printf '| %s | %s | %s | %s |\n' "$name" "$n" "${warned:-none}" "${result:-no result block}"
  [ "$n" -le 25 ] || long=1
done
exit $long
