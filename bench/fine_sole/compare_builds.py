#!/usr/bin/python3
"""The table of compare_builds.sh: OUT_DIR/{old,new}/<scene>/ from two plantar builds.

Per scene: loop time per simulated second (old, new, speed-up), contact solves taken by the
direct solve, mean solver iterations per solve, Gauss-Seidel sweeps after a refused direct
solve; for the walks, the largest relative differences of the new build's figures from the
old one's (filtered peak waist a_z, the landings' impulses and peak forces) and of the
centre-of-pressure path (every 10 ms where a foot carries over 50 N).
"""
import csv
import math
import sys


def summary(directory):
    return {row[0]: row[1] for row in csv.reader(open(directory + "/summary.csv"))}


def landings(directory):
    return list(csv.DictReader(open(directory + "/landings.csv")))


def cop(directory):
    frames = {}
    for row in csv.DictReader(open(directory + "/contacts.csv")):
        step = round(float(row["t"]) * 1e4)
        if step % 100 == 0:
            frames[step] = row
    return frames


def differences(old, new):
    key = "max_waist_acceleration_z_filtered"
    e_af = abs(float(summary(new)[key]) / float(summary(old)[key]) - 1)
    e_j = e_f = 0.0
    l_old, l_new = landings(old), landings(new)
    for foot in "01":
        for a, b in zip([r for r in l_old if r["foot"] == foot], [r for r in l_new if r["foot"] == foot]):
            e_j = max(e_j, abs(float(b["impulse"]) / float(a["impulse"]) - 1))
            e_f = max(e_f, abs(float(b["peak_force"]) / float(a["peak_force"]) - 1))
    c_old, c_new = cop(old), cop(new)
    e_cop = 0.0
    for step, a in c_old.items():
        b = c_new.get(step)
        for side in ("right_", "left_"):
            if b and float(a[side + "fz"]) > 50 and float(b[side + "fz"]) > 50:
                e_cop = max(e_cop, math.hypot(float(a[side + "copx"]) - float(b[side + "copx"]),
                                              float(a[side + "copy"]) - float(b[side + "copy"])))
    return "%.1e | %.1e | %.1e | %.1e" % (e_af, e_j, e_f, e_cop)


def main():
    out, scenes = sys.argv[1], sys.argv[2:]
    print("| scene | loop s per simulated s: old | new | speed-up | direct: old | new | "
          "mean iterations: old | new | sweeps after refusal: old | new | e_af | e_J | e_F | "
          "CoP (m) |")
    print("|" + "---|" * 15)
    for scene in scenes:
        old, new = out + "/old/" + scene, out + "/new/" + scene
        try:
            so, sn = summary(old), summary(new)
        except OSError:
            print("| %s | failed (see %s/%s.*.log) |" % (scene, out, scene))
            continue
        loop_old = float(so["loop_wall_time"]) / float(so["simulated_time"])
        loop_new = float(sn["loop_wall_time"]) / float(sn["simulated_time"])
        direct = [100.0 * int(s["n_direct_solves"]) / int(s["n_solves"]) for s in (so, sn)]
        figures = differences(old, new) if scene.startswith("walk") else "- | - | - | -"
        print("| %s | %.3g | %.3g | %.2f | %.1f %% | %.1f %% | %.2f | %.2f | %s | %s | %s |" %
              (scene, loop_old, loop_new, loop_old / loop_new, direct[0], direct[1],
               float(so["mean_solver_iterations"]), float(sn["mean_solver_iterations"]),
               so["iterations_after_refusal"], sn["iterations_after_refusal"], figures))


if __name__ == "__main__":
    main()
