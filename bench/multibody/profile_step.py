#!/usr/bin/python3
"""Where the time step of a humanoid scene goes: instruction counts by valgrind's callgrind.

    bench/multibody/profile_step.py PLANTAR [OUT_DIR] [--scenes stand,walk] [--duration S]

Runs `PLANTAR run scenes/<scene>.prm` (Simulation/Duration = S, default stand 1 s, walk 2.5 s:
the standing second and the first step) under callgrind, counting only inside
HumanoidSimulation::step (the time loop, outputs included; setup excluded), and prints each
phase's share of the loop's instructions (inclusive counts of the functions named below).
Instruction counts do not depend on the machine's load; they are not times (a cache miss or a
vectorised loop costs differently), so read them next to the timings of mujoco_compare.py.
"""
import argparse
import pathlib
import re
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]

# (label, [function name prefixes, the first found is used]); inclusive counts.
PHASES = [
    ("contact solve (contact::ContactSolver)", [["plantar::contact::ContactSolver::solve("]]),
    ("RNEA (bias forces)", [["plantar::multibody::nonlinear_effects("]]),
    ("CRBA", [["plantar::multibody::crba_from_placements("]]),
    ("factorization of M_eff", [["plantar::multibody::TreeFactorization::compute("],
                                ["plantar::multibody::Stepper::factor_effective_mass("]]),
    ("solves (M_eff^-1 r, U^-1 J_b^T, U^-T)",
     [["plantar::multibody::TreeFactorization::half_solve_in_place(",
       "plantar::multibody::TreeFactorization::half_solve_transpose_in_place("],
      ["plantar::multibody::Stepper::half_solve(", "plantar::multibody::Stepper::half_solve_transpose("]]),
    ("reduced rigid factor (Z Z^T = H H^T)", [["plantar::multibody::Stepper::reduce_rigid_factor("]]),
    ("contact Jacobians", [["plantar::multibody::body_origin_jacobian("]]),
    ("ParaView frames (Output/VTK every)", [["plantar::app::SceneVtkWriter::write("]]),
    ("reference q_ref(t)", [["plantar::app::HumanoidSimulation::reference_at("]]),
    ("kinematics for the reports", [["plantar::multibody::forward_kinematics("]]),
]


def inclusive_counts(callgrind_file):
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", str(callgrind_file)],
                          check=True, capture_output=True, text=True).stdout
    counts = {}
    for line in text.splitlines():
        match = re.match(r"\s*([\d,]+)\s+\([\s\d.]+%\)\s+\S*?:(.*) \[", line)
        if match:
            name = match.group(2)
            counts[name] = max(counts.get(name, 0), int(match.group(1).replace(",", "")))
    return counts


def find(counts, prefix):
    return sum(v for k, v in counts.items() if k.startswith(prefix))


def profile(plantar, scene, duration, out):
    prm = out / f"{scene}_profile.prm"
    prm.write_text(f"include {ROOT / 'scenes' / (scene + '.prm')}\nsubsection Simulation\n"
                   f"  set Duration = {duration:g}\nend\n")
    data = out / f"{scene}.callgrind"
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={data}",
                    "--toggle-collect=plantar::app::HumanoidSimulation::step()", str(plantar), "run",
                    str(prm), "-o", str(out / f"{scene}_run"), "--no-figures"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    counts = inclusive_counts(data)
    total = find(counts, "plantar::app::HumanoidSimulation::step(")
    stepper = find(counts, "plantar::multibody::Stepper::step(")
    n_steps = round(duration / 1e-3)
    rows, inside = [], 0
    for label, alternatives in PHASES:
        value = 0
        for names in alternatives:
            value = sum(find(counts, name) for name in names)
            if value:
                break
        rows.append((label, value))
        if "ParaView" not in label and "reference" not in label and "reports" not in label:
            inside += value
    rows.insert(7, ("rest of the stepper (assembly, candidates, v+, q+)", stepper - inside))
    accounted = sum(v for _, v in rows)
    rows.append(("rest of the scene step (reports, summary, CSV rows)", total - accounted))
    return total, n_steps, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("plantar", type=pathlib.Path)
    parser.add_argument("out", type=pathlib.Path, nargs="?", default=pathlib.Path("profile_step"))
    parser.add_argument("--scenes", default="stand,walk")
    parser.add_argument("--duration", type=float, default=0, help="s (0: stand 1, walk 2.5)")
    args = parser.parse_args()
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for scene in args.scenes.split(","):
        duration = args.duration or {"walk": 2.5}.get(scene, 1.0)
        results[scene] = profile(args.plantar.resolve(), scene, duration, out)
    scenes = list(results)
    lines = ["| phase | " + " | ".join(f"{s} (%)" for s in scenes) + " |",
             "| --- |" + " --- |" * len(scenes)]
    for i, (label, _) in enumerate(results[scenes[0]][2]):
        lines.append(f"| {label} | " + " | ".join(f"{100 * results[s][2][i][1] / results[s][0]:.1f}"
                                                  for s in scenes) + " |")
    lines.append("| instructions per step (thousands) | " +
                 " | ".join(f"{results[s][0] / results[s][1] / 1e3:.0f}" for s in scenes) + " |")
    text = "\n".join(lines) + "\n"
    (out / "profile_step.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
