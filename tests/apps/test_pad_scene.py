#!/usr/bin/python3
"""Deformable pads in a humanoid scene (issue 22): scenes/kneel_drop.prm, HRP-2 dropped from
2 cm onto two knee pads (meshes/pad_knee.geo on the shanks, Pad 1 and Pad 2), read back with
VTK's XML readers and checked against quantities computed elsewhere:
  - the series: pad_right_knee.pvd and pad_left_knee.pvd list one frame per 100 steps;
    contacts.csv has each pad's force and compression;
  - placement (the pad -> link -> body -> world chain, URDF rpy): at the end (waist level) the
    right pad's contact face is the 0.10 x 0.08 m box of the scene, centred at the knee's
    y = waist y - 0.095 m (URDF joint offsets) and 0.3 sin(11.5 deg) - 0.09 m along x from
    the waist, on the ground;
  - per frame: on the contact nodes the recovered displacement equals the stepper's contact
    displacement; the nodal contact forces sum to the pad force of contacts.csv; every loaded
    node lies on the ground after deformation and inside the friction cone;
  - physics: the robot kneels on its pads alone (no foot force), the pads carry the robot's
    weight (URDF masses) at the end within 1 %, the right and left pads carry the same force
    at every step (mirror symmetry), and the landing's peak pad force exceeds the weight;
  - failures: an unknown pad link and a pad compressed past its Max compression stop the run
    with a message naming the pad (and the step and time).
Exit status 0 on success, 1 with the failed checks listed.
"""
import argparse
import math
import pathlib
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from test_vtk_output import (check, failures, point_array, read_csv, read_vtu,  # noqa: E402
                             robot_mass, row_at, unique_nodes)
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def run(plantar, scene, out, extra=None):
    """plantar run @p scene (with @p extra lines appended, in a copy) into @p out."""
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    if extra:
        copy = out.parent / (out.name + ".prm")
        copy.write_text(f"include {scene}\n" + extra)
        scene = copy
    return subprocess.run([plantar, "run", str(scene), "-o", str(out), "--no-figures"],
                          capture_output=True, text=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    source, work = pathlib.Path(args.source), pathlib.Path(args.work)
    scene = source / "scenes/kneel_drop.prm"
    out = work / "kneel"
    result = run(args.plantar, scene, out, "subsection Output\n  set VTK every = 100\nend\n")
    if result.returncode != 0:
        print(result.stdout, result.stderr)
        print("FAIL: plantar run exited with", result.returncode)
        return 1
    print(result.stdout)
    contacts, waist = read_csv(out / "contacts.csv"), read_csv(out / "waist.csv")
    mass = robot_mass(source / "models/hrp2/hrp2.urdf")
    weight, mu, dt = mass * 9.81, 0.8, 0.001

    # Physics over the run.
    feet = np.abs(np.concatenate([contacts["right_fz"], contacts["left_fz"]])).max()
    check(feet == 0, f"a foot touched the ground (max foot force {feet} N)")
    sym = np.abs(contacts["right_knee_fz"] - contacts["left_knee_fz"]).max()
    check(sym <= 1e-6 * weight, f"right and left pad forces differ by {sym} N")
    final = contacts["right_knee_fz"][-1] + contacts["left_knee_fz"][-1]
    print(f"pads at the end: {final:.3f} N, weight {weight:.3f} N (URDF masses {mass:.3f} kg); "
          f"peak {2 * contacts['right_knee_fz'].max():.1f} N; |right - left| max {sym:.2e} N")
    check(abs(final - weight) < 0.01 * weight, f"pads carry {final} N, weight {weight} N")
    check(2 * contacts["right_knee_fz"].max() > 1.5 * weight, "no landing impact on the pads")
    check(contacts["right_knee_compression"].max() > 0, "no pad compression recorded")

    # The ParaView series.
    max_dev = {"u": 0.0, "force": 0.0, "gap": 0.0, "cone": 0.0}
    expected_times = [0.1 * i for i in range(11)]
    for pad in ["right_knee", "left_knee"]:
        sets = ET.parse(out / f"pad_{pad}.pvd").getroot().find("Collection").findall("DataSet")
        times = [float(s.get("timestep")) for s in sets]
        check(np.allclose(times, expected_times, atol=1e-12), f"pad_{pad}.pvd times {times}")
        for t, path in ((float(s.get("timestep")), out / s.get("file")) for s in sets):
            grid = read_vtu(path)
            x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
            u = point_array(grid, "displacement", 3)
            uc = point_array(grid, "contact_displacement", 3)
            f = point_array(grid, "contact_force", 3)
            flag = point_array(grid, "contact_node", 1)[:, 0]
            point_array(grid, "von_mises", 1)
            x, u, uc, f, flag = unique_nodes(x, u, uc, f, flag)
            bottom = flag > 0.5
            check(bottom.sum() == 99, f"{pad} t = {t}: {bottom.sum()} contact nodes, not 11 x 9")
            if t == 0:
                continue
            scale = max(np.abs(uc).max(), 1e-9)
            max_dev["u"] = max(max_dev["u"], np.abs(u[bottom] - uc[bottom]).max() / scale)
            i = row_at(contacts, t)
            f_csv = np.array([contacts[f"{pad}_f{c}"][i] for c in "xyz"])
            max_dev["force"] = max(max_dev["force"],
                                   np.abs(f[bottom].sum(axis=0) - f_csv).max() / weight)
            loaded = f[:, 2] > 1e-6 * weight
            if loaded.any():
                gap = x[loaded, 2] + u[loaded, 2]
                max_dev["gap"] = max(max_dev["gap"], np.abs(gap).max())
                ft = np.hypot(f[loaded, 0], f[loaded, 1])
                max_dev["cone"] = max(max_dev["cone"], (ft / (mu * f[loaded, 2])).max())
            if pad == "right_knee" and abs(t - 1.0) < 1e-9:
                j = row_at(waist, t)
                face = x[bottom]
                extent = face.max(axis=0) - face.min(axis=0)
                centre = 0.5 * (face.max(axis=0) + face.min(axis=0))
                expected = np.array([waist["x"][j] + 0.3 * math.sin(math.radians(11.5)) - 0.09,
                                     waist["y"][j] - 0.095])
                print(f"right pad face at t = 1: extent {extent}, centre {centre}, expected "
                      f"centre {expected} (pitch {waist['pitch'][j]:.2e} rad)")
                check(np.abs(extent[:2] - [0.10, 0.08]).max() < 1e-3, f"pad extent {extent}")
                check(np.abs(centre[:2] - expected).max() < 2e-3, f"pad centre {centre[:2]}")
    print("max |u - u_c| / max |u_c| = %.2e, |sum f - f_csv| / weight = %.2e, "
          "max |gap| of loaded nodes = %.2e m, max |f_t| / (mu f_n) = %.6f" %
          (max_dev["u"], max_dev["force"], max_dev["gap"], max_dev["cone"]))
    check(max_dev["u"] < 1e-5, "pad field vs stepper displacement")
    check(max_dev["force"] < 1e-6, "pad VTU forces vs contacts.csv")
    check(max_dev["gap"] < 1e-5, "a loaded pad node off the ground")
    check(max_dev["cone"] < 1 + 1e-6, "a pad node outside the friction cone")

    # Failures.
    bad = run(args.plantar, scene, work / "bad_link",
              "subsection Pad 2\n  set Link = NO_SUCH_LINK\nend\n")
    message = bad.stdout + bad.stderr
    check(bad.returncode != 0 and "NO_SUCH_LINK" in message and "left_knee" in message,
          f"unknown pad link: exit {bad.returncode}, '{message.strip()}'")
    crushed = run(args.plantar, scene, work / "crushed",
                  "subsection Pad 1\n  set Max compression = 0.05\nend\n")
    message = crushed.stdout + crushed.stderr
    print(message.strip().splitlines()[-1] if message.strip() else "")
    check(crushed.returncode != 0 and "right_knee" in message and "step" in message
          and "Max compression" in message,
          f"over-compressed pad: exit {crushed.returncode}, '{message.strip()}'")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
