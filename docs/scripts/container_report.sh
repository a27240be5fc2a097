#!/usr/bin/env bash
# Runs problems/container.yaml (coarse, 0.6 ms, under a minute here), prints the burn,
# mass and radius tables, and writes docs/images/container_radius.png (the case's mean
# radius and the gap pressure against time) and docs/images/container_slice.png (the
# products' volume fraction on the mid-z slice with the particles, at the last output).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
dir="$build/demo/container"
rm -rf "$dir" && mkdir -p "$dir"
"$build/miniapp/mpmice" "$root/problems/container.yaml" --output-dir "$dir" --no-progress > "$dir/run.log"
/usr/bin/python3 "$root/docs/scripts/container_plot.py" "$dir" "$root/docs/images/container_radius.png" --check \
  | tee "$dir/report.txt"
last=$(ls "$dir"/fields_*.h5 | tail -1)
/usr/bin/python3 "$root/docs/scripts/render_fields.py" "$last" "$root/docs/images/container_slice.png" \
  volume_fraction_products
echo "slice: $last"
