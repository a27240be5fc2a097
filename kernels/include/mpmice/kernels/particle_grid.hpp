#pragma once
/// \file particle_grid.hpp
/// \brief What particle kernels need of the patch: where local node 0 is and the
///        cell size, plus loading and storing particle tensors.
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/mat3.hpp>
#include <mpmice/kernels/particles.hpp>

namespace mpmice {

/// Local node (i,j,k) sits at lower + (i,j,k) h.
struct NodeGrid {
  double lower[3], h[3], inv_h[3];
};

inline NodeGrid node_grid(const Patch& p) {
  NodeGrid g;
  for (int d = 0; d < 3; ++d) {
    g.h[d] = p.grid.spacing[d];
    g.inv_h[d] = 1.0 / g.h[d];
    g.lower[d] = p.node_position(0, d);
  }
  return g;
}

KOKKOS_INLINE_FUNCTION Mat3 load_tensor(const ParticleData& data, long p, ParticleField first) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = data(p, tensor_column(first, i, j));
  return m;
}

KOKKOS_INLINE_FUNCTION void store_tensor(const ParticleData& data, long p, ParticleField first, const Mat3& m) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) data(p, tensor_column(first, i, j)) = m(i, j);
}

/// Position and half-width (cell units) of particle p.
KOKKOS_INLINE_FUNCTION void particle_position(const ParticleData& data, long p, double* x, double* half) {
  for (int d = 0; d < 3; ++d) {
    x[d] = data(p, column(ParticleField::x) + d);
    half[d] = 0.5 * data(p, column(ParticleField::size_x) + d);
  }
}

}  // namespace mpmice
