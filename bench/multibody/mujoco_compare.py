#!/usr/bin/python3
"""The rigid robot in Plantar and in MuJoCo, side by side (issue 25).

    bench/multibody/mujoco_compare.py BUILD_DIR [OUT_DIR] [--repeat R] [--core C]
                                      [--scenes stand,walk] [--walk-tolerance 1e-4]

For each scene (scenes/stand.prm, scenes/walk.prm; Robot/Foot form = rigid): one `plantar run`
gives the joint references (joints.csv); the MuJoCo model is generated from the scene's URDF
(same bodies, masses, inertias and joint axes; the fixed sole frames merged as sites) with
  - the scene's contact points (apps/rigid_foot.cc: the sole outline's 4 corners and 4 edge
    midpoints per foot, Sole/Length x Sole/Width) as spheres of radius 2 mm whose lowest point
    is the Plantar point ("points"), or one box per sole of the same outline ("box", MuJoCo's
    box-plane contact: up to 4 corners per foot);
  - Contact/Friction coefficient, elliptic cone, Newton solver, Simulation/Time step, Euler;
  - the PD of Control (kp, kd) on every controlled joint as Plantar integrates it (linear-
    implicit, theta = 1: kp (q_ref - q+) + kd (v_ref - v+)): a position servo kp with joint
    damping kd + dt kp (MuJoCo's Euler applies joint damping at v+) driven by
    ctrl = q_ref + kd/kp v_ref.
Then R rounds, each running Plantar (the scene as it is, with its ParaView frames every
Output/VTK every steps and the .pvd collections rewritten at each frame), Plantar with the
collections rewritten every 25 frames (Output/VTK collection every = 25), Plantar without
ParaView frames (Output/Write VTU = false: the outputs MuJoCo's run has), the same without the
direct solve on the warm start's active set (Contact/Sticking direct solve = false: the
iterative solver alone), MuJoCo (points) and
MuJoCo (box) one after the other, pinned to core C (taskset). Plantar's time is its summary's loop_wall_time / n_steps (the whole step: reference,
stepper, CSV rows into memory, ParaView frames); MuJoCo's is its loop (mj_step and the same
per-step records into memory); CSV files are written after both loops.
Prints a markdown table (median and [min, max] us per step) and the physical agreement: the
contact force sum against the weight and the CoM and base heights, averaged over the last
0.5 s; writes OUT_DIR/mujoco_compare.md and the generated models OUT_DIR/<scene>_<contacts>.xml.
"""
import argparse
import math
import os
import pathlib
import statistics
import subprocess
import sys
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]


def read_prm(path, values=None, section=()):
    """deal.II parameter file -> {"Subsection/Name": "value"} (include and subsections)."""
    values = {} if values is None else values
    stack = list(section)
    for raw in pathlib.Path(path).read_text().splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("include "):
            included = pathlib.Path(line.split(None, 1)[1])
            read_prm(included if included.is_absolute() else ROOT / included, values, stack)
        elif line.startswith("subsection "):
            stack.append(line.split(None, 1)[1].strip())
        elif line == "end":
            stack.pop()
        elif line.startswith("set "):
            name, value = line[4:].split("=", 1)
            values["/".join(stack + [name.strip()])] = value.strip()
    return values


def rpy_quaternion(rpy):
    """URDF rpy (fixed axes x, y, z) -> MuJoCo quaternion (w, x, y, z)."""
    r, p, y = (0.5 * float(a) for a in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)


def rotation_matrix(quaternion):
    w, x, y, z = quaternion
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def fmt(values):
    return " ".join(f"{v:.10g}" for v in values)


def origin_of(element):
    origin = element.find("origin") if element is not None else None
    xyz = origin.get("xyz", "0 0 0").split() if origin is not None else ["0"] * 3
    rpy = origin.get("rpy", "0 0 0").split() if origin is not None else ["0"] * 3
    return [float(v) for v in xyz], rpy


def generate_mjcf(prm, contacts):
    """The MJCF text of the scene's robot on a ground plane; contacts "points" or "box"."""
    if prm.get("Robot/Foot form", "rigid") != "rigid":
        raise SystemExit("mujoco_compare: Robot/Foot form = %s, allowed: rigid" % prm["Robot/Foot form"])
    urdf_path = ROOT / prm["Robot/URDF file"]
    urdf = ET.parse(urdf_path).getroot()
    links = {link.get("name"): link for link in urdf.findall("link")}
    children = {}
    for joint in urdf.findall("joint"):
        children.setdefault(joint.find("parent").get("link"), []).append(joint)
    base = prm["Robot/Base link"]
    controlled = [j.strip() for j in prm["Robot/Controlled joints"].split(",")]
    kp, kd = float(prm["Control/Joint stiffness"]), float(prm["Control/Joint damping"])
    mu = float(prm["Contact/Friction coefficient"])
    dt = float(prm["Simulation/Time step"])
    length, width = float(prm["Sole/Length"]), float(prm["Sole/Width"])
    soles = {prm["Robot/Right sole frame"], prm["Robot/Left sole frame"]}
    radius = 0.002
    a, b = length / 2, width / 2
    outline = [(a, -b), (a, 0), (a, b), (0, b), (-a, b), (-a, 0), (-a, -b), (0, -b)]

    out = []

    def inertial(link, indent):
        element = link.find("inertial")
        if element is None:
            return
        xyz, rpy = origin_of(element)
        i = element.find("inertia")
        c = {k: float(i.get(k, "0")) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        tensor = [[c["ixx"], c["ixy"], c["ixz"]], [c["ixy"], c["iyy"], c["iyz"]], [c["ixz"], c["iyz"], c["izz"]]]
        r = rotation_matrix(rpy_quaternion(rpy))  # the inertia in the link frame: R I R^T
        t = [[sum(r[a][k] * tensor[k][l] * r[b][l] for k in range(3) for l in range(3)) for b in range(3)]
             for a in range(3)]
        full = (t[0][0], t[1][1], t[2][2], t[0][1], t[0][2], t[1][2])
        out.append(f'{indent}<inertial pos="{fmt(xyz)}" mass="{element.find("mass").get("value")}" '
                   f'fullinertia="{fmt(full)}"/>')

    def sole_geoms(xyz, quat, indent):
        # The sole frame's contact geometry in its parent body (the frame: xyz, quat, no rotation
        # assumed beyond identity: the URDF's sole frames are axis-aligned).
        if any(abs(q - e) > 1e-12 for q, e in zip(quat, (1, 0, 0, 0))):
            raise SystemExit("mujoco_compare: a rotated sole frame is not supported")
        if contacts == "points":
            for x, y in outline:
                p = (xyz[0] + x, xyz[1] + y, xyz[2] + radius)
                out.append(f'{indent}<geom type="sphere" size="{radius}" pos="{fmt(p)}" class="foot"/>')
        else:
            p = (xyz[0], xyz[1], xyz[2] + 0.005)
            out.append(f'{indent}<geom type="box" size="{fmt((a, b, 0.005))}" pos="{fmt(p)}" class="foot"/>')

    def body(link_name, joint, indent):
        link = links[link_name]
        if joint is None:
            out.append(f'{indent}<body name="{link_name}" pos="0 0 1">')
            out.append(f'{indent}  <freejoint name="base"/>')
        else:
            xyz, rpy = origin_of(joint)
            out.append(f'{indent}<body name="{link_name}" pos="{fmt(xyz)}" quat="{fmt(rpy_quaternion(rpy))}">')
            kind = joint.get("type")
            if kind not in ("revolute", "continuous"):
                raise SystemExit(f"mujoco_compare: joint {joint.get('name')} of type {kind}")
            axis = joint.find("axis").get("xyz")
            damping = f' damping="{kd + dt * kp:.10g}"' if joint.get("name") in controlled else ""
            out.append(f'{indent}  <joint name="{joint.get("name")}" axis="{axis}"{damping}/>')
        inertial(link, indent + "  ")
        for child in children.get(link_name, []):
            if child.get("type") == "fixed":
                xyz, rpy = origin_of(child)
                name = child.find("child").get("link")
                if links[name].find("inertial") is not None:
                    raise SystemExit(f"mujoco_compare: fixed link {name} with an inertia")
                quat = rpy_quaternion(rpy)
                out.append(f'{indent}  <site name="{name}" pos="{fmt(xyz)}" quat="{fmt(quat)}"/>')
                if name in soles:
                    sole_geoms(xyz, quat, indent + "  ")
            else:
                body(child.find("child").get("link"), child, indent + "  ")
        out.append(f"{indent}</body>")

    out.append(f'<mujoco model="{urdf.get("name")} ({contacts})">')
    out.append(f"  <!-- GENERATED by bench/multibody/mujoco_compare.py from {urdf_path.relative_to(ROOT)} -->")
    out.append('  <compiler angle="radian" inertiafromgeom="false" boundmass="0" boundinertia="0"/>')
    out.append(f'  <option timestep="{dt}" gravity="0 0 -9.81" integrator="Euler" cone="elliptic" '
               'solver="Newton"/>')
    out.append("  <default>")
    out.append('    <joint limited="false" armature="0" damping="0"/>')
    out.append(f'    <geom contype="1" conaffinity="0" condim="3" friction="{mu} 0 0"/>')
    out.append('    <default class="foot"><geom contype="1" conaffinity="0"/></default>')
    out.append("  </default>")
    out.append("  <worldbody>")
    out.append(f'    <geom name="ground" type="plane" size="0 0 1" contype="0" conaffinity="1" friction="{mu} 0 0"/>')
    body(base, None, "    ")
    out.append("  </worldbody>")
    out.append("  <actuator>")
    for name in controlled:
        out.append(f'    <position name="{name}" joint="{name}" kp="{kp}" ctrllimited="false"/>')
    out.append("  </actuator>")
    out.append("</mujoco>")
    return "\n".join(out) + "\n"


def read_table(path):
    lines = pathlib.Path(path).read_text().splitlines()
    names = lines[0].split(",")
    return [dict(zip(names, map(float, line.split(",")))) for line in lines[1:]]


def read_summary(path):
    return {k: v for k, v in (line.split(",", 1) for line in pathlib.Path(path).read_text().splitlines()[1:])}


def last_mean(rows, key, seconds, dt):
    window = rows[-max(1, round(seconds / dt)):]
    return sum(r[key] for r in window) / len(window)


def run_plantar(plantar, scene, out_dir, core):
    subprocess.run(["taskset", "-c", str(core), str(plantar), "run", str(scene),
                    "-o", str(out_dir), "--no-figures"], check=True, stdout=subprocess.DEVNULL)
    summary = read_summary(out_dir / "summary.csv")
    return 1e6 * float(summary["loop_wall_time"]) / float(summary["n_steps"])


def run_mujoco(build, model, plantar_dir, out_csv, core, fall_height):
    result = subprocess.run(["taskset", "-c", str(core), str(build / "bench" / "multibody" / "mujoco_bench"),
                             str(model), str(plantar_dir / "joints.csv"), str(plantar_dir / "waist.csv"),
                             str(out_csv), "--fall-height", str(fall_height)],
                            check=True, capture_output=True, text=True)
    return {k: float(v) for k, v in (line.split(",") for line in result.stdout.split())}


def fall(figures):
    return "-" if figures["fall_time"] < 0 else f"{figures['fall_time']:.2f}"


def spread(values):
    return f"{statistics.median(values):.1f} [{min(values):.1f}, {max(values):.1f}]"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build", type=pathlib.Path)
    parser.add_argument("out", type=pathlib.Path, nargs="?", default=pathlib.Path("mujoco_compare"))
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--core", type=int, default=1)
    parser.add_argument("--scenes", default="stand,walk")
    parser.add_argument("--walk-tolerance", type=float, default=1e-4,
                        help="also the walk at this Contact/Tolerance (0: not)")
    parser.add_argument("--plantar-reference", type=pathlib.Path,
                        help="another plantar program (e.g. an earlier build) run in each round too")
    args = parser.parse_args()
    build = args.build.resolve()
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    for needed in (build / "apps" / "plantar", build / "bench" / "multibody" / "mujoco_bench"):
        if not needed.exists():
            raise SystemExit(f"mujoco_compare: {needed} not found (build the targets plantar and "
                             "mujoco_bench; mujoco_bench needs libmujoco-dev)")
    cases = []  # (label, scene file, prm)
    for name in args.scenes.split(","):
        scene = ROOT / "scenes" / f"{name}.prm"
        cases.append((name, scene, read_prm(scene)))
        if name == "walk" and args.walk_tolerance > 0:
            variant = out / f"walk_tolerance_{args.walk_tolerance:g}.prm"
            variant.write_text(f"include {scene}\nsubsection Contact\n  set Tolerance = "
                               f"{args.walk_tolerance:g}\nend\n")
            cases.append((f"walk, tolerance {args.walk_tolerance:g}", variant, read_prm(variant)))
    rows = []
    for label, scene, prm in cases:
        tag = label.replace(", ", "_").replace(" ", "_")
        models = {}
        for contacts in ("points", "box"):
            models[contacts] = out / f"{tag}_{contacts}.xml"
            models[contacts].write_text(generate_mjcf(prm, contacts))
        times = {"plantar": [], "plantar_pvd25": [], "plantar_no_vtk": [], "plantar_iterative": [],
                 "points": [], "box": [],
                 "reference": [],
                 "points_upright": [], "box_upright": []}
        figures = {}
        plantar_dir = out / f"{tag}_plantar"
        no_vtk = out / f"{tag}_no_vtk.prm"
        no_vtk.write_text(f"include {scene}\nsubsection Output\n  set Write VTU = false\nend\n")
        iterative = out / f"{tag}_iterative.prm"
        iterative.write_text(f"include {no_vtk}\nsubsection Contact\n  set Sticking direct solve = false\n"
                             "end\n")
        pvd25 = out / f"{tag}_pvd25.prm"
        pvd25.write_text(f"include {scene}\nsubsection Output\n  set VTK collection every = 25\nend\n")
        for _ in range(args.repeat):
            plantar = build / "apps" / "plantar"
            times["plantar"].append(run_plantar(plantar, scene, plantar_dir, args.core))
            times["plantar_pvd25"].append(run_plantar(plantar, pvd25, out / f"{tag}_plantar_pvd25", args.core))
            times["plantar_no_vtk"].append(run_plantar(plantar, no_vtk, out / f"{tag}_plantar_no_vtk", args.core))
            times["plantar_iterative"].append(run_plantar(plantar, iterative, out / f"{tag}_plantar_iterative",
                                                          args.core))
            if args.plantar_reference:
                times["reference"].append(run_plantar(args.plantar_reference.resolve(), scene,
                                                      out / f"{tag}_plantar_reference", args.core))
            for contacts, model in models.items():
                result = run_mujoco(build, model, plantar_dir, out / f"{tag}_{contacts}.csv", args.core,
                                    float(prm["Simulation/Fall height"]))
                times[contacts].append(result["us_per_step"])
                times[contacts + "_upright"].append(result["us_per_step_upright"])
                figures[contacts] = result
        dt = float(prm["Simulation/Time step"])
        contacts_rows = read_table(plantar_dir / "contacts.csv")
        waist_rows = read_table(plantar_dir / "waist.csv")
        weight = figures["points"]["weight"]
        rows.append({
            "label": label, "times": times, "weight": weight,
            "plantar_fz": last_mean(contacts_rows, "right_fz", 0.5, dt) + last_mean(contacts_rows, "left_fz", 0.5, dt),
            "plantar_base_z": last_mean(waist_rows, "z", 0.5, dt),
            "plantar_com_z": figures["points"]["plantar_final_com_z"],
            "plantar_contacts": last_mean(contacts_rows, "n_contacts", 0.5, dt),
            "mujoco": figures,
        })
        print(f"{label}: done", file=sys.stderr)

    text = []
    reference = " | Plantar, --plantar-reference" if args.plantar_reference else ""
    text.append("| scene | Plantar, 16 points | Plantar, .pvd every 25 frames | Plantar, no ParaView "
                "frames | Plantar, no frames, no direct solve | MuJoCo, 16 points | MuJoCo, box "
                f"feet{reference} |")
    text.append("| --- | --- | --- | --- | --- | --- | --- |" + (" --- |" if reference else ""))
    for r in rows:
        t = r["times"]
        text.append(f"| {r['label']} | {spread(t['plantar'])} | {spread(t['plantar_pvd25'])} | "
                    f"{spread(t['plantar_no_vtk'])} | {spread(t['plantar_iterative'])} | "
                    f"{spread(t['points'])} | {spread(t['box'])} |" +
                    (f" {spread(t['reference'])} |" if reference else ""))
    text.append("")
    text.append("us per step, median [min, max] of %d alternating runs on core %d." % (args.repeat, args.core))
    for r in rows:
        p, bx = r["mujoco"]["points"], r["mujoco"]["box"]
        if p["fall_time"] >= 0 or bx["fall_time"] >= 0:
            text.append(f"{r['label']}: MuJoCo's robot falls (below Simulation/Fall height) at "
                        f"{fall(p)} s (points) / {fall(bx)} s (box); before the fall "
                        f"{spread(r['times']['points_upright'])} / {spread(r['times']['box_upright'])} us per step.")
    text.append("")
    text.append("| scene | weight (N) | contact force z (N): Plantar / MuJoCo points / box | "
                "CoM height (m): Plantar / points / box | base height (m): Plantar / points / box | "
                "contacts: Plantar / points / box | MuJoCo falls at (s): points / box |")
    text.append("| --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        p, bx = r["mujoco"]["points"], r["mujoco"]["box"]
        text.append(f"| {r['label']} | {r['weight']:.2f} | {r['plantar_fz']:.2f} / {p['contact_fz']:.2f} / "
                    f"{bx['contact_fz']:.2f} | {r['plantar_com_z']:.4f} / {p['com_z']:.4f} / {bx['com_z']:.4f} | "
                    f"{r['plantar_base_z']:.4f} / {p['base_z']:.4f} / {bx['base_z']:.4f} | "
                    f"{r['plantar_contacts']:.1f} / {p['mean_contacts']:.1f} / {bx['mean_contacts']:.1f} | "
                    f"{fall(p)} / {fall(bx)} |")
    text.append("")
    text.append("Averages over the last 0.5 s (Plantar's CoM: its last step, by MuJoCo's kinematics); "
                "Plantar's run stops with an error if the robot falls (Simulation/Fall height), "
                "MuJoCo's goes on (its time per step then covers fewer contacts).")
    load = os.getloadavg()
    text.append(f"Load average before the table was printed: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}.")
    report = "\n".join(text) + "\n"
    (out / "mujoco_compare.md").write_text(report)
    print(report)


if __name__ == "__main__":
    main()
