#!/usr/bin/python3
"""A/B comparison of two or more builds of mpmice_bench on this machine.

Usage: /usr/bin/python3 bench/ab.py FILTER ROUNDS BENCH_A BENCH_B [BENCH_C ...]
Environment: THREADS (OMP_NUM_THREADS, default 1), MINT (--benchmark_min_time, 0.3).

Runs the benchmarks matching FILTER with each binary in turn, ROUNDS times, and prints
each benchmark's best items/s per binary, the ratio of the last binary's best to the
first's, and the median over the rounds of each round's ratio (last/first). Alternating
the builds spreads the machine's slow stretches over all of them; the best of several
rounds is the least disturbed. The median of the rounds' ratios is the steadier of the
two: in session 27 two builds' best of 3 rounds gave 0.72-1.05x from one comparison to
the next, while their median ratio over 8-12 rounds was 0.60-0.75x each time (and
0.96-1.01x for a binary against its copy). Each binary is copied to one path and run
from there, since the path alone moved a kernel's speed (docs/performance.md, session
22); the path is new for every comparison, so compare ratios within one, not items/s
between two."""
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

from report import load  # Google Benchmark's JSON results by name (bench/report.py)


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    filt, rounds, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    if rounds < 1:
        sys.exit("ROUNDS must be at least 1")
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("THREADS", "1"), OMP_PROC_BIND="false")
    min_time = "--benchmark_min_time=" + os.environ.get("MINT", "0.3")
    best = [dict() for _ in bins]
    ratios = dict()  # name: each round's last/first
    names = []  # in the order the builds report them, each once
    with tempfile.TemporaryDirectory() as work:
        exe, results = os.path.join(work, "mpmice_bench"), os.path.join(work, "results.json")
        for _ in range(rounds):
            this_round = [dict() for _ in bins]
            for i, b in enumerate(bins):
                shutil.copy(b, exe)
                if os.path.exists(results):
                    os.remove(results)
                r = subprocess.run([exe, "--benchmark_filter=" + filt, min_time, "--benchmark_out=" + results,
                                    "--benchmark_out_format=json"], env=env, capture_output=True, text=True)
                if r.returncode != 0:
                    sys.exit("%s exited %d:\n%s" % (b, r.returncode, r.stderr))
                if not os.path.exists(results) or os.path.getsize(results) == 0:
                    continue  # no benchmark matched the filter
                for name, bm in load(results).items():
                    if name not in names:
                        names.append(name)
                    this_round[i][name] = bm.get("items_per_second", 0.0)
                    best[i][name] = max(best[i].get(name, 0.0), this_round[i][name])
            for name, last in this_round[-1].items():
                if this_round[0].get(name):
                    ratios.setdefault(name, []).append(last / this_round[0][name])
    if not names:
        sys.exit("no benchmark matches '%s'" % filt)
    print("%-64s" % "benchmark (best items/s, millions)" + "".join("%14s" % ("build %d" % i) for i in range(len(bins)))
          + "   last/first   median of rounds")
    for name in names:
        values = [b.get(name) for b in best]
        shown = "".join("%14.2f" % (v / 1e6) if v is not None else "%14s" % "-" for v in values)
        ratio = values[-1] / values[0] if values[0] and values[-1] is not None else float("nan")
        median = statistics.median(ratios[name]) if name in ratios else float("nan")
        print("%-64s" % name + shown + "   %.2f" % ratio + "         %.2f" % median)


if __name__ == "__main__":
    main()
