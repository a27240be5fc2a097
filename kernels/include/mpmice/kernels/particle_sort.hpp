#pragma once
/// \file particle_sort.hpp
/// \brief Particles sorted by the window of nodes their shape reaches (row-major, by
///        its first node), so that particles with the same nodes are neighbours in
///        memory: for the linear shape the cell they are in; for GIMP the node nearest
///        them (its 27 nodes depend on which half of its cell a particle is in). The
///        scatters add runs of them together and g2p reads their nodes once per group
///        (p2g.hpp, node_reads.hpp). A counting sort (Kokkos::BinSort), made stable:
///        BinSort places a bin's particles with atomics, so on more than one thread
///        their order among themselves varied from run to run, and with it sums taken
///        in particle order (the history's particle totals, in their last digits:
///        crossflow's beam momentum on 2 threads) and, built without
///        MPMICE_REPRODUCIBLE, a particle's arithmetic in a loop's scalar tail, by an
///        ulp (docs/design.md, "Order-independent particle sums"). Each bin's particles
///        are put back in their order before the sort, so the order after it is the
///        same on any number of threads.
#include <Kokkos_Sort.hpp>

#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {

/// Reorders the live particles of `particles` by the first node of their Shape's
/// window (as ParticleWeights<Shape> finds it); every component moves with its
/// particle. A particle outside the patch's cells is sorted as if on its edge.
template <class Shape>
void sort_particles_by_window(const Patch& patch, ParticleSet& particles) {
  const long n = long(particles.size());
  if (n < 2) return;
  const NodeGrid grid = node_grid(patch);
  // The window's middle node, first + (nodes - 1) / 2: the cell (linear) or the nearest
  // node (GIMP), from 0 to the patch's cell extent.
  constexpr int middle = (Shape::nodes - 1) / 2;
  const int b0 = patch.extent(Location::cell, 0) + 1, b1 = patch.extent(Location::cell, 1) + 1,
            b2 = patch.extent(Location::cell, 2) + 1;  // bins along i, j, k
  Kokkos::View<int*, MemSpace> key("mpmice::sort_key", n);
  const ParticleData data = particles.data();
  Kokkos::parallel_for(
      "mpmice::window_key", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long p) {
        const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
        const int last[3] = {b0 - 1, b1 - 1, b2 - 1};
        int c[3];
        for (int d = 0; d < 3; ++d) {
          const long m = long(wt.first[d]) + middle;
          c[d] = m < 0 ? 0 : m > last[d] ? last[d] : int(m);
        }
        key(p) = (c[0] * b1 + c[1]) * b2 + c[2];
      });
  // Already in order (a set made in order, or no particle changed window since the
  // last sort): nothing moves, and the gather of every component is skipped.
  long out_of_order = 0;
  Kokkos::parallel_reduce(
      "mpmice::window_order", Kokkos::RangePolicy<ExecSpace>(0, n - 1),
      KOKKOS_LAMBDA(long p, long& count) { count += key(p) > key(p + 1) ? 1 : 0; }, out_of_order);
  if (out_of_order == 0) return;
  const int nbin = b0 * b1 * b2;
  using Comp = Kokkos::BinOp1D<Kokkos::View<int*, MemSpace>>;
  Kokkos::BinSort<Kokkos::View<int*, MemSpace>, Comp> sorter(key, Comp(nbin, 0, nbin), /*sort_within_bins=*/false);
  sorter.create_permute_vector();
  // A bin's entries are the particles' places before the sort: an insertion sort of
  // each bin (a few particles per cell or node) puts them in that order.
  const auto order = sorter.get_permute_vector();
  const auto bin_start = sorter.get_bin_offsets();
  const auto bin_size = sorter.get_bin_count();
  Kokkos::parallel_for(
      "mpmice::stable_bins", Kokkos::RangePolicy<ExecSpace>(0, nbin), KOKKOS_LAMBDA(int b) {
        const long lo = long(bin_start(b)), size = long(bin_size(b));
        for (long i = lo + 1; i < lo + size; ++i) {
          const auto place = order(i);
          long j = i;
          for (; j > lo && order(j - 1) > place; --j) order(j) = order(j - 1);
          order(j) = place;
        }
      });
  particles = gather_particles(particles, order, n);
}

/// Reorders the live particles of `particles` by cell (the linear shape's windows).
inline void sort_particles_by_cell(const Patch& patch, ParticleSet& particles) {
  sort_particles_by_window<LinearShape>(patch, particles);
}

}  // namespace mpmice
