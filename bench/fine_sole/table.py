#!/usr/bin/python3
"""Tables and the log-log plot of issue 25's fine-sole study (bench/fine_sole/run.sh).

    table.py OUT_DIR   (writes Markdown to stdout and OUT_DIR/scaling.png)

Reads OUT_DIR/scaling/ and OUT_DIR/scaling_reduced/work_precision.csv (stand, cost against
contact nodes),
OUT_DIR/walk_1cm/ and OUT_DIR/walk_5mm/work_precision.csv (the walk, reduced soles against the
full one) and OUT_DIR/hmatrix.txt (hierarchical_compliance_bench). Slopes are least-squares fits
of log(cost) against log(contact nodes per foot).
"""
import csv
import math
import os
import re
import sys


def read(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return math.nan


def slope(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return math.nan
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return math.nan
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def pct(x):
    return "-" if math.isnan(x) else f"{100 * x:.2g} %"


def mesh_nodes(h):
    """Bottom nodes of meshes/sole_box.geo's Q1 mesh (transfinite) of size h."""
    return (math.ceil(0.2172 / h - 1e-9) + 1) * (math.ceil(0.138 / h - 1e-9) + 1)


def scaling(out):
    rows = [r for d in ("scaling", "scaling_reduced")
            for r in read(os.path.join(out, d, "work_precision.csv"))
            if r["knob"] == "mesh size" or r["knob"].startswith("mesh reduced")]
    if not rows:
        return {}
    print("## Cost per step against contact nodes (stand, both feet loaded)\n")
    print("| method | h (m) | nodes per foot | contacts (max, both feet) | loop ms/step | solve share |"
          " set-up s | kept MB | x real time | status |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    curves = {}
    for r in rows:
        method = "full" if r["knob"] == "mesh size" else r["knob"].replace("mesh ", "")
        dt, wall = num(r, "dt"), num(r, "wall_per_sim_s")
        step_ms = 1e3 * wall * dt
        share = num(r, "contact_solve") / wall if wall > 0 else math.nan
        n = mesh_nodes(float(r["value"]))
        ok = r["status"] == "ok"
        print(f"| {method} | {r['value']} | {n} | {r['max_contacts']} | {step_ms:.3g} |"
              f" {pct(share)} | {num(r, 'setup_s'):.3g} | {num(r, 'kept_MB'):.3g} |"
              f" {1 / wall:.3g} | {'ok' if ok else r['status'][:60]} |")
        if ok:
            c = curves.setdefault(method, {"n": [], "step": [], "setup": [], "kept": []})
            c["n"].append(n)
            c["step"].append(step_ms)
            c["setup"].append(num(r, "setup_s"))
            c["kept"].append(num(r, "kept_MB"))
    print("\nFitted log-log slopes against the contact nodes per foot (all sizes; in brackets"
          " from 500 nodes on):\n")
    print("| method | loop per step | set-up | kept operator |")
    print("|---|---|---|---|")
    for method, c in curves.items():
        big = [i for i, n in enumerate(c["n"]) if n >= 500]
        cols = []
        for key in ("step", "setup", "kept"):
            s_all = slope(c["n"], c[key])
            s_big = slope([c["n"][i] for i in big], [c[key][i] for i in big])
            cols.append(f"{s_all:.2f} ({s_big:.2f})")
        print(f"| {method} | {' | '.join(cols)} |")
    print()
    return curves


def hmatrix(out):
    path = os.path.join(out, "hmatrix.txt")
    if not os.path.exists(path):
        return {}
    line = re.compile(r"^\s*(0\.\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+\|\s+(\S+)\s+([\d.]+)\s+"
                      r"([\d.]+)%\s+(\S+)\s+(\d+)\s+\|\s+([\d.]+)\s+(\d+)\S?\s+([\d.]+)\s+(\d+)")
    rows = [m.groups() for m in map(line.match, open(path)) if m]
    if not rows:
        return {}
    print("## One contact solve: dense against H-matrix compliance (hmatrix.txt)\n")
    print("| h (m) | nodes | dense MB | tolerance | H MB | H / dense | rel. error | dense GS s |"
          " H GS s |")
    print("|---|---|---|---|---|---|---|---|---|")
    curves = {}
    for g in rows:
        print(f"| {g[0]} | {g[1]} | {g[3]} | {g[4]} | {g[5]} | {g[6]} % | {g[7]} | {g[9]} |"
              f" {g[11]} |")
        n = int(g[1])
        curves.setdefault("dense GS solve", {}).setdefault(n, float(g[9]))
        curves.setdefault(f"H-matrix {g[4]} GS solve", {})[n] = float(g[11])
    print("\nFitted slopes of the solve time against the nodes:",
          ", ".join(f"{k} {slope(list(v), list(v.values())):.2f}" for k, v in curves.items()))
    print()
    return curves


def reduction(out):
    path = os.path.join(out, "reduction.txt")
    if not os.path.exists(path):
        return
    setup, grids = {}, []
    for line in open(path):
        f = line.split()
        if f and f[0] == "setup":
            setup[(f[1], float(f[2]))] = (int(f[3]), float(f[4]), float(f[5]))
        elif f and f[0] == "grid":
            grids.append((float(f[1]), f[2], int(f[3]), int(f[4]), float(f[5]), float(f[6]),
                          float(f[7]), [float(v) for v in f[8:11]]))
    print("## Reduced soles from the factorization of K (reduction.txt)\n")
    print("Set-up of the condensed sole: the factorization route (assembly, Cholesky of K, the"
          " rigid-motion stiffness through K_nn; kept: the factor of K) against the dense route"
          " (C = [K^-1]_cc by 3n solves; kept: C and the factor of K_nn); then C_r of a reduced"
          " sole by 3P solves.\n")
    print("| h (m) | nodes | factorization s | factor MB | dense s | dense MB | 8x8 C_r s |"
          " 16x16 C_r s |")
    print("|---|---|---|---|---|---|---|---|")
    for (route, h), (n, t, mb) in sorted(setup.items(), key=lambda kv: -kv[0][1]):
        if route != "factorization":
            continue
        dense = setup.get(("dense", h))
        c8 = [g[5] for g in grids if g[0] == h and g[1] == "uniform" and g[2] == 8]
        c16 = [g[5] for g in grids if g[0] == h and g[1] == "uniform" and g[2] == 16]
        print(f"| {h} | {n} | {t:.3g} | {mb:.3g} | {dense[1]:.3g} | {dense[2]:.3g} |" if dense
              else f"| {h} | {n} | {t:.3g} | {mb:.3g} | - | - |", end="")
        print(f" {c8[0]:.3g} |" if c8 else " - |", f"{c16[0]:.3g} |" if c16 else "- |")
    print("\nThe reduction error estimate against the patches: uniform and Chebyshev-graded grids"
          " (constant basis, equal shares), and graded grids in the bilinear basis (one patch per"
          " vertex, area weights); the pressure error under a pitch of the bonded face (relative"
          " L2, where the dense route ran); max |C_r from K - C_r from C| / max |C_r|:\n")
    print("| h (m) | g | uniform patches | uniform estimate | graded patches | graded estimate |"
          " graded pitch pressure | bilinear patches | bilinear estimate | bilinear pitch"
          " pressure | route difference |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")

    def pitch(rows):
        return f"{rows[0][7][1]:.3g}" if rows and len(rows[0][7]) > 1 and rows[0][7][1] >= 0 \
            else "-"
    for h in sorted({g[0] for g in grids}, reverse=True):
        for g in sorted({g[2] for g in grids if g[0] == h}):
            u = [x for x in grids if x[0] == h and x[2] == g and x[1] == "uniform"]
            c = [x for x in grids if x[0] == h and x[2] == g and x[1] == "chebyshev"]
            b = [x for x in grids if x[0] == h and x[2] == g and x[1] == "chebyshev-bilinear"]
            diff = max([x[6] for x in u + c + b] + [-1])
            print(f"| {h} | {g} | {u[0][3] if u else '-'} | {f'{u[0][4]:.3g}' if u else '-'} |"
                  f" {c[0][3] if c else '-'} | {f'{c[0][4]:.3g}' if c else '-'} | {pitch(c)} |"
                  f" {b[0][3] if b else '-'} | {f'{b[0][4]:.3g}' if b else '-'} | {pitch(b)} |"
                  f" {f'{diff:.1e}' if diff >= 0 else '-'} |")
    print()


def walk(out, name, title):
    rows = [r for r in read(os.path.join(out, name, "work_precision.csv"))
            if r["knob"] == "sole model"]
    if not rows:
        return
    print(f"## {title}\n")
    print("Estimates: the sole's reduction error estimates (Sole/Reduction quantity = stiffness,"
          " pressure). Errors against the reference (the full sole of the same mesh, or the"
          " finest reduced sole): filtered waist a_z peak (e_af), the worst landing's impulse and"
          " peak force, centre-of-pressure path (largest distance, mm), nodal normal force field"
          " (relative, worst and median frame, every 10 ms), and the reference field's"
          " least-squares projection on the sole's shares (its representation error alone).\n")
    print("| sole | contacts per foot | estimate | pressure estimate | x real time | loop s/sim s |"
          " solve share | set-up s | kept MB | e_af | e_J landing | e_F landing | CoP mm |"
          " field worst | field median | projected worst | projected median | landings |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        wall = num(r, "wall_per_sim_s")
        share = num(r, "contact_solve") / wall if wall > 0 else math.nan
        ref = r["reference"] == "1"
        status = "" if r["status"] == "ok" else f" ({r['status'][:50]})"
        est = num(r, "reduction_estimate")
        p_est = num(r, "pressure_estimate")
        print(f"| {r['value']}{status} | {r['contacts_per_foot']} |"
              f" {'-' if math.isnan(est) else f'{est:.3g}'} |"
              f" {'-' if math.isnan(p_est) else f'{p_est:.3g}'} | {1 / wall:.3g} | {wall:.3g} |"
              f" {pct(share)} | {num(r, 'setup_s'):.3g} | {num(r, 'kept_MB'):.3g} |"
              + (" reference |" * 8 if ref else
                 f" {pct(num(r, 'e_af'))} | {pct(num(r, 'e_landing_impulse'))} |"
                 f" {pct(num(r, 'e_landing_peak_force'))} | {1e3 * num(r, 'e_cop_m'):.3g} |"
                 f" {pct(num(r, 'e_field_max'))} | {pct(num(r, 'e_field_median'))} |"
                 f" {pct(num(r, 'e_field_best_max'))} | {pct(num(r, 'e_field_best_median'))} |")
              + f" {r['n_landings']} |")
    print()


def plot(out, curves, hcurves):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    for method, c in curves.items():
        a.loglog(c["n"], c["step"], "o-", label=f"{method}: loop (slope {slope(c['n'], c['step']):.2f})")
        b.loglog(c["n"], c["setup"], "o-", label=f"{method} (slope {slope(c['n'], c['setup']):.2f})")
    for method, v in hcurves.items():
        a.loglog(list(v), [1e3 * t for t in v.values()], "s--",
                 label=f"{method} (slope {slope(list(v), list(v.values())):.2f})")
    a.set_xlabel("contact nodes per foot")
    a.set_ylabel("ms per step (stand) / per solve (landing)")
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7)
    b.set_xlabel("contact nodes per foot")
    b.set_ylabel("set-up s (mesh, assembly, condensation, robot)")
    b.grid(True, which="both", alpha=0.3)
    b.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling.png"), dpi=120)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: table.py OUT_DIR")
    out = sys.argv[1]
    curves = scaling(out)
    hcurves = hmatrix(out)
    reduction(out)
    walk(out, "walk_1cm", "The six-step walk on the 1 cm sole (345 contact nodes per foot)")
    walk(out, "walk_5mm", "The six-step walk on the 5 mm sole (1305 contact nodes per foot)")
    walk(out, "walk_5mm_p2", "The six-step walk on the 5 mm Q2 sole (5073 bottom nodes per foot;"
         " reference: the bilinear 20 x 20 sole)")
    plot(out, curves, hcurves)


if __name__ == "__main__":
    main()
