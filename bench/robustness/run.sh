#!/bin/sh
# The robustness matrix of the six-step walk with the DCM stabilizer (issue 23) in one command:
#   bench/robustness/run.sh [BUILD_DIR] [OUT_DIR] [JOBS]
# Sweeps (plantar sweep, resumable): forms_dt_theta.prm (3 forms x 4 dt x 3 theta),
# sole_material.prm (E x nu), the sole meshes of bench/impact_convergence/walk_mesh.prm, rough
# ground planned on it (rough.prm; rough_foothold.prm: with 9 x 9 contact grids and a foothold
# search; rough_foothold_p2.prm: its FEM sole on P2 tetrahedra; rough_foothold_seeds.prm: the
# rigid feet and the compliant ankle on two more rough grounds; rough_sole_stiffness.prm: the FEM sole from 4 MPa to 1 GPa on three rough grounds;
# rough_sole_thickness.prm: the 4 MPa sole 1, 3 and 4 cm thick;
# rough_foothold_timing.prm, rough_foothold_timing_short.prm: the three grounds with 0.6 / 0.2 s
# and 0.5 / 0.3 s support times),
# an unplanned 2 cm step (unplanned_step.prm) and the same step planned on (planned_step.prm);
# the flat walks, the rough grounds and the unplanned step with step adjustment (*_stepping.prm)
# and the walk pushed forward and sideways with and without it (push_walk.prm,
# push_walk_sideways.prm); step timing on the pushed walks (push_walk_timing.prm,
# push_walk_timing_sideways.prm, on FEM soles push_walk_timing_fem.prm), its gains
# (push_walk_timing_gains*.prm), on the rough grounds and over the unplanned step
# (rough_foothold_step_timing.prm, unplanned_step_step_timing.prm), the unplanned step on the
# Neo-Hookean sole (unplanned_step_hyperelastic.prm); the soft soles the linear
# sole cannot take with the Neo-Hookean sole (sole_material_hyperelastic.prm), the materials with
# the foot damping of the sole's tilt stiffness (sole_material_rate.prm; the Neo-Hookean soft
# soles with it, sole_material_hyperelastic_rate.prm), the published soft
# sole, linear and Neo-Hookean, with the default and the tilt-matched foot damping
# (soft_sole.prm, soft_sole_hyperelastic.prm), that damping on the default walk
# (foot_damping_rate.prm) and with the F/T sensors' 25 Hz low-pass on the three forms
# (forms_dt_theta_rule.prm; at dt 2 ms with that low-pass at 12.5 and 8 Hz,
# forms_dt2_theta_rule.prm), the sensors' delay, noise and bias (sensor_delay.prm,
# sensor_noise.prm, sensor_bias.prm); then OUT_DIR/tables.md by table.py (outcome and figures
# per case).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$build/robustness}
jobs=${3:-1}
cmake --build "$build" --target plantar -j2
export PLANTAR_MESH_CACHE=${PLANTAR_MESH_CACHE:-$build/mesh-cache}
mkdir -p "$out"
for scene in "$here/forms_dt_theta.prm" "$here/sole_material.prm" \
  "$root/bench/impact_convergence/walk_mesh.prm" "$here/rough.prm" "$here/rough_foothold.prm" \
  "$here/rough_foothold_p2.prm" \
  "$here/rough_foothold_seeds.prm" "$here/rough_sole_stiffness.prm" \
  "$here/rough_sole_thickness.prm" \
  "$here/rough_foothold_timing.prm" "$here/rough_foothold_timing_short.prm" \
  "$here/unplanned_step.prm" \
  "$here/planned_step.prm" "$here/flat_stepping.prm" "$here/rough_stepping.prm" \
  "$here/rough_foothold_stepping.prm" "$here/unplanned_step_stepping.prm" "$here/push_walk.prm" \
  "$here/push_walk_sideways.prm" "$here/push_walk_timing.prm" \
  "$here/push_walk_timing_sideways.prm" "$here/push_walk_timing_fem.prm" \
  "$here/push_walk_timing_gains.prm" "$here/push_walk_timing_gains_sideways.prm" \
  "$here/rough_foothold_step_timing.prm" \
  "$here/unplanned_step_step_timing.prm" "$here/unplanned_step_hyperelastic.prm" \
  "$here/sole_material_hyperelastic.prm" \
  "$here/sole_material_rate.prm" "$here/sole_material_hyperelastic_rate.prm" \
  "$here/soft_sole.prm" "$here/soft_sole_hyperelastic.prm" "$here/foot_damping_rate.prm" \
  "$here/forms_dt_theta_rule.prm" "$here/forms_dt2_theta_rule.prm" \
  "$here/sensor_delay.prm" "$here/sensor_noise.prm" "$here/sensor_bias.prm"; do
  # A failed point (a fall) is a result of the matrix, not an error of the script.
  "$build/apps/plantar" sweep "$scene" -o "$out/$(basename "$scene" .prm)" -j "$jobs" || true
done
/usr/bin/python3 "$here/table.py" "$out/forms_dt_theta" "$out/sole_material" "$out/walk_mesh" \
  "$out/rough" "$out/rough_foothold" "$out/rough_foothold_p2" "$out/rough_foothold_seeds" "$out/rough_sole_stiffness" "$out/rough_sole_thickness" \
  "$out/rough_foothold_timing" "$out/rough_foothold_timing_short" "$out/unplanned_step" \
  "$out/planned_step" "$out/flat_stepping" "$out/rough_stepping" \
  "$out/rough_foothold_stepping" "$out/unplanned_step_stepping" "$out/push_walk" \
  "$out/push_walk_sideways" "$out/push_walk_timing" "$out/push_walk_timing_sideways" \
  "$out/push_walk_timing_fem" "$out/push_walk_timing_gains" "$out/push_walk_timing_gains_sideways" \
  "$out/rough_foothold_step_timing" "$out/unplanned_step_step_timing" \
  "$out/unplanned_step_hyperelastic" \
  "$out/sole_material_hyperelastic" "$out/sole_material_rate" \
  "$out/sole_material_hyperelastic_rate" "$out/soft_sole" \
  "$out/soft_sole_hyperelastic" \
  "$out/foot_damping_rate" "$out/forms_dt_theta_rule" "$out/forms_dt2_theta_rule" "$out/sensor_delay" "$out/sensor_noise" \
  "$out/sensor_bias" \
  >"$out/tables.md"
cat "$out/tables.md"
