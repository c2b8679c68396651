"""Crack patterns of the fracturing specimens, drawn by ParaView itself (pvbatch), for
docs/howto-fracturing-specimen.md: the triangles (results.pvd) coloured by a stress component, and
the joints (joints.pvd, line cells) on top: damaged joints coloured by damage, broken joints
(threshold broken = 1) as thick black lines. Makes notched-beam-fracture-crack.png,
block-compression-fracture-crack.png and brazilian-disc-fracture-crack.png.

Run from the repository root after the example runs:
    cargo run --release -- run examples/notched-beam-fracture.json
    cargo run --release -- run examples/block-compression-fracture.json
    cargo run --release -- run examples/brazilian-disc-fracture.json
    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/paraview_fracture.py [--out DIR] [beam] [block] [disc]

The pictures go to DIR (default ${TMPDIR:-/tmp}/fdem-figures, created if missing). The docs'
copies are regenerated with `--out docs/img`.
"""
import argparse
import os

SPECIMENS = ["beam", "block", "disc"]


def parse_args():
    tmp = os.environ.get("TMPDIR") or "/tmp"
    p = argparse.ArgumentParser(
        description="Crack patterns of the fracturing specimens (notched-beam-fracture-crack.png, "
        "block-compression-fracture-crack.png, brazilian-disc-fracture-crack.png), drawn with "
        "pvbatch. Regenerate the docs' copies with --out docs/img.")
    p.add_argument("which", nargs="*", metavar="SPECIMEN",
                   help="beam, block and/or disc (default: all three)")
    p.add_argument("--out", default=os.path.join(tmp, "fdem-figures"),
                   help="folder for the pictures (default: %(default)s; created if missing)")
    p.add_argument("--results", default="results",
                   help="folder of the runs' results (default: %(default)s)")
    args = p.parse_args()
    for w in args.which:
        if w not in SPECIMENS:
            p.error(f"unknown specimen {w!r}: use beam, block or disc")
    return args


def threshold(src, array, lo, hi):
    from paraview.simple import Threshold

    t = Threshold(Input=src)
    t.Scalars = ["CELLS", array]
    try:  # ParaView >= 5.10
        t.LowerThreshold = lo
        t.UpperThreshold = hi
    except AttributeError:
        t.ThresholdRange = [lo, hi]
    return t


def shot(results, run, time, png, stress_title, component, rng, focus, scale):
    from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                                 GetScalarBar, Hide, PVDReader, SaveScreenshot, Show)

    tri = PVDReader(FileName=os.path.join(results, run, "results.pvd"))
    joints = PVDReader(FileName=os.path.join(results, run, "joints.pvd"))
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [1000, 800]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.ViewTime = time
    d = Show(tri, view)
    ColorBy(d, ("CELLS", "stress"))
    lut = GetColorTransferFunction("stress")
    lut.VectorMode = "Component"
    lut.VectorComponent = component
    lut.ApplyPreset("Cool to Warm", True)
    lut.RescaleTransferFunction(*rng)
    d.SetScalarBarVisibility(view, True)
    sb = GetScalarBar(lut, view)
    sb.Title = stress_title
    sb.ComponentTitle = ""
    sb.TitleColor = [0, 0, 0]
    sb.LabelColor = [0, 0, 0]
    sb.RangeLabelFormat = "%-#6.2g"
    sb.WindowLocation = "Any Location"
    sb.Position = [0.80, 0.05]
    sb.ScalarBarLength = 0.4
    # Damaged joints (damage above 1 %), coloured by damage (light to dark).
    damaged = threshold(joints, "damage", 0.01, 1.0)
    dd = Show(damaged, view)
    ColorBy(dd, ("CELLS", "damage"))
    dl = GetColorTransferFunction("damage")
    dl.ApplyPreset("Inferno (matplotlib)", True)
    dl.InvertTransferFunction()  # light: barely damaged; dark: nearly broken
    dl.RescaleTransferFunction(0.0, 1.0)
    dd.LineWidth = 2.5
    dd.SetScalarBarVisibility(view, True)
    dsb = GetScalarBar(dl, view)
    dsb.Title = "joint damage"
    dsb.TitleColor = [0, 0, 0]
    dsb.LabelColor = [0, 0, 0]
    dsb.WindowLocation = "Any Location"
    dsb.Position = [0.80, 0.55]
    dsb.ScalarBarLength = 0.4
    # Broken joints: the crack.
    broken = threshold(joints, "broken", 0.5, 1.5)
    bd = Show(broken, view)
    bd.ColorArrayName = [None, ""]
    bd.AmbientColor = [0, 0, 0]
    bd.DiffuseColor = [0, 0, 0]
    bd.LineWidth = 3.5
    view.CameraPosition = [focus[0], focus[1], 1]
    view.CameraFocalPoint = [focus[0], focus[1], 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = scale
    SaveScreenshot(png, view, ImageResolution=[1000, 800], TransparentBackground=0)
    for s in (broken, damaged, joints, tri):
        Hide(s, view)


def main():
    args = parse_args()
    which = args.which or SPECIMENS
    os.makedirs(args.out, exist_ok=True)
    shots = {
        "beam": ("notched-beam-fracture", 4e-3, "sigma_xx [Pa]", 0, (-6e6, 6e6),
                 (0.006, 0.025), 0.03),
        "block": ("block-compression-fracture", 4.5e-4, "sigma_yy [Pa]", 4, (-60e6, 5e6),
                  (0.031, 0.025), 0.032),
        "disc": ("brazilian-disc-fracture", 1.65e-3, "sigma_xx [Pa]", 0, (-6e6, 3e6),
                 (0.006, 0.0), 0.03),
    }
    for key in SPECIMENS:
        if key not in which:
            continue
        run, time, title, component, rng, focus, scale = shots[key]
        png = os.path.join(args.out, f"{run}-crack.png")
        shot(args.results, run, time, png, title, component, rng, focus, scale)
        print(png)


if __name__ == "__main__":
    main()
