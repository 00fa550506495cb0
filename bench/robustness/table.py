#!/usr/bin/python3
"""The robustness matrix's tables (issue 23) from `plantar sweep` outputs.

Usage: table.py SWEEP_DIR [SWEEP_DIR ...]   (prints Markdown)

One row per point: its setting (foot form, dt, E, nu, general axes), the outcome (completes, or
the first line of failure.txt: the fall's or the numerical failure's time and cause) and the
figures of summary.csv: peak filtered waist |a_z|, largest landing peak force, largest waist
height error against the reference, the balance figures (the stance foot's smallest CoP margin
to its sole's edge in single support, the largest true DCM error; "-" in outputs without them),
unconverged contact solves, validity warnings, loop time.
"""
import csv
import os
import sys


def summary(directory):
    values = {}
    path = os.path.join(directory, "summary.csv")
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                key, _, value = line.strip().partition(",")
                values[key] = value
    return values


def cell(text):
    """A setting's value as written short: numbers with %g."""
    try:
        return format(float(text), "g")
    except ValueError:
        return text


def millimetres(s, key):
    """summary value @p key in mm, or '-' when absent or not finite."""
    try:
        value = float(s[key])
    except (KeyError, ValueError):
        return "-"
    return f"{1e3 * value:.1f}" if abs(value) < float("inf") and value == value else "-"


def table(sweep_dir):
    with open(os.path.join(sweep_dir, "sweep.csv")) as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0].keys())
    axes = header[header.index("max_landing_acceleration_z") + 1:]
    setting = ["foot_form", "time_step"] + [c for c in ("E", "nu") if any(r[c] for r in rows)]
    setting += axes
    print(f"### {os.path.basename(os.path.normpath(sweep_dir))}\n")
    print("| " + " | ".join(setting) + " | outcome | peak a_z filtered (m/s^2) | max landing "
          "F_z (N) | max waist height error (mm) | single-support CoP margin (mm) | max DCM "
          "error (mm) | unconverged solves | validity warnings | loop (s) |")
    print("|---" * (len(setting) + 9) + "|")
    completed = 0
    for r in rows:
        point = os.path.join(sweep_dir, "points", r["id"])
        cells = [cell(r[c]) for c in setting]
        s = summary(point)
        if r["status"] == "ok":
            completed += 1
            cells += ["completes", f"{float(s['max_waist_acceleration_z_filtered']):.3g}",
                      f"{float(s['max_landing_peak_force']):.4g}",
                      f"{1e3 * float(s['max_waist_height_error']):.2f}",
                      millimetres(s, "min_single_support_margin"),
                      millimetres(s, "max_true_dcm_error"), s["n_unconverged"],
                      s["n_validity_warnings"], f"{float(s['loop_wall_time']):.1f}"]
        else:
            failure = os.path.join(point, "failure.txt")
            text = open(failure).readline().strip() if os.path.exists(failure) else r["status"]
            cells += [text.replace("|", "/")] + ["-"] * 8
        print("| " + " | ".join(cells) + " |")
    print(f"\n{completed} of {len(rows)} complete.\n")


for d in sys.argv[1:]:
    table(d)
