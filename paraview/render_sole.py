"""Image sequence of one sole's deformation from a Plantar run (ParaView, pvpython).

    xvfb-run -a pvpython paraview/render_sole.py OUT_DIR [--foot right|left] [--field NAME]
        [--warp 20] [--every 1] [--size 800 500] [--images DIR]

OUT_DIR is the directory of `plantar run` (Foot form = fem sole): it reads
OUT_DIR/sole_<foot>.pvd and writes DIR/sole_<foot>_NNNN.png (default DIR = OUT_DIR/images),
one per frame (every --every frames): the sole seen from below and the side, warped by its
displacement times --warp, coloured by --field (von_mises, contact_pressure, or the magnitude
of displacement / contact_force), with the nodal contact forces as arrows. The colour range
is fixed over the whole series. See docs/paraview.md.
"""
import argparse
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene,
                             GetColorTransferFunction, GetScalarBar, Glyph, Hide,
                             PVDReader, Render, SaveScreenshot, Show, Text, WarpByVector)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run", help="output directory of plantar run")
    parser.add_argument("--foot", choices=["right", "left"], default="right")
    parser.add_argument("--field", default="von_mises")
    parser.add_argument("--warp", type=float, default=20.0, help="displacement scale")
    parser.add_argument("--every", type=int, default=1, help="render every N-th frame")
    parser.add_argument("--size", type=int, nargs=2, default=[800, 500])
    parser.add_argument("--images", help="PNG directory (default RUN/images)")
    args = parser.parse_args()
    pvd = os.path.join(args.run, "sole_%s.pvd" % args.foot)
    if not os.path.isfile(pvd):
        raise SystemExit("render_sole.py: %s not found (run a scene with Robot/Foot form = "
                         "fem sole and Output/Write VTU = true)" % pvd)
    images = args.images or os.path.join(args.run, "images")
    os.makedirs(images, exist_ok=True)

    reader = PVDReader(FileName=pvd)
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    warp = WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=args.warp)
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = args.size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 1
    display = Show(warp, view)
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.3, 0.3, 0.3]
    ColorBy(display, ("POINTS", args.field, "Magnitude"))
    lut = GetColorTransferFunction(args.field)
    # A fixed colour range: the maximum over the frames.
    top = 0.0
    for t in times:
        warp.UpdatePipeline(t)
        array = warp.PointData[args.field]
        top = max(top, array.GetRange(-1)[1])
    lut.RescaleTransferFunction(0.0, top if top > 0 else 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    bar = GetScalarBar(lut, view)
    bar.Title = args.field
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    display.SetScalarBarVisibility(view, True)

    arrows = Glyph(Input=warp, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "contact_force"]
    arrows.ScaleArray = ["POINTS", "contact_force"]
    arrows.ScaleFactor = 0.002  # m per N
    arrows.GlyphMode = "All Points"
    arrows.GlyphTransform.Translate = [-1, 0, 0]  # the tip on the node, pushing on the sole
    arrow_display = Show(arrows, view)
    arrow_display.DiffuseColor = arrow_display.AmbientColor = [0.1, 0.1, 0.1]
    ColorBy(arrow_display, None)

    label = Text()
    label_display = Show(label, view)
    label_display.Color = [0, 0, 0]
    label_display.WindowLocation = "Upper Left Corner"

    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    for frame, t in enumerate(times[:: max(args.every, 1)]):
        scene.AnimationTime = t
        label.Text = ("%s sole, t = %.3f s, displacement x %g, arrows: ground reaction "
                      "(2 mm/N)" % (args.foot, t, args.warp))
        # Follow the foot: the camera looks at the sole from below, front and side.
        bounds = reader.GetDataInformation().GetBounds()
        center = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
                  (bounds[4] + bounds[5]) / 2]
        view.CameraFocalPoint = center
        view.CameraPosition = [center[0] + 0.25, center[1] - 0.3, center[2] - 0.2]
        view.CameraViewUp = [0, 0, 1]
        view.CameraParallelProjection = 0
        Render(view)
        SaveScreenshot(os.path.join(images, "sole_%s_%04d.png" % (args.foot, frame)), view,
                       ImageResolution=args.size)
    print("render_sole.py: %d images in %s" % (len(times[:: max(args.every, 1)]), images))


if __name__ == "__main__":
    main()
