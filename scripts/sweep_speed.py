"""How much a sweep on several processes gains: 8 variants of the fracturing Brazilian disc
(examples/brazilian-disc-fracture.json, tensile strengths 2.0 to 3.4 MPa), run one after
another with ``fdem.run`` (one thread each) and then with ``fdem.sweep`` on 2 processes (one
thread per run); prints both wall times and checks that every variant gives the same peak
load, steps and energy ledger both ways.

    .venv/bin/python scripts/sweep_speed.py [--processes 2] [--variants 8]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import fdem

SCENE = Path(__file__).resolve().parents[1] / "examples" / "brazilian-disc-fracture.json"
STRENGTH = "fracture.material.tensile_strength"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--variants", type=int, default=8)
    args = parser.parse_args()
    scene = fdem.Scene(SCENE)
    n = args.variants
    variants = [{STRENGTH: 2.0e6 + 1.4e6 * i / max(n - 1, 1)} for i in range(n)]
    t0 = time.perf_counter()
    single = []
    for v in variants:
        r = fdem.run(scene.edit(v), progress=False, threads=1)
        single.append((r.peak_load, r.summary["steps"], r.energy))
    t_seq = time.perf_counter() - t0
    t0 = time.perf_counter()
    rows = fdem.sweep(scene, variants, processes=args.processes, threads=1)
    t_par = time.perf_counter() - t0
    same = True
    for v, (peak, steps, energy), row in zip(variants, single, rows):
        if row["error"]:
            raise SystemExit(f"variant {v}: {row['error']}")
        ok = (
            row["peak_load"] == peak
            and row["steps"] == steps
            and row["energy_supplied"] == energy["supplied"]
            and row["energy_dissipated"] == energy["dissipated"]
            and row["energy_error"] == energy["error"]
        )
        same &= ok
        print(f"ft = {v[STRENGTH] / 1e6:.2f} MPa: peak {peak:.3f} N, {steps} steps, same: {ok}")
    print(
        f"{n} variants: one after another {t_seq:.1f} s, sweep on {args.processes} processes "
        f"{t_par:.1f} s ({t_seq / t_par:.2f}x); the same numbers: {same}"
    )
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
