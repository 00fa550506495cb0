#!/usr/bin/python3
"""Runs fc3d_bench on the shared Siconos-format problems and writes a markdown table and a
Dolan-More performance profile (fraction of problems each solver solves within a factor tau of
the best time; a failure counts as never solved).

    /usr/bin/python3 bench/contact/fc3d_profile.py [--bench build/bench/contact/fc3d_bench]
        [--data ../shared/data/fc3d] [--table out.md] [--plot docs/images/fc3d_profile.png]
    [--from-raw]
"""
import argparse
import glob
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--bench", default=os.path.join(root, "build/bench/contact/fc3d_bench"))
parser.add_argument("--data", default=os.path.join(root, "../shared/data/fc3d"))
parser.add_argument("--table", default=os.path.join(root, "build/fc3d_table.md"))
parser.add_argument("--plot", default=os.path.join(root, "docs/images/fc3d_profile.png"))
parser.add_argument("--raw", default=os.path.join(root, "build/fc3d_bench.txt"))
parser.add_argument("--from-raw", action="store_true",
                    help="re-plot the output of an earlier run (--raw) without running the bench")
args = parser.parse_args()

files = sorted(glob.glob(os.path.join(args.data, "*.dat")))
if not files:
    sys.exit("no .dat file in " + args.data)
rows = []  # (problem, n, solver, iterations, seconds, error, status, note)
if not args.from_raw:
    with open(args.raw, "w") as raw:
        for path in files:  # one process per file: a crash loses one problem, not all
            out = subprocess.run([args.bench, path], capture_output=True, text=True,
                                 check=True).stdout
            raw.write(out)
for line in open(args.raw):
    f = line.split(None, 7)
    if not f or f[0] == "problem":
        continue
    rows.append((f[0], int(f[1]), f[2], int(f[3]), float(f[4]), float(f[5]), f[6],
                 f[7].strip() if len(f) > 7 else ""))

solvers = []
for r in rows:
    if r[2] not in solvers:
        solvers.append(r[2])
problems = []
for r in rows:
    if r[0] not in problems:
        problems.append(r[0])
cell = {(r[0], r[2]): r for r in rows}
labels = {"gs": "Plantar GS", "admm": "Plantar ADMM", "newton": "Plantar Newton",
          "auto": "Plantar auto", "nsgs": "Siconos NSGS", "nsn_ac": "Siconos NSN_AC"}

with open(args.table, "w") as out:
    out.write("| problem | n | " + " | ".join(labels.get(s, s) for s in solvers) + " |\n")
    out.write("|---|---:|" + "---|" * len(solvers) + "\n")
    for p in problems:
        cells = []
        for s in solvers:
            r = cell.get((p, s))
            if r is None:
                cells.append("")
                continue
            text = "%d it, %.3g s, %.1e" % (r[3], r[4], r[5])
            cells.append(text if r[6] == "converged" else "**failed** (" + text + ")")
        n = cell[(p, solvers[0])][1]
        out.write("| %s | %d | %s |\n" % (p, n, " | ".join(cells)))

# Dolan-More: ratio t_s,p / min_s t_s,p over the converged runs.
best = {}
for p in problems:
    times = [cell[(p, s)][4] for s in solvers if (p, s) in cell and cell[(p, s)][6] == "converged"]
    best[p] = min(times) if times else None
taus = [1.05 ** k for k in range(0, 190)]  # 1 .. 1e4
plt.figure(figsize=(7, 4.5))
summary = []
for s in solvers:
    ratios = []
    for p in problems:
        r = cell.get((p, s))
        if r is not None and r[6] == "converged" and best[p]:
            ratios.append(max(r[4], 1e-9) / max(best[p], 1e-9))
    fractions = [sum(1 for x in ratios if x <= t) / len(problems) for t in taus]
    plt.step(taus, fractions, where="post", label=labels.get(s, s))
    summary.append((s, sum(1 for x in ratios if x <= 1.0 + 1e-12), len(ratios)))
plt.xscale("log")
plt.xlabel("tau (time / best time on the problem)")
plt.ylabel("fraction of the %d problems solved" % len(problems))
plt.title("Performance profile, tolerance 1e-8 (Siconos's error measure)")
plt.ylim(0, 1.02)
plt.grid(True, which="both", alpha=0.3)
plt.legend(loc="lower right")
plt.tight_layout()
os.makedirs(os.path.dirname(args.plot), exist_ok=True)
plt.savefig(args.plot, dpi=110)
with open(args.table, "a") as out:
    out.write("\n| solver | fastest on | solved |\n|---|---:|---:|\n")
    for s, fastest, solved in summary:
        out.write("| %s | %d | %d / %d |\n" % (labels.get(s, s), fastest, solved, len(problems)))
siconos = [s for s in solvers if s in ("nsgs", "nsn_ac")]
with open(args.table, "a") as out:
    for s in solvers:
        if s in siconos or not siconos:
            continue
        count = 0
        for p in problems:
            r = cell.get((p, s))
            theirs = [cell[(p, t)][4] for t in siconos
                      if (p, t) in cell and cell[(p, t)][6] == "converged"]
            if r is not None and r[6] == "converged" and (not theirs or r[4] <= min(theirs)):
                count += 1
        out.write("\n%s converged and at most as slow as Siconos's best converged solver on %d of "
                  "%d problems." % (labels.get(s, s), count, len(problems)))
    out.write("\n")
print(open(args.table).read())
print("profile:", args.plot)
