#!/usr/bin/python3
"""A/B comparison of two or more builds of mpmice_bench on this machine.

Usage: /usr/bin/python3 bench/ab.py FILTER ROUNDS BENCH_A BENCH_B [BENCH_C ...]
Environment: THREADS (OMP_NUM_THREADS, default 1), MINT (--benchmark_min_time, 0.3).

Runs the benchmarks matching FILTER with each binary in turn, ROUNDS times, and prints
each benchmark's best items/s per binary and the ratio of the last binary to the first.
Alternating the builds spreads the machine's slow stretches over all of them; the best
of several rounds is the least disturbed. Each binary is copied to one fixed path and
run from there: the same file measured g2p at 52 to 75 million particles/s depending
only on the path it ran from (docs/performance.md, session 22)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    filt, rounds, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("THREADS", "1"), OMP_PROC_BIND="false")
    best = [dict() for _ in bins]
    with tempfile.TemporaryDirectory() as work:
        exe = os.path.join(work, "mpmice_bench")
        for _ in range(rounds):
            for i, b in enumerate(bins):
                shutil.copy(b, exe)
                r = subprocess.run([exe, "--benchmark_filter=" + filt,
                                    "--benchmark_min_time=" + os.environ.get("MINT", "0.3"),
                                    "--benchmark_format=json"], env=env, capture_output=True, text=True)
                if r.returncode != 0:
                    sys.exit("%s exited %d:\n%s" % (b, r.returncode, r.stderr))
                for bm in json.loads(r.stdout)["benchmarks"]:
                    name = bm["name"]
                    best[i][name] = max(best[i].get(name, 0.0), bm.get("items_per_second", 0.0))
    print("%-64s" % "benchmark (best items/s, millions)" + "".join("%14s" % ("build %d" % i) for i in range(len(bins)))
          + "   last/first")
    for name in best[0]:
        values = [b.get(name, 0.0) for b in best]
        ratio = values[-1] / values[0] if values[0] > 0 else float("nan")
        print("%-64s" % name + "".join("%14.2f" % (v / 1e6) for v in values) + "   %.2f" % ratio)


if __name__ == "__main__":
    main()
