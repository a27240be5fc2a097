#pragma once
/// \file particle_grid.hpp
/// \brief What particle kernels need of the patch: where local node 0 is and the
///        cell size, plus loading and storing particle tensors.
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/math.hpp>
#include <mpmice/kernels/mat3.hpp>
#include <mpmice/kernels/particles.hpp>
#include <mpmice/kernels/shape.hpp>

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

/// A node field (m, i, j, k) as one flat array over its whole span, for particle
/// kernels: a particle finds its first node once (NodeStencil) and reaches the others by
/// constant steps, instead of each field's view indexing every node again.
using ConstNodeArray = Kokkos::View<const double*, MemSpace, Kokkos::MemoryUnmanaged>;

inline ConstNodeArray node_array(const ConstField4& f) { return ConstNodeArray(f.data(), f.span()); }

/// Where material m's node (first + (a, b, c)) is in the node_array of any field shaped
/// like `like` (every node field of a patch is): at(first) + step(a, b, c). Any layout.
template <int Nodes>
struct NodeStencil {
  long base = 0, stride[3] = {0, 0, 0};
  long steps[Nodes * Nodes * Nodes] = {};  ///< step(a, b, c), a slowest

  NodeStencil(const ConstField4& like, int m)
      : NodeStencil(long(m) * long(like.stride(0)), long(like.stride(1)), long(like.stride(2)), long(like.stride(3))) {}
  /// Node (i, j, k) at base + i stride_i + j stride_j + k stride_k.
  NodeStencil(long base_, long stride_i, long stride_j, long stride_k) : base(base_), stride{stride_i, stride_j, stride_k} {
    for (int a = 0; a < Nodes; ++a)
      for (int b = 0; b < Nodes; ++b)
        for (int c = 0; c < Nodes; ++c) steps[(a * Nodes + b) * Nodes + c] = a * stride[0] + b * stride[1] + c * stride[2];
  }
  KOKKOS_INLINE_FUNCTION long at(const NodeOffset* first) const {
    return base + first[0] * stride[0] + first[1] * stride[1] + first[2] * stride[2];
  }
  KOKKOS_INLINE_FUNCTION long step(int a, int b, int c) const { return steps[(a * Nodes + b) * Nodes + c]; }
  /// The place of the middle node of a particle whose first node is at `first`: its
  /// nearest node, which has weight for the linear and GIMP shapes.
  KOKKOS_INLINE_FUNCTION long middle(long first) const {
    constexpr int mid = (Nodes - 1) / 2;
    return first + step(mid, mid, mid);
  }
};

/// Loads and stores of a particle's tensor are written out (`unrolled_for`), so that a
/// particle loop around them vectorises (loops.hpp).
KOKKOS_INLINE_FUNCTION Mat3 load_tensor(const ParticleData& data, long p, ParticleField first) {
  Mat3 m;
  unrolled_for<3>([&](int i) { unrolled_for<3>([&](int j) { m(i, j) = data(p, tensor_column(first, i, j)); }); });
  return m;
}

KOKKOS_INLINE_FUNCTION void store_tensor(const ParticleData& data, long p, ParticleField first, const Mat3& m) {
  unrolled_for<3>([&](int i) { unrolled_for<3>([&](int j) { data(p, tensor_column(first, i, j)) = m(i, j); }); });
}

/// Position and half-width (cell units) of particle p.
KOKKOS_INLINE_FUNCTION void particle_position(const ParticleData& data, long p, double* x, double* half) {
  for (int d = 0; d < 3; ++d) {
    x[d] = data(p, column(ParticleField::x) + d);
    half[d] = 0.5 * data(p, column(ParticleField::size_x) + d);
  }
}

/// Particle p's weights over the nodes of its Shape's window, from local node `first`.
template <class Shape>
KOKKOS_FORCEINLINE_FUNCTION ParticleWeights<Shape> particle_weights(const NodeGrid& grid, const ParticleData& data,
                                                                   long p) {
  double x[3], half[3];
  particle_position(data, p, x, half);
  return ParticleWeights<Shape>(x, grid.origin, grid.inv_h, grid.first_node, half);
}

}  // namespace mpmice
