"""The same run on 1 and 2 ranks gives the same history (and, with --exact-probes, the
same probes bit for bit).

Usage: /usr/bin/python3 check_ranks.py [--exact-probes] MPMICE PROBLEM.yaml WORK_DIR TOLERANCE END_TIME
                                      MPIEXEC [FLAGS...]
Runs PROBLEM to END_TIME on 1 rank and on 2 ranks (one thread each) and compares
history.csv column by column: the largest difference over all rows, relative to the
column's largest magnitude (a momentum against the run's scale sqrt(total mass x total
energy)), must not exceed TOLERANCE. Prints the worst columns. The history's totals are
sums whose order depends on the ranks; the probes read single cells, and with
--exact-probes (a build with MPMICE_REPRODUCIBLE, kernels/CMakeLists.txt) probes.csv must
be the same file on 1 and 2 ranks, every digit of every row."""
import os
import shutil
import subprocess
import sys

import numpy as np


def run(cmd, env):
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
        sys.exit("FAIL: %s exited %d" % (" ".join(cmd), r.returncode))


def main():
    args = sys.argv[1:]
    exact = "--exact-probes" in args[:1]
    if exact:
        args = args[1:]
    if len(args) < 6:
        sys.exit(__doc__)
    exe, problem, work, tol, end = args[0], args[1], args[2], float(args[3]), args[4]
    mpi = args[5:]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    shutil.rmtree(work, ignore_errors=True)
    dirs = {}
    for ranks in (1, 2):
        dirs[ranks] = os.path.join(work, "np%d" % ranks)
        launch = mpi + ["-n", str(ranks)] if ranks > 1 else []
        run(launch + [exe, problem, "--no-progress", "--end-time", end, "--output-dir", dirs[ranks]], env)
    with open(os.path.join(dirs[1], "history.csv")) as f:
        header = f.readline().strip().split(",")
    a = np.loadtxt(os.path.join(dirs[1], "history.csv"), delimiter=",", skiprows=1)
    b = np.loadtxt(os.path.join(dirs[2], "history.csv"), delimiter=",", skiprows=1)
    if a.shape != b.shape:
        sys.exit("FAIL: the histories have %s and %s rows x columns" % (a.shape, b.shape))
    scale = np.maximum(np.abs(a).max(axis=0), 1e-300)
    momentum_scale = np.sqrt(np.abs(a[:, header.index("mass:total")] * a[:, header.index("energy:total")])).max()
    for c, name in enumerate(header):
        if name.startswith("momentum"):
            scale[c] = max(scale[c], momentum_scale)
    rel = (np.abs(a - b) / scale).max(axis=0)
    order = np.argsort(rel)[::-1]
    for c in order[:4]:
        print("  %-28s %.2e" % (header[c], rel[c]))
    worst = rel.max()
    if worst > tol:
        sys.exit("FAIL: 1 and 2 ranks differ by %.2e (> %g) in %s" % (worst, tol, header[order[0]]))
    print("1 and 2 ranks: every history column within %.2e (bound %g) over %d rows" % (worst, tol, len(a)))
    if exact:
        compare_probes(dirs[1], dirs[2])


def compare_probes(one, two):
    """probes.csv of the two runs must be the same file, byte for byte."""
    text = []
    for d in (one, two):
        path = os.path.join(d, "probes.csv")
        if not os.path.exists(path):
            sys.exit("FAIL: %s was not written" % path)
        with open(path) as f:
            text.append(f.read())
    rows = [t.splitlines() for t in text]
    if len(rows[0]) < 2:
        sys.exit("FAIL: %s holds no probe values" % os.path.join(one, "probes.csv"))
    if text[0] != text[1]:
        for n, (x, y) in enumerate(zip(rows[0], rows[1])):
            if x != y:
                sys.exit("FAIL: probes.csv differs at data row %d: '%s' on 1 rank, '%s' on 2" % (n, x, y))
        sys.exit("FAIL: probes.csv has %d data rows on 1 rank and %d on 2" % (len(rows[0]) - 1, len(rows[1]) - 1))
    print("1 and 2 ranks: probes.csv the same, every digit of its %d rows" % (len(rows[0]) - 1))


if __name__ == "__main__":
    main()
