#!/usr/bin/env bash
# Runs problems/piston.yaml at 100 and 200 cells, prints the deviation from the
# adiabat for each, and writes docs/images/piston.png from the 200-cell run.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
for n in 100 200; do
  dir="$build/validation/piston_$n"
  "$build/miniapp/mpmice" "$root/problems/piston.yaml" --output-dir "$dir" --no-progress \
    --set "grid.cells=[1,$n,1]" > /dev/null
  echo "$n cells:"
  /usr/bin/python3 "$root/docs/scripts/piston_plot.py" "$dir" \
    $([ "$n" = 200 ] && echo "$root/docs/images/piston.png")
done
