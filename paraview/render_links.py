#!/usr/bin/python3
"""Renders the robot's links of a plantar run to a PNG without ParaView.

    /usr/bin/python3 paraview/render_links.py OUT_DIR/vtk/links_000080.vtp -o links.png
    /usr/bin/python3 paraview/render_links.py OUT_DIR --time 3.2 -o links.png

INPUT is a links file (.vtp, or .vtu of older runs; any VTK XML surface or volume mesh works)
or a run directory / links.pvd, from which the frame nearest to --time (default: the last) is
taken. VTK (python3-vtk9 or python3-paraview) reads the file; its surface polygons are drawn
with matplotlib's mplot3d (Agg, headless), flat-shaded by a light from the viewer's side,
coloured by the cell data "body" (--color body, the default when present) or in one grey
(--color grey). Vertices and lines (e.g. the body origins) are not drawn. Options: --elev and
--azim (degrees, the mplot3d view), --size W H (inches), --dpi, --ground (z = 0 as a grey
plane), --title.
"""
import argparse
import pathlib
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import vtk  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def pick_frame(path, time):
    """The data file of a run directory or .pvd nearest to @p time (None: the last)."""
    pvd = path / "links.pvd" if path.is_dir() else path
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    if not sets:
        raise RuntimeError(f"{pvd}: no DataSet")
    times = np.array([float(s.get("timestep")) for s in sets])
    i = len(sets) - 1 if time is None else int(np.argmin(np.abs(times - time)))
    return pvd.parent / sets[i].get("file"), times[i]


def read_surface(path):
    """(polygons as lists of points (n x 3), their "body" values or None) of @p path."""
    reader = vtk.vtkXMLGenericDataObjectReader()
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput()
    if data is None or data.GetNumberOfPoints() == 0:
        raise RuntimeError(f"{path}: VTK read no points")
    surface = vtk.vtkDataSetSurfaceFilter()  # polydata passes; volume cells -> boundary faces
    surface.SetInputData(data)
    surface.Update()
    polydata = surface.GetOutput()
    points = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    body = polydata.GetCellData().GetArray("body")
    n_verts, n_lines = polydata.GetNumberOfVerts(), polydata.GetNumberOfLines()
    first = n_verts + n_lines  # cell order of vtkPolyData: verts, lines, polys, strips
    polygons, bodies = [], []
    ids = vtk.vtkIdList()
    polys = polydata.GetPolys()
    polys.InitTraversal()
    cell = first
    while polys.GetNextCell(ids):
        polygons.append(points[[ids.GetId(k) for k in range(ids.GetNumberOfIds())]])
        bodies.append(body.GetTuple1(cell) if body is not None else 0)
        cell += 1
    if not polygons:
        raise RuntimeError(f"{path}: no polygons")
    return polygons, (np.array(bodies) if body is not None else None)


def view_direction(elev, azim):
    """Unit vector from the scene towards the mplot3d camera."""
    e, a = np.radians(elev), np.radians(azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def shade(polygons, colors, light):
    """Flat shading: ambient 0.35 + diffuse 0.65 |n . light| (two-sided; Newell normals)."""
    shaded = []
    for polygon, color in zip(polygons, colors):
        p = polygon - polygon.mean(axis=0)
        n = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
        norm = np.linalg.norm(n)
        intensity = 0.35 + 0.65 * (abs(n @ light) / norm if norm > 0 else 0.0)
        shaded.append(np.clip(np.asarray(color[:3]) * intensity, 0, 1))
    return shaded


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("input", type=pathlib.Path, help=".vtp/.vtu file, run directory or .pvd")
    parser.add_argument("-o", "--output", type=pathlib.Path, required=True, help="PNG file")
    parser.add_argument("--time", type=float, help="frame nearest to this time (s)")
    parser.add_argument("--color", choices=["body", "grey"], default="body")
    parser.add_argument("--elev", type=float, default=15.0)
    parser.add_argument("--azim", type=float, default=-60.0)
    parser.add_argument("--size", type=float, nargs=2, default=[5.0, 6.0], metavar=("W", "H"))
    parser.add_argument("--dpi", type=int, default=100)
    parser.add_argument("--ground", action="store_true", help="draw z = 0 under the robot")
    parser.add_argument("--title", default=None)
    args = parser.parse_args()

    path, time = args.input, None
    if path.is_dir() or path.suffix == ".pvd":
        path, time = pick_frame(path, args.time)
    polygons, bodies = read_surface(path)

    if args.color == "body" and bodies is not None:
        cmap = plt.get_cmap("tab20")
        colors = [cmap(int(b) % 20) for b in bodies]
    else:
        colors = [(0.62, 0.64, 0.68)] * len(polygons)
    light = view_direction(args.elev, args.azim)

    points = np.vstack(polygons)
    lo, hi = points.min(axis=0), points.max(axis=0)
    if args.ground:  # a margin of 10 % of the height around the footprint, down to z = 0
        margin = 0.1 * (hi[2] - min(lo[2], 0.0))
        lo = np.array([lo[0] - margin, lo[1] - margin, min(lo[2], 0.0)])
        hi = np.array([hi[0] + margin, hi[1] + margin, hi[2]])

    fig = plt.figure(figsize=args.size, dpi=args.dpi)
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False  # the ground first, then the links sorted by depth
    if args.ground:
        ground = np.array([[lo[0], lo[1], 0], [hi[0], lo[1], 0], [hi[0], hi[1], 0],
                           [lo[0], hi[1], 0]])
        ax.add_collection3d(Poly3DCollection([ground], facecolors=[(0.88, 0.88, 0.85)],
                                             edgecolors="none", zorder=0))
    ax.add_collection3d(Poly3DCollection(polygons, facecolors=shade(polygons, colors, light),
                                         edgecolors="none", zorder=1))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(np.maximum(hi - lo, 1e-9))  # equal scales on the three axes
    ax.view_init(elev=args.elev, azim=args.azim)
    ax.set_axis_off()
    title = args.title if args.title is not None else (
        f"{path.name}" + (f", t = {time:g} s" if time is not None else ""))
    if title:
        ax.set_title(title, fontsize=9)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.95)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output, bbox_inches="tight", pad_inches=0.05)
    print(f"{args.output}: {len(polygons)} polygons of {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
