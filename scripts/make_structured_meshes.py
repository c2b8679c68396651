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


if __name__ == "__main__":
    # Cantilever 10 m x 1 m: coarse and fine.
    rectangle("cantilever-coarse", 10.0, 1.0, 40, 4, "beam")
    rectangle("cantilever-fine", 10.0, 1.0, 200, 20, "beam")
    # Long bar 1 m x 0.02 m for the wave-arrival test.
    rectangle("bar", 1.0, 0.02, 200, 4, "bar")
