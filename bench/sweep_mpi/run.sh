#!/bin/bash
# Speed-up of `plantar sweep` under MPI (docs/cluster.md): bench/sweep_mpi/sweep_8.prm run
# serially, at 1 and 2 MPI ranks, and with -j 2 on one process, R rounds of the four commands
# in turn (so that a change in the machine's load hits all four; fresh output directory each
# time). Prints a Markdown table: wall time of the whole command (median, min - max over the
# rounds), points per minute (from the median), the mean 1-minute load average at the starts,
# and whether every sweep.csv equals the serial one but for loop_wall_time.
#   bench/sweep_mpi/run.sh BUILD_DIR [OUT_DIR] [ROUNDS]
set -euo pipefail
build=$(realpath "$1")
out=$(realpath -m "${2:-out/sweep_mpi}")
rounds=${3:-3}
here=$(dirname "$(realpath "$0")")
plantar=$build/apps/plantar
mpirun="mpirun --allow-run-as-root --oversubscribe --bind-to none"
rm -rf "$out" && mkdir -p "$out"
comparable() { cut -d, -f1-13,15- "$1"; }
names=(serial "mpirun -np 1" "mpirun -np 2" "-j 2")
declare -A command=(
  [serial]="$plantar sweep $here/sweep_8.prm -j 1"
  [mpirun -np 1]="$mpirun -np 1 $plantar sweep $here/sweep_8.prm -j 1"
  [mpirun -np 2]="$mpirun -np 2 $plantar sweep $here/sweep_8.prm -j 1"
  [-j 2]="$plantar sweep $here/sweep_8.prm -j 2"
)
declare -A times loads
for r in $(seq "$rounds"); do
  for name in "${names[@]}"; do
    dir="$out/${name// /_}_$r"
    loads[$name]+="$(cut -d' ' -f1 /proc/loadavg) "
    start=$(date +%s.%N)
    ${command[$name]} -o "$dir" > "$dir.log" 2>&1
    end=$(date +%s.%N)
    times[$name]+="$(echo "$end - $start" | bc) "
  done
done
n=$(($(wc -l < "$out/serial_1/sweep.csv") - 1))
echo "| command | wall time (s): median (min - max of $rounds) | points/min | load average | sweep.csv = serial |"
echo "|---|---|---|---|---|"
for name in "${names[@]}"; do
  sorted=($(printf '%s\n' ${times[$name]} | sort -g))
  median=${sorted[$((${#sorted[@]} / 2))]}
  load=$(printf '%s\n' ${loads[$name]} | awk '{s += $1} END {printf "%.1f", s / NR}')
  same=yes
  for r in $(seq "$rounds"); do
    cmp -s <(comparable "$out/${name// /_}_$r/sweep.csv") <(comparable "$out/serial_1/sweep.csv") ||
      same=no
  done
  printf '| %s | %.1f (%.1f - %.1f) | %.1f | %s | %s |\n' "$name" "$median" "${sorted[0]}" \
    "${sorted[-1]}" "$(echo "60 * $n / $median" | bc -l)" "$load" "$same"
done
