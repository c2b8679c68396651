#!/usr/bin/env bash
# The charts of the time-integration studies, under the names the docs use:
#   oscillator               -> time-CHART.png and .svg (docs/time-integration.md), from
#                               `fdem study oscillator`
#   bar-pulse, cantilever-vibration, disc-collision, brazilian-disc-fracture
#                            -> study-SCENE-CHART.png (docs/speed-vs-accuracy.md), from
#                               `fdem study scene examples/SCENE.json` (its SCENE.study.json)
# The studies write their own files into out/study-* (CSV, JSON, charts); this script then
# copies the charts into DIR (default ${TMPDIR:-/tmp}/fdem-figures, created if missing).
# The docs' copies are regenerated with --out docs/img.
#
# Usage, from the repository root:
#   bash scripts/study_figures.sh [--out DIR] [--fdem COMMAND] [STUDY...]
# STUDY: oscillator and/or the scene names above (default: all five; the scene studies take
# minutes each). COMMAND runs fdem (default: cargo run --release --quiet --).
set -euo pipefail
cd "$(dirname "$0")/.."

out="${TMPDIR:-/tmp}/fdem-figures"
fdem="cargo run --release --quiet --"
studies=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --fdem) fdem="$2"; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "unknown option $1 (see --help)" >&2; exit 2 ;;
    *) studies+=("$1"); shift ;;
  esac
done
[ ${#studies[@]} -gt 0 ] || studies=(oscillator bar-pulse cantilever-vibration disc-collision brazilian-disc-fracture)
mkdir -p "$out"

for s in "${studies[@]}"; do
  case "$s" in
    oscillator)
      $fdem study oscillator --out out/study-oscillator
      for f in error_vs_h error_end_vs_h error_vs_evaluations error_vs_seconds energy_error_vs_h spectral_radius; do
        for ext in png svg; do
          cp "out/study-oscillator/$f.$ext" "$out/time-$f.$ext"
          echo "wrote $out/time-$f.$ext"
        done
      done
      ;;
    bar-pulse|cantilever-vibration|disc-collision|brazilian-disc-fracture)
      $fdem study scene "examples/$s.json" --out "out/study-$s"
      for f in work_precision error_vs_step energy_vs_step work_precision_reference error_vs_step_reference; do
        if [ -f "out/study-$s/$f.png" ]; then
          cp "out/study-$s/$f.png" "$out/study-$s-$f.png"
          echo "wrote $out/study-$s-$f.png"
        fi
      done
      ;;
    *) echo "unknown study $s (see --help)" >&2; exit 2 ;;
  esac
done
