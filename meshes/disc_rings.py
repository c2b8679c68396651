#!/usr/bin/env python3
"""Writes a disc of radius R as concentric rings of well-shaped triangles (Gmsh 2.2 ASCII).

Standard library only (no gmsh): ring k (k = 1..n) has 6k nodes at radius k R / n, rotated so
that nodes lie at the poles (0, +-R); consecutive rings are joined by merging their nodes by
angle. Element size h = R / n; 6 n^2 triangles. Physical groups: `body` (2), `rim` (1),
`top`, `bottom`, `center` (0).

    python3 meshes/disc_rings.py R N OUT.msh
"""
import math
import sys


def disc(r, n):
    nodes = [(0.0, 0.0)]
    rings = [[0]]
    for k in range(1, n + 1):
        m = 6 * k
        ring = []
        for j in range(m):
            a = math.pi / 2 + 2 * math.pi * j / m
            nodes.append((r * k / n * math.cos(a), r * k / n * math.sin(a)))
            ring.append(len(nodes) - 1)
        rings.append(ring)
    tris = []
    for j in range(6):
        tris.append((0, rings[1][j], rings[1][(j + 1) % 6]))
    for k in range(2, n + 1):
        inner, outer = rings[k - 1], rings[k]
        ni, no = len(inner), len(outer)
        i = o = 0
        while i < ni or o < no:
            # next angles (fraction of a turn) of the candidates
            ai = (i + 1) / ni if i < ni else 2.0
            ao = (o + 1) / no if o < no else 2.0
            if ao <= ai:
                tris.append((inner[i % ni], outer[o % no], outer[(o + 1) % no]))
                o += 1
            else:
                tris.append((inner[i % ni], outer[o % no], inner[(i + 1) % ni]))
                i += 1
    # CCW orientation
    out = []
    for a, b, c in tris:
        (xa, ya), (xb, yb), (xc, yc) = nodes[a], nodes[b], nodes[c]
        if (xb - xa) * (yc - ya) - (yb - ya) * (xc - xa) < 0:
            b, c = c, b
        out.append((a, b, c))
    return nodes, out, rings[-1]


def main():
    r, n, path = float(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    nodes, tris, rim = disc(r, n)
    top = rim[0]
    bottom = rim[len(rim) // 2]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "5",
             '0 1 "top"', '0 2 "bottom"', '0 3 "center"', '1 4 "rim"', '2 5 "body"',
             "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(nodes)]
    lines += ["$EndNodes", "$Elements"]
    els = [f"15 2 1 1 {top + 1}", f"15 2 2 2 {bottom + 1}", "15 2 3 3 1"]
    for j in range(len(rim)):
        els.append(f"1 2 4 4 {rim[j] + 1} {rim[(j + 1) % len(rim)] + 1}")
    for a, b, c in tris:
        els.append(f"2 2 5 5 {a + 1} {b + 1} {c + 1}")
    lines += [str(len(els))] + [f"{i + 1} {e}" for i, e in enumerate(els)] + ["$EndElements"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{path}: {len(nodes)} nodes, {len(tris)} triangles, h = R/{n}")


if __name__ == "__main__":
    main()
