"""The pieces in which ci/bench runs the kernel benchmarks: reads benchmark names (the
output of `mpmice_bench --benchmark_list_tests`) on standard input and prints one
--benchmark_filter per piece, in the order the benchmarks are registered.

A piece is made of whole groups, in order, of at most `MOST` benchmarks unless one group
alone has more. A group is one kernel's sizes (every benchmark of one name before its
first '/'), except that the templated particle kernels of one particle count
(p2g<LinearShape>, g2p<GimpShape>, ...) are one group: bench_particles.cpp registers
them count by count so that they share one sorted set of particles, which at 4e6
particles takes seconds to make. The STREAM triad is left out: ci/bench runs it after
every piece, which takes about 2 s (its arrays are 800 MB), so pieces of one kernel
each (21) made ci/bench's benchmarks take 4.9 minutes, against 4.3 with these (13).

ci/bench runs each piece on 1 thread, then on 2: a piece's speedups then come from two
runs seconds apart, not minutes (this machine's speed moves by 2-3x over minutes)."""
import re
import sys

MOST = 16

# A templated particle kernel at one count: its group is that count.
PARTICLE_KERNEL = re.compile(r"^BM_[A-Za-z_0-9]+<[A-Za-z]+>/particles:([0-9]+)(/|$)")


def group(name):
    """What names the group of benchmark `name`: its particle count or its kernel."""
    match = PARTICLE_KERNEL.match(name)
    return "particles:" + match.group(1) if match else name.partition("/")[0]


def main():
    groups = {}  # group -> its benchmarks' names, in order (dicts keep the first's place)
    for line in sys.stdin:
        name = line.strip()
        if name.startswith("BM_") and not name.startswith("BM_stream_triad"):
            groups.setdefault(group(name), []).append(name)
    pieces = []
    for names in groups.values():
        if pieces and len(pieces[-1]) + len(names) <= MOST:
            pieces[-1] += names
        else:
            pieces.append(list(names))
    # Each piece as its names exactly (POSIX extended regex, as Google Benchmark reads a
    # filter; the names hold no special characters), so that a filter given to ci/bench,
    # which chose these names, still holds.
    for names in pieces:
        print("^(%s)$" % "|".join(names))


if __name__ == "__main__":
    main()
