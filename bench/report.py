"""Table of kernel benchmark results, from the JSON files (Google Benchmark's) that
ci/bench writes: per piece of the benchmarks (bench/pieces.py) and thread count t,
pieceNN.threads<t>.json (the kernels) and pieceNN.triad<t>.json (the STREAM triad run
right after them, repeated).

Usage: report.py DIR
Each row's speedup compares its piece's two runs, seconds apart: with one run of
everything per thread count, minutes apart, this machine's slow stretches skewed whole
columns. The roof is the best 2-thread triad of all pieces: the triads after the
memory-heavy pieces (4e6 particles, 2.2 GB) came out at 36-38 GB/s among 46-69 while
the kernels measured just before them ran as fast as in other runs, so a piece's own
triad would have inflated its rows."""
import glob
import json
import os
import sys


def iterations(path):
    """The results of a Google Benchmark JSON file, repetitions included, aggregates left out."""
    with open(path) as f:
        return [b for b in json.load(f)["benchmarks"] if b.get("run_type", "iteration") == "iteration"]


def load(path):
    return {b["name"]: b for b in iterations(path)}


def roof(path):
    """The memory roof: the best triad on the largest arrays (the small ones fit in
    cache) in the JSON file `path`, repetitions included."""
    runs = [(int(b["name"].split("n:")[1].split("/")[0]), b["bytes_per_second"])
            for b in iterations(path) if "stream_triad" in b["name"]]
    if not runs:
        return 0.0
    largest = max(n for n, _ in runs)
    return max(bps for n, bps in runs if n == largest)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    pieces = sorted(p[:-len(".threads2.json")] for p in glob.glob(os.path.join(sys.argv[1], "piece*.threads2.json")))
    if not pieces:
        sys.exit("report.py: no piece*.threads2.json in %s" % sys.argv[1])
    one, two = {}, {}  # by benchmark name
    for piece in pieces:
        one.update(load(piece + ".threads1.json"))
        two.update(load(piece + ".threads2.json"))
    after = {t: [roof(piece + ".triad%d.json" % t) for piece in pieces] for t in (1, 2)}
    triad = max(after[2])
    print("STREAM triad (largest arrays, best of all pieces): %.1f GB/s on 2 threads, %.1f GB/s on 1 "
          "(after each piece: %.1f-%.1f and %.1f-%.1f)" % (triad / 1e9, max(after[1]) / 1e9, min(after[2]) / 1e9,
                                                           triad / 1e9, min(after[1]) / 1e9, max(after[1]) / 1e9))
    print()
    print("| kernel | size | items/s | GB/s | % of triad | 2-thread speedup |")
    print("|---|---|---:|---:|---:|---:|")
    # One kernel's sizes together, kernels in the order they first ran (the particle
    # benchmarks run count by count, sharing their particles).
    names = list(two)
    first = {}
    for i, name in enumerate(names):
        first.setdefault(name.partition("/")[0], i)
    for name in sorted(names, key=lambda name: first[name.partition("/")[0]]):
        b = two[name]
        kernel, _, rest = name.partition("/")
        size = rest.replace("/manual_time", "")
        gbs = b.get("bytes_per_second", 0.0) / 1e9
        items = b.get("items_per_second", 0.0)
        speedup = items / one[name]["items_per_second"] if name in one and one[name].get("items_per_second") else 0
        pct = 100 * gbs * 1e9 / triad if triad else 0
        print("| %s | %s | %.3g | %.2f | %.0f%% | %.2f |" % (kernel.replace("BM_", ""), size, items, gbs, pct, speedup))
    print()
    mpm_substep(one)


def mpm_substep(one):
    """The issue's whole MPM sub-step with linear weights on 1 thread, in ns per particle:
    p2g + internal force + g2p + stress (neo-Hookean, benchmarked at 1e6 particles only)
    + the nodal update (grid_acceleration per node at 64^3 and 128^3 cells, a little more
    than the particle benchmarks' cubes, at one node per 8 particles)."""
    def ns(name):
        b = one.get(name + "/manual_time")
        return 1e9 / b["items_per_second"] if b and b.get("items_per_second") else None
    for particles, cells in ((1000000, 64), (4000000, 128)):
        node = ns("BM_grid_acceleration/cells:%d" % cells)
        parts = [("p2g", ns("BM_p2g<LinearShape>/particles:%d" % particles)),
                 ("internal force", ns("BM_internal_force<LinearShape>/particles:%d" % particles)),
                 ("g2p", ns("BM_g2p<LinearShape>/particles:%d" % particles)),
                 ("stress", ns("BM_stress_update/particles:1000000/plastic:0")),
                 ("nodal update", node / 8 if node else None)]
        if any(v is None for _, v in parts):
            continue
        print("MPM sub-step, linear weights, 1 thread, %.0e particles: %.0f ns per particle (%s)" % (
            particles, sum(v for _, v in parts), ", ".join("%s %.0f" % (k, v) for k, v in parts)))


if __name__ == "__main__":
    main()
