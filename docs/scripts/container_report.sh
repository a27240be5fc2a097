#!/usr/bin/env bash
# Runs problems/container.yaml (coarse, 0.6 ms, under a minute here), prints the burn,
# mass, radius and failure tables, and writes docs/images/container_radius.png (the
# case's mean radius, its failed particles and the gap pressure against time),
# docs/images/container_side.png (the products' volume fraction on the y = 0 cell layer
# with the particles, failed copper in red, at four times) and
# docs/images/container_slice.png (the pressure on the cell layer at the z = 0 symmetry
# plane with the particles, at the output nearest 0.45 ms, when the case is swelling).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
dir="$build/demo/container"
rm -rf "$dir" && mkdir -p "$dir"
"$build/miniapp/mpmice" "$root/problems/container.yaml" --output-dir "$dir" --no-progress > "$dir/run.log"
/usr/bin/python3 "$root/docs/scripts/container_plot.py" "$dir" "$root/docs/images/container_radius.png" \
  --side "$root/docs/images/container_side.png" --check \
  | tee "$dir/report.txt"
pick=$(/usr/bin/python3 - "$dir" <<'PY'
import glob, sys, h5py
files = sorted(glob.glob(sys.argv[1] + "/fields_*.h5"))
print(min(files, key=lambda p: abs(float(h5py.File(p, "r").attrs["time"]) - 4.5e-4)))
PY
)
/usr/bin/python3 "$root/docs/scripts/render_fields.py" "$pick" "$root/docs/images/container_slice.png" pressure 0
echo "slice: $pick"
