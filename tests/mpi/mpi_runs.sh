#!/usr/bin/env bash
# Distributed runs through MPI: fdem built with the `mpi` feature, started by `mpirun -np 2`
# and `-np 4` (oversubscribed on a machine with fewer cores), against the single-process run
# of the bar pulse, the cantilever, the disc collision, the fracturing Brazilian disc and the
# block compressed to failure: every output file but summary.json identical byte for byte;
# a run stopped with its checkpoint and resumed on another number of processes; and a
# relaxation (which a distributed run does not do) refused with exit code 2, the message once
# and nothing written. Installs Open MPI and libclang from Debian's packages when they are
# missing and this runs as root (scripts/mpi_packages.sh); FDEM_SKIP_MPI=1 skips these checks
# on a machine without them (it says so). The MPI binary stays in target/release/fdem-mpi.
set -euo pipefail
cd "$(dirname "$0")/../.."

if [ "${FDEM_SKIP_MPI:-0}" = 1 ] && ! missing=$(bash scripts/mpi_packages.sh --check); then
  echo "MPI checks SKIPPED (FDEM_SKIP_MPI=1): $missing"
  exit 0
fi
bash scripts/mpi_packages.sh || { echo "  or FDEM_SKIP_MPI=1 to skip these checks" >&2; exit 1; }

# The MPI build reuses the release build of the test command (and of the main job): only the
# MPI bindings, fdem-mpi and the fdem binary compile. Its binary is copied to fdem-mpi, then
# the default build is linked back to target/release/fdem (nothing compiles), which the
# other tests and `cargo run --release` use.
target=${CARGO_TARGET_DIR:-target}
cargo build --release --locked --features mpi --bin fdem
cp "$target/release/fdem" "$target/release/fdem-mpi"
cargo build --release --locked --bin fdem
bin=$target/release/fdem-mpi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
mpi=(mpirun --oversubscribe)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# the cantilever with sparse histories: most steps exchange only the ghosts and loaded nodes
python3 - "$work/cantilever.json" <<'PY'
import json, os, sys
s = json.load(open("examples/cantilever-vibration.json"))
for b in s["bodies"]:
    b["mesh"] = os.path.abspath(os.path.join("examples", b["mesh"]))
s["histories"] = {"every": 37, "probes": [{"displacement": {"group": "tip"}}]}
s["output"]["frames"] = 7
json.dump(s, open(sys.argv[1], "w"))
PY

checked=0
for scene in examples/bar-pulse.json "$work/cantilever.json" examples/disc-collision.json \
  examples/brazilian-disc-fracture.json examples/block-compression-fracture.json; do
  name=$(basename "$scene" .json)
  # each run in a folder of the scene's name (the plots' legends name it)
  "$bin" run "$scene" --out "$work/np1/$name" >/dev/null 2>&1
  # the default build's single-process run: the MPI build changes nothing of it
  "$target/release/fdem" run "$scene" --out "$work/default/$name" >/dev/null 2>&1
  diff -r -x summary.json "$work/default/$name" "$work/np1/$name"
  for np in 2 4; do
    "${mpi[@]}" -np "$np" "$bin" run "$scene" --out "$work/np$np/$name" >/dev/null 2>"$work/err"
    if ! diff -r -x summary.json "$work/np1/$name" "$work/np$np/$name"; then
      echo "FAIL: $name on $np processes differs from the single-process run" >&2
      exit 1
    fi
    n=$(ls "$work/np$np/$name" | wc -l)
    python3 - "$work/np1/$name/summary.json" "$work/np$np/$name/summary.json" "$np" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["steps"] == b["steps"] and a["energy"] == b["energy"], "summary"
assert b["distributed"]["ranks"] == int(sys.argv[3]), b.get("distributed")
PY
    echo "ok: $name on $np processes: $n files identical to the single-process run's"
    checked=$((checked + 1))
  done
done

# a checkpoint: the disc collision stopped at step 6 000 on 2 processes (exit code 4), then
# resumed on 4; and stopped on 1 process, resumed on 2: the files of the run that never stopped
for pair in "2 4" "1 2"; do
  set -- $pair
  out="$work/restart-$1-$2/disc-collision"
  set +e
  if [ "$1" = 1 ]; then
    "$bin" run examples/disc-collision.json --out "$out" --stop-after 6000 >/dev/null 2>&1
  else
    "${mpi[@]}" -np "$1" "$bin" run examples/disc-collision.json --out "$out" --stop-after 6000 >/dev/null 2>&1
  fi
  code=$?
  set -e
  [ "$code" = 4 ] || { echo "FAIL: stopped run on $1 processes: exit $code" >&2; exit 1; }
  "${mpi[@]}" -np "$2" "$bin" run --resume "$out" >/dev/null 2>"$work/err"
  if ! diff -r -x summary.json -x checkpoint.fdem -x run_id.txt "$work/np1/disc-collision" "$out"; then
    echo "FAIL: stopped on $1 processes and resumed on $2: not the run that never stopped" >&2
    exit 1
  fi
  echo "ok: disc-collision stopped on $1 process(es) at step 6000 and resumed on $2: identical"
done

# repartitioning: the notched beam on 3 processes (its joints only in the strip above the
# notch: the first cut leaves them to two of the three), cut again at its first check
out="$work/rebalanced/notched-beam-fracture"
"$bin" run examples/notched-beam-fracture.json --out "$work/np1/notched-beam-fracture" >/dev/null 2>&1
"${mpi[@]}" -np 3 "$bin" run examples/notched-beam-fracture.json --out "$out" >/dev/null 2>"$work/err"
if ! diff -r -x summary.json "$work/np1/notched-beam-fracture" "$out"; then
  echo "FAIL: the notched beam repartitioned on 3 processes differs from the single-process run" >&2
  exit 1
fi
python3 - "$out/summary.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))["distributed"]
assert d["repartitions"] >= 1 and d["imbalance_after_repartition"] < 1.1, d
PY
echo "ok: notched-beam-fracture repartitioned on 3 processes: identical to the single-process run"
checked=$((checked + 1))

# refusals: exit code 2 from the job, the field named once, nothing written
set +e
"${mpi[@]}" -np 2 "$bin" run examples/cantilever-relaxation.json --out "$work/refused" >/dev/null 2>"$work/err"
code=$?
set -e
[ "$code" = 2 ] || { echo "FAIL: relaxation on 2 processes: exit $code" >&2; cat "$work/err" >&2; exit 1; }
[ "$(grep -c 'at `analysis`' "$work/err")" = 1 ] || { echo "FAIL: the error once, at analysis" >&2; cat "$work/err" >&2; exit 1; }
[ ! -e "$work/refused" ] || { echo "FAIL: a refused run wrote files" >&2; exit 1; }
echo "ok: a relaxation on 2 processes is refused at \`analysis\` (exit 2, the message once, nothing written)"
echo "MPI checks: $checked distributed runs identical to the single-process run"
