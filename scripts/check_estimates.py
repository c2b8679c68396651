#!/usr/bin/env python3
"""`fdem check`'s run-time estimate against the real run, for every shipped example
(examples/*.json without .study.json), one at a time: the estimate of the scene's scheme
(the `<- scene` row), the run's stepping time (triangles x steps / triangle_steps_per_second
of summary.json) and its wall time less the frame output, and their ratio. Static analyses
have no estimate (one sparse Cholesky solve) and are listed as such.

Run from the repository root after `cargo build --release`:
    python3 scripts/check_estimates.py [OUT_DIR]
"""
import glob
import json
import os
import re
import subprocess
import sys
import tempfile

fdem = os.path.join("target", "release", "fdem")
out = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="fdem-estimates-")
print("| example | estimate [s] | stepping [s] | wall - output [s] | estimate / stepping |")
print("|---|---|---|---|---|")
for scene in sorted(glob.glob("examples/*.json")):
    if scene.endswith(".study.json"):
        continue
    name = os.path.basename(scene)[:-5]
    check = subprocess.run([fdem, "check", scene], capture_output=True, text=True, check=True).stdout
    m = re.search(r"([0-9.]+)s\s+<- scene", check)
    if not m:
        print(f"| {name} | static: no estimate | | | |")
        continue
    est = float(m.group(1))
    subprocess.run([fdem, "run", scene, "--out", os.path.join(out, name)],
                   capture_output=True, check=True)
    s = json.load(open(os.path.join(out, name, "summary.json")))
    stepping = s["triangles"] * s["steps"] / s["triangle_steps_per_second"]
    wall = s["wall_time"] - s["timers"]["output"]
    print(f"| {name} | {est:.3f} | {stepping:.3f} | {wall:.3f} | {est / stepping:.2f} |")
