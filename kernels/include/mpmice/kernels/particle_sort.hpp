#pragma once
/// \file particle_sort.hpp
/// \brief Particles sorted by the cell they are in (row-major local cell index), so
///        that particles of one cell are neighbours in memory (better locality for
///        the scatter and gather). A counting sort by cell key (Kokkos::BinSort). It
///        is not stable on more than one thread: BinSort places a cell's particles with
///        atomics, so their order among themselves varies from run to run. The step's
///        sums do not depend on it (p2g and the internal force add in exact quanta,
///        g2p gathers); sums in particle order do, at round-off (the history's
///        particle totals: crossflow's beam momentum on 2 threads, 17th digit).
#include <Kokkos_Sort.hpp>

#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {

/// Reorders the live particles of `particles` by cell; every component moves with
/// its particle.
inline void sort_particles_by_cell(const Patch& patch, ParticleSet& particles) {
  const long n = long(particles.size());
  if (n < 2) return;
  const NodeGrid grid = node_grid(patch);
  const int ny = patch.extent(Location::cell, 1), nz = patch.extent(Location::cell, 2);
  const int ncell = patch.extent(Location::cell, 0) * ny * nz;
  Kokkos::View<int*, MemSpace> key("mpmice::sort_key", n);
  const ParticleData data = particles.data();
  Kokkos::parallel_for(
      "mpmice::cell_key", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long p) {
        int c[3];
        for (int d = 0; d < 3; ++d)
          c[d] = grid.cell(data(p, column(ParticleField::x) + d), d);
        key(p) = (c[0] * ny + c[1]) * nz + c[2];
      });
  using Comp = Kokkos::BinOp1D<Kokkos::View<int*, MemSpace>>;
  Kokkos::BinSort<Kokkos::View<int*, MemSpace>, Comp> sorter(key, Comp(ncell, 0, ncell), /*sort_within_bins=*/false);
  sorter.create_permute_vector();
  particles = gather_particles(particles, sorter.get_permute_vector(), n);
}

}  // namespace mpmice
