#!/usr/bin/env python3
"""Regenerates every .msh in meshes/ from its .geo source with the gmsh Python package.

    python3 -m venv .venv && .venv/bin/pip install -r meshes/requirements.txt
    .venv/bin/python meshes/generate.py

Writes Gmsh 4.1 ASCII files; cantilever-coarse is also written as 4.1 binary and 2.2 ASCII
(to exercise every reader). Meshing is single-threaded and deterministic for a given gmsh
version (4.15.2 made the committed files).
"""
import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
GEOS = [
    "brazilian-disc",
    "plate-with-hole",
    "thick-cylinder",
    "cantilever-coarse",
    "cantilever-fine",
    "long-bar",
    "notched-beam",
    "block",
    "hertz-disc",
    "notched-beam-coarse",
    "block-coarse",
    "griffith-plate-coarse",
    "griffith-plate",
    "wing-crack",
    "dfn-block",
]
# (suffix, MshFileVersion, Binary)
VARIANTS = {"cantilever-coarse": [("-bin", 4.1, 1), ("-v22", 2.2, 0)]}


def write(name, suffix, version, binary):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", binary)
    out = os.path.join(HERE, f"{name}{suffix}.msh")
    gmsh.write(out)
    print(f"{out}: {os.path.getsize(out)} bytes")


def main(names):
    for name in names:
        # A fresh session per mesh: options set in one .geo must not leak into the next.
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.open(os.path.join(HERE, f"{name}.geo"))
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.optimize("Laplace2D")
        write(name, "", 4.1, 0)
        for suffix, version, binary in VARIANTS.get(name, []):
            write(name, suffix, version, binary)
        gmsh.finalize()


if __name__ == "__main__":
    main(sys.argv[1:] or GEOS)
