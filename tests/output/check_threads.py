"""The same run on 1 and 2 OpenMP threads gives the same state, bit for bit.

Usage: /usr/bin/python3 check_threads.py MPMICE PROBLEM.yaml WORK_DIR STEPS
Runs PROBLEM for STEPS steps with OMP_NUM_THREADS = 1 and 2 and compares the final
cell state (fields.csv, every digit) and each solid's particles (position, velocity,
temperature, stress), in their order: the sort by window is stable
(kernels/.../particle_sort.hpp), so the particles come in the same order on any number
of threads (until session 42 they were compared as sets of rows). The particle
scatters add multiples of one quantum (kernels/.../quanta.hpp), so no sum depends on
the threads' order. (history.csv is not compared: its totals are reductions whose
grouping does depend on the threads.)"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np


def main():
    exe, problem, work, steps = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    out = {}
    for threads in (1, 2):
        out[threads] = os.path.join(work, "threads%d" % threads)
        r = subprocess.run([exe, problem, "--no-progress", "--max-steps", steps, "--output-dir", out[threads],
                            "--set", "output.final_fields=true", "--set", "output.field_interval=" + steps],
                           capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
        if r.returncode != 0:
            print(r.stdout, r.stderr)
            sys.exit("FAIL: the run on %d threads exited %d" % (threads, r.returncode))
    with open(os.path.join(out[1], "fields.csv")) as a, open(os.path.join(out[2], "fields.csv")) as b:
        if a.read() != b.read():
            sys.exit("FAIL: the cell state differs between 1 and 2 threads")
    last = "fields_%06d.h5" % int(steps)
    with h5py.File(os.path.join(out[1], last), "r") as a, h5py.File(os.path.join(out[2], last), "r") as b:
        for solid in a["particles"]:
            rows = []
            for f in (a, b):
                g = f["particles"][solid]
                x = np.hstack([np.asarray(g[q]).reshape(len(g["position"]), -1)
                               for q in ("position", "velocity", "temperature", "stress")])
                rows.append(x)
            if rows[0].shape != rows[1].shape or not np.array_equal(rows[0], rows[1]):
                sys.exit("FAIL: the particles of '%s' differ between 1 and 2 threads" % solid)
            print("  %s: %d particles identical, in the same order" % (solid, len(rows[0])))
    print("1 and 2 threads: the cell state and every particle identical after %s steps" % steps)


if __name__ == "__main__":
    main()
