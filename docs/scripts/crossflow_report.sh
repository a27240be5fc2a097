#!/usr/bin/env bash
# Runs problems/crossflow.yaml (coarse, 0.2 s, about a minute here), prints the tip
# deflection and inflow tables, and writes docs/images/crossflow_tip.png and
# docs/images/crossflow_slice.png (pressure on the mid-z slice with the beam's particles,
# at the output nearest the largest deflection).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/ci/build" > /dev/null
build=${MPMICE_BUILD_DIR:-$root/build}
dir="$build/demo/crossflow"
rm -rf "$dir"
"$build/miniapp/mpmice" "$root/problems/crossflow.yaml" --output-dir "$dir" --no-progress > /dev/null
/usr/bin/python3 "$root/docs/scripts/crossflow_plot.py" "$dir" "$root/docs/images/crossflow_tip.png" | tee "$dir/report.txt"
step=$(/usr/bin/python3 - "$dir" <<'PY'
import glob, sys, h5py, numpy as np
best, name = -1e300, None
for path in sorted(glob.glob(sys.argv[1] + "/fields_*.h5")):
    with h5py.File(path, "r") as f:
        x = np.array(f["particles/beam/position"])
    top = x[:, 1] >= x[:, 1].max() - 0.0625
    if x[top, 0].mean() > best:
        best, name = x[top, 0].mean(), path
print(name)
PY
)
/usr/bin/python3 "$root/docs/scripts/render_fields.py" "$step" "$root/docs/images/crossflow_slice.png" pressure
echo "slice: $step"
