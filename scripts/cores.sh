#!/usr/bin/env bash
# Thread and process scaling of the fracturing Brazilian disc on a many-core machine.
#
# The disc of the benchmarks (R = 25 mm, t = 10 mm, E = 30 GPa, brittle joints everywhere,
# platens closing at 2 x 10 m/s; `benches/common/disc.rs`) with RINGS rings (6 RINGS^2
# triangles; default 408: 998 784 triangles), run for STEPS steps (default 300) without frames,
# first by one process on each thread count of THREADS (default 1,2,4,8,16), then by
# `mpirun -np P` with one thread per process for each P of PROCS (default 1,2,4,8,16; skipped
# without mpirun or without the MPI build). Each line gives the stepping rate from
# summary.json (triangle-steps per second of the stepping loop) and the whole run's wall
# time; the speed-ups are against the first entry of each list. A history row is written
# every 100 steps (the cadence of a long run). REPEAT (default 1) runs each variant that many
# times, alternating, and keeps the fastest.
#
# Needs only python3 and the programs, so it runs on a machine without a Rust toolchain:
# build here (`cargo build --release`, and `bash tests/mpi/mpi_runs.sh` for the MPI program)
# and copy target/release/fdem (and target/release/fdem-mpi) with this repository.
#
#   bash scripts/cores.sh
#   RINGS=60 THREADS=1,2 PROCS=1,2 bash scripts/cores.sh     # a quick check on 2 cores
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${FDEM:-target/release/fdem}
mpibin=${FDEM_MPI:-target/release/fdem-mpi}
rings=${RINGS:-408}
steps=${STEPS:-300}
threads=${THREADS:-1,2,4,8,16}
procs=${PROCS:-1,2,4,8,16}
repeat=${REPEAT:-1}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 meshes/disc_rings.py 0.025 "$rings" "$work/disc.msh" >/dev/null
python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
scene = {
    "bodies": [{
        "name": "disc", "mesh": "disc.msh", "thickness": 0.01,
        "materials": {"*": {"young": 30e9, "poisson": 0.2, "density": 2500.0, "plane": "stress"}},
    }],
    "fracture": {
        "regions": [{"body": "disc"}],
        "material": {
            "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
            "fracture_energy_i": 1.0, "fracture_energy_ii": 1.0,
            "penalty_normal": 300e9, "penalty_tangential": 300e9,
        },
    },
    "contact": {"walls": [
        {"name": "top", "point": [0.0, 0.025], "normal": [0.0, -1.0], "velocity": [0.0, -10.0]},
        {"name": "bottom", "point": [0.0, -0.025], "normal": [0.0, 1.0], "velocity": [0.0, 10.0]},
    ]},
    "output": {"frames": 0},
    # a history row every 100 steps, as in a run of 10^5 steps: by default a short run writes
    # one every step, and a distributed run then gathers the whole state every step
    "histories": {"every": 100},
    "duration": 1e-6,
}
json.dump(scene, open(f"{w}/disc.scene.json", "w"), indent=1)
PY
# the duration of STEPS steps of the scene's own step (from `fdem check`)
h=$("$bin" check "$work/disc.scene.json" | sed -n 's/.* with h = \([0-9.e+-]*\) s .*/\1/p' | head -1)
python3 - "$work/disc.scene.json" "$steps" "$h" <<'PY'
import json, sys
path, steps, h = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
scene = json.load(open(path))
scene["duration"] = (steps - 0.5) * h
json.dump(scene, open(path, "w"), indent=1)
PY

# one run: prints "rate wall" (the summary's stepping rate, the process's wall time)
run() {
    local out=$1
    shift
    local t0 t1
    t0=$(date +%s.%N)
    "$@" run --checkpoint-every off --out "$out" "$work/disc.scene.json" >"$out.log" 2>&1 ||
        { cat "$out.log" >&2; exit 1; }
    t1=$(date +%s.%N)
    python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(s['triangle_steps_per_second'], float(sys.argv[3])-float(sys.argv[2]), s['steps'])" \
        "$out/summary.json" "$t0" "$t1"
}

# the fastest of REPEAT runs of each variant, the variants alternating
sweep() {
    local kind=$1 list=$2
    declare -A best
    for _ in $(seq 1 "$repeat"); do
        for n in ${list//,/ }; do
            if [ "$kind" = threads ]; then
                r=$(RAYON_NUM_THREADS=$n run "$work/t$n" "$bin")
            else
                r=$(RAYON_NUM_THREADS=1 run "$work/p$n" mpirun --oversubscribe -np "$n" "$mpibin")
            fi
            if [ -z "${best[$n]:-}" ] || python3 -c "import sys; sys.exit(not float(sys.argv[1].split()[0]) > float(sys.argv[2].split()[0]))" "$r" "${best[$n]}"; then
                best[$n]=$r
            fi
        done
    done
    local first=""
    for n in ${list//,/ }; do
        read -r rate wall nsteps <<<"${best[$n]}"
        [ -z "$first" ] && first=$rate
        python3 -c "import sys; r, w, f = map(float, sys.argv[3:6]); print(f'{sys.argv[1]:>9} {sys.argv[2]:>3}: {r:.4e} triangle-steps/s, speed-up {r / f:5.2f}x, whole run {w:.2f} s ({sys.argv[6]} steps)')" \
            "$kind" "$n" "$rate" "$wall" "$first" "$nsteps"
    done
}

echo "fracturing disc: $((6 * rings * rings)) triangles, $steps steps, no frames; $(nproc) cores"
sweep threads "$threads"
if command -v mpirun >/dev/null && [ -x "$mpibin" ]; then
    sweep processes "$procs"
else
    echo "processes: skipped (no mpirun or no $mpibin)"
fi
