"""Piston compression: the gas pressure at the closed end against the adiabat.

Usage: /usr/bin/python3 docs/scripts/piston_plot.py RUN_DIR [OUT.png]
Reads RUN_DIR/probes.csv of a run of problems/piston.yaml (probe `closed_end`) and
compares the pressure with P1 (L1/L2)^gamma, L2 = L1 - v min(t, t_stop) the
instantaneous gas length (seed paper eq. 11). Prints the largest relative
deviation during the compression and the final pressure ratio against the analytic
one; draws both curves if OUT.png is given.
"""
import csv
import os
import sys

P1, L1, V, T_STOP, GAMMA = 101325.0, 0.10, 10.0, 8.305e-3, 1.4


def analytic(t):
    return P1 * (L1 / (L1 - V * min(t, T_STOP))) ** GAMMA


def main():
    run = sys.argv[1]
    with open(os.path.join(run, "probes.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["probe"] == "closed_end" and r["quantity"] == "pressure"]
    t = [float(r["time"]) for r in rows]
    p = [float(r["value"]) for r in rows]
    during = [(ti, pi) for ti, pi in zip(t, p) if 0 < ti <= T_STOP]
    worst = max(abs(pi - analytic(ti)) / analytic(ti) for ti, pi in during)
    settled = max(abs(pi - analytic(ti)) / analytic(ti) for ti, pi in during if ti >= 2e-3)
    final_ratio, exact_ratio = p[-1] / P1, analytic(t[-1]) / P1
    print("largest deviation from the adiabat during the compression: %.2f%% (%.2f%% after the start "
          "transient, t >= 2 ms)" % (100 * worst, 100 * settled))
    print("final pressure ratio %.4f, analytic %.4f (%+.2f%%) at t = %.4g s"
          % (final_ratio, exact_ratio, 100 * (final_ratio - exact_ratio) / exact_ratio, t[-1]))
    if len(sys.argv) > 2:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4.2))
        ax.plot([x * 1e3 for x in t], [x / 1e5 for x in p], label="mpmice, gas at y = 0")
        tt = [i * max(t) / 400 for i in range(401)]
        ax.plot([x * 1e3 for x in tt], [analytic(x) / 1e5 for x in tt], "k--", label="adiabat P1 (L1/L2)^gamma")
        ax.set_xlabel("time [ms]")
        ax.set_ylabel("pressure [bar]")
        ax.set_title("Piston compression to L1/L2 = 5.9")
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
