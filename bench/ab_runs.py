#!/usr/bin/python3
"""A/B comparison of whole runs of two builds of the mini-app on this machine.

Usage: /usr/bin/python3 bench/ab_runs.py PROBLEM STEPS ROUNDS MPMICE_A MPMICE_B
Environment: THREADS (OMP_NUM_THREADS, default 1).

Runs problems/PROBLEM.yaml for STEPS steps with each binary in turn, ROUNDS times, and
prints for every row of the per-step timer table (and "all steps") the least total
seconds of each build and their ratio A/B (above 1: B is faster), then whether the two
builds wrote the same probes.csv. As bench/ab.py, each binary is copied to one path and
run from there (docs/performance.md, session 22), and the builds alternate."""
import filecmp
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROW = re.compile(r"^([a-z0-9_]+(?: steps)?)\s+(?:\d+\s+)?([0-9.]+)(?:\s|$)")


def timer_table(output):
    """{step: total seconds} from the mini-app's per-step timer table."""
    totals = {}
    in_table = False
    for line in output.splitlines():
        if line.startswith("step ") and "total [s]" in line:
            in_table = True
            continue
        if in_table:
            m = ROW.match(line)
            if not m:
                break
            totals[m.group(1)] = float(m.group(2))
    return totals


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    problem, steps, bins = sys.argv[1], sys.argv[2], sys.argv[4:]
    if not sys.argv[3].isdigit():
        sys.exit("ROUNDS must be a whole number")
    rounds = int(sys.argv[3])
    for b in bins:
        if not os.access(b, os.X_OK):
            sys.exit("not an executable: " + b)
    if rounds < 1:
        sys.exit("ROUNDS must be at least 1")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    yaml = os.path.join(root, "problems", problem + ".yaml")
    if not os.path.exists(yaml):
        sys.exit("no problem file " + yaml)
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("THREADS", "1"), OMP_PROC_BIND="false")
    best = [dict() for _ in bins]
    with tempfile.TemporaryDirectory() as work:
        exe = os.path.join(work, "mpmice")
        outs = [os.path.join(work, "out%d" % i) for i in range(len(bins))]
        for _ in range(rounds):
            for i, b in enumerate(bins):
                shutil.copy(b, exe)
                r = subprocess.run([exe, yaml, "--max-steps", steps, "--output-dir", outs[i], "--no-progress"],
                                   env=env, capture_output=True, text=True)
                if r.returncode != 0:
                    sys.exit("%s exited %d:\n%s" % (b, r.returncode, r.stderr))
                table = timer_table(r.stdout + r.stderr)
                if "all steps" not in table:
                    sys.exit("%s printed no whole timer table (no 'all steps' row)" % b)
                for step, seconds in table.items():
                    best[i][step] = min(best[i].get(step, seconds), seconds)
        print("%-30s%12s%12s%8s" % ("step (least total s)", "A", "B", "A/B"))
        for step in list(best[0]) + [s for s in best[1] if s not in best[0]]:
            a, b = best[0].get(step), best[1].get(step)
            if a is None or b is None:
                print("%-30s%12s%12s" % (step, "-" if a is None else "%.3f" % a, "-" if b is None else "%.3f" % b))
                continue
            print("%-30s%12.3f%12.3f%8.2f" % (step, a, b, a / b if b > 0 else float("nan")))
        same = filecmp.cmp(os.path.join(outs[0], "probes.csv"), os.path.join(outs[1], "probes.csv"), shallow=False)
        print("probes.csv " + ("the same" if same else "DIFFERENT"))


if __name__ == "__main__":
    main()
