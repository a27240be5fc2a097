"""Restart reproduces the uninterrupted run.

Usage: /usr/bin/python3 check_restart.py MPMICE PROBLEM.yaml WORK_DIR RANKS [MPIEXEC FLAGS...]
Runs PROBLEM for 40 steps straight, and for 20 steps then restarted for 20 more from
its checkpoint (`--restart latest`), both on RANKS ranks, checkpointing every 20 steps:
history.csv and the step-40 checkpoint must be identical bit for bit. With RANKS = 2
it also restarts the 2-rank step-20 checkpoint on 1 rank: history within 1e-12
relative (per column, against the column's largest magnitude; momentum against the
run's momentum scale)."""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
        sys.exit("FAIL: %s exited %d" % (" ".join(cmd), r.returncode))


def history(d):
    with open(os.path.join(d, "history.csv")) as f:
        return f.read()


def same_checkpoint(a, b):
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        for name in fa:
            x, y = np.asarray(fa[name]), np.asarray(fb[name])
            if name.startswith("particles"):  # rows in rank order; compare as sets of rows by id
                x, y = x[np.argsort(x[:, -1])], y[np.argsort(y[:, -1])]
            if x.shape != y.shape or not np.array_equal(x, y):
                return name
    return None


def main():
    exe, problem, work, ranks = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    mpi = sys.argv[5:]
    launch = (mpi + ["-n", str(ranks)]) if ranks > 1 else []
    common = [problem, "--no-progress", "--set", "checkpoint.interval=20", "--set", "checkpoint.keep=5"]
    shutil.rmtree(work, ignore_errors=True)
    straight, split = os.path.join(work, "straight"), os.path.join(work, "split")
    run(launch + [exe] + common + ["--output-dir", straight, "--max-steps", "40"])
    run(launch + [exe] + common + ["--output-dir", split, "--max-steps", "20"])
    run(launch + [exe] + common + ["--output-dir", split, "--max-steps", "40", "--restart", "latest"])
    if history(straight) != history(split):
        sys.exit("FAIL: history.csv differs between the straight and the restarted run")
    diff = same_checkpoint(os.path.join(straight, "checkpoint_000040.h5"), os.path.join(split, "checkpoint_000040.h5"))
    if diff:
        sys.exit("FAIL: the final state differs (%s)" % diff)
    print("restart on %d rank(s): history.csv and the final state identical" % ranks)
    if ranks > 1:
        one = os.path.join(work, "one_rank")
        os.makedirs(one)
        shutil.copy(os.path.join(split, "checkpoint_000020.h5"), one)
        with open(os.path.join(split, "history.csv")) as f:
            rows = [l for l in f.read().splitlines()[1:] if int(l.split(",")[0]) <= 20]
        with open(os.path.join(one, "history.csv"), "w") as f:
            f.write(history(straight).splitlines()[0] + "\n" + "\n".join(rows) + "\n")
        shutil.copy(os.path.join(split, "probes.csv"), one)
        run([exe] + common + ["--output-dir", one, "--max-steps", "40", "--restart", "latest"])
        a = np.loadtxt(os.path.join(straight, "history.csv"), delimiter=",", skiprows=1)
        b = np.loadtxt(os.path.join(one, "history.csv"), delimiter=",", skiprows=1)
        header = history(straight).splitlines()[0].split(",")
        scale = np.maximum(np.abs(a).max(axis=0), 1e-300)
        # A momentum that is zero by symmetry is measured against the run's momentum
        # scale sqrt(total mass x total energy), not against its own round-off.
        momentum_scale = np.sqrt(np.abs(a[:, header.index("mass:total")] * a[:, header.index("energy:total")])).max()
        for c, name in enumerate(header):
            if name.startswith("momentum"):
                scale[c] = max(scale[c], momentum_scale)
        worst = (np.abs(a - b) / scale).max()
        if a.shape != b.shape or worst > 1e-12:
            sys.exit("FAIL: a 2-rank checkpoint restarted on 1 rank differs by %g" % worst)
        print("2-rank checkpoint restarted on 1 rank: history within %.2e" % worst)


if __name__ == "__main__":
    main()
