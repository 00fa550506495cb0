#!/usr/bin/env python3
"""The build targets that the selected tests run: read `ctest --show-only=json-v1` on stdin and
the build's target list (`cmake --build TREE --target help`) from the file argv[2]; print, one
per line, the targets whose executable a test command names inside TREE (argv[1]), the command
itself or an argument (e.g. `--plantar TREE/apps/plantar`). Prints nothing if either input
cannot be read: the caller then builds every target."""
import json
import os
import sys

tree = os.path.realpath(sys.argv[1])
try:
    tests = json.load(sys.stdin)["tests"]
    with open(sys.argv[2]) as listing:
        known = {line.split()[1] for line in listing if line.startswith("... ")}
except (OSError, ValueError, KeyError, IndexError):
    sys.exit(0)
targets = set()
for test in tests:
    for word in test.get("command", []):
        path = os.path.realpath(word)
        if path.startswith(tree + os.sep) and os.path.basename(path) in known:
            targets.add(os.path.basename(path))
print("\n".join(sorted(targets)))
