// Ghost exchange (pack, copy, unpack) of a cell field with 2 ghost layers on a patch
// periodic in every direction on one rank: the halo layer's own cost without the
// network. Items: ghost entries filled (all materials). Bytes per item: 4 x 8 (read
// the owned value, write it to the buffer, read the buffer, write the ghost) -> 32.
#include <benchmark/benchmark.h>

#include <mpmice/halo/halo.hpp>
#include <mpmice/kernels/grid_state.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

void BM_halo_fill(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  Grid g;
  g.cells = {n, n, n};
  DecompositionOptions opt;
  opt.periodic = {true, true, true};
  opt.ghosts = 2;
  Decomposition dec(MPI_COMM_SELF, g, opt);
  Halo halo(dec);
  const Field4 f = cell_field(dec.patch(), mats, 1.0, 0.1, 1);
  const long ghosts = (dec.patch().ghosted_cells(2).size() - dec.patch().owned_cells().size()) * mats;
  for (auto _ : state) state.SetIterationTime(timed([&] { halo.fill(f, Location::cell, 2); }));
  report(state, ghosts, 32.0);
}

}  // namespace

BENCHMARK(BM_halo_fill)
    ->ArgNames({"cells", "mats"})
    ->ArgsProduct({{16, 32, 64, 128}, {1, 4}})
    ->UseManualTime();
