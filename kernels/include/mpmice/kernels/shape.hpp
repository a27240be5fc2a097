#pragma once
/// \file shape.hpp
/// \brief Particle-node shape functions: linear (E6, E7) and uniform GIMP (E8, E9).
///
/// Per direction a shape gives the first node of its support and the weights N and
/// derivatives dN/dx of `nodes` consecutive nodes; 3D weights are products. Positions
/// are in cell units: xi = (x - grid.lower)/h, so node i sits at xi = i.
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// Tent functions on the 2 nodes of the particle's cell (E6, E7).
struct LinearShape {
  static constexpr int nodes = 2;
  /// `half_width` (particle half-size in cell units) is not used.
  KOKKOS_INLINE_FUNCTION static void weights(double xi, double /*half_width*/, double inv_h,
                                             int& first, double* w, double* dw) {
    first = int(math::floor(xi));
    const double r = xi - first;
    w[0] = 1.0 - r;
    w[1] = r;
    dw[0] = -inv_h;
    dw[1] = inv_h;
  }
};

/// Uniform GIMP with particle half-width l in cell units, l <= 1/2: 3 nodes, the
/// nearest node and one on each side (E8, E9).
struct GimpShape {
  static constexpr int nodes = 3;
  KOKKOS_INLINE_FUNCTION static void weights(double xi, double l, double inv_h, int& first,
                                             double* w, double* dw) {
    first = int(math::floor(xi + 0.5)) - 1;
    for (int a = 0; a < 3; ++a) {
      const double r = xi - (first + a);  // particle minus node, cell units
      const double ar = math::abs(r);
      const double s = r < 0 ? -1.0 : 1.0;
      if (ar < l) {
        w[a] = 1.0 - (r * r + l * l) / (2.0 * l);
        dw[a] = -r / l * inv_h;
      } else if (ar < 1.0 - l) {
        w[a] = 1.0 - ar;
        dw[a] = -s * inv_h;
      } else if (ar < 1.0 + l) {
        const double t = 1.0 + l - ar;
        w[a] = t * t / (4.0 * l);
        dw[a] = -s * t / (2.0 * l) * inv_h;
      } else {
        w[a] = 0.0;
        dw[a] = 0.0;
      }
    }
  }
};

/// Weights and gradients of one particle on its Shape::nodes^3 nodes: node
/// (first[0] + a, first[1] + b, first[2] + c) has weight w[0][a] w[1][b] w[2][c].
template <class Shape>
struct ParticleWeights {
  int first[3];
  double w[3][Shape::nodes], dw[3][Shape::nodes];

  /// `x` in m; lower, inv_h per direction; `half_width` in cell units.
  KOKKOS_INLINE_FUNCTION ParticleWeights(const double* x, const double* lower, const double* inv_h,
                                         const double* half_width) {
    for (int d = 0; d < 3; ++d)
      Shape::weights((x[d] - lower[d]) * inv_h[d], half_width[d], inv_h[d], first[d], w[d], dw[d]);
  }
  /// The same from the grid's origin (global node 0) with local node 0 the global node
  /// `first_node`: the weights do not depend on where the patch starts (NodeGrid).
  KOKKOS_INLINE_FUNCTION ParticleWeights(const double* x, const double* origin, const double* inv_h,
                                         const int* first_node, const double* half_width) {
    for (int d = 0; d < 3; ++d) {
      Shape::weights((x[d] - origin[d]) * inv_h[d], half_width[d], inv_h[d], first[d], w[d], dw[d]);
      first[d] -= first_node[d];
    }
  }
  KOKKOS_INLINE_FUNCTION double weight(int a, int b, int c) const { return w[0][a] * w[1][b] * w[2][c]; }
  KOKKOS_INLINE_FUNCTION void gradient(int a, int b, int c, double* g) const {
    g[0] = dw[0][a] * w[1][b] * w[2][c];
    g[1] = w[0][a] * dw[1][b] * w[2][c];
    g[2] = w[0][a] * w[1][b] * dw[2][c];
  }
};

}  // namespace mpmice
