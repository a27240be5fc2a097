"""Table of kernel benchmark results, from the JSON files (Google Benchmark's) that
ci/bench writes: per piece of the benchmarks (bench/pieces.py) and thread count t,
pieceNN.threads<t>.json (the kernels) and pieceNN.triad<t>.json (the STREAM triad run
right after them, repeated).

Usage: report.py DIR
Each row's bandwidth is relative to the best 2-thread triad run next to it, just after
its piece or just before (after the piece before), and its speedup compares its piece's
two runs: measurements seconds apart, where one roof for a whole table, measured
minutes before or after some of its rows, was skewed by this machine's slow stretches.
Both neighbours, because in one run a triad right after a piece caught a dip alone
(36 GB/s among 55-69) and made the piece's rows 1.5x too high."""
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
    after = {t: [roof(piece + ".triad%d.json" % t) for piece in pieces] for t in (1, 2)}
    one, two, triad = {}, {}, {}  # by benchmark name; triad: the 2-thread roof of its row
    for i, piece in enumerate(pieces):
        kernels2 = load(piece + ".threads2.json")
        one.update(load(piece + ".threads1.json"))
        two.update(kernels2)
        triad.update({name: max(after[2][max(i - 1, 0):i + 1]) for name in kernels2})
    print("STREAM triad (largest arrays, best of 3 after each piece): %.1f-%.1f GB/s on 2 threads, "
          "%.1f-%.1f GB/s on 1" % (min(after[2]) / 1e9, max(after[2]) / 1e9, min(after[1]) / 1e9,
                                   max(after[1]) / 1e9))
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
        pct = 100 * gbs * 1e9 / triad[name] if triad[name] else 0
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
