"""Calibrate the joints' tensile strength of the fracturing Brazilian disc to a target peak load.

The disc of examples/brazilian-disc-fracture.json (D = 50 mm, t = 10 mm) between two platens
breaks at a peak load close to the splitting-test formula P = pi D t ft / 2, so the peak grows
about linearly with the joints' tensile strength ft. The calibration:

1. a sweep of four strengths around the formula's estimate, run in parallel processes
   (``fdem.sweep``), brackets the target;
2. secant steps on (ft, peak) pairs, one run each (``fdem.run``), until the peak is within
   ``--tolerance`` of the target.

Usage (from the repository root, with the package installed: docs/python.md):

    python examples/python/calibrate_disc.py --target 2000 --processes 2

It prints the table of the sweep, each secant step and the calibrated strength.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import fdem

SCENE = Path(__file__).resolve().parents[1] / "brazilian-disc-fracture.json"
STRENGTH = "fracture.material.tensile_strength"


def peak_of(ft: float, scene: fdem.Scene) -> float:
    """The peak load [N] of the disc with tensile strength ``ft`` [Pa] (one run)."""
    edited = scene.edit({STRENGTH: ft})
    result = fdem.run(edited, progress=False)
    if result.peak_load is None:
        raise RuntimeError(
            f"the disc of ft = {ft:.4g} Pa did not fail within the run "
            f"({result.failure['criterion']}): lengthen its duration"
        )
    return float(result.peak_load)


def calibrate(target: float, processes: int, tolerance: float) -> float:
    scene = fdem.Scene(SCENE)
    # the splitting-test formula's strength for the target, and a bracket around it
    d = 0.05
    t = float(scene["bodies[0].thickness"])
    guess = 2.0 * target / (math.pi * d * t)
    strengths = [guess * f for f in (0.8, 0.93, 1.07, 1.2)]
    rows = fdem.sweep(scene, [{STRENGTH: ft} for ft in strengths], processes=processes)
    for r in rows:
        if r["error"]:
            raise RuntimeError(r["error"])
        if not r["failed"]:
            raise RuntimeError(
                f"the disc of ft = {r[STRENGTH]:.4g} Pa did not fail within the run: no peak"
            )
    print(f"{'ft [MPa]':>10} {'peak [N]':>10} {'wall [s]':>9}")
    pairs = []
    for r in rows:
        print(f"{r[STRENGTH] / 1e6:10.4f} {r['peak_load']:10.1f} {r['wall_time']:9.1f}")
        pairs.append((r[STRENGTH], r["peak_load"]))
    # secant steps from the two sweep points nearest to the target
    pairs.sort(key=lambda p: abs(p[1] - target))
    (f0, p0), (f1, p1) = pairs[0], pairs[1]
    for step in range(1, 9):
        if abs(p1 - target) <= tolerance * target:
            break
        if p1 == p0:
            raise RuntimeError("the peak does not change with the strength: no secant step")
        f0, p0, f1 = f1, p1, f1 + (target - p1) * (f1 - f0) / (p1 - p0)
        p1 = peak_of(f1, scene)
        print(f"secant step {step}: ft = {f1 / 1e6:.4f} MPa, peak {p1:.1f} N")
    else:
        raise RuntimeError("no convergence in 8 secant steps")
    print(
        f"calibrated: ft = {f1 / 1e6:.4f} MPa gives a peak of {p1:.1f} N "
        f"({(p1 - target) / target:+.2%} from the target {target:.1f} N)"
    )
    return f1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--target", type=float, default=2000.0, help="target peak load [N]")
    parser.add_argument("--processes", type=int, default=2, help="processes of the sweep")
    parser.add_argument(
        "--tolerance", type=float, default=0.005, help="relative tolerance on the peak"
    )
    args = parser.parse_args()
    calibrate(args.target, args.processes, args.tolerance)


if __name__ == "__main__":  # the sweep's worker processes import this module again
    main()
