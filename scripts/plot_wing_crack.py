#!/usr/bin/env python3
"""The wing-crack example's picture: the crack pattern at the end of the run (broken joints,
the pre-existing flaw in red, the cracks that grew coloured by their time of failure) and the
load curve (mean axial stress on the top platen against the platens' strain, from walls.csv).

    cargo run --release -- run examples/wing-crack.json --out results/wing-crack
    .venv/bin/python scripts/plot_wing_crack.py results/wing-crack docs/img/wing-crack.png

Needs numpy, meshio and matplotlib (tests/python/requirements.txt's venv plus matplotlib).
"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

W, H, T = 0.05, 0.1, 0.05  # block width, height, thickness [m]


def main(run, png):
    last = sorted(glob.glob(os.path.join(run, "joints_*.vtu")))[-1]
    m = meshio.read(last)
    lines = m.cells_dict["line"]
    p = m.points[:, :2]
    d = m.cell_data_dict
    broken = d["broken"]["line"] == 1
    tf = d["time_of_failure"]["line"]
    flaw = broken & (tf < 0)
    grown = broken & (tf >= 0)
    frames = sorted(glob.glob(os.path.join(run, "frame_*.vtu")))
    f = meshio.read(frames[-1])

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9, 5), gridspec_kw={"width_ratios": [1, 1.3]})
    tri = f.cells_dict["triangle"]
    ax.triplot(f.points[:, 0] * 1e3, f.points[:, 1] * 1e3, tri, lw=0.15, color="0.75")
    seg = p[lines] * 1e3
    lc = LineCollection(seg[grown], array=tf[grown] * 1e3, cmap="viridis", lw=1.6)
    ax.add_collection(lc)
    ax.add_collection(LineCollection(seg[flaw], colors="red", lw=2.5))
    fig.colorbar(lc, ax=ax, label="time of failure [ms]", shrink=0.7)
    ax.set_aspect("equal")
    ax.set_xlim(-1, W * 1e3 + 1)
    ax.set_ylim(-1, H * 1e3 + 1)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("cracks at the end of the run (flaw in red)")

    rows = list(csv.DictReader(open(os.path.join(run, "walls.csv"))))
    u = np.array([float(r["u_y[bottom]"]) - float(r["u_y[top]"]) for r in rows])
    s = np.array([-float(r["force_y[top]"]) for r in rows]) / (W * T)
    bx.plot(u / H * 1e3, s / 1e6, color="k", lw=1)
    bx.set_xlabel("platen strain [1e-3]")
    bx.set_ylabel("axial stress on the top platen [MPa]")
    bx.set_title("load curve (walls.csv)")
    bx.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"{png}: peak stress {s.max() / 1e6:.2f} MPa at strain {u[s.argmax()] / H:.3e}; "
          f"{int(grown.sum())} joints broke during the run, {int(flaw.sum())} flaw joints")


if __name__ == "__main__":
    main(*sys.argv[1:3])
