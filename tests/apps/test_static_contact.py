#!/usr/bin/python3
"""plantar run of a static contact scene (issue 26) serially and under mpirun.

The scene: the sole of meshes/sole_box.geo in 8 x 6 x 1 hexahedra (Mesh size 0.0272), refined
once, Q1, under the tilted foot of the fem test fem.distributed_contact (translation (0.3, 0.1,
-1) mm, rotation (0.004, 0.015, 0) rad about the top face's centre, mu = 0.5). Checks:
  * `plantar run` without mpirun, and `mpirun -np 1` and `-np 2`: exit status 0, summary.csv,
    summary.txt, parameters.prm; contact.pvtu lists one piece per rank and each piece exists;
  * the three summaries agree: dofs, contact nodes, node states, Newton iterations equal,
    forces and moments to 1e-9 relative (the fem test holds the solver against the condensed
    reference; here the scene reads the same case from a gmsh mesh);
  * the forces balance: foot force + ground force = 0 to 1e-9 of |ground force|;
  * part of the sole lifts off, part sticks, part slips (the case of the fem test);
  * force control (serial): the serial run's force and moments as the load, started from another
    displacement, give back the prescribed displacement (1e-6) and force (1e-9);
  * a tetrahedral sole at 2 ranks: exit status 1, one error message naming Sole/Cell kind.
Exit status 0 on success, 1 with the failed checks listed.
"""
import argparse
import pathlib
import re
import shutil
import subprocess
import sys

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)
    return ok


SCENE = """set Scene type = static contact
subsection Sole
  set Geometry file = {source}/meshes/sole_box.geo
  set Mesh size = 0.0272
  set Cell kind = {kind}
  set Element degree = 1
  set Materials = rubber: law=linear, E=4e6, nu=0.3
  set Mesh cache directory = {work}/mesh-cache
end
subsection Static contact
  set Foot translation = 0.0003, 0.0001, -0.001
  set Foot rotation = 0.004, 0.015, 0
  set Friction coefficient = 0.5
  set Refinements = 1
  set Tolerance = 1e-12
end
"""


def summary(directory):
    values = {}
    for line in (directory / "summary.csv").read_text().splitlines()[1:]:
        name, value = line.split(",")
        values[name] = float(value)
    return values


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--mpirun", required=True)
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    scene = work / "static_contact.prm"
    scene.write_text(SCENE.format(source=args.source, work=work, kind="hexahedron"))
    runs = {"serial": [args.plantar], "np1": args.mpirun.split() + ["-np", "1", args.plantar],
            "np2": args.mpirun.split() + ["-np", "2", args.plantar]}
    results = {}
    for name, command in runs.items():
        out = work / name
        done = subprocess.run(command + ["run", str(scene), "-o", str(out)], capture_output=True,
                              text=True, timeout=300)
        print(name, "exit", done.returncode, done.stdout, done.stderr)
        if not check(done.returncode == 0, f"{name}: exit status {done.returncode}"):
            continue
        for file in ("summary.csv", "summary.txt", "parameters.prm", "contact.pvtu"):
            check((out / file).is_file(), f"{name}: no {file}")
        ranks = 2 if name == "np2" else 1
        pieces = re.findall(r'<Piece Source="([^"]+)"', (out / "contact.pvtu").read_text())
        check(len(pieces) == ranks, f"{name}: contact.pvtu lists {len(pieces)} pieces, not {ranks}")
        for piece in pieces:
            check((out / piece).is_file(), f"{name}: piece {piece} missing")
        values = summary(out)
        check(values["ranks"] == ranks, f"{name}: summary says {values['ranks']} ranks")
        results[name] = values

    if len(results) == 3:
        reference = results["serial"]
        scale = abs(reference["ground_force_z"])
        for name in ("np1", "np2"):
            for key in ("dofs", "contact_nodes", "separated", "stick", "slip", "iterations"):
                check(results[name][key] == reference[key],
                      f"{name}: {key} = {results[name][key]}, serial {reference[key]}")
            for key in ("foot_force_x", "foot_force_y", "foot_force_z", "ground_force_x",
                        "ground_force_y", "ground_force_z"):
                check(abs(results[name][key] - reference[key]) <= 1e-9 * scale,
                      f"{name}: {key} = {results[name][key]}, serial {reference[key]}")
            for key in ("foot_moment_x", "foot_moment_y", "foot_moment_z"):
                check(abs(results[name][key] - reference[key]) <= 1e-9 * scale * 0.2,
                      f"{name}: {key} = {results[name][key]}, serial {reference[key]}")
        for name, values in results.items():
            for axis in "xyz":
                balance = values["foot_force_" + axis] + values["ground_force_" + axis]
                check(abs(balance) <= 1e-9 * scale, f"{name}: force balance {axis}: {balance} N")
            check(values["separated"] > 0 and values["stick"] > 0 and values["slip"] > 0,
                  f"{name}: separated/stick/slip = {values['separated']}/{values['stick']}/"
                  f"{values['slip']}, expected all > 0")
            check(values["residual"] <= 1e-12, f"{name}: residual {values['residual']}")
        print("ground force z: %.9f N, max pressure %.6g Pa, states %d/%d/%d" %
              (reference["ground_force_z"], reference["max_pressure"], reference["separated"],
               reference["stick"], reference["slip"]))

    # Force control: the serial run's force and moments as the load, from another start.
    if "serial" in results:
        reference = results["serial"]
        forced = work / "force.prm"
        forced.write_text(SCENE.format(source=args.source, work=work, kind="hexahedron") +
                          "subsection Static contact\n  set Control = force\n"
                          f"  set Normal force = {-reference['foot_force_z']!r}\n"
                          f"  set Moment x = {reference['foot_moment_x']!r}\n"
                          f"  set Moment y = {reference['foot_moment_y']!r}\n"
                          "  set Foot translation = 0.0003, 0.0001, -0.0002\n"
                          "  set Foot rotation = 0, 0, 0\n  set Load tolerance = 1e-10\nend\n")
        done = subprocess.run([args.plantar, "run", str(forced), "-o", str(work / "force")],
                              capture_output=True, text=True, timeout=300)
        print("force exit", done.returncode, done.stdout, done.stderr)
        if check(done.returncode == 0, f"force control: exit status {done.returncode}"):
            values = summary(work / "force")
            check(values["load_iterations"] > 0, "force control: no quasi-Newton iteration")
            for key, expected, scale in (("foot_translation_z", -0.001, 1e-3),
                                         ("foot_rotation_x", 0.004, 0.015),
                                         ("foot_rotation_y", 0.015, 0.015)):
                check(abs(values[key] - expected) <= 1e-6 * scale,
                      f"force control: {key} = {values[key]}, prescribed {expected}")
            check(abs(values["foot_force_z"] - reference["foot_force_z"]) <=
                  1e-9 * abs(reference["foot_force_z"]),
                  f"force control: foot_force_z = {values['foot_force_z']}")

    bad = work / "tetrahedra.prm"
    bad.write_text(SCENE.format(source=args.source, work=work, kind="tetrahedron"))
    done = subprocess.run(args.mpirun.split() + ["-np", "2", args.plantar, "run", str(bad), "-o",
                                                 str(work / "bad")],
                          capture_output=True, text=True, timeout=300)
    check(done.returncode == 1, f"tetrahedra: exit status {done.returncode}")
    check(done.stderr.count("plantar: error:") == 1,
          f"tetrahedra: {done.stderr.count('plantar: error:')} error messages:\n{done.stderr}")
    check("Sole/Cell kind" in done.stderr, f"tetrahedra: message {done.stderr!r}")
    check(not (work / "bad" / "summary.csv").exists(), "tetrahedra: summary.csv written")

    if failures:
        print(f"{len(failures)} failed checks")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
