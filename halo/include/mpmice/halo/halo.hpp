#pragma once
/// \file halo.hpp
/// \brief Ghost exchange of cell, node and face fields between patches.
///
/// `fill` copies owned values into the neighbours' ghost layers (including edges and
/// corners, by sweeping x, then y, then z, each sweep carrying the ghosts already
/// filled, and the extra layers that the owner's boundary conditions filled beyond a
/// domain boundary). `sum_into_owned` is its reverse: values accumulated in ghost layers (a
/// particle-to-grid scatter) are added to the owning patch, and the ghost layers are
/// then stale. Ghosts beyond a non-periodic domain boundary are left to the boundary
/// conditions. Periodic directions with one rank across copy locally.
///
/// Buffers are device views handed to MPI directly (a GPU build needs a GPU-aware MPI).
#include <mpi.h>

#include <mpmice/halo/decomposition.hpp>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

class Halo {
 public:
  explicit Halo(const Decomposition& decomposition) : m_decomp(decomposition) {}

  /// Fill `depth` ghost layers (1 <= depth <= G) of `field` at `loc` from the owners.
  void fill(const Field4& field, Location loc, int depth);
  void fill(const Field3& field, Location loc, int depth);

  /// Add the `depth` ghost layers of `field` into the patches that own those entries.
  void sum_into_owned(const Field4& field, Location loc, int depth);
  void sum_into_owned(const Field3& field, Location loc, int depth);

  const Decomposition& decomposition() const { return m_decomp; }

  /// Bytes this rank sent to other ranks since construction (for the scaling model).
  double bytes_sent() const { return m_bytes_sent; }

  using Field4U = Kokkos::View<double****, MemSpace, Kokkos::MemoryUnmanaged>;

 private:
  void exchange(const Field4U& field, Location loc, int depth, bool reverse);
  const Decomposition& m_decomp;
  Kokkos::View<double*, MemSpace> m_send[2], m_recv[2];
  double m_bytes_sent = 0;
};

}  // namespace mpmice
