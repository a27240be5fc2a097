#pragma once
/// \file particle_sort.hpp
/// \brief Particles sorted by the window of nodes their shape reaches (row-major, by
///        its first node), so that particles with the same nodes are neighbours in
///        memory: for the linear shape the cell they are in; for GIMP the node nearest
///        them (its 27 nodes depend on which half of its cell a particle is in). The
///        scatters add runs of them together and g2p reads their nodes once per group
///        (p2g.hpp, node_reads.hpp). A counting sort (Kokkos::BinSort). It is not
///        stable on more than one thread: BinSort places a bin's particles with
///        atomics, so their order among themselves varies from run to run. The step's
///        sums do not depend on it (p2g and the internal force add in exact quanta,
///        g2p reads per particle); sums in particle order do, at round-off (the
///        history's particle totals: crossflow's beam momentum on 2 threads, 17th digit),
///        and, built without MPMICE_REPRODUCIBLE, a particle in a loop's scalar tail, by
///        an ulp (docs/design.md, "Order-independent particle sums").
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
  particles = gather_particles(particles, sorter.get_permute_vector(), n);
}

/// Reorders the live particles of `particles` by cell (the linear shape's windows).
inline void sort_particles_by_cell(const Patch& patch, ParticleSet& particles) {
  sort_particles_by_window<LinearShape>(patch, particles);
}

}  // namespace mpmice
