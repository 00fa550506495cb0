#!/bin/sh
# Issue 25's fine-sole study in one command:
#   bench/fine_sole/run.sh [BUILD_DIR] [OUT_DIR] [STAGE ...]
# Stages (all by default, in this order; each resumable by rerunning it alone):
#   scaling   cost per step, contact-solve share, set-up time and kept operator against the
#             contact nodes per foot: the robot standing 0.05 s on Q1 soles, the full condensed
#             sole from 2 cm to 4 mm (96 to 2016 nodes; at 3 mm the run was killed for memory)
#             and reduced soles of 8 x 8 and 16 x 16 patches from 2 cm to 2.5 mm (to 5016
#             nodes) (work_precision --only "mesh size" / "mesh reduced", stand_hex.prm)
#   reduction reduced soles from the factorization of K (no dense C) against the dense route:
#             set-up time and memory, the reduction error estimate of uniform and Chebyshev
#             grids, 2 cm to 2.5 mm (reduction_bench; the dense route to 5 mm)
#   walk_1cm  the six-step walk on the 1 cm sole (walk_1cm.prm, 345 nodes): uniform reduced
#             soles of 8 x 8 and 16 x 16 patches, Chebyshev-graded ones of 4 x 4 to 16 x 16 and
#             graded auto at 0.01, graded 16 x 16 with area shares (the scene default) and the
#             bilinear basis on graded 4 x 4 to 12 x 12 grids, against the full sole
#             (work_precision --only "sole model")
#             and auto on the pressure estimate at 0.05 and 0.03 (Sole/Reduction quantity)
#   walk_5mm  the same on the 5 mm sole (walk_5mm.prm, 1305 nodes): uniform 8 x 8 and
#             16 x 16, graded 8 x 8 to 16 x 16 and graded auto at 0.01, bilinear 6 x 6 to
#             12 x 12 (9 x 9: walk_5mm_bilinear.prm), auto on the pressure at 0.01
#   walk_5mm_p2  the 5 mm sole in Q2 hexahedra (walk_5mm_p2.prm, 5073 nodes; no full sole):
#             bilinear 6 x 6 to 12 x 12 against the bilinear 20 x 20
#   hmatrix   one contact solve on the H-matrix compliance against the dense one, 96 to 2016
#             nodes (hierarchical_compliance_bench)
#   table     OUT_DIR/tables.md and OUT_DIR/scaling.png (table.py)
# Every run is pinned to core 1 (taskset -c 1; PLANTAR_BENCH_CORE=0 for core 0); run two stages
# at once (one per core) only to save time, and say so next to the figures. Results: docs/performance.md, "Fine soles".
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/fine_sole}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] && shift
stages=${*:-scaling reduction walk_1cm walk_5mm walk_5mm_p2 hmatrix table}
cmake --build "$build" --target work_precision hierarchical_compliance_bench reduction_bench -j2
export PLANTAR_MESH_CACHE=${PLANTAR_MESH_CACHE:-$build/mesh-cache}
mkdir -p "$out"
core=${PLANTAR_BENCH_CORE:-1}
wp="taskset -c $core $build/bench/work_precision/work_precision"
cd "$root"
for stage in $stages; do
  case $stage in
  scaling)
    $wp "$here/stand_hex.prm" --out "$out/scaling" --duration 0.05 --no-hyperelastic \
      --only "mesh size" --mesh-sizes 0.02,0.0125,0.008,0.006,0.005,0.004 >"$out/scaling.txt"
    $wp "$here/stand_hex.prm" --out "$out/scaling_reduced" --duration 0.05 --no-hyperelastic \
      --only "mesh reduced" --mesh-patches 8,16 \
      --mesh-sizes 0.02,0.0125,0.008,0.006,0.005,0.004,0.003,0.0025 >"$out/scaling_reduced.txt" ;;
  reduction)
    taskset -c "$core" "$build/bench/coupling/reduction_bench" --dense-up-to 0.005 0.02 0.01 \
      0.005 0.004 0.003 0.0025 >"$out/reduction.txt" ;;
  walk_1cm)
    $wp "$here/walk_1cm.prm" --out "$out/walk_1cm" --no-hyperelastic --only "sole model" \
      --patches 8,16 --graded-patches 4,8,12,16 --graded-auto 0.01 --area-patches 16 \
      --bilinear-patches 4,6,8,12 --pressure-auto 0.05,0.03 >"$out/walk_1cm.txt" ;;
  walk_5mm)
    $wp "$here/walk_5mm.prm" --out "$out/walk_5mm" --no-hyperelastic --only "sole model" \
      --patches 8,16 --graded-patches 8,12,16 --graded-auto 0.01 --bilinear-patches 6,8,9,12,16 \
      --pressure-auto 0.01 >"$out/walk_5mm.txt" ;;
  walk_5mm_p2)
    $wp "$here/walk_5mm_p2.prm" --out "$out/walk_5mm_p2" --no-hyperelastic --only "sole model" \
      --patches 2 --bilinear-patches 6,9,12,20 --no-full >"$out/walk_5mm_p2.txt" ;;
  hmatrix)
    taskset -c "$core" "$build/bench/coupling/hierarchical_compliance_bench" 0.02 0.0125 0.008 0.005 \
      0.004 >"$out/hmatrix.txt" ;;
  table)
    /usr/bin/python3 "$here/table.py" "$out" >"$out/tables.md"
    cat "$out/tables.md" ;;
  *)
    echo "run.sh: unknown stage '$stage' (scaling, reduction, walk_1cm, walk_5mm, walk_5mm_p2," \
      "hmatrix, table)" >&2
    exit 1 ;;
  esac
done
