#!/usr/bin/python3
"""Convergence tables of the walk's impact figures (issue 23) from `plantar sweep` outputs.

Usage: table.py [--landings-from T] SWEEP_DIR [SWEEP_DIR ...]   (prints Markdown tables)

Per foot form (and per general axis value besides the one refined), the figures against the
refined parameter (time step, or Sole/Mesh size), finest last:
  a_f   peak filtered waist |a_z| over the run (summary max_waist_acceleration_z_filtered)
  F_max largest landing peak vertical force (summary max_landing_peak_force)
  F_med median landing peak force over the step landings (landings.csv, t >= t_step)
  J_med median landing impulse over the step landings (first 50 ms)
  E_d   energy dissipated by the soles over the run (summary sole_dissipated_energy; only in
        sweeps where a sole dissipates)
The step landings are those from T = 1.6 s on (the first lift-off of scenes/walk.prm; a drop
scene: --landings-from 0).
Over the finest unbroken run of finished points, for each figure f_1, f_2, ... (coarse to fine, refinement ratio r between neighbours), the
difference to the next d_k = f_k - f_(k+1) and the observed order p_k = log(d_k / d_(k+1)) /
log(r) (only where d_k and d_(k+1) have the same sign); the error estimate of the finest value
is |d_last| / (r^p - 1) with the last observed order (|d_last| when no order is observed).
"""
import csv
import math
import os
import statistics
import sys

T_STEP = 1.6  # s: the first lift-off of scenes/walk.prm; earlier landings are the settling
if len(sys.argv) > 2 and sys.argv[1] == "--landings-from":
    T_STEP = float(sys.argv[2])
    del sys.argv[1:3]


def landings(directory):
    path = os.path.join(directory, "landings.csv")
    rows = []
    if not os.path.exists(path):
        return rows
    with open(path) as f:
        for r in csv.DictReader(f):
            if float(r["t"]) >= T_STEP:
                rows.append(r)
    return rows


def summary(directory):
    values = {}
    path = os.path.join(directory, "summary.csv")
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                key, _, value = line.strip().partition(",")
                values[key] = value
    return values


def figures(sweep_dir, row):
    point = os.path.join(sweep_dir, "points", row["id"])
    s = summary(point)
    if row["status"] != "ok":
        failure = os.path.join(point, "failure.txt")
        text = open(failure).readline().strip() if os.path.exists(failure) else row["status"]
        return None, text
    land = landings(point)
    peaks = [float(r["peak_force"]) for r in land]
    impulses = [float(r["impulse"]) for r in land]
    return {
        "a_f": float(s["max_waist_acceleration_z_filtered"]),
        "F_max": float(s["max_landing_peak_force"]),
        "F_med": statistics.median(peaks) if peaks else math.nan,
        "J_med": statistics.median(impulses) if impulses else math.nan,
        "n": len(land),
        "loop": float(s["loop_wall_time"]),
        "E_d": float(s.get("sole_dissipated_energy", "0") or 0),
    }, ""


def observed_order(h, f):
    """p with (f0 - f1) / (f1 - f2) = (h0^p - h1^p) / (h1^p - h2^p) (bisection on [0.05, 10]);
    nan when the differences change sign or no p fits."""
    d0, d1 = f[0] - f[1], f[1] - f[2]
    if d1 == 0 or d0 / d1 <= 0:
        return math.nan
    target = d0 / d1
    g = lambda p: (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p) - target
    lo, hi = 0.05, 10.0
    if g(lo) * g(hi) > 0:
        return math.nan
    for _ in range(100):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if g(lo) * g(mid) > 0 else (lo, mid)
    return (lo + hi) / 2


def orders(h, values):
    """Observed orders of each three consecutive values and the error estimate of the finest
    value: |f_n-1 - f_n| h_n^p / (h_n-1^p - h_n^p) with the order p of the finest three
    (|f_n-1 - f_n| when none is observed there)."""
    p = [observed_order(h[k:k + 3], values[k:k + 3]) for k in range(len(values) - 2)]
    last = p[-1] if p else math.nan
    d = abs(values[-2] - values[-1])
    if math.isfinite(last):
        return p, d * h[-1] ** last / (h[-2] ** last - h[-1] ** last)
    return p, d


def table(sweep_dir):
    with open(os.path.join(sweep_dir, "sweep.csv")) as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0].keys())
    axes = header[header.index("max_landing_acceleration_z") + 1:]
    refined = "time_step"
    if len({r["time_step"] for r in rows}) == 1 and "Sole/Mesh size" in axes:
        refined = "Sole/Mesh size"
    others = [a for a in axes if a != refined]
    groups = {}
    for r in rows:
        key = (r["foot_form"],) + tuple(r[a] for a in others)
        groups.setdefault(key, []).append(r)
    names = ["a_f", "F_max", "F_med", "J_med"]
    units = {"a_f": "m/s^2", "F_max": "N", "F_med": "N", "J_med": "N s", "E_d": "J"}
    if any(float(r.get("sole_dissipated_energy") or 0) > 0 for r in rows):
        names.append("E_d")
    print(f"### {os.path.basename(os.path.normpath(sweep_dir))}: refined {refined}\n")
    for key, group in groups.items():
        group.sort(key=lambda r: -float(r[refined]))
        label = ", ".join([key[0]] + [f"{a} = {v}" for a, v in zip(others, key[1:])])
        print(f"{label}:\n")
        print(f"| {refined} | landings | " + " | ".join(f"{n} ({units[n]})" for n in names) +
              " | loop (s) | note |")
        print("|---" * (len(names) + 4) + "|")
        series = {n: [] for n in names}
        hs = []
        failed_since_last = False
        for r in group:
            f, failure = figures(sweep_dir, r)
            if f is None:
                failed_since_last = True
                print(f"| {float(r[refined]):g} | - | " + " | ".join("-" for _ in names) +
                      f" | - | {failure} |")
                continue
            if failed_since_last:  # orders only over the finest unbroken run of points
                hs.clear()
                for n in names:
                    series[n].clear()
                failed_since_last = False
            hs.append(float(r[refined]))
            for n in names:
                series[n].append(f[n])
            print(f"| {float(r[refined]):g} | {f['n']} | " + " | ".join(f"{f[n]:.4g}" for n in names) +
                  f" | {f['loop']:.1f} | |")
        if len(hs) >= 3:
            cells_p, cells_e = [], []
            for n in names:
                p, e = orders(hs, series[n])
                cells_p.append(", ".join("-" if not math.isfinite(x) else f"{x:.2f}" for x in p))
                finest = series[n][-1]
                cells_e.append(f"{e:.3g} ({100 * e / abs(finest):.1f} %)" if finest else "-")
            print("| observed orders | | " + " | ".join(cells_p) + " | | |")
            print("| error of the finest | | " + " | ".join(cells_e) + " | | |")
        print()


for d in sys.argv[1:]:
    table(d)
