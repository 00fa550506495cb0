#!/usr/bin/python3
"""The touching nodes of a walk's sole series, one line per snapshot, for
sole_tilt_stiffness_bench.

Usage: active_sets.py RUN_DIR left|right OUT.txt
Reads RUN_DIR/sole_<side>.pvd (a walk's ParaView series, docs/paraview.md) and writes, for every
snapshot whose sole carries at least 400 N, "t F n x_1 y_1 ... x_n y_n": the time (s), the
sole's total normal force (N) and the positions (m) of the contact nodes carrying more than 1 %
of the mean nodal force, from the contact nodes' centroid (world axes: a straight walk's sole
axes to its yaw). deal.II writes each cell's vertices separately, so nodes are merged by their
reference position. Needs the vtk module (/usr/bin/python3 with python3-vtk9, or pvpython).
"""
import os
import re
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def main():
    if len(sys.argv) != 4 or sys.argv[2] not in ("left", "right"):
        sys.exit(__doc__)
    run, side, out_path = sys.argv[1:]
    series = open(f"{run}/sole_{side}.pvd").read()
    entries = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', series)
    lines = []
    for t, name in entries:
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(f"{run}/{name}")
        reader.Update()
        grid = reader.GetOutput()
        points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
        data = grid.GetPointData()
        is_contact = vtk_to_numpy(data.GetArray("contact_node")) > 0.5
        force = vtk_to_numpy(data.GetArray("contact_force")).astype(float)
        displacement = vtk_to_numpy(data.GetArray("displacement")).astype(float)
        nodes = np.where(is_contact)[0]
        _, first = np.unique(np.round(points[nodes] - displacement[nodes], 5), axis=0,
                             return_index=True)
        nodes = nodes[np.sort(first)]
        fz = np.abs(force[nodes, 2])
        total = fz.sum()
        if total < 400.0:
            continue
        position = points[nodes] - points[nodes].mean(axis=0)
        touching = np.where(fz > 0.01 * total / len(nodes))[0]
        lines.append(f"{float(t):.3f} {total:.0f} {len(touching)}" +
                     "".join(f" {position[k, 0]:.4f} {position[k, 1]:.4f}" for k in touching))
    with open(out_path + ".tmp", "w") as out:
        out.write("\n".join(lines) + "\n")
    os.replace(out_path + ".tmp", out_path)
    print(f"{out_path}: {len(lines)} snapshots")


if __name__ == "__main__":
    main()
