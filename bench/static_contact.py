#!/usr/bin/python3
"""Static contact on distributed PETSc (issue 26): time and memory against DoF, pressure
convergence under refinement. Prints figures; never passes or fails (bench/README.md).

    bench/static_contact.py --plantar BUILD/apps/plantar [--out DIR] [--refinements 0 1 2 3]
                            [--ranks 1 2] [--linear-solver mumps|"gmres amg"]

Runs scenes/static_contact.prm (the tilted, pushed foot, mu = 0.5, Q1) on the sole of
meshes/sole_box.geo meshed at Mesh size 0.02 (11 x 7 x 1 hexahedra) and refined r times, at each
rank count (mpirun -np R, oversubscribed if R exceeds the cores). Writes DIR/static_contact.csv
(one row per run: DoF, ranks, iterations, setup, assembly, solve and per-iteration times and
peak memory per rank, wall time) and DIR/pressure_convergence.csv (per refinement: the relative
L2 difference of the nodal pressure to the finest mesh on the coarser mesh's nodes,
sqrt(sum_k A_k (p_k - p_fine,k)^2 / sum_k A_k p_fine,k^2), its observed rate, the peak
pressure), DIR/static_contact.png (log-log time and memory against DoF with fitted slopes) and
DIR/tables.md (the tables of docs/static_contact.md).
"""
import argparse
import csv
import math
import pathlib
import subprocess
import time

SCENE = """include {source}/scenes/static_contact.prm
subsection Sole
  set Mesh size = 0.02
end
subsection Static contact
  set Refinements = {refinements}
  set Linear solver = {solver}
end
subsection Output
  set Write VTU = false
end
"""


def read_summary(path):
    values = {}
    for line in path.read_text().splitlines()[1:]:
        name, value = line.split(",")
        values[name] = float(value)
    return values


def read_nodes(path):
    nodes = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            key = (round(float(row["x"]) * 1e9), round(float(row["y"]) * 1e9))
            nodes[key] = (float(row["area"]), float(row["pressure"]))
    return nodes


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(xs)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def main():
    source = pathlib.Path(__file__).resolve().parent.parent
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--out", default="out/bench_static_contact")
    parser.add_argument("--refinements", type=int, nargs="+", default=[0, 1, 2, 3])
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--linear-solver", default="mumps")
    parser.add_argument("--mpirun", default="mpirun --allow-run-as-root --oversubscribe")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for refinements in args.refinements:
        for ranks in args.ranks:
            name = f"r{refinements}_np{ranks}"
            scene = out / f"{name}.prm"
            scene.write_text(SCENE.format(source=source, refinements=refinements,
                                          solver=args.linear_solver))
            start = time.time()
            done = subprocess.run(args.mpirun.split() + ["-np", str(ranks), args.plantar, "run",
                                                         str(scene), "-o", str(out / name)],
                                  capture_output=True, text=True)
            wall = time.time() - start
            if done.returncode != 0:
                print(f"{name}: failed ({done.returncode}): {done.stderr.strip()}")
                continue
            s = read_summary(out / name / "summary.csv")
            row = {"refinements": refinements, "ranks": ranks, "dofs": int(s["dofs"]),
                   "contact_nodes": int(s["contact_nodes"]), "iterations": int(s["iterations"]),
                   "separated": int(s["separated"]), "stick": int(s["stick"]),
                   "slip": int(s["slip"]), "ground_force_z": s["ground_force_z"],
                   "max_pressure": s["max_pressure"], "wall": wall}
            for key in ("setup_time", "assembly_time", "solve_time", "iteration_time",
                        "peak_memory_mb"):
                row[key] = max(s[f"{key}_{r}"] for r in range(ranks))
            rows.append(row)
            print(", ".join(f"{k} {v:.6g}" if isinstance(v, float) else f"{k} {v}"
                            for k, v in row.items()), flush=True)
    if not rows:
        return 1
    with open(out / "static_contact.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)

    lines = ["| refinements | ranks | DoF | contact nodes | Newton it. | setup s | assembly s | "
             "solve s | s / iteration | peak MB / rank | wall s |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['refinements']} | {r['ranks']} | {r['dofs']} | {r['contact_nodes']} "
                     f"| {r['iterations']} | {r['setup_time']:.3g} | {r['assembly_time']:.3g} | "
                     f"{r['solve_time']:.3g} | {r['iteration_time']:.3g} | "
                     f"{r['peak_memory_mb']:.0f} | {r['wall']:.3g} |")
    lines.append("")
    lines.append("| ranks | slope assembly | slope solve | slope s / iteration | slope memory |")
    lines.append("| --- | --- | --- | --- | --- |")
    for ranks in args.ranks:
        sel = [r for r in rows if r["ranks"] == ranks and r["dofs"] >= 1e4]
        if len(sel) >= 2:
            dofs = [r["dofs"] for r in sel]
            lines.append(f"| {ranks} | " + " | ".join(
                f"{slope(dofs, [r[k] for r in sel]):.2f}" for k in
                ("assembly_time", "solve_time", "iteration_time", "peak_memory_mb")) + " |")
    lines.append("")

    # Pressure convergence (1 rank, or the lowest rank count run).
    ranks = min(r["ranks"] for r in rows)
    levels = sorted(r["refinements"] for r in rows if r["ranks"] == ranks)
    finest = read_nodes(out / f"r{levels[-1]}_np{ranks}" / "contact_nodes.csv")
    convergence = []
    for level in levels:
        nodes = read_nodes(out / f"r{level}_np{ranks}" / "contact_nodes.csv")
        num = sum(a * (p - finest[k][1]) ** 2 for k, (a, p) in nodes.items())
        den = sum(a * finest[k][1] ** 2 for k, (a, p) in nodes.items())
        peak = max(p for a, p in nodes.values())
        convergence.append({"refinements": level, "contact_nodes": len(nodes),
                            "l2_difference": math.sqrt(num / den), "peak_pressure": peak})
    for i in range(1, len(convergence)):
        a, b = convergence[i - 1]["l2_difference"], convergence[i]["l2_difference"]
        convergence[i]["rate"] = math.log2(a / b) if a > 0 and b > 0 else float("nan")
    with open(out / "pressure_convergence.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["refinements", "contact_nodes", "l2_difference",
                                               "rate", "peak_pressure"])
        writer.writeheader()
        writer.writerows(convergence)
    lines.append("| refinements | contact nodes | rel. L2 difference to finest | rate | "
                 "peak pressure (kPa) |")
    lines.append("| --- | --- | --- | --- | --- |")
    for c in convergence:
        rate = c.get("rate", float("nan"))
        lines.append(f"| {c['refinements']} | {c['contact_nodes']} | {c['l2_difference']:.3g} | "
                     f"{rate:.2f} | {c['peak_pressure'] / 1e3:.1f} |")
    (out / "tables.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ranks in args.ranks:
        sel = [r for r in rows if r["ranks"] == ranks]
        dofs = [r["dofs"] for r in sel]
        for key, style in (("assembly_time", "o-"), ("solve_time", "s-"),
                           ("iteration_time", "^--")):
            axes[0].loglog(dofs, [r[key] for r in sel], style,
                           label=f"{key.replace('_', ' ')}, {ranks} rank(s)")
        axes[1].loglog(dofs, [r["peak_memory_mb"] for r in sel], "o-",
                       label=f"peak memory per rank, {ranks} rank(s)")
    axes[0].set_xlabel("DoF")
    axes[0].set_ylabel("s")
    axes[1].set_xlabel("DoF")
    axes[1].set_ylabel("MB")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "static_contact.png", dpi=120)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
