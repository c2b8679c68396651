#!/usr/bin/env python3
"""Cross-check of fdem-mesh's Gmsh reader with meshio: for every meshes/*.msh, the node,
triangle and per-group element counts that meshio reports must equal the counts recorded in
crates/mesh/tests/meshes.rs (which fdem-mesh's own reader must also give).

Prints the table (--print) or checks it; exits non-zero on a mismatch and prints
`N passed, N failed`.
"""
import glob
import os
import re
import sys

import meshio
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DIM_OF = {"vertex": 0, "line": 1, "triangle": 2}


def counts(path):
    m = meshio.read(path)
    tris = sum(len(c.data) for c in m.cells if c.type == "triangle")
    used = np.unique(np.concatenate([c.data.ravel() for c in m.cells if c.type == "triangle"]))
    groups = []
    phys = m.cell_data.get("gmsh:physical")
    for name, (tag, dim) in sorted(m.field_data.items(), key=lambda kv: (kv[1][1], kv[1][0])):
        n = 0
        for block, ph in zip(m.cells, phys):
            if DIM_OF.get(block.type) == dim:
                n += int(np.sum(ph == tag))
        groups.append((name, int(dim), n))
    return len(m.points), len(used), tris, groups


def recorded():
    """Reads the table `("file", nodes, triangles, "name:dim:count,...")` from meshes.rs."""
    src = open(os.path.join(ROOT, "crates/mesh/tests/meshes.rs")).read()
    rows = re.findall(r'\(\s*"([\w.-]+\.msh)",\s*(\d+),\s*(\d+),\s*"([^"]*)",?\s*\)', src)
    return {r[0]: (int(r[1]), int(r[2]), r[3]) for r in rows}


def main():
    files = sorted(glob.glob(os.path.join(ROOT, "meshes", "*.msh")))
    if "--print" in sys.argv:
        for f in files:
            n, used, t, g = counts(f)
            gs = ",".join(f"{a}:{b}:{c}" for a, b, c in g)
            print(f'("{os.path.basename(f)}", {n}, {t}, "{gs}"),  // used nodes {used}')
        return 0
    rec = recorded()
    passed = failed = 0
    for f in files:
        name = os.path.basename(f)
        n, used, t, g = counts(f)
        gs = ",".join(f"{a}:{b}:{c}" for a, b, c in g)
        want = rec.get(name)
        if want is None or want != (n, t, gs) or used != n:
            print(f"FAIL {name}: meshio {(n, t, gs)} (used nodes {used}), recorded {want}")
            failed += 1
        else:
            passed += 1
    if len(rec) != len(files):
        print(f"FAIL: {len(rec)} meshes recorded, {len(files)} in meshes/")
        failed += 1
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
