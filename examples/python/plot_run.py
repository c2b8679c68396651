"""Read a run into meshio and matplotlib: the last frame's von Mises stress on the deformed
mesh (from the .vtu, read by meshio) and the load-displacement curve (fdem's reader).

Usage (from the repository root, with the package installed: docs/python.md):

    python examples/python/plot_run.py                # runs the elastic Brazilian disc first
    python examples/python/plot_run.py RUN_DIR --png run.png

Needs meshio and matplotlib (``pip install meshio matplotlib``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402

import fdem  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "brazilian-disc-fracture.json"


def plot(run_dir: Path, png: Path) -> None:
    out = fdem.read(run_dir)
    last = out.frames[-1]
    mesh = meshio.read(last.file)  # the same file ParaView opens
    tri = Triangulation(mesh.points[:, 0], mesh.points[:, 1], mesh.cells_dict["triangle"])
    von_mises = mesh.cell_data_dict["von_mises"]["triangle"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    shown = a.tripcolor(tri, facecolors=von_mises / 1e6, cmap="viridis")
    fig.colorbar(shown, ax=a, label="von Mises stress [MPa]")
    a.set_aspect("equal")
    a.set_title(f"t = {last.time * 1e3:.3f} ms")
    a.set_xlabel("x [m]")
    a.set_ylabel("y [m]")
    if out.largest_load is not None:  # the run has a load-displacement curve
        u, p = out.load_displacement()
        b.plot(u * 1e3, p / 1e3)
        b.set_xlabel("displacement [mm]")
        b.set_ylabel("load [kN]")
        peak = out.peak_load  # None unless the specimen failed
        b.set_title(f"peak {peak / 1e3:.3f} kN" if peak else "load (no failure)")
    else:
        b.set_axis_off()
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"wrote {png} ({len(out.frames)} frames in {run_dir})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", nargs="?", type=Path, help="a run folder (default: run one)")
    parser.add_argument("--png", type=Path, default=Path("run.png"), help="the picture to write")
    args = parser.parse_args()
    run_dir = args.run_dir
    if run_dir is None:
        run_dir = Path("results") / "brazilian-disc-fracture-python"
        fdem.run(fdem.Scene(EXAMPLE), out=run_dir)
    plot(run_dir, args.png)


if __name__ == "__main__":
    main()
