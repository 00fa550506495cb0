#!/usr/bin/python3
"""Markdown tables of bench/work_precision, one per scene, in the layout of
docs/performance.md. Usage: table.py DIR (reads DIR/work_precision.csv, prints the tables)."""
import csv
import math
import re
import sys

directory = sys.argv[1] if len(sys.argv) > 1 else "work_precision"
rows = list(csv.DictReader(open(f"{directory}/work_precision.csv")))
header = ("| knob | value | CPU s/s | x real time | solve share | GS iter | solve / pass | "
          "peak a_z | e_a | e_a_walk | e_a_avg10 | e_u | e_p | note |")


def number(text, form):
    value = float(text)
    return "-" if not math.isfinite(value) else format(value, form)


def error(r, key):
    if r["reference"] == "1" and r["knob"] != "rigid feet":
        return "ref"
    return number(r[key], ".2g")


def note(status):
    fell = re.search(r"t = ([0-9.]+) s: the robot fell", status)
    return f"fell at {fell.group(1)} s" if fell else status


for scene in dict.fromkeys(r["scene"] for r in rows):
    print(f"{scene}:\n\n{header}\n" + "| --- " * 14 + "|")
    for r in rows:
        if r["scene"] != scene or r["knob"] == "base":
            continue
        ok = r["status"] == "ok"
        cpu = float(r["cpu_per_sim_s"])
        share = 100 * float(r["contact_solve"]) / float(r["wall_per_sim_s"])
        cells = [r["knob"], r["value"], format(cpu, ".3g"), format(1 / cpu, ".2g"),
                 f"{share:.0f} %", number(r["mean_iterations"], ".1f"),
                 number(r["solve_over_pass"], ".1f") if ok else "-",
                 number(r["peak_az"], ".2f"),
                 error(r, "e_a") if ok else "-", error(r, "e_a_walk"), error(r, "e_a_avg10"),
                 error(r, "e_u") if ok else "-", error(r, "e_p") if ok else "-",
                 "" if ok else note(r["status"])]
        print("| " + " | ".join(cells) + " |")
    print()
