#!/usr/bin/python3
"""Scene fuzzer (issue 27): mutations of every scene in scenes/ and of the .prm, .geo and URDF
files they include or name, each run by `plantar run` in its own directory.

Mutation kinds (one per case, chosen by a seeded generator, so a failing case is replayed by
its seed and index):
  value      one `set` entry of the scene or of an included .prm: NaN, inf, huge, tiny,
             negative, zero, wrong type, empty, a broken number, a long string, a digit lost
  missing    one `set` entry deleted
  duplicate  one `set` entry set twice, the second value mutated (the last one wins, as in
             deal.II's ParameterHandler and as the scenes' overrides use)
  unknown    an undeclared entry or subsection added
  truncated  the scene, an included .prm, the .geo or the URDF cut at a random byte
  bytes      random bytes written over the scene, the .geo or the URDF
  geo        one number of the .geo replaced (NaN, huge, negative, zero)
  urdf       one numeric attribute of the URDF replaced (NaN, inf, huge, negative, zero), or a
             link, joint or inertial element deleted
Every case runs with Simulation/Duration = 0.02 s (unless the mutation is on Duration itself)
and --no-figures. A case passes if it either
  - exits 0, with a summary.txt and no NaN or inf in any CSV, or
  - exits 1 with an error message that names the file or the parameter (its name, or the file
    mutated), or a run failure with its step and time,
and in both cases within the time limit, with no signal, no sanitizer report on stderr, no
temporary file (*.tmp-*) left and every CSV complete (rows as long as the header).
Prints a table of outcomes per kind (for docs/reliability.md) and exits 1 if any case failed.
"""
import argparse
import collections
import concurrent.futures
import math
import os
import pathlib
import random
import re
import shutil
import subprocess
import sys
import time

DURATION = 0.02
BAD_VALUES = ["nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e-308", "-1", "0", "-0.5",
              "1e30", "abc", "", "1.2.3", "0x1p3", "1,2", "true", "9" * 400, "1e", "--1"]
# Entries whose legal values can make a run arbitrarily long: a case that reaches the time
# limit after mutating one of them is a valid but expensive request, counted as such.
COST_KEYS = {"Duration", "Time step", "Mesh size", "Element degree", "Max iterations",
             "Output every", "VTK every", "Settle time", "Number of steps", "Step duration",
             "Patch count", "Patches", "Refinements"}


class PrmFile:
    """A .prm file's lines with, for each `set` line, its subsection path and key."""

    def __init__(self, text):
        self.lines = text.split("\n")
        self.entries = []  # (line index, "Sub/Key", key)
        path = []
        for i, line in enumerate(self.lines):
            s = line.strip()
            if s.startswith("subsection "):
                path.append(s[len("subsection "):].strip())
            elif s == "end" and path:
                path.pop()
            elif s.startswith("set ") and "=" in s:
                key = s[4:s.index("=")].strip()
                self.entries.append((i, "/".join(path + [key]), key))

    def includes(self):
        return [l.strip()[len("include "):].strip() for l in self.lines
                if l.strip().startswith("include ")]

    def named_files(self):
        """Values of entries that name a file (Geometry file, URDF file)."""
        out = []
        for i, _, key in self.entries:
            if key.endswith("file"):
                out.append((key, self.lines[i].split("=", 1)[1].strip()))
        return out


def resolve(path, directory, source):
    for base in (directory, source):
        p = (base / path)
        if p.is_file():
            return p.resolve()
    return None


def scene_files(scene, source):
    """The scene's included .prm files (recursively) and the .geo / URDF files they name,
    as (role, path relative to the directory that resolves it, absolute path)."""
    files, seen = [], set()

    def visit(prm_path, directory, depth):
        prm = PrmFile(prm_path.read_text())
        for inc in prm.includes():
            p = resolve(inc, directory, source)
            if p and p not in seen:
                seen.add(p)
                # Only the top scene's own includes are found first next to the case's copy.
                if depth == 0:
                    files.append(("prm", inc, p))
                visit(p, p.parent, depth + 1)
        for key, value in prm.named_files():
            # Named files are resolved against the top scene's directory.
            p = resolve(value, scene.parent, source)
            if p and p not in seen:
                seen.add(p)
                files.append(("urdf" if value.endswith(".urdf") else "geo", value, p))

    visit(scene, scene.parent, 0)
    return files


def mutate_value(rng, value):
    choice = rng.random()
    if choice < 0.75 or not value:
        return rng.choice(BAD_VALUES)
    # A digit lost, or the number scaled by a large power of ten.
    numbers = list(re.finditer(r"-?\d+\.?\d*(e-?\d+)?", value))
    if not numbers:
        return rng.choice(BAD_VALUES)
    m = rng.choice(numbers)
    if choice < 0.9:
        new = m.group(0)[:-1] or "0"
    else:
        try:
            new = repr(float(m.group(0)) * 10.0 ** rng.choice([-12, -6, 6, 12]))
        except ValueError:
            new = "nan"
    return value[:m.start()] + new + value[m.end():]


def mutate_prm_text(rng, text, kind):
    """Returns (new text, mutated key or None)."""
    prm = PrmFile(text)
    lines = list(prm.lines)
    if kind in ("value", "missing", "duplicate") and prm.entries:
        i, full, key = rng.choice(prm.entries)
        head, value = lines[i].split("=", 1)
        if kind == "value":
            lines[i] = head + "= " + mutate_value(rng, value.strip())
        elif kind == "missing":
            lines[i] = ""
        else:
            lines.insert(i + 1, head + "= " + mutate_value(rng, value.strip()))
        return "\n".join(lines), key
    if kind == "unknown":
        i = rng.randrange(len(lines) + 1)
        extra = rng.choice(["set Bogus entry = 1", "subsection Bogus\nset A = 1\nend",
                            "include no/such/file.prm", "sett Duration = 1", "end",
                            "subsection Simulation"])
        lines.insert(i, extra)
        return "\n".join(lines), extra.split("\n")[0]
    return mutate_bytes(rng, text, kind), None


def mutate_bytes(rng, text, kind):
    data = bytearray(text.encode())
    if kind == "truncated" or not data:
        return bytes(data[:rng.randrange(len(data) + 1)]).decode(errors="replace")
    for _ in range(rng.randint(1, 8)):
        data[rng.randrange(len(data))] = rng.randrange(256)
    return bytes(data).decode("latin-1")


def mutate_geo(rng, text):
    numbers = list(re.finditer(r"(?<![A-Za-z_])\d+\.?\d*(e-?\d+)?", text))
    m = rng.choice(numbers)
    return text[:m.start()] + rng.choice(["nan", "1e308", "-1", "0", "1e-30"]) + text[m.end():]


def mutate_urdf(rng, text):
    if rng.random() < 0.7:
        attrs = list(re.finditer(r'(xyz|rpy|value|mass|ixx|iyy|izz|ixy|lower|upper|effort|'
                                 r'velocity|size|radius|length)="([^"]*)"', text))
        m = rng.choice(attrs)
        parts = m.group(2).split()
        parts[rng.randrange(len(parts))] = rng.choice(["nan", "inf", "1e308", "-1", "0",
                                                        "abc", ""])
        return text[:m.start(2)] + " ".join(parts) + text[m.end(2):]
    tag = rng.choice(["link", "joint", "inertial"])
    starts = [m.start() for m in re.finditer(f"<{tag}[ >]", text)]
    s = rng.choice(starts)
    end = text.find(f"</{tag}>", s)
    if end < 0:
        return text
    return text[:s] + text[end + len(tag) + 3:]


def make_case(rng, scenes, source, case_dir):
    """Writes one mutated case into @p case_dir; returns (scene path, kind, target, key)."""
    scene = rng.choice(scenes)
    files = scene_files(scene, source)
    kind = rng.choice(["value"] * 6 + ["missing", "duplicate", "unknown", "truncated", "bytes",
                                       "geo", "urdf"])
    case_dir.mkdir(parents=True)
    for sibling in scene.parent.glob("*.prm"):  # the scene's own includes, unmutated
        shutil.copy(sibling, case_dir / sibling.name)
    scene_text = scene.read_text()
    target, key = scene.name, None
    override = f"\nsubsection Simulation\n  set Duration = {DURATION}\nend\n"
    prms = [f for f in files if f[0] == "prm"]
    if kind == "geo" or kind == "urdf":
        candidates = [f for f in files if f[0] == kind]
        if not candidates:
            kind = "value"
    if kind in ("geo", "urdf") or (kind in ("truncated", "bytes") and rng.random() < 0.5):
        candidates = [f for f in files if kind not in ("geo", "urdf") or f[0] == kind]
        if candidates:
            role, rel, path = rng.choice(candidates)
            text = path.read_text()
            if kind == "geo":
                text = mutate_geo(rng, text)
            elif kind == "urdf":
                text = mutate_urdf(rng, text)
            else:
                text = mutate_bytes(rng, text, kind)
            dest = case_dir / rel
            dest.parent.mkdir(parents=True, exist_ok=True)
            if role == "urdf":  # the URDF's mesh files are found next to it
                for sibling in path.parent.iterdir():
                    if sibling.is_dir():
                        shutil.copytree(sibling, dest.parent / sibling.name, dirs_exist_ok=True)
            dest.write_text(text, errors="replace")
            target = rel
            (case_dir / "scene.prm").write_text(scene_text + override)
            return scene, kind, target, key
    if prms and kind in ("value", "missing", "duplicate", "unknown") and rng.random() < 0.3:
        role, rel, path = rng.choice(prms)
        text, key = mutate_prm_text(rng, path.read_text(), kind)
        dest = case_dir / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_text(text, errors="replace")
        (case_dir / "scene.prm").write_text(scene_text + override)
        return scene, kind, rel, key
    if kind in ("value", "missing", "duplicate", "unknown"):
        text, key = mutate_prm_text(rng, scene_text, kind)
        if key == "Duration":
            override = ""
        (case_dir / "scene.prm").write_text(text + override, errors="replace")
    else:
        # A cut or scrambled scene still gets the short duration (a line of its own).
        text = mutate_bytes(rng, scene_text, kind)
        (case_dir / "scene.prm").write_text(text + "\n" + override, errors="replace")
    return scene, kind, target, key


def undefined_allowed(header, cells, column):
    """A foot's centre of pressure (or the feet's ZMP) is undefined, and written as NaN, where
    the foot (both feet) carries less than 1 N (apps/humanoid_simulation.cc, docs/scenes.md)."""
    name = header[column]
    value = dict(zip(header, cells))
    min_load = 1.0
    for suffix in ("_copx", "_copy"):
        if name.endswith(suffix):
            return float(value.get(name[:-len(suffix)] + "_fz", "nan")) <= min_load
    if name.startswith("zmp_"):
        return float(value["right_fz"]) + float(value["left_fz"]) <= min_load
    return False


def csv_problems(out):
    problems = []
    for f in out.rglob("*.csv"):
        rows = f.read_text(errors="replace").strip().split("\n")
        header = rows[0].split(",")
        for r in rows[1:]:
            cells = r.split(",")
            if len(cells) != len(header):
                problems.append(f"{f.name}: a row of {len(cells)} cells, header {len(header)}")
                break
            bad = [header[j] for j, c in enumerate(cells)
                   if c.strip().lower() in ("nan", "-nan", "inf", "-inf") and
                   not undefined_allowed(header, cells, j)]
            if bad:
                problems.append(f"{f.name}: NaN or inf in {bad[:3]} at {cells[0]}")
                break
    return problems


def run_case(args, index):
    rng = random.Random(f"{args.seed}-{index}")
    case_dir = pathlib.Path(args.work) / f"case{index}"
    shutil.rmtree(case_dir, ignore_errors=True)
    scene, kind, target, key = make_case(rng, args.scenes, args.source, case_dir)
    out = case_dir / "out"
    start = time.time()
    try:
        r = subprocess.run([args.plantar, "run", str(case_dir / "scene.prm"), "-o", str(out),
                            "--no-figures"], capture_output=True, timeout=args.time_limit,
                           cwd=case_dir)
        rc, err = r.returncode, r.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired as e:
        rc, err = None, (e.stderr or b"").decode(errors="replace")
    seconds = time.time() - start
    label = f"case {index} ({scene.relative_to(args.source)}, {kind} of {target}" + \
            (f", entry {key}" if key else "") + ")"
    problems = []
    if re.search(r"AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|runtime error:",
                 err):
        problems.append("sanitizer report: " + err[:300])
    if rc is None:
        outcome = "slow" if key in COST_KEYS else "timeout"
        if outcome == "timeout":
            problems.append(f"no answer within {args.time_limit} s")
    elif rc == 0:
        outcome = "ran"
        if not (out / "summary.txt").is_file():
            problems.append("exit 0 without summary.txt")
    elif rc == 1:
        outcome = "rejected"
        lines = [l for l in err.split("\n") if re.search("error|failed", l, re.I)]
        names = {pathlib.Path(target).name, "scene.prm"} | ({key} if key else set())
        named = any(n and n in err for n in names) or re.search(r"step \d+, t = ", err) or \
            re.search(r"[A-Z][a-z]+( [a-z]+)*/[A-Z]", err)
        if not lines:
            problems.append("exit 1 without an error message")
        elif not named:
            problems.append("message names neither the file nor the parameter: " +
                            lines[0][:300])
    else:
        outcome = "crash"
        problems.append(f"exit status {rc}: " + err[-300:])
    if out.exists():
        left = [p.name for p in out.rglob("*") if ".tmp-" in p.name]
        if left:
            problems.append(f"temporary files left: {left[:3]}")
        problems += csv_problems(out) if rc == 0 else []
    if not problems and not args.keep:
        shutil.rmtree(case_dir, ignore_errors=True)
    return kind, outcome, problems, label, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--plantar", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--time-limit", type=float, default=400,
                        help="s per case (gmsh stops itself at 300 s)")
    parser.add_argument("--only", type=int, help="run only this case index")
    parser.add_argument("--keep", action="store_true", help="keep the case directories")
    parser.add_argument("--log", help="append one line per case (kind, outcome, problems) here")
    args = parser.parse_args()
    args.source = pathlib.Path(args.source).resolve()
    args.scenes = sorted(p for p in (args.source / "scenes").rglob("*.prm")
                         if p.name != "kestrel.prm")
    pathlib.Path(args.work).mkdir(parents=True, exist_ok=True)
    indices = [args.only] if args.only is not None else range(args.cases)
    table = collections.defaultdict(collections.Counter)
    failed = []
    start = time.time()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for kind, outcome, problems, label, seconds in pool.map(lambda i: run_case(args, i),
                                                                 indices):
            table[kind][outcome] += 1
            if args.log:
                with open(args.log, "a") as log:
                    log.write(f"{kind}\t{outcome}\t{seconds:.1f}\t{label}\t{'; '.join(problems)}\n")
            if problems:
                table[kind]["failed"] += 1
                failed.append(label + ": " + "; ".join(problems))
    outcomes = ["ran", "rejected", "slow", "timeout", "crash", "failed"]
    print(f"{len(indices)} cases, seed {args.seed}, {time.time() - start:.0f} s, "
          f"{len(args.scenes)} scenes")
    print("| kind | cases | " + " | ".join(outcomes) + " |")
    print("|---" * (len(outcomes) + 2) + "|")
    for kind in sorted(table):
        row = table[kind]
        print(f"| {kind} | {sum(row[o] for o in outcomes[:5])} | " +
              " | ".join(str(row[o]) for o in outcomes) + " |")
    for f in failed:
        print("FAIL:", f)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
