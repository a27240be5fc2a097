"""Checks a run's HDF5 field output against its probes and its XDMF description.

Usage: /usr/bin/python3 check_output.py RUN_DIR PROBLEM.yaml
- every fields_*.h5 holds the cell fields with the grid's shape (z, y, x) and the
  particle fields with one row per particle;
- at each output step, the cell values at every probe's cell equal the probe's
  values in probes.csv (same state, written through a different path);
- every XDMF file parses as XML and every dataset it references exists with the
  dimensions it states.
Exits non-zero with a message on the first failure."""
import csv
import glob
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def main():
    run = sys.argv[1]
    files = sorted(glob.glob(os.path.join(run, "fields_*.h5")))
    if not files:
        fail("no fields_*.h5 in " + run)
    if glob.glob(os.path.join(run, "*.tmp")):
        fail("a temporary file was left behind")
    probes = {}
    with open(os.path.join(run, "probes.csv")) as f:
        for r in csv.DictReader(f):
            probes[(int(r["step"]), r["probe"], r["quantity"], r["material"])] = float(r["value"])
    checked = 0
    for path in files:
        with h5py.File(path, "r") as h5:
            step = int(h5.attrs["step"])
            if "cells" in h5:
                shape = h5["cells/pressure"].shape
                for name, ds in h5["cells"].items():
                    if ds.shape[:3] != shape:
                        fail("%s: %s has shape %s, pressure %s" % (path, name, ds.shape, shape))
                    if name.startswith("velocity_") and ds.shape[3:] != (3,):
                        fail("%s: %s is not a 3-vector field" % (path, name))
                # Probe values: find the probe's cell from the XDMF origin and spacing.
                xdmf = ET.parse(path[:-3] + ".xdmf").getroot()
                geo = [g for g in xdmf.iter("Geometry") if g.get("GeometryType") == "ORIGIN_DXDYDZ"][0]
                origin, spacing = [list(map(float, d.text.split())) for d in geo.findall("DataItem")]
                for (s, probe, quantity, material), value in probes.items():
                    if s != step:
                        continue
                    pos = probe_positions[probe]
                    idx = [min(int(math.floor((pos[2 - a] - origin[a]) / spacing[a])), shape[a] - 1) for a in range(3)]
                    name = quantity if material == "all" else quantity + "_" + material
                    if name not in h5["cells"]:
                        continue
                    got = float(h5["cells"][name][tuple(idx)])
                    if got != value:
                        fail("%s: %s at probe %s is %r, probes.csv says %r" % (path, name, probe, got, value))
                    checked += 1
            if "particles" in h5:
                for mat, group in h5["particles"].items():
                    n = group["position"].shape[0]
                    for name, ds in group.items():
                        if ds.shape[0] != n:
                            fail("%s: particles/%s/%s has %d rows, position %d" % (path, mat, name, ds.shape[0], n))
        # The XDMF of this output references datasets that exist, with their shapes.
        for item in ET.parse(path[:-3] + ".xdmf").getroot().iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            fname, dset = item.text.strip().split(":")
            dims = tuple(int(x) for x in item.get("Dimensions").split())
            with h5py.File(os.path.join(run, fname), "r") as h5:
                if dset not in h5:
                    fail("%s references missing %s" % (fname, dset))
                if h5[dset].shape != dims:
                    fail("%s: %s has shape %s, the XDMF says %s" % (fname, dset, h5[dset].shape, dims))
    series = ET.parse(os.path.join(run, "fields.xdmf")).getroot()
    times = [float(t.get("Value")) for t in series.iter("Time")]
    if times != sorted(times):
        fail("fields.xdmf: times out of order")
    print("output checked: %d files, %d probe values equal, XDMF references valid" % (len(files), checked))


probe_positions = {}
if __name__ == "__main__":
    import yaml_probes  # noqa: F401  (fills probe_positions)
    main()
