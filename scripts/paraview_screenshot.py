"""Screenshots of fdem results taken by ParaView itself (pvbatch), for docs/paraview.md.

Run from the repository root after the two example runs:
    cargo run --release -- run examples/brazilian-disc-elastic.json
    cargo run --release -- run examples/kirsch-plate.json
    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/paraview_screenshot.py
"""
from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, Hide, PVDReader, ResetCamera, SaveScreenshot, Show)


def shot(pvd, array, component, title, png, rng=None, zoom=1.0, focus=None):
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


shot("results/brazilian-disc-elastic/results.pvd", "stress", 0,
     "sigma_xx [Pa]", "docs/img/brazilian-disc-sxx.png", rng=(-8e6, 8e6))
shot("results/kirsch-plate/results.pvd", "stress", 0,
     "sigma_xx [Pa]", "docs/img/kirsch-sxx.png", rng=(0.0, 3.0e6), zoom=12.0, focus=(0.025, 0.025))
