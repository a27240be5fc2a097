"""Sod shock tube: the mini-app's profiles against the exact Riemann solution.

Usage: /usr/bin/python3 docs/scripts/sod_plot.py OUT.png RUN_DIR [RUN_DIR ...]
Each RUN_DIR holds the fields.csv of a run of problems/sod.yaml. Prints a markdown
table of L1 errors (per unit length) of density, velocity and pressure with the
observed order between successive resolutions and the finest run's shocked density
plateau, and writes the profiles to OUT.png.
"""
import csv
import math
import os
import sys

from riemann import sample

LEFT = (1.0, 0.0, 1.0)
RIGHT = (0.125, 0.0, 0.1)
GAMMA, X0, T = 1.4, 0.5, 0.2


def load(run_dir):
    with open(os.path.join(run_dir, "fields.csv")) as f:
        rows = list(csv.DictReader(f))
    return ([float(r["x"]) for r in rows], [float(r["density"]) for r in rows],
            [float(r["velocity_x"]) for r in rows], [float(r["pressure"]) for r in rows])


def exact(x):
    return sample(x, T, X0, *LEFT, *RIGHT, GAMMA)


def main():
    out_png, runs = sys.argv[1], sys.argv[2:]
    data = sorted((load(r) for r in runs), key=lambda d: len(d[0]))
    print("| cells | L1 density | L1 velocity | L1 pressure | order (density) |")
    print("|---:|---:|---:|---:|---:|")
    previous = None
    for x, rho, u, p in data:
        n = len(x)
        dx = 1.0 / n
        err = [0.0, 0.0, 0.0]
        for xi, ri, ui, pi in zip(x, rho, u, p):
            e = exact(xi)
            err[0] += abs(ri - e[0]) * dx
            err[1] += abs(ui - e[1]) * dx
            err[2] += abs(pi - e[2]) * dx
        order = "" if previous is None else "%.2f" % (math.log(previous[1] / err[0]) / math.log(n / previous[0]))
        print("| %d | %.5f | %.5f | %.5f | %s |" % (n, err[0], err[1], err[2], order))
        previous = (n, err[0])
    # The shocked plateau between the contact (x = 0.685) and the shock (x = 0.850) at the
    # finest resolution, away from both fronts.
    x, rho = data[-1][0], data[-1][1]
    inside = [r for xi, r in zip(x, rho) if 0.72 < xi < 0.83]
    print("shocked density plateau, %d cells, x in (0.72, 0.83): mean %.5f, exact %.5f"
          % (len(x), sum(inside) / len(inside), exact(0.775)[0]))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    xs = [i / 2000.0 for i in range(2001)]
    ex = [exact(x) for x in xs]
    for ax, k, name in zip(axes, range(3), ["density", "velocity", "pressure"]):
        for x, rho, u, p in data:
            ax.plot(x, (rho, u, p)[k], lw=1.0, label="%d cells" % len(x))
        ax.plot(xs, [e[k] for e in ex], "k--", lw=1.0, label="exact")
        ax.set_xlabel("x")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Sod shock tube at t = 0.2 (mpmice ICE, second-order advection)")
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)


if __name__ == "__main__":
    main()
