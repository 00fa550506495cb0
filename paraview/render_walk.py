"""Side view of a Plantar humanoid run, one PNG per frame (ParaView, pvpython).

    xvfb-run -a pvpython paraview/render_walk.py OUT_DIR [--every 1] [--size 800 600]
        [--warp 1] [--images DIR]

OUT_DIR is the directory of `plantar run`: it reads OUT_DIR/links.pvd and, for Foot form =
fem sole, OUT_DIR/sole_right.pvd and sole_left.pvd, and writes DIR/walk_NNNN.png (default
DIR = OUT_DIR/images): the links (grey), the soles warped by their displacement times --warp
and coloured by contact pressure, the ground z = 0, seen from the robot's right side (-y),
the camera following the waist. See docs/paraview.md.
"""
import argparse
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene,
                             GetColorTransferFunction, Plane, PVDReader, Render,
                             SaveScreenshot, Show, Text, WarpByVector)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run", help="output directory of plantar run")
    parser.add_argument("--every", type=int, default=1, help="render every N-th frame")
    parser.add_argument("--size", type=int, nargs=2, default=[800, 600])
    parser.add_argument("--warp", type=float, default=1.0, help="sole displacement scale")
    parser.add_argument("--images", help="PNG directory (default RUN/images)")
    args = parser.parse_args()
    links_pvd = os.path.join(args.run, "links.pvd")
    if not os.path.isfile(links_pvd):
        raise SystemExit("render_walk.py: %s not found (run a humanoid scene with "
                         "Output/Write VTU = true)" % links_pvd)
    images = args.images or os.path.join(args.run, "images")
    os.makedirs(images, exist_ok=True)

    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = args.size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    links = PVDReader(FileName=links_pvd)
    links.UpdatePipelineInformation()
    times = list(links.TimestepValues) if links.TimestepValues else [0.0]
    links_display = Show(links, view)
    ColorBy(links_display, None)
    links_display.DiffuseColor = [0.55, 0.57, 0.62]

    ground = Plane(Origin=[-1, -1, 0], Point1=[4, -1, 0], Point2=[-1, 1, 0])
    ground_display = Show(ground, view)
    ground_display.DiffuseColor = [0.85, 0.8, 0.7]

    for foot in ["right", "left"]:
        pvd = os.path.join(args.run, "sole_%s.pvd" % foot)
        if not os.path.isfile(pvd):
            continue
        warp = WarpByVector(Input=PVDReader(FileName=pvd),
                            Vectors=["POINTS", "displacement"], ScaleFactor=args.warp)
        sole_display = Show(warp, view)
        ColorBy(sole_display, ("POINTS", "contact_pressure"))
        lut = GetColorTransferFunction("contact_pressure")
        lut.RescaleTransferFunction(0.0, 1.0e5)  # Pa
        lut.AutomaticRescaleRangeMode = "Never"
        sole_display.SetScalarBarVisibility(view, True)

    label = Text()
    label_display = Show(label, view)
    label_display.Color = [0, 0, 0]
    label_display.WindowLocation = "Upper Left Corner"

    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    selected = times[:: max(args.every, 1)]
    for frame, t in enumerate(selected):
        scene.AnimationTime = t
        label.Text = "t = %.3f s" % t
        bounds = links.GetDataInformation().GetBounds()
        x = (bounds[0] + bounds[1]) / 2
        view.CameraFocalPoint = [x, 0.0, 0.75]
        view.CameraPosition = [x, -3.2, 0.85]
        view.CameraViewUp = [0, 0, 1]
        Render(view)
        SaveScreenshot(os.path.join(images, "walk_%04d.png" % frame), view,
                       ImageResolution=args.size)
    print("render_walk.py: %d images in %s" % (len(selected), images))


if __name__ == "__main__":
    main()
