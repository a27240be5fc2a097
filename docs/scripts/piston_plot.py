"""Piston compression: the gas pressure at the closed end against the adiabat.

Usage: /usr/bin/python3 docs/scripts/piston_plot.py RUN_DIR [OUT.png]
Reads RUN_DIR/probes.csv of a run of problems/piston.yaml (probe `closed_end`) and
the run's resolved input RUN_DIR/input.yaml (the rigid piston's speed, ramp and stop
time, the gas column's length and gamma), and compares the pressure with
P1 (L1/L2)^gamma, L2 = L1 - stroke(t) the instantaneous gas length (seed paper
eq. 11). Prints the largest relative deviation during the compression and the final
pressure ratio against the analytic one; draws both curves if OUT.png is given.
"""
import csv
import math
import os
import sys

import yaml


def stroke_function(speed, stop, ramp):
    """Distance travelled by a rigid body whose speed rises as sin^2 over `ramp`, holds,
    and falls as cos^2 to rest at `stop` (SolidModel::rigid_speed_fraction)."""

    def ramp_integral(s):  # integral of sin^2(pi u / (2 ramp)) for u in [0, s]
        return s if ramp <= 0 else s / 2 - ramp / (2 * math.pi) * math.sin(math.pi * s / ramp)

    def stroke(t):
        t = min(max(t, 0.0), stop)
        if t < ramp:
            return speed * ramp_integral(t)
        full = stop - ramp
        if t <= stop - ramp:
            return speed * (ramp_integral(ramp) + t - ramp)
        return speed * (full - ramp_integral(stop - t))

    return stroke


def piston_parameters(run):
    with open(os.path.join(run, "input.yaml")) as f:
        inp = yaml.safe_load(f)
    piston = next(m for m in inp["materials"] if m["model"] == "rigid")
    gas = next(m for m in inp["materials"] if m["model"] == "ideal_gas")
    box = next(g["box"] for g in inp["geometry"] if g["material"] == piston["name"])
    length = box["lower"][1] - inp["grid"]["lower"][1]
    speed = abs(piston["prescribed_velocity"][1])
    stroke = stroke_function(speed, piston["stop_time"], piston.get("ramp_time", 0.0))
    return length, stroke, gas["gamma"], piston["stop_time"]


def main():
    run = sys.argv[1]
    l1, stroke, gamma, t_stop = piston_parameters(run)
    with open(os.path.join(run, "probes.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["probe"] == "closed_end" and r["quantity"] == "pressure"]
    t = [float(r["time"]) for r in rows]
    p = [float(r["value"]) for r in rows]
    p1 = p[0]

    def analytic(time):
        return p1 * (l1 / (l1 - stroke(time))) ** gamma

    during = [(ti, pi) for ti, pi in zip(t, p) if 0 < ti <= t_stop]
    worst = max(abs(pi - analytic(ti)) / analytic(ti) for ti, pi in during)
    final_ratio, exact_ratio = p[-1] / p1, analytic(t[-1]) / p1
    print("compression ratio L1/L2 = %.3f; largest deviation from the adiabat during the compression: %.2f%%"
          % (l1 / (l1 - stroke(t_stop)), 100 * worst))
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
        ax.set_title("Piston compression to L1/L2 = %.1f" % (l1 / (l1 - stroke(t_stop))))
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
