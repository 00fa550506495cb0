#!/usr/bin/env bash
# Runs a paraview/*.py script with pvpython on a virtual X server (Debian: paraview,
# python3-paraview, xvfb), e.g.
#   paraview/render.sh render_walk.py out/walk --every 5
# Xvfb sometimes refuses the first connection ("bad X server connection"): up to 3 tries.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
script=$1
shift
[ -f "$script" ] || script=$here/$script
for attempt in 1 2 3; do
  xvfb-run -n $((100 + RANDOM % 800)) -s "-screen 0 1920x1080x24" pvpython "$script" "$@" &&
    exit 0
  status=$?
  echo "render.sh: attempt $attempt failed (status $status)" >&2
done
exit "$status"
