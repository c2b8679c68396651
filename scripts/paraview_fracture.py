"""Crack patterns of the fracturing specimens, drawn by ParaView itself (pvbatch), for
docs/howto-fracturing-specimen.md: the triangles (results.pvd) coloured by a stress component, and
the joints (joints.pvd, line cells) on top: damaged joints coloured by damage, broken joints
(threshold broken = 1) as thick black lines. Makes notched-beam-fracture-crack.png,
block-compression-fracture-crack.png, brazilian-disc-fracture-crack.png and
wing-crack-crack.png. The wing-crack picture has two panels: sigma_yy, damage and cracks at
0.6 ms, the pre-existing flaw (joints broken from the start, time_of_failure = -1) in magenta;
and the joints coloured by their drawn tensile_strength (Weibull) with the cracks at the end of
the run (1 ms) on top.

Run from the repository root after the example runs:
    cargo run --release -- run examples/notched-beam-fracture.json
    cargo run --release -- run examples/block-compression-fracture.json
    cargo run --release -- run examples/brazilian-disc-fracture.json
    cargo run --release -- run examples/wing-crack.json --out results/wing-crack
    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/paraview_fracture.py [--out DIR] [beam] [block] [disc] [wing]

The pictures go to DIR (default ${TMPDIR:-/tmp}/fdem-figures, created if missing). The docs'
copies are regenerated with `--out docs/img`. The runs are read from RESULTS/<example name>
(`--results`, default results/).
"""
import argparse
import os

SPECIMENS = ["beam", "block", "disc", "wing"]


def parse_args():
    tmp = os.environ.get("TMPDIR") or "/tmp"
    p = argparse.ArgumentParser(
        description="Crack patterns of the fracturing specimens (notched-beam-fracture-crack.png, "
        "block-compression-fracture-crack.png, brazilian-disc-fracture-crack.png, "
        "wing-crack-crack.png), drawn with pvbatch. Regenerate the docs' copies with "
        "--out docs/img.")
    p.add_argument("which", nargs="*", metavar="SPECIMEN",
                   help="beam, block, disc and/or wing (default: all four)")
    p.add_argument("--out", default=os.path.join(tmp, "fdem-figures"),
                   help="folder for the pictures (default: %(default)s; created if missing)")
    p.add_argument("--results", default="results",
                   help="folder of the runs' results (default: %(default)s)")
    args = p.parse_args()
    for w in args.which:
        if w not in SPECIMENS:
            p.error(f"unknown specimen {w!r}: use beam, block, disc or wing")
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


def wing(results, time, end, png):
    """The wing-crack specimen in two panels of one view. Left, at `time`: sigma_yy of the
    triangles, damaged joints by damage, the broken joints black and the pre-existing flaw (broken
    from the start: time_of_failure = -1) magenta. Right, the joints at `end` shifted by 85 mm:
    every joint coloured by its drawn tensile_strength (Weibull), the cracks on top."""
    from paraview.simple import (ColorBy, ForceTime, GetActiveViewOrCreate,
                                 GetColorTransferFunction, GetScalarBar, GetSources, Hide,
                                 PVDReader, SaveScreenshot, Show, Text, Transform)

    run = os.path.join(results, "wing-crack")
    tri = PVDReader(FileName=os.path.join(run, "results.pvd"))
    joints = PVDReader(FileName=os.path.join(run, "joints.pvd"))
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [1200, 800]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.ViewTime = time

    def bar(lut, title, pos, fmt="%-#6.2g"):
        sb = GetScalarBar(lut, view)
        sb.Title = title
        sb.ComponentTitle = ""
        sb.TitleColor = [0, 0, 0]
        sb.LabelColor = [0, 0, 0]
        sb.RangeLabelFormat = fmt
        sb.WindowLocation = "Any Location"
        sb.Position = pos
        sb.ScalarBarLength = 0.4

    def cracks(src, width):
        broken = threshold(src, "broken", 0.5, 1.5)
        grown = threshold(broken, "time_of_failure", 0.0, 1e30)
        flaw = threshold(broken, "time_of_failure", -1.5, -0.5)
        for s, rgb, w in ((grown, [0, 0, 0], width), (flaw, [1, 0, 1], width + 1.5)):
            d = Show(s, view)
            d.ColorArrayName = [None, ""]
            d.AmbientColor = rgb
            d.DiffuseColor = rgb
            d.LineWidth = w

    # Left panel.
    d = Show(tri, view)
    ColorBy(d, ("CELLS", "stress"))
    lut = GetColorTransferFunction("stress")
    lut.VectorMode = "Component"
    lut.VectorComponent = 4
    lut.ApplyPreset("Cool to Warm", True)
    lut.RescaleTransferFunction(-30e6, 30e6)
    d.SetScalarBarVisibility(view, True)
    bar(lut, "sigma_yy [Pa]", [0.37, 0.05])
    damaged = threshold(joints, "damage", 0.01, 1.0)
    dd = Show(damaged, view)
    ColorBy(dd, ("CELLS", "damage"))
    dl = GetColorTransferFunction("damage")
    dl.ApplyPreset("Inferno (matplotlib)", True)
    dl.InvertTransferFunction()
    dl.RescaleTransferFunction(0.0, 1.0)
    dd.LineWidth = 2.0
    dd.SetScalarBarVisibility(view, True)
    bar(dl, "joint damage", [0.37, 0.55])
    cracks(joints, 3.0)
    # Right panel.
    last = ForceTime(Input=joints)
    last.IgnorePipelineTime = 1
    last.ForcedTime = end
    moved = Transform(Input=last)
    moved.Transform.Translate = [0.085, 0.0, 0.0]
    sd = Show(moved, view)
    ColorBy(sd, ("CELLS", "tensile_strength"))
    sl = GetColorTransferFunction("tensile_strength")
    sl.ApplyPreset("Viridis (matplotlib)", True)
    sl.InvertTransferFunction()  # light: weak; dark: strong
    sl.RescaleTransferFunction(1.5e6, 4.0e6)
    sd.LineWidth = 2.0
    sd.SetScalarBarVisibility(view, True)
    bar(sl, "tensile strength [Pa]", [0.88, 0.3])
    cracks(moved, 3.0)
    for txt, pos in ((f"sigma_yy, joint damage, cracks (flaw magenta) at {time * 1e3:.2g} ms",
                      [0.02, 0.95]),
                     (f"drawn tensile strength of the joints, cracks at {end * 1e3:.2g} ms",
                      [0.52, 0.95])):
        t = Text(Text=txt)
        td = Show(t, view)
        td.Color = [0, 0, 0]
        td.FontSize = 14
        td.WindowLocation = "Any Location"
        td.Position = pos
    view.CameraPosition = [0.075, 0.05, 1]
    view.CameraFocalPoint = [0.075, 0.05, 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 0.057
    SaveScreenshot(png, view, ImageResolution=[1200, 800], TransparentBackground=0)
    for s in GetSources().values():
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
        if key == "wing":
            png = os.path.join(args.out, "wing-crack-crack.png")
            wing(args.results, 6e-4, 1e-3, png)
            print(png)
            continue
        run, time, title, component, rng, focus, scale = shots[key]
        png = os.path.join(args.out, f"{run}-crack.png")
        shot(args.results, run, time, png, title, component, rng, focus, scale)
        print(png)


if __name__ == "__main__":
    main()
