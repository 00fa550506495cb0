#!/usr/bin/python3
"""Plots of bench/work_precision: error against wall time per simulated second, one curve per
knob, one figure per scene and error measure. Usage: plot.py DIR (reads DIR/work_precision.csv,
writes DIR/<scene>_work_precision.png)."""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

directory = sys.argv[1] if len(sys.argv) > 1 else "work_precision"
rows = list(csv.DictReader(open(f"{directory}/work_precision.csv")))
errors = [("e_a", "waist |a_z| peak"), ("e_u", "max sole deformation"),
          ("e_p", "contact impulse per 4 ms window")]
for scene in sorted({r["scene"] for r in rows}):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    rigid = [r for r in rows if r["scene"] == scene and r["knob"] == "rigid feet"]
    for ax, (key, title) in zip(axes, errors):
        for knob in ["mesh size", "degree", "time step", "damped theta 1/2 dt", "tolerance",
                     "sole model", "hyperelastic tol"]:
            pts = []
            for r in rows:
                if r["scene"] != scene or r["knob"] != knob or r["status"] != "ok":
                    continue
                if r["reference"] == "1":
                    continue  # zero error by definition
                e = float(r[key])
                if math.isfinite(e):
                    pts.append((float(r["cpu_per_sim_s"]), max(e, 1e-16), r["value"]))
            if not pts:
                continue
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=knob)
            for x, y, label in pts:
                ax.annotate(label, (x, y), fontsize=6, xytext=(2, 2), textcoords="offset points")
        for r in rigid:
            if r["status"] == "ok":
                ax.axvline(float(r["cpu_per_sim_s"]), color="gray", ls=":", label="rigid feet cost")
        ax.axvline(0.1, color="red", ls="--", lw=0.8, label="10x real time")
        ax.axhline(0.02, color="black", ls="--", lw=0.8, label="2 %")
        ax.set_xlabel("CPU s per simulated s (one core, min of repeats)")
        ax.set_ylabel("relative error vs the knob's finest run")
        ax.set_title(f"{scene}: {title}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{directory}/{scene}_work_precision.png", dpi=110)
    print(f"{directory}/{scene}_work_precision.png")
