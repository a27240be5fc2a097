#!/usr/bin/env bash
# Runs problems/block_in_gas.yaml with field output every 100 steps and renders the
# last output (docs/images/block_in_gas.png, docs/visualization.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
dir="$build/visualization/block_in_gas"
rm -rf "$dir"
"$build/miniapp/mpmice" "$root/problems/block_in_gas.yaml" --output-dir "$dir" --no-progress \
  --set output.field_interval=100 > /dev/null
/usr/bin/python3 "$root/docs/scripts/render_fields.py" "$dir/fields_000500.h5" "$root/docs/images/block_in_gas.png" \
  pressure
