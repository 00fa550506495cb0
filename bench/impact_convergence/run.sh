#!/bin/sh
# The convergence study of the walk's impact figures (issue 23) in one command:
#   bench/impact_convergence/run.sh [BUILD_DIR] [OUT_DIR] [JOBS]
# Thirteen sweeps (plantar sweep, resumable): walk_dt.prm (three foot forms, dt 2 to 0.125 ms,
# theta 1/2 and 1), walk_dt_damping_rate.prm (rigid feet and soles with the foot damping of
# their tilt stiffness, theta 1/2), walk_dt_force_bandwidth.prm (that damping with the F/T
# sensors' 25 Hz low-pass, three forms, theta 1/2), walk_dt_sole.prm (elastic and viscoelastic sole, theta 1/2 and 1),
# walk_dt_visco.prm (the viscoelastic and the 2 MPa sole to 31.25 us), walk_mesh.prm (FEM sole,
# P1 3 to 1 cm), walk_mesh_p2.prm (P2 3 to 1.5 cm),
# walk_mesh_rule.prm, walk_mesh_rule_p2.prm, walk_mesh_rule_fine.prm (the default scene's FEM
# sole: P1 3 to 1 cm, P2 3 and 2 cm, reduced P1 and P2 at 1 cm and 5 mm), step_dt.prm and step_dt_playback.prm (the
# walk over a planned 2 cm step with and without the stabilizer), drop_dt_visco.prm (the drop
# on the viscoelastic and elastic soles, theta 1/2 and 1); then OUT_DIR/tables.md by table.py
# (figures, observed orders, error of the finest).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$build/impact_convergence}
jobs=${3:-1}
cmake --build "$build" --target plantar -j2
export PLANTAR_MESH_CACHE=${PLANTAR_MESH_CACHE:-$build/mesh-cache}
mkdir -p "$out"
for study in walk_dt walk_dt_damping_rate walk_dt_force_bandwidth walk_dt_sole walk_dt_visco walk_mesh walk_mesh_p2 walk_mesh_rule walk_mesh_rule_p2 walk_mesh_rule_fine step_dt step_dt_playback \
  drop_dt_visco; do
  # A failed point (a fall) is a result of the study, not an error of the script.
  "$build/apps/plantar" sweep "$here/$study.prm" -o "$out/$study" -j "$jobs" || true
done
/usr/bin/python3 "$here/table.py" "$out/walk_dt" "$out/walk_dt_damping_rate" \
  "$out/walk_dt_force_bandwidth" "$out/walk_dt_sole" \
  "$out/walk_dt_visco" \
  "$out/walk_mesh" "$out/walk_mesh_p2" "$out/walk_mesh_rule" "$out/walk_mesh_rule_p2" "$out/walk_mesh_rule_fine" \
  "$out/step_dt" "$out/step_dt_playback" >"$out/tables.md"
/usr/bin/python3 "$here/table.py" --landings-from 0 "$out/drop_dt_visco" >>"$out/tables.md"
cat "$out/tables.md"
exit 0
