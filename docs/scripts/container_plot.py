"""Exploding container: where the burn starts, the product gas, the case's mean radius.

Usage: /usr/bin/python3 docs/scripts/container_plot.py RUN_DIR [OUT.png] [--check]
Reads a run of problems/container.yaml: RUN_DIR/input.yaml (geometry), history.csv
(masses, heat of reaction released), probes.csv (probe `gap`) and every fields_*.h5
(the copper's particle positions, the products' volume fraction).
Mean radius: the mean of sqrt(x^2 + y^2) over the copper particles of the side wall
(|z| below the cavity's half-length). Prints the table; draws the mean radius and the gap
pressure against time if OUT.png is given. With --check, exits 1 unless every mass in
history.csv is finite and not negative, the products (at TINY_RHO at the start) gained
mass, the first output with product gas has it only within two cells of the
copper/PBX interface, and, from the first output where the gap pressure is twice its
initial value ("pressurised"), the mean radius never decreases.
"""
import csv
import glob
import os
import sys

import h5py
import numpy as np
import yaml


def main():
    check = "--check" in sys.argv
    args = [a for a in sys.argv[1:] if a != "--check"]
    run = args[0]
    with open(os.path.join(run, "input.yaml")) as f:
        inp = yaml.safe_load(f)
    grid = inp["grid"]
    h = (grid["upper"][0] - grid["lower"][0]) / grid["cells"][0]
    cyl = {g["material"]: g["cylinder"] for g in inp["geometry"] if "cylinder" in g}
    r_pbx, r_case = cyl["pbx"]["radius"], cyl["copper"]["radius"]
    z_cavity = max(g["cylinder"]["top"][2] for g in inp["geometry"] if "cylinder" in g and g["material"] != "copper")

    hist = np.genfromtxt(os.path.join(run, "history.csv"), delimiter=",", names=True)
    masses = [n for n in hist.dtype.names if n.startswith("mass")]
    ok_masses = all(np.all(np.isfinite(hist[n])) and np.all(hist[n] >= 0) for n in masses)
    products0, products1 = hist["massproducts"][0], hist["massproducts"][-1]
    print("total mass: %.3e relative change; products %.3e kg -> %.3e kg; PBX burned %.3e kg; heat released %.3e J"
          % (hist["masstotal"][-1] / hist["masstotal"][0] - 1, products0, products1,
             hist["masspbx"][0] - hist["masspbx"][-1], hist["chemical_energy_released"][-1]))

    gap = {}
    with open(os.path.join(run, "probes.csv")) as f:
        for r in csv.DictReader(f):
            if r["probe"] == "gap" and r["quantity"] == "pressure":
                gap[float(r["time"])] = float(r["value"])

    times, radii, first_products = [], [], None
    for path in sorted(glob.glob(os.path.join(run, "fields_*.h5"))):
        with h5py.File(path, "r") as f:
            x = np.array(f["particles/copper/position"])
            side = np.abs(x[:, 2]) < z_cavity
            times.append(float(f.attrs["time"]))
            radii.append(np.hypot(x[side, 0], x[side, 1]).mean())
            theta = np.array(f["cells/volume_fraction_products"])  # (z, y, x)
            if first_products is None and times[-1] > 0 and (theta > 1e-6).any():
                k, j, i = np.nonzero(theta > 1e-6)
                rc = np.hypot((i + 0.5) * h + grid["lower"][0], (j + 0.5) * h + grid["lower"][1])
                zc = (k + 0.5) * h + grid["lower"][2]
                # distance of each such cell centre from the cavity wall (side or end)
                dist = np.minimum(np.abs(rc - 0.5 * (r_pbx + r_case)), np.where(rc < r_case, np.abs(zc - z_cavity), 1e9))
                first_products = (times[-1], dist.max() / h, len(i))
    times, radii = np.array(times), np.array(radii)
    print("case mean radius (side wall):")
    for t, r in zip(times, radii):
        p = gap[min(gap, key=lambda s: abs(s - t))] if gap else float("nan")
        print("  t = %9.3e s   r = %.6f m   (%+.3e)   gap pressure %.4e Pa" % (t, r, r - radii[0], p))
    if first_products:
        print("first product gas (theta > 1e-6) at t = %.3e s, all within %.2f cells of the cavity wall (%d cells)"
              % first_products)

    if len(args) > 1:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].plot(times * 1e3, (radii - radii[0]) * 1e3, "o-", ms=3)
        ax[0].set_xlabel("time [ms]")
        ax[0].set_ylabel("mean radius change of the side wall [mm]")
        ax[0].set_title("copper case")
        tg = np.array(sorted(gap))
        ax[1].semilogy(tg * 1e3, [gap[t] / 1e6 for t in tg])
        ax[1].set_xlabel("time [ms]")
        ax[1].set_ylabel("pressure at probe 'gap' [MPa]")
        ax[1].set_title("gas between case and PBX")
        fig.tight_layout()
        fig.savefig(args[1], dpi=110)
        print("wrote", args[1])

    p_gap = np.array([gap[min(gap, key=lambda s: abs(s - t))] for t in times])
    pressurised = np.nonzero(p_gap >= 2 * p_gap[0])[0]
    growing = len(pressurised) > 1 and bool(np.all(np.diff(radii[pressurised[0]:]) >= 0))
    if len(pressurised):
        print("pressurised (gap pressure >= 2x initial) from t = %.3e s; mean radius %s since"
              % (times[pressurised[0]], "never decreased" if growing else "DECREASED"))

    if check:
        near = first_products is not None and first_products[1] <= 2.0
        gained = products1 > 1e3 * max(products0, 1e-30)
        passed = ok_masses and gained and near and growing
        print("check: %s (masses finite and >= 0: %s; products gained mass: %s; burn started at the interface: %s; "
              "radius grows once pressurised: %s)" % ("passed" if passed else "FAILED", ok_masses, gained, near, growing))
        sys.exit(0 if passed else 1)


if __name__ == "__main__":
    main()
