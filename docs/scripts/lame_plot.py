"""Pressurised thick-walled cylinder: the steel's particle stresses against Lame.

Usage: /usr/bin/python3 docs/scripts/lame_plot.py RUN_DIR [OUT.png] [--max-error E]
Reads a run of problems/lame.yaml: RUN_DIR/input.yaml (inner radius a = the inner gas
cylinder, outer radius b = the steel cylinder), the last RUN_DIR/fields_*.h5 (the
particles' positions and Cauchy stresses) and RUN_DIR/probes.csv (the gas pressure
inside, p_i, and outside, p_o, at that time). Averages the radial and hoop stress of
the particles in rings one cell wide across the wall and compares them with
sigma_rr = A - B/r^2, sigma_tt = A + B/r^2, A = (p_i a^2 - p_o b^2)/(b^2 - a^2),
B = (p_i - p_o) a^2 b^2/(b^2 - a^2). The error of a ring is |mean - exact| / p_i (the
load; sigma_rr runs from -p_i to -p_o, so an error relative to the local value would
be meaningless near r = b). Prints the table; with --max-error, exits 1 if any ring is
further off than E; draws both profiles if OUT.png is given.
"""
import csv
import glob
import math
import os
import sys

import h5py
import numpy as np
import yaml


def lame(r, a, b, p_i, p_o):
    A = (p_i * a * a - p_o * b * b) / (b * b - a * a)
    B = (p_i - p_o) * a * a * b * b / (b * b - a * a)
    return A - B / r ** 2, A + B / r ** 2


def last_probe(run, probe):
    value = None
    with open(os.path.join(run, "probes.csv")) as f:
        for row in csv.DictReader(f):
            if row["probe"] == probe and row["quantity"] == "pressure":
                value = (float(row["time"]), float(row["value"]))
    return value


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    max_error = None
    if "--max-error" in sys.argv:
        max_error = float(sys.argv[sys.argv.index("--max-error") + 1])
        args.remove(sys.argv[sys.argv.index("--max-error") + 1])
    run = args[0]
    with open(os.path.join(run, "input.yaml")) as f:
        inp = yaml.safe_load(f)
    solid = next(m["name"] for m in inp["materials"] if m["model"] != "ideal_gas")
    cylinders = [g for g in inp["geometry"] if "cylinder" in g]
    b = next(g["cylinder"]["radius"] for g in cylinders if g["material"] == solid)
    a = next(g["cylinder"]["radius"] for g in cylinders if g["material"] != solid)
    grid = inp["grid"]
    h = (grid["upper"][0] - grid["lower"][0]) / grid["cells"][0]

    path = sorted(glob.glob(os.path.join(run, "fields_*.h5")))[-1]
    with h5py.File(path, "r") as f:
        time = float(f.attrs["time"])
        x = np.array(f["particles/%s/position" % solid])
        s = np.array(f["particles/%s/stress" % solid]).reshape(-1, 3, 3)
    t_in, p_i = last_probe(run, "inside")
    t_out, p_o = last_probe(run, "outside")
    r = np.hypot(x[:, 0], x[:, 1])
    n = np.stack([x[:, 0] / r, x[:, 1] / r, 0 * r], axis=1)
    t = np.stack([-x[:, 1] / r, x[:, 0] / r, 0 * r], axis=1)
    s_rr = np.einsum("pi,pij,pj->p", n, s, n)
    s_tt = np.einsum("pi,pij,pj->p", t, s, t)

    rings = max(1, int(round((b - a) / h)))
    edges = np.linspace(a, b, rings + 1)
    print("Lame cylinder at t = %.4g s (fields %s): p_i = %.6g Pa, p_o = %.6g Pa, a = %g m, b = %g m, "
          "%d particles" % (time, os.path.basename(path), p_i, p_o, a, b, len(r)))
    print("%8s %6s %12s %12s %8s %12s %12s %8s" % ("r [m]", "n", "s_rr", "exact", "err", "s_tt", "exact", "err"))
    worst = 0.0
    table = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (r >= lo) & (r < hi)
        if not sel.any():
            continue
        rm = r[sel].mean()
        er, et = lame(rm, a, b, p_i, p_o)
        mr, mt = s_rr[sel].mean(), s_tt[sel].mean()
        dr, dt = abs(mr - er) / p_i, abs(mt - et) / p_i
        worst = max(worst, dr, dt)
        table.append((rm, mr, mt))
        print("%8.4f %6d %12.5g %12.5g %7.2f%% %12.5g %12.5g %7.2f%%" % (rm, sel.sum(), mr, er, 100 * dr, mt, et,
                                                                          100 * dt))
    print("largest ring error: %.2f%% of p_i" % (100 * worst))

    pngs = [a for a in args[1:] if a.endswith(".png")]
    if pngs:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4.2))
        rr = np.linspace(a, b, 200)
        er, et = lame(rr, a, b, p_i, p_o)
        ax.plot(r, s_rr / 1e6, ".", ms=1.5, color="tab:blue", alpha=0.3)
        ax.plot(r, s_tt / 1e6, ".", ms=1.5, color="tab:red", alpha=0.3)
        tr = np.array(table)
        ax.plot(tr[:, 0], tr[:, 1] / 1e6, "o", color="tab:blue", label="radial, ring mean")
        ax.plot(tr[:, 0], tr[:, 2] / 1e6, "s", color="tab:red", label="hoop, ring mean")
        ax.plot(rr, er / 1e6, "k-", lw=1, label="Lame")
        ax.plot(rr, et / 1e6, "k-", lw=1)
        ax.set_xlabel("r [m]")
        ax.set_ylabel("stress [MPa]")
        ax.set_title("Thick-walled cylinder, p_i = %.1f MPa, t = %.2f ms" % (p_i / 1e6, time * 1e3))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(pngs[0], dpi=110)
    if max_error is not None and worst > max_error:
        print("FAILED: %.2f%% > %.2f%%" % (100 * worst, 100 * max_error))
        sys.exit(1)


if __name__ == "__main__":
    main()
