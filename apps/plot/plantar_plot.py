#!/usr/bin/python3
"""plantar plot DIR: PNG figures from the CSV outputs of plantar run / plantar sweep.

  DIR/waist.csv, joints.csv             one run
  DIR/<form>/{waist,joints}.csv          a comparison of foot forms (rigid, compliant_ankle,
  (or DIR/<form>/failed/*.csv)           fem_sole); a failed form is drawn up to its failure
  DIR/sweep.csv                          a sweep (plantar sweep)

Figures (DIR/figures/, written to a temporary name and renamed), laid out like David et al.
2008: one panel per foot form, time on the x axis.
  waist_z.png (Fig. 5), waist_velocity_z.png (Fig. 6), waist_acceleration_z.png (Fig. 7),
  right_knee_torque.png (Fig. 8); sweep_E_nu.png (Fig. 3 drop, Fig. 4 lean), sweep_time_step.png.
Run with Debian's /usr/bin/python3 (python3-matplotlib). Exit status 1 with one message if DIR
holds none of these CSVs.
"""
import csv
import math
import os
import sys

FORMS = [("rigid", "rigid feet"), ("compliant_ankle", "compliant ankle joints"),
         ("fem_sole", "FEM soles")]
COLORS = {"rigid": "tab:red", "compliant_ankle": "tab:blue", "fem_sole": "tab:green"}


def fail(message):
    sys.stderr.write("plantar plot: " + message + "\n")
    sys.exit(1)


def read_csv(path):
    """Columns of a CSV file as lists of floats (empty cells: nan)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    columns = {name: [] for name in header}
    for row in body:
        for name, cell in zip(header, row):
            try:
                columns[name].append(float(cell))
            except ValueError:
                columns[name].append(cell if cell else math.nan)
    return columns


def read_key_values(path):
    values = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                if "," in line:
                    key, value = line.strip().split(",", 1)
                    try:
                        values[key] = float(value)
                    except ValueError:
                        values[key] = value
    return values


def prm_value(directory, name):
    """Value of 'set NAME = ...' in DIR/parameters.prm (first match), or None."""
    path = os.path.join(directory, "parameters.prm")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        for line in f:
            words = line.strip()
            if words.startswith("set ") and words[4:].split("=")[0].strip() == name:
                return words.split("=", 1)[1].split("#")[0].strip()
    return None


class Run:
    """The CSVs of one run (or of a failed run up to its failure)."""

    def __init__(self, directory, label, key):
        self.key, self.label, self.failure = key, label, None
        source = directory
        if not os.path.exists(os.path.join(directory, "waist.csv")):
            source = os.path.join(directory, "failed")
            failure = os.path.join(directory, "failure.txt")
            self.failure = open(failure).read().strip() if os.path.exists(failure) else "failed"
        self.waist = read_csv(os.path.join(source, "waist.csv"))
        joints = os.path.join(source, "joints.csv")
        self.joints = read_csv(joints) if os.path.exists(joints) else {}
        # FEM soles lift the robot by the sole thickness: shift z down to compare (paper: 2 cm).
        thickness = prm_value(directory, "Thickness")
        form = prm_value(directory, "Foot form")
        self.lift = float(thickness) if (thickness and form == "fem sole") else 0.0

    def title(self):
        if self.failure is None:
            return self.label
        t = self.waist["t"][-1] if self.waist.get("t") else 0.0
        return "%s: FAILED at t = %.3f s" % (self.label, t)


def find_runs(directory):
    runs = []
    for key, label in FORMS:
        sub = os.path.join(directory, key)
        if (os.path.exists(os.path.join(sub, "waist.csv"))
                or os.path.exists(os.path.join(sub, "failed", "waist.csv"))):
            runs.append(Run(sub, label, key))
    if not runs and os.path.exists(os.path.join(directory, "waist.csv")):
        form = prm_value(directory, "Foot form") or "run"
        key = form.replace(" ", "_")
        runs.append(Run(directory, dict(FORMS).get(key, form), key))
    return runs


def save(figure, directory, name):
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, name)
    tmp = path + ".tmp-%d" % os.getpid()
    figure.savefig(tmp, dpi=90, format="png")
    os.replace(tmp, path)
    return path


def time_figure(plt, runs, series, column, ylabel, title, shift=False):
    figure, axes = plt.subplots(len(runs), 1, figsize=(7.5, 2.1 * len(runs) + 0.6), sharex=True,
                                squeeze=False)
    for axis, run in zip(axes[:, 0], runs):
        data = getattr(run, series)
        if column not in data:
            fail("column '%s' missing in the %s CSV of %s" % (column, series, run.label))
        values = data[column]
        if shift:
            values = [v - run.lift for v in values]
        axis.plot(data["t"], values, color=COLORS.get(run.key, "k"), linewidth=0.8)
        axis.set_title(run.title(), fontsize=9)
        axis.set_ylabel(ylabel, fontsize=8)
        axis.grid(True, linewidth=0.3)
        finite = [abs(v) for v in values if isinstance(v, float) and math.isfinite(v)]
        if finite and series == "waist" and column == "az":
            axis.text(0.99, 0.92, "max |a_z| = %.1f m/s^2" % max(finite),
                      transform=axis.transAxes, ha="right", va="top", fontsize=8)
    axes[-1, 0].set_xlabel("time (s)")
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    return figure


def plot_runs(plt, directory, runs):
    out = os.path.join(directory, "figures")
    made = []
    shifted = " (FEM soles: minus the sole thickness)" if any(r.lift for r in runs) else ""
    made.append(save(time_figure(plt, runs, "waist", "z", "z (m)",
                                 "Waist position along z" + shifted, shift=True), out,
                     "waist_z.png"))
    made.append(save(time_figure(plt, runs, "waist", "vz", "v_z (m/s)", "Waist velocity along z"),
                     out, "waist_velocity_z.png"))
    made.append(save(time_figure(plt, runs, "waist", "az", "a_z (m/s^2)",
                                 "Waist acceleration along z"), out, "waist_acceleration_z.png"))
    if all("RLEG_JOINT3_tau" in r.joints for r in runs):
        made.append(save(time_figure(plt, runs, "joints", "RLEG_JOINT3_tau", "torque (N m)",
                                     "Right knee torque (RLEG_JOINT3)"), out,
                         "right_knee_torque.png"))
    return made


def plot_sweep(plt, directory):
    table = read_csv(os.path.join(directory, "sweep.csv"))
    if not table or not table.get("id"):
        fail("'%s' has no sweep points" % os.path.join(directory, "sweep.csv"))
    scene_type = prm_value(directory, "Scene type") or "drop"
    out = os.path.join(directory, "figures")
    made = []
    n = len(table["id"])
    ok = [i for i in range(n) if table["status"][i] == "ok"]
    metric, ylabel = (("roll_difference_deg", "commanded - measured roll (deg)")
                      if scene_type == "lean" else
                      ("max_waist_acceleration_z", "max |waist a_z| (m/s^2)"))
    # Fig. 3 / 4: the criterion against E, one curve per nu (FEM-sole points).
    fem = [i for i in ok if table["foot_form"][i] == "fem sole" and isinstance(table["E"][i], float)
           and math.isfinite(table["E"][i])]
    steps = sorted({table["time_step"][i] for i in ok})
    if fem:
        figure, axis = plt.subplots(figsize=(6.5, 4.2))
        for dt in steps:
            ratios = sorted({table["nu"][i] for i in fem if table["time_step"][i] == dt},
                            key=lambda v: (not isinstance(v, float), v))
            for nu in ratios:
                pts = sorted((table["E"][i], table[metric][i]) for i in fem
                             if table["nu"][i] == nu and table["time_step"][i] == dt)
                label = "nu = %g" % nu if isinstance(nu, float) and math.isfinite(nu) else "scene nu"
                if len(steps) > 1:
                    label += ", dt = %g ms" % (dt * 1e3)
                axis.plot([p[0] * 1e-6 for p in pts], [p[1] for p in pts], "o-", label=label)
        axis.set_xlabel("Young's modulus E (MPa)")
        axis.set_ylabel(ylabel)
        axis.set_title(("Inclination test (Fig. 4)" if scene_type == "lean" else
                        "Drop test (Fig. 3)") + ": FEM sole", fontsize=10)
        axis.grid(True, linewidth=0.3)
        axis.legend(fontsize=8)
        figure.tight_layout()
        made.append(save(figure, out, "sweep_E_nu.png"))
    # The time-step study: the criterion against dt, one curve per form (and material).
    if len(steps) > 1:
        figure, axis = plt.subplots(figsize=(6.5, 4.2))
        groups = {}
        for i in ok:
            key = (table["foot_form"][i], table["E"][i] if isinstance(table["E"][i], float) else
                   math.nan, table["nu"][i] if isinstance(table["nu"][i], float) else math.nan)
            groups.setdefault(key, []).append((table["time_step"][i], table[metric][i]))
        for (form, e, nu), pts in sorted(groups.items(), key=lambda g: str(g[0])):
            pts.sort()
            label = form
            if math.isfinite(e):
                label += ", E = %g MPa" % (e * 1e-6)
            if math.isfinite(nu):
                label += ", nu = %g" % nu
            axis.loglog([p[0] * 1e3 for p in pts], [abs(p[1]) for p in pts], "o-", label=label,
                        color=COLORS.get(form.replace(" ", "_")))
        axis.set_xlabel("time step dt (ms)")
        axis.set_ylabel(ylabel)
        axis.set_title("Dependence on the time step", fontsize=10)
        axis.grid(True, which="both", linewidth=0.3)
        axis.legend(fontsize=8)
        figure.tight_layout()
        made.append(save(figure, out, "sweep_time_step.png"))
    # The relaxation-time axis (viscoelastic soles): criterion and dissipated energy against tau1.
    taus = [i for i in ok if isinstance(table.get("tau1", [None] * n)[i], float)
            and math.isfinite(table["tau1"][i])]
    if taus:
        figure, axes = plt.subplots(1, 2, figsize=(9, 3.8))
        pts = sorted((table["tau1"][i], table[metric][i], table["sole_dissipated_energy"][i])
                     for i in taus)
        axes[0].semilogx([p[0] * 1e3 for p in pts], [p[1] for p in pts], "o-")
        axes[0].set_ylabel(ylabel)
        axes[1].semilogx([p[0] * 1e3 for p in pts], [p[2] for p in pts], "o-")
        axes[1].set_ylabel("dissipated by the soles (J)")
        for axis in axes:
            axis.set_xlabel("relaxation time tau1 (ms)")
            axis.grid(True, which="both", linewidth=0.3)
        figure.suptitle("Viscoelastic sole: relaxation-time sweep", fontsize=10)
        figure.tight_layout()
        made.append(save(figure, out, "sweep_relaxation_time.png"))
    # The general axes (Sweep/Axis N, the columns after the landing figures): the criterion
    # against each axis's values, one curve per foot form and values of the other axes.
    header = list(table.keys())
    first = header.index("max_landing_acceleration_z") + 1 if (
        "max_landing_acceleration_z" in header) else len(header)
    axes_names = header[first:]
    for k, name in enumerate(axes_names):
        others = [a for a in axes_names if a != name]
        curves = {}
        for i in ok:
            key = (table["foot_form"][i],) + tuple(table[a][i] for a in others)
            curves.setdefault(key, []).append((table[name][i], table[metric][i]))
        if not curves:
            continue
        numeric = all(isinstance(table[name][i], float) for i in ok)
        categories = list(dict.fromkeys(str(table[name][i]) for i in ok))
        figure, axis = plt.subplots(figsize=(6.5, 4.2))
        for key, pts in curves.items():
            label = ", ".join([key[0]] + ["%s = %s" % (a, v) for a, v in zip(others, key[1:])])
            if numeric:
                pts.sort()
                xs = [p[0] for p in pts]
            else:
                xs = [categories.index(str(p[0])) for p in pts]
            axis.plot(xs, [p[1] for p in pts], "o-", label=label,
                      color=COLORS.get(key[0].replace(" ", "_")) if not others else None)
        if not numeric:
            axis.set_xticks(range(len(categories)))
            axis.set_xticklabels(categories)
        axis.set_xlabel(name)
        axis.set_ylabel(ylabel)
        axis.set_title("Sweep over %s" % name, fontsize=10)
        axis.grid(True, linewidth=0.3)
        axis.legend(fontsize=7)
        figure.tight_layout()
        made.append(save(figure, out, "sweep_axis_%d.png" % (k + 1)))
    if not made:
        fail("'%s': no finished point to plot" % os.path.join(directory, "sweep.csv"))
    return made


def main():
    if len(sys.argv) != 2:
        fail("usage: plantar plot DIR")
    directory = sys.argv[1]
    if not os.path.isdir(directory):
        fail("'%s' is not a directory" % directory)
    runs = find_runs(directory)
    has_sweep = os.path.exists(os.path.join(directory, "sweep.csv"))
    if not runs and not has_sweep:
        fail("no CSV outputs in '%s' (expected waist.csv, <form>/waist.csv with form rigid, "
             "compliant_ankle or fem_sole, or sweep.csv)" % directory)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail("matplotlib is missing (%s): apt-get install python3-matplotlib" % e)
    made = []
    if runs:
        made += plot_runs(plt, directory, runs)
    if has_sweep:
        made += plot_sweep(plt, directory)
    for path in made:
        print("figure: " + path)


if __name__ == "__main__":
    main()
