#!/bin/sh
# Two plantar builds side by side on the fine-sole scenes (issue 25): the loop time per
# simulated second, the share of contact solves taken directly, the iterations, and how far the
# new build's figures are from the old one's.
#   bench/fine_sole/compare_builds.sh OLD_PLANTAR NEW_PLANTAR OUT_DIR [SCENE ...]
# Scenes (all by default): stand_<h> (the robot standing 0.05 s on the full Q1 sole of mesh size
# h = 0.02, 0.0125, 0.008, 0.006, 0.005 m), walk_<mesh>_g<g> (the six-step walk of walk_1cm.prm
# or walk_5mm.prm on the Chebyshev-graded reduced sole of g x g patches in the constant basis,
# g = 8, 12, 16), walk_<mesh>_b<g> (the same in the bilinear basis; not by default) and
# walk_1cm_full. Builds from 42b7492 on (Sole/Reduction basis). NEW runs on core 0 while OLD runs the same scene on core 1 (the same load on
# both). Writes OUT_DIR/compare.md (compare_builds.py). Results: docs/performance.md.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
old=$(realpath "$1")
new=$(realpath "$2")
out=$3
shift 3
scenes=${*:-stand_0.02 stand_0.0125 stand_0.008 stand_0.006 stand_0.005 walk_1cm_g8 walk_1cm_g12 \
walk_1cm_g16 walk_5mm_g8 walk_5mm_g12 walk_5mm_g16 walk_1cm_full}
mkdir -p "$out/scenes"
export PLANTAR_MESH_CACHE=${PLANTAR_MESH_CACHE:-$root/build/mesh-cache}
for scene in $scenes; do
  prm="$out/scenes/$scene.prm"
  case $scene in
  stand_*)
    printf 'include %s\nsubsection Sole\n  set Mesh size = %s\nend\nsubsection Simulation\n  set Duration = 0.05\nend\n' \
      "$here/stand_hex.prm" "${scene#stand_}" >"$prm" ;;
  walk_*_full)
    mesh=${scene#walk_}
    printf 'include %s\n' "$here/walk_${mesh%_full}.prm" >"$prm" ;;
  walk_*_g* | walk_*_b*)
    mesh=${scene#walk_}
    g=${mesh##*_[gb]}
    case $mesh in *_g*) basis=constant ;; *) basis=bilinear ;; esac
    printf 'include %s\nsubsection Sole\n  set Reduced patches = %s, %s\n  set Reduction basis = %s\nend\n' \
      "$here/walk_${mesh%_[gb]*}.prm" "$g" "$g" "$basis" >"$prm" ;;
  *)
    echo "compare_builds.sh: unknown scene '$scene'" >&2
    exit 1 ;;
  esac
  printf 'subsection Output\n  set Write VTU = false\nend\n' >>"$prm"
  (cd "$root" && taskset -c 0 "$new" run "$prm" -o "$out/new/$scene" --no-figures >"$out/$scene.new.log" 2>&1) &
  (cd "$root" && taskset -c 1 "$old" run "$prm" -o "$out/old/$scene" --no-figures >"$out/$scene.old.log" 2>&1)
  wait
done
/usr/bin/python3 "$here/compare_builds.py" "$out" $scenes >"$out/compare.md"
cat "$out/compare.md"
