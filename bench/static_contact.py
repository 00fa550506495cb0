#!/usr/bin/python3
"""Static contact on distributed PETSc (issue 26): time and memory against DoF, pressure
convergence under refinement. Prints figures; never passes or fails (bench/README.md).

    bench/static_contact.py --plantar BUILD/apps/plantar [--out DIR] [--refinements 0 1 2 3]
                            [--ranks 1 2] [--linear-solver mumps|"gmres amg"|"gmres gamg"]
    bench/static_contact.py --condensation BUILD/bench/fem/distributed_condensation_bench
                            [--out DIR] [--refinements 0 1 2] [--ranks 1 2] [--block-size 128]

Runs scenes/static_contact.prm (the tilted, pushed foot, mu = 0.5, Q1) on the sole of
meshes/sole_box.geo meshed at Mesh size 0.02 (11 x 7 x 1 hexahedra) and refined r times, at each
rank count (mpirun -np R, oversubscribed if R exceeds the cores). Writes DIR/static_contact.csv
(one row per run: DoF, ranks, iterations, setup, assembly, solve and per-iteration times and
peak memory per rank, wall time) and DIR/pressure_convergence.csv (per refinement: the relative
L2 difference of the nodal pressure to the finest mesh on the coarser mesh's nodes,
sqrt(sum_k A_k (p_k - p_fine,k)^2 / sum_k A_k p_fine,k^2), its observed rate, the peak
pressure), DIR/static_contact.png (log-log time and memory against DoF with fitted slopes) and
DIR/tables.md (the tables of docs/static_contact.md).

With --solver-bench BUILD/bench/fem/static_contact_solver_bench, runs that program instead of
plantar (the same case, sole built by GridGenerator) for each --linear-solver in mumps, amg,
gamg: DIR/solver.csv, DIR/solver.md (Newton and GMRES iterations, times, memory, slopes, and the
pressure convergence against the finest mesh of the first solver) and DIR/solver.png.

With --condensation, runs instead the contact compliance built on R ranks
(fem/distributed_condensation.h, MUMPS) on the same sole at each refinement and rank count, and
writes DIR/condensation.csv, DIR/condensation.md (table and fitted log-log slopes of time and
memory against DoF) and DIR/condensation.png.
"""
import argparse
import csv
import math
import os
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


def environment(args):
    """One BLAS thread per rank unless told otherwise: OpenBLAS's threads oversubscribe the cores
    under several ranks (MUMPS's solves 13x slower on this 2-core machine)."""
    env = dict(os.environ)
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        env[name] = str(args.blas_threads)
    return env


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


def condensation(args):
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for refinements in args.refinements:
        for ranks in args.ranks:
            done = subprocess.run(args.mpirun.split() + ["-np", str(ranks), args.condensation,
                                                         str(refinements), str(args.block_size)],
                                  capture_output=True, text=True, env=environment(args))
            if done.returncode != 0:
                print(f"r{refinements} np{ranks}: failed ({done.returncode}): "
                      f"{done.stderr.strip()[-2000:]}")
                continue
            lines = [l for l in done.stdout.splitlines() if "," in l]
            row = dict(zip(lines[0].split(","), lines[1].split(",")))
            row = {k: float(v) for k, v in row.items()}
            rows.append(row)
            print(row, flush=True)
    if not rows:
        return 1
    with open(out / "condensation.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    lines = ["| refinements | ranks | DoF | contact nodes | assembly s | factorisation s | "
             "solves s | total s | peak MB / rank | MUMPS factor MB (all ranks) | C MB / rank |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        total = r["setup_s"] + r["assembly_s"] + r["factorization_s"] + r["solves_s"]
        lines.append(f"| {r['refinements']:.0f} | {r['ranks']:.0f} | {r['dofs']:.0f} | "
                     f"{r['contact_nodes']:.0f} | {r['assembly_s']:.3g} | "
                     f"{r['factorization_s']:.3g} | {r['solves_s']:.3g} | {total:.3g} | "
                     f"{r['peak_mb_rank']:.0f} | {r['factor_mb_total']:.0f} | "
                     f"{r['c_mb_rank']:.0f} |")
    lines += ["", "| ranks | DoF range | slope factorisation | slope solves | slope peak memory |",
              "| --- | --- | --- | --- | --- |"]
    for ranks in args.ranks:
        sel = [r for r in rows if r["ranks"] == ranks and r["dofs"] >= 3000]
        sel = sel[-2:]
        if len(sel) == 2:
            dofs = [r["dofs"] for r in sel]
            lines.append(f"| {ranks} | {dofs[0]:.0f}-{dofs[1]:.0f} | " + " | ".join(
                f"{slope(dofs, [r[k] for r in sel]):.2f}" for k in
                ("factorization_s", "solves_s", "peak_mb_rank")) + " |")
    (out / "condensation.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ranks in args.ranks:
        sel = [r for r in rows if r["ranks"] == ranks]
        dofs = [r["dofs"] for r in sel]
        for key, style in (("factorization_s", "o-"), ("solves_s", "s-")):
            axes[0].loglog(dofs, [r[key] for r in sel], style,
                           label=f"{key[:-2]}, {ranks} rank(s)")
        axes[1].loglog(dofs, [r["peak_mb_rank"] for r in sel], "o-",
                       label=f"peak memory per rank, {ranks} rank(s)")
        axes[1].loglog(dofs, [r["c_mb_rank"] for r in sel], "x:",
                       label=f"rows of C per rank, {ranks} rank(s)")
    for ax, label in zip(axes, ("s", "MB")):
        ax.set_xlabel("DoF")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "condensation.png", dpi=120)
    return 0


def pressure_convergence(paths):
    """paths: {refinements: contact nodes csv}; the rows of the pressure convergence table."""
    levels = sorted(paths)
    finest = read_nodes(paths[levels[-1]])
    convergence = []
    for level in levels:
        nodes = read_nodes(paths[level])
        num = sum(a * (p - finest[k][1]) ** 2 for k, (a, p) in nodes.items())
        den = sum(a * finest[k][1] ** 2 for k, (a, p) in nodes.items())
        peak = max(p for a, p in nodes.values())
        convergence.append({"refinements": level, "contact_nodes": len(nodes),
                            "l2_difference": math.sqrt(num / den), "peak_pressure": peak})
    for i in range(1, len(convergence)):
        a, b = convergence[i - 1]["l2_difference"], convergence[i]["l2_difference"]
        convergence[i]["rate"] = math.log2(a / b) if a > 0 and b > 0 else float("nan")
    return convergence


def convergence_lines(convergence):
    lines = ["| refinements | contact nodes | rel. L2 difference to finest | rate | "
             "peak pressure (kPa) |", "| --- | --- | --- | --- | --- |"]
    for c in convergence:
        rate = c.get("rate", float("nan"))
        lines.append(f"| {c['refinements']} | {c['contact_nodes']} | {c['l2_difference']:.3g} | "
                     f"{rate:.2f} | {c['peak_pressure'] / 1e3:.1f} |")
    return lines


def solver_bench(args):
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows, nodes = [], {}
    solvers = args.linear_solver.split(",")
    for refinements in args.refinements:
        for ranks in args.ranks:
            for solver in solvers:
                name = f"r{refinements}_np{ranks}_{solver}"
                done = subprocess.run(args.mpirun.split() + [
                    "-np", str(ranks), args.solver_bench, str(refinements), solver,
                    str(args.linear_tolerance), str(out / f"{name}_nodes.csv")],
                    capture_output=True, text=True, env=environment(args))
                lines = [l for l in done.stdout.splitlines() if l.count(",") > 5]
                if done.returncode != 0 or len(lines) < 2:
                    print(f"{name}: failed ({done.returncode}): {done.stdout.strip()[-500:]} "
                          f"{done.stderr.strip()[-1500:]}", flush=True)
                    continue
                row = dict(zip(lines[0].split(","), lines[1].split(",")))
                row = {k: (v if k == "solver" else float(v)) for k, v in row.items()}
                rows.append(row)
                nodes.setdefault(solver, {})[refinements] = out / f"{name}_nodes.csv"
                print(row, flush=True)
    if not rows:
        return 1
    with open(out / "solver.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    lines = ["| refinements | ranks | solver | DoF | Newton it. | GMRES it. | residual | setup s | "
             "assembly s | solve s | s / iteration | peak MB / rank |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['refinements']:.0f} | {r['ranks']:.0f} | {r['solver']} | "
                     f"{r['dofs']:.0f} | {r['newton_iterations']:.0f} | "
                     f"{r['gmres_iterations']:.0f} | {r['residual']:.1e} | {r['setup_s']:.3g} | "
                     f"{r['assembly_s']:.3g} | {r['solve_s']:.3g} | {r['iteration_s']:.3g} | "
                     f"{r['peak_mb_rank']:.0f} |")
    lines += ["", "| ranks | solver | DoF range | slope solve | slope s / iteration | "
              "slope peak memory |", "| --- | --- | --- | --- | --- | --- |"]
    for ranks in args.ranks:
        for solver in solvers:
            sel = [r for r in rows if r["ranks"] == ranks and r["solver"] == solver][-2:]
            if len(sel) == 2:
                dofs = [r["dofs"] for r in sel]
                lines.append(f"| {ranks} | {solver} | {dofs[0]:.0f}-{dofs[1]:.0f} | " + " | ".join(
                    f"{slope(dofs, [r[k] for r in sel]):.2f}" for k in
                    ("solve_s", "iteration_s", "peak_mb_rank")) + " |")
    lines.append("")
    for solver, paths in nodes.items():
        if len(paths) >= 2:
            lines += [f"Pressure convergence ({solver}):", ""]
            lines += convergence_lines(pressure_convergence(paths)) + [""]
    (out / "solver.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ranks in args.ranks:
        for solver in solvers:
            sel = [r for r in rows if r["ranks"] == ranks and r["solver"] == solver]
            if not sel:
                continue
            dofs = [r["dofs"] for r in sel]
            axes[0].loglog(dofs, [r["solve_s"] for r in sel], "o-",
                           label=f"solve, {solver}, {ranks} rank(s)")
            axes[1].loglog(dofs, [r["peak_mb_rank"] for r in sel], "o-",
                           label=f"peak memory per rank, {solver}, {ranks} rank(s)")
    for ax, label in zip(axes, ("s", "MB")):
        ax.set_xlabel("DoF")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "solver.png", dpi=120)
    return 0


def main():
    source = pathlib.Path(__file__).resolve().parent.parent
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar")
    parser.add_argument("--condensation", help="distributed_condensation_bench: condensation "
                        "time and memory instead of the contact solve")
    parser.add_argument("--block-size", type=int, default=128)
    parser.add_argument("--blas-threads", type=int, default=1)
    parser.add_argument("--solver-bench", help="static_contact_solver_bench: the contact solve "
                        "by that program; --linear-solver then lists mumps,amg,gamg")
    parser.add_argument("--linear-tolerance", type=float, default=1e-8)
    parser.add_argument("--out", default="out/bench_static_contact")
    parser.add_argument("--refinements", type=int, nargs="+", default=[0, 1, 2, 3])
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--linear-solver", default="mumps")
    parser.add_argument("--mpirun", default="mpirun --allow-run-as-root --oversubscribe")
    args = parser.parse_args()
    if args.condensation:
        return condensation(args)
    if args.solver_bench:
        return solver_bench(args)
    if not args.plantar:
        parser.error("--plantar or --condensation is required")
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
                                  capture_output=True, text=True, env=environment(args))
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
    convergence = pressure_convergence(
        {level: out / f"r{level}_np{ranks}" / "contact_nodes.csv" for level in levels})
    with open(out / "pressure_convergence.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["refinements", "contact_nodes", "l2_difference",
                                               "rate", "peak_pressure"])
        writer.writeheader()
        writer.writerows(convergence)
    lines += convergence_lines(convergence)
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
