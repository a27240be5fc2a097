// Cartesian decomposition: every cell owned once, uneven splits, neighbours, errors.
#include <gtest/gtest.h>

#include <mpmice/halo/decomposition.hpp>
#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/errors.hpp>

using namespace mpmice;

namespace {
Grid grid_of(int nx, int ny, int nz) {
  Grid g;
  g.cells = {nx, ny, nz};
  g.spacing = {0.1, 0.2, 0.3};
  return g;
}
}  // namespace

TEST(Decomposition, EveryCellOwnedExactlyOnce) {
  for (bool periodic : {false, true}) {
    DecompositionOptions opt;
    opt.periodic = {periodic, periodic, periodic};
    Decomposition dec(MPI_COMM_WORLD, grid_of(11, 7, 5), opt);
    const Patch& p = dec.patch();
    long owned = long(p.owned_cells(0)) * p.owned_cells(1) * p.owned_cells(2);
    EXPECT_EQ(global_sum(dec.comm(), owned), 11L * 7 * 5);
    // Node ownership: every global node exactly once (N+1 per non-periodic direction).
    const long nodes = p.owned_nodes().size();
    const long expect = periodic ? 11L * 7 * 5 : 12L * 8 * 6;
    EXPECT_EQ(global_sum(dec.comm(), nodes), expect);
    for (int d = 0; d < 3; ++d) {
      EXPECT_GE(p.owned_cells(d), 1);
      // Uneven splits differ by at most one cell.
      const int n = p.owned_cells(d);
      EXPECT_LE(global_max(dec.comm(), n) - global_min(dec.comm(), n), 1);
    }
  }
}

TEST(Decomposition, NeighboursAreMutual) {
  DecompositionOptions opt;
  opt.periodic = {true, false, false};
  Decomposition dec(MPI_COMM_WORLD, grid_of(12, 12, 12), opt);
  // Each rank tells its +x neighbour who it is; the answer must be that rank's -x.
  const int up = dec.neighbor(1, 0, 0), down = dec.neighbor(-1, 0, 0);
  int from_down = -1, me = dec.rank();
  MPI_Sendrecv(&me, 1, MPI_INT, up, 5, &from_down, 1, MPI_INT, down, 5, dec.comm(),
               MPI_STATUS_IGNORE);
  EXPECT_EQ(from_down, down);
  EXPECT_EQ(dec.neighbor(0, 0, 0), dec.rank());
  if (dec.coords()[1] == 0) {
    EXPECT_EQ(dec.neighbor(0, -1, 0), MPI_PROC_NULL);  // non-periodic domain boundary
  }
}

TEST(Decomposition, ExplicitRankGridAndErrors) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  DecompositionOptions opt;
  opt.ranks = {1, size, 1};
  Decomposition dec(MPI_COMM_WORLD, grid_of(4, 40, 4), opt);
  EXPECT_EQ(dec.dims()[1], size);
  // A rank grid whose product is not the rank count.
  opt.ranks = {size + 1, 1, 1};
  EXPECT_THROW(Decomposition(MPI_COMM_WORLD, grid_of(40, 4, 4), opt), InputError);
  // Too few cells for the ghost layers.
  DecompositionOptions small;
  small.periodic = {true, false, false};
  EXPECT_THROW(Decomposition(MPI_COMM_WORLD, grid_of(2, 1, 1), small), InputError);
  // Degenerate directions are never split.
  const auto dims = Decomposition::choose_dims(grid_of(64, 1, 1), DecompositionOptions{}, 4);
  EXPECT_EQ(dims[0], 4);
  EXPECT_EQ(dims[1] * dims[2], 1);
}
