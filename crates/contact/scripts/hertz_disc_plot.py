#!/usr/bin/env python3
"""Plots the contact pressure of the Hertz disc study against Hertz's p0 sqrt(1 - x^2/a^2):
hertz-disc.png, for docs/contact.md.

    mkdir -p /tmp/hz && FDEM_HERTZ_CSV=/tmp/hz FDEM_HERTZ_MESHES="..." \\
        cargo test --release -p fdem-contact --test all -- hertz:: --ignored --nocapture
    .venv/bin/python crates/contact/scripts/hertz_disc_plot.py /tmp/hz [--out DIR]

Reads the profiles (*.csv) from SRC. The picture goes to DIR (default
${TMPDIR:-/tmp}/fdem-figures, created if missing). The docs' copy is regenerated with
`--out docs/img`. Needs matplotlib and numpy.
"""
import argparse
import glob
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main(src, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    out = os.path.join(out_dir, "hertz-disc.png")
    fig, ax = plt.subplots(figsize=(6, 3.6))
    x = np.linspace(-1, 1, 401)
    ax.plot(x, np.sqrt(1 - x * x), "k-", lw=1.2, label="Hertz")
    for path, marker in zip(sorted(glob.glob(os.path.join(src, "*.csv"))), "os^dv"):
        with open(path) as f:
            title = f.readline().lstrip("# ").strip()
        d = np.loadtxt(path, delimiter=",", skiprows=2)
        ax.plot(d[:, 0], d[:, 1], marker, ms=3.5, mfc="none", label=title)
    ax.set_xlabel("x / a (Hertz)")
    ax.set_ylabel("p / p0 (Hertz)")
    ax.set_xlim(-1.4, 1.4)
    ax.set_title("Disc on a rigid plane, a = R/20: nodal pressures")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    tmp = os.environ.get("TMPDIR") or "/tmp"
    parser = argparse.ArgumentParser(
        description="Nodal pressures of the Hertz disc study against Hertz (hertz-disc.png). "
        "Regenerate the docs' copy with --out docs/img.")
    parser.add_argument("src", help="folder of the profiles written with FDEM_HERTZ_CSV=SRC")
    parser.add_argument("--out", default=os.path.join(tmp, "fdem-figures"),
                        help="folder for the picture (default: %(default)s; created if missing)")
    args = parser.parse_args()
    main(args.src, args.out)
