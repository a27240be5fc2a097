// Uses mpmice::kernels from the installed package: allocate a cell field on a patch
// and sum a linear field over the owned cells, against the closed form.
#include <cstdio>

#include <Kokkos_Core.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/version.hpp>

int main(int argc, char* argv[]) {
  Kokkos::ScopeGuard guard(argc, argv);
  mpmice::Grid grid;
  grid.cells = {8, 4, 2};
  const mpmice::Patch patch = mpmice::whole_grid_patch(grid, 2);
  mpmice::Field4 f = mpmice::make_field("f", patch, mpmice::Location::cell, 1);
  const int G = patch.ghosts;
  double sum = 0;
  Kokkos::parallel_reduce(
      "consumer_sum", patch.owned_cells().policy(),
      KOKKOS_LAMBDA(int i, int j, int k, double& s) {
        f(0, i, j, k) = (i - G) + 10.0 * (j - G);
        s += f(0, i, j, k);
      },
      sum);
  // sum over i of i = 28 (times 4*2), sum over j of 10 j = 60 (times 8*2).
  const double want = 28.0 * 8 + 60.0 * 16;
  std::printf("mpmice %s consumer: sum %g (expected %g)\n", MPMICE_VERSION_STRING, sum, want);
  return sum == want ? 0 : 1;
}
