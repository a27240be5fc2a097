"""Exploding container: where the burn starts, the product gas, the case's mean radius.

Usage: /usr/bin/python3 docs/scripts/container_plot.py RUN_DIR [OUT.png] [--side SIDE.png] [--check]
Reads a run of problems/container.yaml: RUN_DIR/input.yaml (geometry, the copper's
failure_strain), history.csv (masses, heat of reaction released), probes.csv (probe
`gap`) and every fields_*.h5 (the copper's particle positions and plastic strain, the
products' volume fraction).
Mean radius: the mean of sqrt(x^2 + y^2) over the copper particles of the side wall
(|z| below the cavity's half-length). Failed: copper particles whose plastic strain has
reached failure_strain (they carry no tension or shear any more: the case breaks there).
Prints the table; draws the mean radius, the failed particles and the gap pressure
against time if OUT.png is given, and with --side the y = 0 cell layer (products' volume
fraction, the particles of that layer, failed copper in red) at four times of the second
half of the run. With --check, exits 1 unless every mass in history.csv is finite and
not negative, the products (at TINY_RHO at the start) gained mass, the first output with
product gas has it only within two cells of the copper/PBX interface, from the first
output where the gap pressure is twice its initial value ("pressurised") the mean
radius never decreases, and, if the copper has a failure_strain, the case has failed
somewhere by the end.
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
    argv = sys.argv[1:]
    side_png = None
    if "--side" in argv:
        side_png = argv[argv.index("--side") + 1]
        del argv[argv.index("--side"):argv.index("--side") + 2]
    args = [a for a in argv if a != "--check"]
    run = args[0]
    with open(os.path.join(run, "input.yaml")) as f:
        inp = yaml.safe_load(f)
    grid = inp["grid"]
    h = (grid["upper"][0] - grid["lower"][0]) / grid["cells"][0]
    cyl = {g["material"]: g["cylinder"] for g in inp["geometry"] if "cylinder" in g}
    r_pbx, r_case = cyl["pbx"]["radius"], cyl["copper"]["radius"]
    z_cavity = max(g["cylinder"]["top"][2] for g in inp["geometry"] if "cylinder" in g and g["material"] != "copper")
    copper = next(m for m in inp["materials"] if m["name"] == "copper")
    eps_f = copper.get("failure_strain")

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

    times, radii, failed, first_products, first_failure = [], [], [], None, None
    outputs = sorted(glob.glob(os.path.join(run, "fields_*.h5")))
    for path in outputs:
        with h5py.File(path, "r") as f:
            x = np.array(f["particles/copper/position"])
            side = np.abs(x[:, 2]) < z_cavity
            times.append(float(f.attrs["time"]))
            radii.append(np.hypot(x[side, 0], x[side, 1]).mean())
            broken = np.zeros(len(x), bool)
            if eps_f is not None and "plastic_strain" in f["particles/copper"]:
                broken = np.array(f["particles/copper/plastic_strain"]) >= eps_f
            failed.append(int(broken.sum()))
            if first_failure is None and broken.any():
                r = np.hypot(x[broken, 0], x[broken, 1])
                first_failure = (times[-1], broken.sum(), r.min(), r.max(), x[broken, 2].min(), x[broken, 2].max())
            theta = np.array(f["cells/volume_fraction_products"])  # (z, y, x)
            if first_products is None and times[-1] > 0 and (theta > 1e-6).any():
                k, j, i = np.nonzero(theta > 1e-6)
                rc = np.hypot((i + 0.5) * h + grid["lower"][0], (j + 0.5) * h + grid["lower"][1])
                zc = (k + 0.5) * h + grid["lower"][2]
                # distance of each such cell centre from the cavity wall (side or end)
                dist = np.minimum(np.abs(rc - 0.5 * (r_pbx + r_case)), np.where(rc < r_case, np.abs(zc - z_cavity), 1e9))
                first_products = (times[-1], dist.max() / h, len(i))
    times, radii = np.array(times), np.array(radii)
    print("case mean radius (side wall), failed copper particles:")
    for t, r, nf in zip(times, radii, failed):
        p = gap[min(gap, key=lambda s: abs(s - t))] if gap else float("nan")
        print("  t = %9.3e s   r = %.6f m   (%+.3e)   gap pressure %.4e Pa   failed %5d"
              % (t, r, r - radii[0], p, nf))
    if first_products:
        print("first product gas (theta > 1e-6) at t = %.3e s, all within %.2f cells of the cavity wall (%d cells)"
              % first_products)
    if first_failure:
        print("first failed copper at t = %.3e s: %d particles, r %.1f-%.1f mm, z %.1f-%.1f mm"
              % (first_failure[0], first_failure[1], *[1e3 * v for v in first_failure[2:]]))
    elif eps_f is not None:
        print("no copper particle reached the failure strain %g" % eps_f)

    if len(args) > 1:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].plot(times * 1e3, (radii - radii[0]) * 1e3, "o-", ms=3, label="mean radius change")
        ax[0].set_xlabel("time [ms]")
        ax[0].set_ylabel("mean radius change of the side wall [mm]")
        ax[0].set_title("copper case")
        if eps_f is not None:
            twin = ax[0].twinx()
            twin.plot(times * 1e3, failed, "r--", label="failed particles")
            twin.set_ylabel("failed copper particles (plastic strain >= %g)" % eps_f, color="r")
        tg = np.array(sorted(gap))
        ax[1].semilogy(tg * 1e3, [gap[t] / 1e6 for t in tg])
        ax[1].set_xlabel("time [ms]")
        ax[1].set_ylabel("pressure at probe 'gap' [MPa]")
        ax[1].set_title("gas between case and PBX")
        fig.tight_layout()
        fig.savefig(args[1], dpi=110)
        print("wrote", args[1])

    if side_png:
        draw_side_view(outputs, times, grid, h, eps_f, side_png)
        print("wrote", side_png)

    p_gap = np.array([gap[min(gap, key=lambda s: abs(s - t))] for t in times])
    pressurised = np.nonzero(p_gap >= 2 * p_gap[0])[0]
    growing = len(pressurised) > 1 and bool(np.all(np.diff(radii[pressurised[0]:]) >= 0))
    if len(pressurised):
        print("pressurised (gap pressure >= 2x initial) from t = %.3e s; mean radius %s since"
              % (times[pressurised[0]], "never decreased" if growing else "DECREASED"))

    if check:
        near = first_products is not None and first_products[1] <= 2.0
        gained = products1 > 1e3 * max(products0, 1e-30)
        ruptured = eps_f is None or failed[-1] > 0
        passed = ok_masses and gained and near and growing and ruptured
        print("check: %s (masses finite and >= 0: %s; products gained mass: %s; burn started at the interface: %s; "
              "radius grows once pressurised: %s; case failed: %s)"
              % ("passed" if passed else "FAILED", ok_masses, gained, near, growing,
                 ruptured if eps_f is not None else "no failure_strain"))
        sys.exit(0 if passed else 1)


def draw_side_view(outputs, times, grid, h, eps_f, png):
    """The y = 0 cell layer (x, z) at four times of the run's second half: the products'
    volume fraction, with the particles whose centres lie in that layer."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lo, hi = grid["lower"], grid["upper"]
    picks = [int(np.argmin(np.abs(times - t))) for t in np.linspace(0.5, 1.0, 4) * times[-1]]
    fig, axes = plt.subplots(1, 4, figsize=(15, 4.2), constrained_layout=True)
    for ax, i in zip(axes, picks):
        with h5py.File(outputs[i], "r") as f:
            theta = np.array(f["cells/volume_fraction_products"])[:, 0, :]  # (z, x) at the y = 0 layer
            im = ax.imshow(theta, origin="lower", extent=[1e3 * lo[0], 1e3 * hi[0], 1e3 * lo[2], 1e3 * hi[2]],
                           vmin=0, vmax=1, cmap="Greens")
            x = np.array(f["particles/pbx/position"])
            layer = x[:, 1] < lo[1] + h
            ax.scatter(1e3 * x[layer, 0], 1e3 * x[layer, 2], s=3, c="orange", label="PBX")
            x = np.array(f["particles/copper/position"])
            layer = x[:, 1] < lo[1] + h
            broken = np.zeros(len(x), bool)
            if eps_f is not None and "plastic_strain" in f["particles/copper"]:
                broken = np.array(f["particles/copper/plastic_strain"]) >= eps_f
            ax.scatter(1e3 * x[layer & ~broken, 0], 1e3 * x[layer & ~broken, 2], s=3, c="b", label="copper")
            ax.scatter(1e3 * x[layer & broken, 0], 1e3 * x[layer & broken, 2], s=3, c="r", label="copper, failed")
        ax.set_title("t = %.3f ms" % (1e3 * times[i]))
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("z [mm]")
    axes[0].legend(loc="upper right", fontsize=7)
    fig.colorbar(im, ax=axes, label="products' volume fraction (cell layer at y = 0)", shrink=0.9)
    fig.savefig(png, dpi=90)


if __name__ == "__main__":
    main()
