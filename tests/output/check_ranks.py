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
    exact = args[0] == "--exact-probes"
    if exact:
        args = args[1:]
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
        probes = []
        for ranks in (1, 2):
            with open(os.path.join(dirs[ranks], "probes.csv")) as f:
                probes.append(f.read().splitlines())
        if len(probes[0]) < 2 or len(probes[0]) != len(probes[1]):
            sys.exit("FAIL: probes.csv has %d and %d rows" % (len(probes[0]), len(probes[1])))
        for row, (x, y) in enumerate(zip(*probes)):
            if x != y:
                sys.exit("FAIL: probes.csv differs from row %d: '%s' on 1 rank, '%s' on 2" % (row, x, y))
        print("1 and 2 ranks: probes.csv the same, every digit of its %d rows" % (len(probes[0]) - 1))


if __name__ == "__main__":
    main()
