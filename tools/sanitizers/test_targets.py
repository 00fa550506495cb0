#!/usr/bin/env python3
"""The build targets that the selected tests run. Reads `ctest --show-only=json-v1` of the
selected tests on stdin (their names: ctest leaves out the command of a test whose program is
not built yet), their commands from the CTestTestfile.cmake files under TREE (argv[1]), and the
build's target list (`cmake --build TREE --target help`) from the file argv[2]; prints, one per
line, the targets whose executable a selected test's command names inside TREE (the program
itself or an argument, e.g. `--plantar TREE/apps/plantar`). Prints nothing if an input cannot be
read: the caller then builds every target."""
import json
import os
import re
import sys

tree = os.path.realpath(sys.argv[1])
try:
    selected = {test["name"] for test in json.load(sys.stdin)["tests"]}
    with open(sys.argv[2]) as listing:
        known = {line.split()[1] for line in listing if line.startswith("... ")}
except (OSError, ValueError, KeyError, IndexError):
    sys.exit(0)
add_test = re.compile(r'^add_test\(\[=\[(.*?)\]=\]\s+(.*)\)\s*$')
quoted = re.compile(r'"((?:[^"\\]|\\.)*)"')
targets = set()
for directory, _, files in os.walk(tree):
    if "CTestTestfile.cmake" not in files:
        continue
    with open(os.path.join(directory, "CTestTestfile.cmake")) as testfile:
        for line in testfile:
            match = add_test.match(line.strip())
            if not match or match.group(1) not in selected:
                continue
            for word in quoted.findall(match.group(2)):
                path = os.path.realpath(word)
                if path.startswith(tree + os.sep) and os.path.basename(path) in known:
                    targets.add(os.path.basename(path))
print("\n".join(sorted(targets)))
