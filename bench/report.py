"""Table of kernel benchmark results: one run on 1 thread, one on 2 (JSON files of
Google Benchmark). Bandwidth is relative to the STREAM triad of the same run.

Usage: report.py THREADS1.json THREADS2.json [TRIAD1.json TRIAD2.json]
The optional files hold repeated triad runs of the same binary on 1 and 2 threads; the
roof is the best triad of all runs on that many threads (one triad caught in a slow
stretch of this machine made a whole table's percentages 1.5-2x too high)."""
import json
import sys


def iterations(path):
    """The results of a Google Benchmark JSON file, repetitions included, aggregates left out."""
    with open(path) as f:
        return [b for b in json.load(f)["benchmarks"] if b.get("run_type", "iteration") == "iteration"]


def load(path):
    return {b["name"]: b for b in iterations(path)}


def roof(paths):
    """The memory roof: the best triad on the largest arrays (the small ones fit in
    cache) among every run, repetitions included, in the JSON files `paths`."""
    runs = [(int(b["name"].split("n:")[1].split("/")[0]), b["bytes_per_second"])
            for path in paths for b in iterations(path) if "stream_triad" in b["name"]]
    if not runs:
        return 0.0
    largest = max(n for n, _ in runs)
    return max(bps for n, bps in runs if n == largest)


def main():
    if len(sys.argv) not in (3, 5):
        sys.exit(__doc__)
    one, two = load(sys.argv[1]), load(sys.argv[2])
    extra = sys.argv[3:]
    triad1 = roof([sys.argv[1]] + extra[:1])
    triad = roof([sys.argv[2]] + extra[1:])
    print("STREAM triad (largest arrays): %.1f GB/s on 2 threads, %.1f GB/s on 1" % (triad / 1e9, triad1 / 1e9))
    print()
    print("| kernel | size | items/s | GB/s | % of triad | 2-thread speedup |")
    print("|---|---|---:|---:|---:|---:|")
    # One kernel's sizes together, kernels in the order they first ran (the particle
    # benchmarks run count by count, sharing their particles).
    names = [name for name in two if "stream_triad" not in name]
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
        print("| %s | %s | %.3g | %.2f | %.0f%% | %.2f |" % (kernel.replace("BM_", ""), size, items, gbs,
                                                         100 * gbs * 1e9 / triad if triad else 0, speedup))
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
