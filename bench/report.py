"""Table of kernel benchmark results: one run on 1 thread, one on 2 (JSON files of
Google Benchmark). Bandwidth is relative to the STREAM triad of the same run."""
import json
import sys


def load(path):
    with open(path) as f:
        data = json.load(f)
    return {b["name"]: b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"}


def main():
    one, two = load(sys.argv[1]), load(sys.argv[2])
    # The memory roof: the triad on the largest arrays (the small ones fit in cache).
    def roof(results):
        runs = [(int(n.split("n:")[1].split("/")[0]), b["bytes_per_second"]) for n, b in results.items()
                if "stream_triad" in n]
        return max(runs)[1] if runs else 0.0
    triad, triad1 = roof(two), roof(one)
    print("STREAM triad (largest arrays): %.1f GB/s on 2 threads, %.1f GB/s on 1" % (triad / 1e9, triad1 / 1e9))
    print()
    print("| kernel | size | items/s | GB/s | % of triad | 2-thread speedup |")
    print("|---|---|---:|---:|---:|---:|")
    for name, b in two.items():
        if "stream_triad" in name:
            continue
        kernel, _, rest = name.partition("/")
        size = rest.replace("/manual_time", "")
        gbs = b.get("bytes_per_second", 0.0) / 1e9
        items = b.get("items_per_second", 0.0)
        speedup = items / one[name]["items_per_second"] if name in one and one[name].get("items_per_second") else 0
        print("| %s | %s | %.3g | %.2f | %.0f%% | %.2f |" % (kernel.replace("BM_", ""), size, items, gbs,
                                                         100 * gbs * 1e9 / triad if triad else 0, speedup))


if __name__ == "__main__":
    main()
