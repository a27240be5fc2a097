#!/usr/bin/env bash
# Runs problems/sod.yaml at 100, 200 and 400 cells, prints the L1 error table
# against the exact solution and writes docs/images/sod.png (docs/validation.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
runs=()
for n in 100 200 400; do
  dir="$build/validation/sod_$n"
  "$build/miniapp/mpmice" "$root/problems/sod.yaml" --output-dir "$dir" --no-progress \
    --set "grid.cells=[$n,1,1]" > /dev/null
  runs+=("$dir")
done
mkdir -p "$root/docs/images"
cd "$root/docs/scripts"
/usr/bin/python3 sod_plot.py "$root/docs/images/sod.png" "${runs[@]}"
