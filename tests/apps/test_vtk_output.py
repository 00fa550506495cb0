#!/usr/bin/python3
"""The ParaView series of a humanoid run, read back with VTK's own XML readers (python3-vtk9).

Runs `plantar run tests/apps/test_vtk_output.prm` (stand on linear FEM soles, 0.2 s, a frame
every 50 steps), `tests/apps/test_vtk_output_reduced.prm` (the same soles reduced to 4 x 4
patches, fields recovered from the patch forces), `tests/apps/test_vtk_output_bilinear.prm` (the
same grid in the bilinear basis: 25 vertex contacts per foot) and `tests/apps/test_vtk_output_hyperelastic.prm` (Neo-Hookean soles,
Sole/Model = hyperelastic, 0.15 s, a Newton check of the sole at every step) and checks, frame by
frame, against quantities computed elsewhere:
  - the series: parameters.prm and the CSVs are there, the .pvd lists one frame per 50 steps
    (t = 0, 0.05, ..., 0.2) with files that exist;
  - links (.vtp, zlib): one VTK_VERTEX per body; body 1's vertex is the waist position of
    waist.csv; the points and polygons of the URDF's boxes and cylinders;
  - soles: every array present, with the right number of components and tuples; on the bottom
    nodes the recovered displacement equals the stepper's contact displacement (linear: to
    1e-5 of max |u_c|; hyperelastic: the written field is the Newton solution at the step's
    forces, the stepper's u_c the affine model C_T f + d, which differ by the prediction error
    bounded by Sole/Recondensation tolerance = 0.02, checked to 0.02 of max |u_c|); the sum of the
    nodal contact forces equals the foot force of contacts.csv; every loaded node lies on the
    ground after deformation (Signorini, within the position-correction penetration) and
    inside the friction cone; in the last frame both feet carry the robot's weight (URDF
    masses) within 10 %.
The linear case is run again with Output/VTK collection every = 1: the same .pvd files at the end.
Exit status 0 on success, 1 with the failed checks listed.
"""
import argparse
import csv
import math
import pathlib
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
    return ok


def read_vtu(path):
    """A .vtu (soles) or .vtp (links) file."""
    reader = (vtk.vtkXMLPolyDataReader() if str(path).endswith(".vtp")
              else vtk.vtkXMLUnstructuredGridReader())
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if grid is None or grid.GetNumberOfPoints() == 0:
        raise RuntimeError(f"{path}: VTK read no points")
    return grid


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def row_at(table, t):
    i = int(np.argmin(np.abs(table["t"] - t)))
    check(abs(table["t"][i] - t) < 1e-9, f"no CSV row at t = {t}")
    return i


def point_array(grid, name, components):
    array = grid.GetPointData().GetArray(name)
    if not check(array is not None, f"point array {name} missing"):
        return np.zeros((grid.GetNumberOfPoints(), components))
    check(array.GetNumberOfComponents() == components,
          f"{name}: {array.GetNumberOfComponents()} components, expected {components}")
    check(array.GetNumberOfTuples() == grid.GetNumberOfPoints(),
          f"{name}: {array.GetNumberOfTuples()} tuples != {grid.GetNumberOfPoints()} points")
    return vtk_to_numpy(array).reshape(grid.GetNumberOfPoints(), components).astype(float)


def unique_nodes(points, *fields):
    """deal.II writes each cell's vertices separately: merge coincident points."""
    keys = np.round(points / 1e-7).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    return (points[first],) + tuple(f[first] for f in fields)


def robot_mass(urdf):
    return sum(float(m.get("value")) for m in ET.parse(urdf).getroot().iter("mass"))


def link_surface_counts(urdf):
    """(points, polygons) of the links' surfaces from the URDF's boxes (8 corners, 6 faces) and
    cylinders (2 x 16 rim points, 16 sides + 2 caps), <visual> else <collision> per link."""
    points = polygons = 0
    for link in ET.parse(urdf).getroot().iter("link"):
        elements = link.findall("visual") or link.findall("collision")
        for geometry in (e.find("geometry") for e in elements):
            if geometry.find("box") is not None:
                points, polygons = points + 8, polygons + 6
            elif geometry.find("cylinder") is not None:
                points, polygons = points + 32, polygons + 18
            else:
                raise RuntimeError(f"{urdf}: link {link.get('name')}: not a box or cylinder")
    return points, polygons


def run_case(plantar, source, out, prm, duration, u_tolerance):
    """One run of @p prm into @p out; the checks above. Returns {(t, foot): max von Mises}, None
    if plantar failed."""
    print(f"== {prm}")
    first = len(failures)
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run([plantar, "run", str(source / "tests/apps" / prm), "-o", str(out),
                          "--no-figures"], capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stdout, run.stderr)
        failures.append(f"{prm}: plantar run exited with {run.returncode}")
        return None

    for name in ["parameters.prm", "waist.csv", "contacts.csv", "joints.csv", "scene.pvd",
                 "links.pvd", "sole_right.pvd", "sole_left.pvd"]:
        check((out / name).is_file(), f"{name} missing")
    waist = read_csv(out / "waist.csv")
    contacts = read_csv(out / "contacts.csv")
    dt, every, mu, max_penetration = 0.001, 50, 0.8, 0.005
    expected_times = [every * dt * i for i in range(int(round(duration / (every * dt))) + 1)]

    series = {}
    for name in ["links", "sole_right", "sole_left"]:
        sets = ET.parse(out / f"{name}.pvd").getroot().find("Collection").findall("DataSet")
        times = [float(s.get("timestep")) for s in sets]
        check(np.allclose(times, expected_times, atol=1e-12),
              f"{name}.pvd times {times} != {expected_times}")
        series[name] = [(float(s.get("timestep")), out / s.get("file")) for s in sets]
    scene_sets = ET.parse(out / "scene.pvd").getroot().find("Collection").findall("DataSet")
    check(len(scene_sets) == 3 * len(expected_times), "scene.pvd: not 3 parts per frame")

    mass = robot_mass(source / "models/hrp2/hrp2.urdf")
    surface_points, surface_polygons = link_surface_counts(source / "models/hrp2/hrp2.urdf")
    max_dev = {"waist": 0.0, "u": 0.0, "force": 0.0, "gap": 0.0, "cone": 0.0}
    peak_von_mises = {}
    for frame, (t, links_file) in enumerate(series["links"]):
        check(links_file.suffix == ".vtp", f"{links_file}: not a .vtp")
        with open(links_file, "rb") as f:
            head = f.read(300)
        check(b'type="PolyData"' in head and b'compressor="vtkZLibDataCompressor"' in head,
              f"{links_file}: not zlib-compressed PolyData")
        links = read_vtu(links_file)
        check(links.GetNumberOfPoints() == 31 + surface_points
              and links.GetNumberOfPolys() == surface_polygons,
              f"t = {t}: links {links.GetNumberOfPoints()} points, {links.GetNumberOfPolys()} "
              f"polygons != 31 + {surface_points}, {surface_polygons} (URDF)")
        types = np.array([links.GetCellType(c) for c in range(links.GetNumberOfCells())])
        body = vtk_to_numpy(links.GetCellData().GetArray("body"))
        vertices = np.flatnonzero(types == vtk.VTK_VERTEX)
        check(sorted(body[vertices]) == list(range(1, 32)),
              f"t = {t}: vertex bodies {sorted(body[vertices])} != 1..31")
        waist_cell = vertices[body[vertices] == 1][0]
        waist_point = np.array(links.GetPoint(links.GetCell(waist_cell).GetPointId(0)))
        if t > 0:  # the CSV rows start at the first output step
            i = row_at(waist, t)
            waist_csv = np.array([waist["x"][i], waist["y"][i], waist["z"][i]])
            max_dev["waist"] = max(max_dev["waist"], np.abs(waist_point - waist_csv).max())
            check(np.abs(waist_point - waist_csv).max() < 1e-7,
                  f"t = {t}: waist vertex {waist_point} != waist.csv {waist_csv}")

        total_fz = 0.0
        for foot in ["right", "left"]:
            ft, path = series[f"sole_{foot}"][frame]
            check(abs(ft - t) < 1e-12, f"sole_{foot} frame {frame} at t = {ft} != {t}")
            grid = read_vtu(path)
            n = grid.GetNumberOfPoints()
            x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
            u = point_array(grid, "displacement", 3)
            uc = point_array(grid, "contact_displacement", 3)
            f = point_array(grid, "contact_force", 3)
            p = point_array(grid, "contact_pressure", 1)[:, 0]
            flag = point_array(grid, "contact_node", 1)[:, 0]
            vm = point_array(grid, "von_mises", 1)[:, 0]
            peak_von_mises[(round(t, 9), foot)] = vm.max()
            point_array(grid, "stress", 9)
            material = point_array(grid, "material_id", 1)  # deal.II: cell data as points
            check(len(np.unique(material)) == 1,  # one material (rubber) in the scene
                  f"t = {t} {foot}: material ids {np.unique(material)}")
            check(np.isfinite(u).all() and np.isfinite(vm).all() and (vm >= 0).all(),
                  f"t = {t} {foot}: non-finite displacement or negative von Mises")
            x, u, uc, f, p, flag = unique_nodes(x, u, uc, f, p, flag)
            bottom = flag > 0.5
            check(bottom.sum() > 10, f"t = {t} {foot}: {bottom.sum()} contact nodes")
            scale = max(np.abs(uc).max(), 1e-9)
            dev = np.abs(u[bottom] - uc[bottom]).max() / scale
            max_dev["u"] = max(max_dev["u"], dev)
            check(dev < u_tolerance,
                  f"t = {t} {foot}: sole field vs stepper displacement {dev:.2e}")
            check(np.abs(f[~bottom]).max(initial=0) == 0, f"t = {t} {foot}: force off the bottom")
            if t > 0:
                i = row_at(contacts, t)
                f_csv = np.array([contacts[f"{foot}_f{c}"][i] for c in "xyz"])
            else:  # before the first step: no impulse yet
                f_csv = np.zeros(3)
            f_sum = f[bottom].sum(axis=0)
            dev = np.abs(f_sum - f_csv).max() / max(np.abs(f_csv).max(), 1.0)
            max_dev["force"] = max(max_dev["force"], dev)
            check(dev < 1e-5, f"t = {t} {foot}: sum of nodal forces {f_sum} != CSV {f_csv}")
            total_fz += f_sum[2]
            loaded = bottom & (f[:, 2] > 1e-3 * max(f[:, 2].max(), 1e-9))
            if t > 0:
                check(loaded.sum() > 0, f"t = {t} {foot}: no loaded node")
                z = x[loaded, 2] + u[loaded, 2]
                max_dev["gap"] = max(max_dev["gap"], np.abs(z).max())
                check((np.abs(z) < max_penetration).all(),
                      f"t = {t} {foot}: loaded nodes at z = [{z.min():.2e}, {z.max():.2e}] m")
                tangential = np.hypot(f[loaded, 0], f[loaded, 1])
                cone = (tangential / (mu * f[loaded, 2])).max()
                max_dev["cone"] = max(max_dev["cone"], cone)
                check(cone <= 1 + 1e-4, f"t = {t} {foot}: |f_t| / (mu f_n) = {cone}")
                check((p[loaded] > 0).all(), f"t = {t} {foot}: loaded node without pressure")
        if frame == len(series["links"]) - 1:
            weight = mass * 9.81
            check(abs(total_fz - weight) < 0.1 * weight,
                  f"last frame: sum f_z = {total_fz:.1f} N, weight {weight:.1f} N")
            print(f"last frame: sum f_z = {total_fz:.1f} N, m g = {weight:.1f} N")

    print("max |waist vertex - waist.csv| = %.2e m" % max_dev["waist"])
    print("max |u - u_c| / max |u_c| on bottom nodes = %.2e" % max_dev["u"])
    print("max |sum f - contacts.csv| / |f| = %.2e" % max_dev["force"])
    print("max |z + u_z| of loaded nodes = %.2e m" % max_dev["gap"])
    print("max |f_t| / (mu f_n) = %.6f" % max_dev["cone"])
    failures[first:] = [f"{prm}: {f}" for f in failures[first:]]
    return peak_von_mises


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    source = pathlib.Path(args.source)
    work = pathlib.Path(args.work)
    linear = run_case(args.plantar, source, work / "linear", "test_vtk_output.prm", 0.2, 1e-5)
    hyper = run_case(args.plantar, source, work / "hyperelastic",
                     "test_vtk_output_hyperelastic.prm", 0.15, 0.02)
    # The reduced sole's fields, recovered from its patch forces: the same checks (the nodal
    # forces A F sum to the foot force, the field's bottom nodes carry the written contact
    # displacement, loaded nodes on the ground and in the cone).
    reduced = run_case(args.plantar, source, work / "reduced", "test_vtk_output_reduced.prm",
                       0.2, 1e-5)
    bilinear = run_case(args.plantar, source, work / "bilinear", "test_vtk_output_bilinear.prm",
                        0.2, 1e-5)
    # Output/VTK collection every = 1: the .pvd collections rewritten at every frame end the
    # same, byte for byte, as when rewritten every 25 frames (the default) and after the last.
    decimated = work / "collection_every"
    shutil.rmtree(decimated, ignore_errors=True)
    decimated.mkdir(parents=True)
    (decimated / "scene.prm").write_text(
        "include tests/apps/test_vtk_output.prm\n"
        "subsection Output\n  set VTK collection every = 1\nend\n")
    run = subprocess.run([args.plantar, "run", str(decimated / "scene.prm"), "-o",
                          str(decimated / "out"), "--no-figures"], capture_output=True, text=True)
    if check(run.returncode == 0, f"VTK collection every = 1: exit {run.returncode}"):
        for name in ["scene.pvd", "links.pvd", "sole_right.pvd", "sole_left.pvd"]:
            same = ((decimated / "out" / name).read_bytes() ==
                    (work / "linear" / name).read_bytes())
            check(same, f"VTK collection every = 1: {name} differs from the default's")
        print("VTK collection every = 1: the four .pvd files equal the default's (every 25)")
    else:
        print(run.stdout, run.stderr)
    if linear and hyper:
        # Same sole, small strains (|u| / thickness ~ 3e-3): the Cauchy von Mises of the
        # Neo-Hookean sole is the linear sole's (same E, nu) to O(strain) plus the difference
        # of the two runs' forces.
        dev = max(abs(hyper[k] - linear[k]) / linear[k] for k in hyper if k[0] > 0)
        print("max |peak von Mises hyperelastic / linear - 1| = %.2e" % dev)
        check(dev < 0.02, f"peak von Mises hyperelastic vs linear sole: {dev:.2e}")
    if linear and reduced:
        dev = max(abs(reduced[k] - linear[k]) / linear[k] for k in reduced if k[0] > 0)
        print("max |peak von Mises reduced 4 x 4 / full - 1| = %.2e" % dev)
    if linear and reduced and bilinear:
        # The bilinear basis's continuous pressure resolves the edge stresses that a constant
        # pressure per cell does not: nearer the full sole's peak von Mises.
        dev_b = max(abs(bilinear[k] - linear[k]) / linear[k] for k in bilinear if k[0] > 0)
        print("max |peak von Mises bilinear 4 x 4 / full - 1| = %.2e" % dev_b)
        check(dev_b < dev, f"peak von Mises bilinear 4 x 4 ({dev_b:.2e}) not nearer the full "
              f"sole's than the constant 4 x 4 ({dev:.2e})")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
