#!/usr/bin/python3
"""Crash safety (issue 27): `plantar run` and `plantar sweep` killed with SIGKILL at random
moments, then started again, leave no corrupt file and give the results of an uninterrupted
run.

  run    a short HRP-2 drop (fem sole, CSV and ParaView series) is killed --kills times at
         moments drawn uniformly over an uninterrupted run's wall time; after each kill every
         file under its final name is complete (CSV rows as long as their header, VTK XML
         files closed by </VTKFile>) and no summary of an earlier run is left beside the new
         run's partial outputs; then the run is started again to completion and every output
         file equals the uninterrupted run's byte for byte (summaries without their wall times),
         with no temporary file left.
  sweep  a 2 x 2 sweep of short drops is killed --kills times, each time resumed, then
         finished; its sweep.csv equals an uninterrupted sweep's (wall-time columns aside).
Exit status 0 on success, 1 with the failed checks listed.
"""
import argparse
import pathlib
import random
import shutil
import signal
import subprocess
import sys
import time

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


RUN_SCENE = """include {source}/scenes/drop.prm
subsection Robot
  set Foot form = fem sole
end
subsection Simulation
  set Duration = 0.25
end
subsection Output
  set VTK every = 10
end
"""

SWEEP_SCENE = """include {source}/scenes/sweep_drop.prm
subsection Simulation
  set Duration = 0.05
end
subsection Sweep
  set Young's moduli = 2e6, 4e6
  set Poisson ratios = 0.3, 0.45
end
"""

WALL_TIME = ("wall time", "wall_time", "outputs in", "seconds")


def incomplete(path):
    """Why @p path is not a complete output file, or None."""
    data = path.read_bytes()
    if path.suffix == ".csv":
        rows = data.decode(errors="replace").split("\n")
        if rows[-1] != "":
            return "no final newline"
        width = len(rows[0].split(","))
        bad = [r for r in rows[1:-1] if len(r.split(",")) != width]
        return f"{len(bad)} rows of the wrong length" if bad else None
    if path.suffix in (".vtu", ".vtp", ".pvd", ".pvtu", ".vtm"):
        return None if data.rstrip().endswith(b"</VTKFile>") else "not closed by </VTKFile>"
    return None


def comparable(path):
    """@p path's lines without what differs between identical runs: wall times (summary lines,
    CSV columns named *wall_time) and deal.II's date stamp in .vtu files."""
    lines = path.read_bytes().split(b"\n")
    if path.suffix == ".vtu":
        lines = [l for l in lines if not l.startswith(b"#This file was generated")]
    elif path.suffix == ".csv" and lines and b"wall_time" in lines[0]:
        keep = [j for j, h in enumerate(lines[0].split(b",")) if b"wall_time" not in h]
        lines = [b",".join(l.split(b",")[j] for j in keep) if l else l for l in lines]
    if path.name.startswith("summary"):
        lines = [l for l in lines if not any(w.encode() in l for w in WALL_TIME)]
    return lines


def files(directory):
    return sorted(p.relative_to(directory) for p in directory.rglob("*") if p.is_file())


def check_state(directory, label):
    for rel in files(directory):
        if ".tmp-" in rel.name:
            continue  # a killed process's temporary file: never under a final name
        why = incomplete(directory / rel)
        check(why is None, f"{label}: {rel}: {why}")


def kill_at(command, delay):
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               start_new_session=True)
    try:
        process.wait(timeout=delay)
        return True  # finished before the kill
    except subprocess.TimeoutExpired:
        import os
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        return False


def same_outputs(reference, directory, label, allow_temporary=False):
    ref, got = files(reference), [f for f in files(directory) if ".tmp-" not in f.name]
    left = [f for f in files(directory) if ".tmp-" in f.name]
    check(allow_temporary or not left, f"{label}: temporary files left after the finished run: {left[:3]}")
    check(ref == got, f"{label}: files differ: only in the reference "
          f"{sorted(set(ref) - set(got))[:3]}, only after the kills {sorted(set(got) - set(ref))[:3]}")
    for rel in set(ref) & set(got):
        check(comparable(reference / rel) == comparable(directory / rel),
              f"{label}: {rel} differs from the uninterrupted run")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--seed", type=int, default=27)
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    rng = random.Random(args.seed)

    # plantar run
    scene = work / "run.prm"
    scene.write_text(RUN_SCENE.format(source=args.source))
    command = lambda out: [args.plantar, "run", str(scene), "-o", str(out), "--no-figures"]
    start = time.time()
    r = subprocess.run(command(work / "run_ref"), capture_output=True, text=True)
    wall = time.time() - start
    check(r.returncode == 0, f"uninterrupted run failed: {r.stderr}")
    out = work / "run_killed"
    finished = 0
    for k in range(args.kills):
        delay = rng.uniform(0.02, 1.1) * wall
        finished += kill_at(command(out), delay)
        check_state(out, f"run, kill {k} at {delay:.2f} s")
        if (out / "summary.csv").exists():
            # summary.csv marks a finished run (plantar sweep relies on it): every output
            # beside it must then be the finished run's.
            same_outputs(work / "run_ref", out, f"run, kill {k} (summary.csv present)",
                         allow_temporary=True)
    print(f"run: {args.kills} kills over an uninterrupted wall time of {wall:.2f} s "
          f"({finished} runs finished before their kill)")
    r = subprocess.run(command(out), capture_output=True, text=True)
    check(r.returncode == 0, f"run after the kills failed: {r.stderr}")
    same_outputs(work / "run_ref", out, "run")

    # plantar sweep
    scene = work / "sweep.prm"
    scene.write_text(SWEEP_SCENE.format(source=args.source))
    command = lambda out: [args.plantar, "sweep", str(scene), "-o", str(out), "-j", "2"]
    start = time.time()
    r = subprocess.run(command(work / "sweep_ref"), capture_output=True, text=True)
    wall = time.time() - start
    check(r.returncode == 0, f"uninterrupted sweep failed: {r.stderr}")
    out = work / "sweep_killed"
    for k in range(args.kills):
        delay = rng.uniform(0.02, 1.1) * wall
        kill_at(command(out), delay)
        check_state(out, f"sweep, kill {k} at {delay:.2f} s")
    r = subprocess.run(command(out), capture_output=True, text=True)
    check(r.returncode == 0, f"sweep after the kills failed: {r.stderr}")
    check(comparable(work / "sweep_ref/sweep.csv") == comparable(out / "sweep.csv"),
          "sweep.csv after the kills differs from the uninterrupted sweep's")
    check_state(out, "sweep after the kills")
    print(f"sweep: {args.kills} kills over an uninterrupted wall time of {wall:.2f} s")
    if failures:
        print(f"{len(failures)} checks failed")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
