#!/usr/bin/env bash
# Strong and weak scaling of distributed runs on this machine: the elastic cantilever on the
# fine mesh (9 378 triangles, 21 000 central-difference steps), one process on 1 and 2
# threads against `mpirun -np 1` and `-np 2` (one thread per process); the weak
# counterpart: two such cantilevers (18 756 triangles) on 2 processes against one on 1; and
# the fracturing Brazilian disc (864 triangles, 1 260 joints, contact with the platens;
# without the energy probe) the same ways.
# Alternates the variants REPEAT times (default 3) and prints each run's triangle-steps per
# second (rank 0's stepping time) and wall time, then the medians. Needs the MPI build
# (tests/mpi/mpi_runs.sh makes it: target/release/fdem-mpi).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/fdem-mpi
repeat=${REPEAT:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_pml=ob1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$work" <<'PY'
import json, os, sys, copy
w = sys.argv[1]
s = json.load(open("examples/cantilever-vibration.json"))
b = s["bodies"][0]
b["mesh"] = os.path.abspath("meshes/cantilever-fine.msh")
b["materials"] = {"*": b["materials"]["beam"]}
s["histories"] = {"every": 1000, "probes": [{"displacement": {"group": "tip"}}]}
s["output"] = {"frames": 2}
s["duration"] = 0.5
json.dump(s, open(f"{w}/one.json", "w"))
two = copy.deepcopy(s)
b2 = copy.deepcopy(b)
b["name"], b2["name"], b2["offset"] = "upper", "lower", [0.0, -2.0]
two["bodies"] = [b, b2]
two["boundary_conditions"] = [
    dict((k, dict(v, body=name)) for k, v in bc.items())
    for name in ("upper", "lower") for bc in s["boundary_conditions"]
]
two["histories"] = {"every": 1000, "probes": [{"displacement": {"body": "upper", "group": "tip"}}]}
json.dump(two, open(f"{w}/two.json", "w"))
d = json.load(open("examples/brazilian-disc-fracture.json"))
d["bodies"][0]["mesh"] = os.path.abspath(os.path.join("examples", d["bodies"][0]["mesh"]))
d["histories"] = {"every": 50, "probes": []}
json.dump(d, open(f"{w}/disc.json", "w"))
PY
run() { # label, command...
  local label=$1; shift
  rm -rf "$work/out"
  "$@" --out "$work/out" >/dev/null 2>&1
  python3 - "$work/out/summary.json" "$label" >>"$work/rows" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]}\t{s['triangle_steps_per_second']:.4g}\t{s['wall_time']:.3f}\t{s['triangles']}")
PY
  tail -1 "$work/rows"
}
for ((k = 0; k < repeat; k++)); do
  RAYON_NUM_THREADS=1 run "1 process, 1 thread" "$bin" run "$work/one.json"
  RAYON_NUM_THREADS=2 run "1 process, 2 threads" "$bin" run "$work/one.json"
  RAYON_NUM_THREADS=1 run "mpirun -np 1" mpirun -np 1 "$bin" run "$work/one.json"
  RAYON_NUM_THREADS=1 run "mpirun -np 2" mpirun -np 2 "$bin" run "$work/one.json"
  RAYON_NUM_THREADS=1 run "weak: 2 beams, 1 process, 1 thread" "$bin" run "$work/two.json"
  RAYON_NUM_THREADS=1 run "weak: 2 beams, mpirun -np 2" mpirun -np 2 "$bin" run "$work/two.json"
  RAYON_NUM_THREADS=1 run "disc: 1 process, 1 thread" "$bin" run "$work/disc.json"
  RAYON_NUM_THREADS=2 run "disc: 1 process, 2 threads" "$bin" run "$work/disc.json"
  RAYON_NUM_THREADS=1 run "disc: mpirun -np 2" mpirun -np 2 "$bin" run "$work/disc.json"
done
echo "medians (triangle-steps/s, wall s):"
python3 - "$work/rows" <<'PY'
import sys, statistics, collections
rows = collections.OrderedDict()
for line in open(sys.argv[1]):
    label, tps, wall, tris = line.rstrip("\n").split("\t")
    rows.setdefault(label, []).append((float(tps), float(wall)))
for label, v in rows.items():
    print(f"  {label:40s} {statistics.median(t for t, _ in v):10.4g} {statistics.median(w for _, w in v):8.3f}")
PY
