#!/usr/bin/env python3
"""Writes the structured rectangle meshes of the solver's examples (fdem JSON mesh format).

Each mesh is an nx x ny grid of rectangles split into two triangles with alternating
diagonals, with groups: the surface (dim 2), the four sides "left", "right", "bottom",
"top" (dim 1 edge groups) and the point "tip" (dim 0: the node at mid-height of the right
side, or the nearest one). Run from the repository root: python3 scripts/make_structured_meshes.py
"""
import json
import os


def rectangle(name, lx, ly, nx, ny, surface):
    nodes = [[lx * i / nx, ly * j / ny - ly / 2] for j in range(ny + 1) for i in range(nx + 1)]
    nid = lambda i, j: j * (nx + 1) + i
    tris = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)
            if (i + j) % 2 == 0:
                tris += [[a, b, c], [a, c, d]]
            else:
                tris += [[a, b, d], [b, c, d]]
    groups = [
        {"name": surface, "dim": 2, "triangles": list(range(len(tris)))},
        {"name": "left", "dim": 1, "edges": [[nid(0, j + 1), nid(0, j)] for j in range(ny)]},
        {"name": "right", "dim": 1, "edges": [[nid(nx, j), nid(nx, j + 1)] for j in range(ny)]},
        {"name": "bottom", "dim": 1, "edges": [[nid(i, 0), nid(i + 1, 0)] for i in range(nx)]},
        {"name": "top", "dim": 1, "edges": [[nid(i + 1, ny), nid(i, ny)] for i in range(nx)]},
        {"name": "tip", "dim": 0, "nodes": [nid(nx, ny // 2)]},
    ]
    path = os.path.join("examples", "meshes", name + ".json")
    with open(path, "w") as f:
        json.dump({"nodes": nodes, "triangles": tris, "groups": groups}, f, separators=(",", ":"))
    print(f"{path}: {len(nodes)} nodes, {len(tris)} triangles")


def kirsch_plate(name, a, w, nt, ratio):
    """Quarter of a square plate [0, w]^2 with a hole of radius a at the origin: rays from the
    hole to the square's sides, nt cells in angle, geometric radial grading (cells near square)."""
    import math
    nr = int(math.ceil(math.log(w / a) / math.log(1.0 + ratio * math.pi / 2 / nt)))
    nodes = []
    for j in range(nr + 1):
        s = j / nr
        for i in range(nt + 1):
            th = 0.5 * math.pi * i / nt
            c, sn = math.cos(th), math.sin(th)
            L = w / max(c, sn)
            r = a * (L / a) ** s
            # Straight rays; snap the outer ring exactly onto the square.
            x, y = r * c, r * sn
            if j == nr:
                x, y = (w, w * sn / c) if c >= sn else (w * c / sn, w)
            if i == 0:
                y = 0.0
            if i == nt:
                x = 0.0
            nodes.append([x, y])
    nid = lambda i, j: j * (nt + 1) + i
    tris = []
    for j in range(nr):
        for i in range(nt):
            p0, p1, p2, p3 = nid(i, j), nid(i, j + 1), nid(i + 1, j + 1), nid(i + 1, j)
            if (i + j) % 2 == 0:
                tris += [[p0, p1, p2], [p0, p2, p3]]
            else:
                tris += [[p0, p1, p3], [p1, p2, p3]]
    # The ray at 45 degrees splits the outer ring between "right" (x = w) and "top" (y = w).
    half = nt // 2
    outer_right = [[nid(i, nr), nid(i + 1, nr)] for i in range(half)]
    outer_top = [[nid(i, nr), nid(i + 1, nr)] for i in range(half, nt)]
    groups = [
        {"name": "plate", "dim": 2, "triangles": list(range(len(tris)))},
        {"name": "hole", "dim": 1, "edges": [[nid(i, 0), nid(i + 1, 0)] for i in range(nt)]},
        {"name": "bottom", "dim": 1, "edges": [[nid(0, j), nid(0, j + 1)] for j in range(nr)]},
        {"name": "left", "dim": 1, "edges": [[nid(nt, j), nid(nt, j + 1)] for j in range(nr)]},
        {"name": "right", "dim": 1, "edges": outer_right},
        {"name": "top", "dim": 1, "edges": outer_top},
    ]
    path = os.path.join("examples", "meshes", name + ".json")
    with open(path, "w") as f:
        json.dump({"nodes": nodes, "triangles": tris, "groups": groups}, f, separators=(",", ":"))
    print(f"{path}: {len(nodes)} nodes, {len(tris)} triangles")


if __name__ == "__main__":
    # Kirsch: hole radius 10 mm in a plate 1 m wide (quarter 0.5 m = 50 a): the plate edge
    # perturbs the field near the hole by less than 0.1 % (a^2/r^2 = 4e-4 there).
    kirsch_plate("kirsch-plate-50a", 0.01, 0.5, 96, 1.0)
    # Cantilever 10 m x 1 m: coarse and fine.
    rectangle("cantilever-coarse", 10.0, 1.0, 40, 4, "beam")
    rectangle("cantilever-fine", 10.0, 1.0, 200, 20, "beam")
    # Long bar 1 m x 0.02 m for the wave-arrival test.
    rectangle("bar", 1.0, 0.02, 200, 4, "bar")
