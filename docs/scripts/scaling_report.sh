#!/usr/bin/env bash
# Strong and weak scaling of problems/blast_3d.yaml (3D, two fluids, 40 steps) on 1,
# 2 and 4 ranks of this machine, and strong scaling of the coarse container (the first
# 0.1 ms); prints cell-steps/s and the halo bytes per step.
# With more ranks than cores (4 here) Open MPI needs --oversubscribe and the ranks
# share cores, so the 4-rank figures measure overhead, not speedup. --bind-to none:
# Open MPI otherwise binds each of up to 2 ranks to one core, and a rank's threads
# then share that core.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
exe="${MPMICE_BUILD_DIR:-$root/build}/miniapp/mpmice"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false
run() {  # ranks threads cells [problem extra-arguments...]
  local out problem=${4:-blast_3d.yaml}
  out=$(OMP_NUM_THREADS=$2 mpiexec -n "$1" --oversubscribe --bind-to none "$exe" "$root/problems/$problem" \
        --output-dir "$(mktemp -d)" --no-progress --set "grid.cells=$3" "${@:5}" 2>/dev/null)
  local rate halo
  rate=$(echo "$out" | sed -n 's/.*(\([0-9.e+]*\) cell-steps\/s.*/\1/p')
  halo=$(echo "$out" | sed -n 's/.*halo exchange: \([0-9.e+]*\) MB.*/\1/p')
  printf "| %s | %s | %s | %s | %s |\n" "$1" "$2" "$3" "$rate" "${halo:-0}"
}
echo "| ranks | threads/rank | cells | cell-steps/s | halo MB/step (busiest rank) |"
echo "|---:|---:|---|---:|---:|"
echo "strong scaling, 32^3:" >&2
run 1 2 "[32,32,32]"
run 2 1 "[32,32,32]"
run 4 1 "[32,32,32]"
echo "weak scaling, 32^3 per rank:" >&2
run 2 1 "[64,32,32]"
run 4 1 "[64,64,32]"
echo "strong scaling, the coarse container (16^3 cells, 5047 particles, 0.1 ms):" >&2
for r in "1 2" "2 1" "4 1"; do
  # shellcheck disable=SC2086
  run $r "[16,16,16]" container.yaml --end-time 1e-4 --set output.field_interval=0
done
