#!/usr/bin/env python3
"""Plots mesh-lame.png (the thick cylinder's CST stresses against Lame) and mesh-kirsch.png
(sigma_xx along x = 0 of the plate with a hole against Kirsch), for docs/mesh.md, from the CSV
files of the mesh crate's validation_data example:

    cargo run --release -p fdem-mesh --example validation_data -- /tmp
    python3 scripts/plot_mesh_validation.py /tmp [--out DIR]

Reads lame.csv and kirsch.csv from DATA (default /tmp). The pictures go to DIR (default
${TMPDIR:-/tmp}/fdem-figures, created if missing). The docs' copies are regenerated with
`--out docs/img`. Needs matplotlib and numpy.
"""
import argparse
import os

tmp = os.environ.get("TMPDIR") or "/tmp"
parser = argparse.ArgumentParser(
    description="Lame and Kirsch validation plots of the mesh crate (mesh-lame.png, "
    "mesh-kirsch.png). Regenerate the docs' copies with --out docs/img.")
parser.add_argument("data", nargs="?", default="/tmp",
                    help="folder with lame.csv and kirsch.csv written by "
                    "`cargo run --release -p fdem-mesh --example validation_data -- DATA` "
                    "(default: %(default)s)")
parser.add_argument("--out", default=os.path.join(tmp, "fdem-figures"),
                    help="folder for the pictures (default: %(default)s; created if missing)")
args = parser.parse_args()
d = args.data
os.makedirs(args.out, exist_ok=True)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Lame: p = 1 MPa, ri = 1, ro = 2
lame = np.loadtxt(os.path.join(d, "lame.csv"), delimiter=",", skiprows=1)
r = np.linspace(1, 2, 200)
A, B = 1.0 / 3.0, 4.0 / 3.0
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(lame[:, 0], lame[:, 1] / 1e6, ".", ms=1.5, color="tab:blue", label="hoop, CST centroids")
ax.plot(lame[:, 0], lame[:, 2] / 1e6, ".", ms=1.5, color="tab:orange", label="radial, CST centroids")
ax.plot(r, A + B / r**2, "k-", lw=1, label="Lame exact")
ax.plot(r, A - B / r**2, "k--", lw=1)
ax.set_xlabel("r [m]")
ax.set_ylabel("stress / p")
ax.set_title("thick-cylinder.msh, plane strain, inner pressure p")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(args.out, "mesh-lame.png"), dpi=110)
print(os.path.join(args.out, "mesh-lame.png"))

# Kirsch: a = 10 mm, s0 = 1 MPa, along x = 0 (theta = 90 deg): s_xx = s0/2 (2 + q + 3 q^2)
k = np.loadtxt(os.path.join(d, "kirsch.csv"), delimiter=",", skiprows=1)
y = np.linspace(0.01, 0.1, 400)
q = (0.01 / y) ** 2
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(k[:, 0] / 0.01, k[:, 1] / 1e6, "o", ms=2.5, label="CST centroids with x < 1 mm")
ax.plot(y / 0.01, 0.5 * (2 + q + 3 * q**2), "k-", lw=1, label="Kirsch (infinite plate)")
ax.set_xlabel("y / a on x = 0")
ax.set_ylabel("sigma_xx / s0")
ax.set_title("plate-with-hole.msh, plane stress, remote tension s0")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(args.out, "mesh-kirsch.png"), dpi=110)
print(os.path.join(args.out, "mesh-kirsch.png"))
