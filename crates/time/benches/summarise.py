#!/usr/bin/env python3
"""Summarises the criterion results of fdem-time's benches (target/criterion) as the
table of docs/performance.md: fastest and median time per iteration, bytes moved per
DOF-step by the model, and the fraction of the triad bandwidth measured at the same size.
Usage: python3 crates/time/benches/summarise.py [target/criterion]"""
import glob, json, os, sys

root = sys.argv[1] if len(sys.argv) > 1 else "target/criterion"
N = 1_000_000
LOOP = {"central-difference": 8, "omf30": 13, "chin": 14, "forest-ruth": 18, "omf32": 30,
        "pc3": 17, "pc4": 21, "pc5": 25}
COST = {"central-difference": 1, "omf30": 2, "chin": 3, "forest-ruth": 3, "omf32": 7,
        "pc3": 1, "pc4": 1, "pc5": 1}

def times(group, bench):
    d = os.path.join(root, group, bench, "new")
    s = json.load(open(os.path.join(d, "sample.json")))
    per = [t / i for t, i in zip(s["times"], s["iters"])]
    e = json.load(open(os.path.join(d, "estimates.json")))
    return min(per) * 1e-9, e["median"]["point_estimate"] * 1e-9

print("| kernel | threads | fastest (ms) | median (ms) | GB/s (fastest) |")
print("|---|---|---|---|---|")
bw = {}
for label, n in (("triad_1e6", 1_000_000), ("triad_2_25", 1 << 25)):
    for th in (1, 2):
        fast, med = times(label, f"{th}-thread")
        bw[(label, th)] = 24 * n / fast / 1e9
        print(f"| {label} | {th} | {fast*1e3:.3f} | {med*1e3:.3f} | {bw[(label, th)]:.1f} |")
print()
print("| scheme | threads | bytes/DOF-step (loops + forces) | fastest (ms/step) | median | ns/DOF-step | GB/s | fraction of triad (1e6) | chain: M DOF-steps/s (fastest) |")
print("|---|---|---|---|---|---|---|---|---|")
for k in LOOP:
    for th in (1, 2):
        try:
            fast, med = times(f"overhead_{k}", f"{th}-thread")
            cfast, _ = times(f"chain_{k}", f"{th}-thread")
        except FileNotFoundError:
            continue
        b = 8 * LOOP[k] + 16 * COST[k]
        gbs = b * N / fast / 1e9
        print(f"| {k} | {th} | {8*LOOP[k]} + {16*COST[k]} = {b} | {fast*1e3:.2f} | {med*1e3:.2f} | "
              f"{fast/N*1e9:.2f} | {gbs:.1f} | {gbs / bw[('triad_1e6', th)]:.2f} | {N/cfast/1e6:.0f} |")
