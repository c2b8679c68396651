"""Screenshots of fdem results taken by ParaView itself (pvbatch), for docs/paraview.md:
brazilian-disc-sxx.png (sigma_xx of the elastic Brazilian disc) and kirsch-sxx.png (sigma_xx
around the hole of the Kirsch plate).

Run from the repository root after the two example runs:
    cargo run --release -- run examples/brazilian-disc-elastic.json
    cargo run --release -- run examples/kirsch-plate.json
    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/paraview_screenshot.py [--out DIR]

The pictures go to DIR (default ${TMPDIR:-/tmp}/fdem-figures, created if missing). The docs'
copies are regenerated with `--out docs/img`.
"""
import argparse
import os


def parse_args():
    tmp = os.environ.get("TMPDIR") or "/tmp"
    p = argparse.ArgumentParser(
        description="Screenshots of sigma_xx on the elastic Brazilian disc and the Kirsch plate "
        "(brazilian-disc-sxx.png, kirsch-sxx.png), taken with pvbatch. "
        "Regenerate the docs' copies with --out docs/img.")
    p.add_argument("--out", default=os.path.join(tmp, "fdem-figures"),
                   help="folder for the pictures (default: %(default)s; created if missing)")
    p.add_argument("--results", default="results",
                   help="folder of the runs' results (default: %(default)s)")
    return p.parse_args()


def shot(pvd, array, component, title, png, rng=None, zoom=1.0, focus=None):
    from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                                 GetScalarBar, Hide, PVDReader, ResetCamera, SaveScreenshot,
                                 Show)

    reader = PVDReader(FileName=pvd)
    reader.UpdatePipeline()
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [1000, 800]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = Show(reader, view)
    ColorBy(display, ("CELLS", array))
    lut = GetColorTransferFunction(array)
    lut.VectorMode = "Component"
    lut.VectorComponent = component  # 0: sigma_xx of the 9-component tensor
    lut.ApplyPreset("Cool to Warm", True)
    if rng:
        lut.RescaleTransferFunction(*rng)
    display.SetScalarBarVisibility(view, True)
    sb = GetScalarBar(lut, view)
    sb.Title = title
    sb.ComponentTitle = ""
    sb.TitleColor = [0, 0, 0]
    sb.LabelColor = [0, 0, 0]
    sb.RangeLabelFormat = "%-#6.2g"
    view.CameraPosition = [0, 0, 1]
    view.CameraViewUp = [0, 1, 0]
    ResetCamera(view)
    if focus:
        view.CameraFocalPoint = [focus[0], focus[1], 0]
        view.CameraPosition = [focus[0], focus[1], 1]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = view.CameraParallelScale / zoom
    SaveScreenshot(png, view, ImageResolution=[1000, 800], TransparentBackground=0)
    Hide(reader, view)


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    disc = os.path.join(args.out, "brazilian-disc-sxx.png")
    shot(os.path.join(args.results, "brazilian-disc-elastic", "results.pvd"), "stress", 0,
         "sigma_xx [Pa]", disc, rng=(-8e6, 8e6))
    print(disc)
    kirsch = os.path.join(args.out, "kirsch-sxx.png")
    shot(os.path.join(args.results, "kirsch-plate", "results.pvd"), "stress", 0,
         "sigma_xx [Pa]", kirsch, rng=(0.0, 3.0e6), zoom=12.0, focus=(0.025, 0.025))
    print(kirsch)


if __name__ == "__main__":
    main()
