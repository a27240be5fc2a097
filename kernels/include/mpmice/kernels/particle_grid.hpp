#pragma once
/// \file particle_grid.hpp
/// \brief What particle kernels need of the patch: where local node 0 is and the
///        cell size, plus loading and storing particle tensors.
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/math.hpp>
#include <mpmice/kernels/mat3.hpp>
#include <mpmice/kernels/particles.hpp>

namespace mpmice {

/// Local node (i,j,k) sits at lower + (i,j,k) h; it is global node first_node + (i,j,k)
/// of the grid that starts at `origin`. Particle kernels place a particle by its global
/// coordinate (x - origin)/h, the same number on every patch, so its weights are bit for
/// bit those of any other decomposition (the local index is then an integer shift).
struct NodeGrid {
  double lower[3], h[3], inv_h[3];
  double origin[3] = {0, 0, 0};
  int first_node[3] = {0, 0, 0};
  /// Position along d in cells from the grid's origin.
  KOKKOS_INLINE_FUNCTION double global_coordinate(double x, int d) const { return (x - origin[d]) * inv_h[d]; }
  /// Local index of the cell holding coordinate x along d.
  KOKKOS_INLINE_FUNCTION int cell(double x, int d) const {
    return int(math::floor(global_coordinate(x, d))) - first_node[d];
  }
};

inline NodeGrid node_grid(const Patch& p) {
  NodeGrid g;
  for (int d = 0; d < 3; ++d) {
    g.h[d] = p.grid.spacing[d];
    g.inv_h[d] = 1.0 / g.h[d];
    g.lower[d] = p.node_position(0, d);
    g.origin[d] = p.grid.lower[d];
    g.first_node[d] = p.global_index(0, d);
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
