#!/bin/sh
# The work-precision study in one command (issue 8):
#   bench/work_precision/run.sh [BUILD_DIR] [OUT_DIR] [extra work_precision options]
# Builds the bench, runs it on scenes/drop.prm and scenes/walk.prm pinned to one core
# (taskset -c 1 when available), writes OUT_DIR/work_precision.csv, the PNG plots and the
# target runs (OUT_DIR/targets_*); OUT_DIR/tables.md holds the tables of docs/performance.md.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$build/work_precision}
[ $# -ge 2 ] && shift 2 || shift $#
cmake --build "$build" --target work_precision -j2
pin=""
command -v taskset >/dev/null 2>&1 && pin="taskset -c 1"
export PLANTAR_MESH_CACHE=${PLANTAR_MESH_CACHE:-$build/mesh-cache}
bench="$build/bench/work_precision/work_precision"
# The sweeps: drop 0.5 s, the whole 8 s walk; one run per configuration (the walk's
# reference runs are minutes each).
mkdir -p "$out"
$pin "$bench" "$root/scenes/drop.prm" "$root/scenes/walk.prm" --out "$out" --repeat 1 "$@" |
  tee "$out.txt"
/usr/bin/python3 "$here/plot.py" "$out"
/usr/bin/python3 "$here/table.py" "$out" >"$out/tables.md"
# The targets: the whole 8 s walk at the scene setting and at the fast setting (+ rigid feet).
$pin "$bench" "$root/scenes/walk.prm" --out "$out/targets_scene" --base-only --repeat 2 |
  tee "$out/targets_scene.txt"
$pin "$bench" "$here/drop_fast.prm" "$here/walk_fast.prm" --out "$out/targets_fast" --base-only \
  --repeat 2 | tee "$out/targets_fast.txt"
# The damped-sole walk (Kelvin-Voigt beta = 1 ms, theta = 1/2): fast setting and reference.
$pin "$bench" "$here/walk_damped_fast.prm" "$here/walk_damped_reference.prm" \
  --out "$out/targets_damped" --base-only --repeat 2 | tee "$out/targets_damped.txt"
# The elastic sole at theta = 0.6, dt 1 ms (fragile in dt and theta; see the scene file).
$pin "$bench" "$here/walk_elastic_fast.prm" --out "$out/targets_elastic" --base-only --repeat 2 |
  tee "$out/targets_elastic.txt"
