#!/usr/bin/python3
"""Where the waist |a_z| peak of a run comes from (issue 8), from `plantar run` outputs.

Usage: walk_peak.py [--plot FILE.png] [--window T0 T1] LABEL=RUN_DIR ...

For each run (RUN_DIR/waist.csv, RUN_DIR/contacts.csv) prints:
  peak      max |a_z| over the run (a_z = backward difference of the step velocities: the
            summary's max_waist_acceleration_z), its time and the soles' vertical forces then;
  start     |a_z| of the first step (the robot settling onto unloaded soles at t = 0);
  walk      max |a_z| for t >= 0.1 s (the walk without the start);
  avg10     max |a_z| averaged over centred 10 ms windows, (v(t+5ms) - v(t-5ms)) / 10 ms, for
            t >= 0.1 s: a low-pass measure independent of dt (first zero at 100 Hz). Not the
            paper's criterion (the paper gives no bandwidth); a companion measure only;
  win, win10  max |a_z| and max of the 10 ms average in the window;
  f_dom     the dominant frequency of a_z in the window (default 3.8 to 4.3 s) with the
            window's mean removed (Hann window, zero-padded FFT).
With --plot, draws a_z of every run over the whole run and in the window, and the waist roll
minus the commanded roll (the lateral rocking).
"""
import csv
import sys

import numpy as np


def load(directory):
    w = list(csv.DictReader(open(f"{directory}/waist.csv")))
    c = list(csv.DictReader(open(f"{directory}/contacts.csv")))
    t = np.array([float(r["t"]) for r in w])
    vz = np.array([float(r["vz"]) for r in w])
    az = np.array([float(r["az"]) for r in w])
    rf = np.array([float(r["right_fz"]) for r in c])
    lf = np.array([float(r["left_fz"]) for r in c])
    roll = np.degrees([float(r["roll"]) - float(r["roll_ref"]) for r in w])
    return t, vz, az, rf, lf, roll


def main(argv):
    plot, window, runs = None, (3.8, 4.3), []
    i = 0
    while i < len(argv):
        if argv[i] == "--plot":
            plot = argv[i + 1]
            i += 2
        elif argv[i] == "--window":
            window = (float(argv[i + 1]), float(argv[i + 2]))
            i += 3
        else:
            label, _, directory = argv[i].partition("=")
            runs.append((label, directory or label))
            i += 1
    print(f"{'run':>14} {'dt_ms':>6} {'peak':>7} {'t_peak':>7} {'R_fz':>6} {'L_fz':>6} "
          f"{'start':>7} {'walk':>7} {'t_walk':>7} {'avg10':>7} {'t_avg10':>7} {'win':>6} {'win10':>6} "
          f"{'f_dom':>6}")
    curves = []
    for label, directory in runs:
        t, vz, az, rf, lf, roll = load(directory)
        dt = t[1] - t[0]
        k = int(np.argmax(np.abs(az)))
        walk = t >= 0.1
        kw = int(np.argmax(np.where(walk, np.abs(az), 0)))
        h = int(round(0.005 / dt))
        v = np.concatenate(([0.0], vz))  # v at t = 0 is zero (the robot starts at rest)
        avg = np.zeros_like(az)
        avg[h:-h] = (v[2 * h + 1:] - v[:-2 * h - 1])[: len(az) - 2 * h] / (2 * h * dt)
        ka = int(np.argmax(np.where(walk, np.abs(avg), 0)))
        sel = (t >= window[0]) & (t <= window[1])
        x = az[sel] - az[sel].mean()
        n = 1 << (8 * len(x) - 1).bit_length()
        spectrum = np.abs(np.fft.rfft(x * np.hanning(len(x)), n))
        freq = np.fft.rfftfreq(n, dt)
        f_dom = freq[int(np.argmax(spectrum[1:])) + 1]
        print(f"{label:>14} {1e3 * dt:6.3f} {abs(az[k]):7.2f} {t[k]:7.4f} {rf[k]:6.0f} {lf[k]:6.0f} "
              f"{abs(az[0]):7.2f} {abs(az[kw]):7.2f} {t[kw]:7.4f} {abs(avg[ka]):7.2f} {t[ka]:7.4f} "
              f"{np.abs(az[sel]).max():6.2f} {np.abs(avg[sel]).max():6.2f} {f_dom:6.1f}")
        curves.append((label, t, az, sel, roll))
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 3, figsize=(16, 4.2))
        for label, tt, aa, sel, roll in curves:
            axes[0].plot(tt, aa, lw=0.6, label=label)
            axes[1].plot(tt[sel], aa[sel], lw=1, label=label)
            axes[2].plot(tt, roll, lw=0.8, label=label)
        for ax, ylabel, title in zip(
                axes, ["waist a_z (m/s^2)", "waist a_z (m/s^2)", "roll - commanded roll (deg)"],
                ["whole run", f"window {window[0]} to {window[1]} s", "lateral rocking"]):
            ax.set_xlabel("t (s)")
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(plot, dpi=110)
        print(plot)


if __name__ == "__main__":
    main(sys.argv[1:])
