// The memory roof of a cell kernel with as many streams as the exchange of 4 materials:
// 8 fields of 4 materials read (32 arrays) and 5 written (20), with nothing but a sum
// and a product per cell in between. Bytes per item: 52 x 8 = 416, the exchange's count.
//
// It runs over the owned cells of a patch with 2 ghost layers (the driver's layout: rows
// n + 4 cells apart, so for even n the owned cells of a row start 16 or 48 B into a
// cache line, every 64-byte vector spanning two lines), and over the same arrays with no
// ghost layers (rows contiguous, every vector on one line). In a plain loop on this
// project's machine (mpmice_row_alignment, row_alignment.cpp), 52 arrays on misaligned
// rows ran at half the rate of aligned ones and 13 lost little (docs/performance.md,
// session 18); here the two layouts differ by 0.8-1.7x. The exchange's roof is this
// benchmark, not the triad.
#include <benchmark/benchmark.h>

#include <mpmice/kernels/loops.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

constexpr int materials = 4, inputs = 8, outputs = 5;

void BM_cell_streams(benchmark::State& state) {
  const int n = int(state.range(0)), ghosts = int(state.range(1));
  const Patch p = cube_patch(n, ghosts);
  Kokkos::Array<Field4, inputs> in;
  Kokkos::Array<Field4, outputs> out;
  for (int f = 0; f < inputs; ++f) in[f] = cell_field(p, materials, 1.0 + f, 0.1, unsigned(f + 1));
  for (int f = 0; f < outputs; ++f) out[f] = make_field("out", p, Location::cell, materials);
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      for_each_index("mpmice::bench::cell_streams", p.owned_cells(), KOKKOS_LAMBDA(long i, long j, long k) {
        unrolled_for<materials>([&](int r) {
          double sum = 0;
          unrolled_for<inputs>([&](int f) { sum += in[f](r, i, j, k); });
          unrolled_for<outputs>([&](int f) { out[f](r, i, j, k) = (f + 1) * sum; });
        });
      });
    }));
  report(state, p.grid.cell_count(), 8.0 * materials * (inputs + outputs));
}

}  // namespace

BENCHMARK(BM_cell_streams)
    ->ArgNames({"cells", "ghosts"})
    ->ArgsProduct({{16, 64, 128}, {2, 0}})
    ->UseManualTime();
