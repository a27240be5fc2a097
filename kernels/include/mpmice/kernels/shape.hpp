#pragma once
/// \file shape.hpp
/// \brief Particle-node shape functions: linear (E6, E7) and uniform GIMP (E8, E9).
///
/// Per direction a shape gives the first node of its support and the weights N and
/// derivatives dN/dx of `nodes` consecutive nodes; 3D weights are products. Positions
/// are in cell units: xi = (x - grid.lower)/h, so node i sits at xi = i.
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// Tent functions on the 2 nodes of the particle's cell (E6, E7).
struct LinearShape {
  static constexpr int nodes = 2;
  /// `half_width` (particle half-size in cell units) is not used.
  KOKKOS_INLINE_FUNCTION static void weights(double xi, double /*half_width*/, double inv_h,
                                             NodeOffset& first, double* w, double* dw) {
    first = NodeOffset(math::floor(xi));
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
  KOKKOS_INLINE_FUNCTION static void weights(double xi, double l, double inv_h, NodeOffset& first,
                                             double* w, double* dw) {
    // The nearest node is floor(xi + 0.5), written with floor(xi) so that no sum
    // uses xi: GCC then never fuses xi's product (ParticleWeights) into an FMA, and
    // every kernel gets the same weights (see ParticleWeights).
    const double cell = math::floor(xi);
    first = NodeOffset(cell) - (xi - cell < 0.5 ? 1 : 0);
    unrolled_for<3>([&](int a) {
      const double r = xi - (first + a);  // particle minus node, cell units
      const double ar = math::abs(r);
      const double s = r < 0 ? -1.0 : 1.0;
      // The three pieces are all evaluated and the right one selected: no branch and
      // no loop left, so particle loops vectorise (loops.hpp).
      const double t = 1.0 + l - ar;
      const double w_inside = 1.0 - 0.5 * (r * r / l + l), dw_inside = -r / l * inv_h;
      const double w_between = 1.0 - ar, dw_between = -s * inv_h;
      const double w_edge = t * t / (4.0 * l), dw_edge = -s * t / (2.0 * l) * inv_h;
      w[a] = ar < l ? w_inside : ar < 1.0 - l ? w_between : ar < 1.0 + l ? w_edge : 0.0;
      dw[a] = ar < l ? dw_inside : ar < 1.0 - l ? dw_between : ar < 1.0 + l ? dw_edge : 0.0;
    });
  }
};

/// Weights and gradients of one particle on its Shape::nodes^3 nodes: node
/// (first[0] + a, first[1] + b, first[2] + c) has weight w[0][a] w[1][b] w[2][c].
///
/// Every particle kernel (p2g, internal force, g2p, ...) must get the same weights to
/// the last bit: the momentum that g2p gives a particle balances what p2g took from it
/// only then. GCC fuses a product and a sum into one FMA (-ffp-contract=fast, its
/// default) only when every use of the product is a sum, so it decides differently in
/// differently shaped kernels (scalar or vectorised). The shapes are therefore written
/// without a product whose uses are all sums, or with one whose fusing is exact
/// (0.5 x). Tests: `Transfer.*WeightsAgreeBetweenKernels`.
template <class Shape>
struct ParticleWeights {
  NodeOffset first[3];
  double w[3][Shape::nodes], dw[3][Shape::nodes];

  /// `x` in m; lower, inv_h per direction; `half_width` in cell units.
  KOKKOS_INLINE_FUNCTION ParticleWeights(const double* x, const double* lower, const double* inv_h,
                                         const double* half_width) {
    unrolled_for<3>([&](int d) {
      Shape::weights((x[d] - lower[d]) * inv_h[d], half_width[d], inv_h[d], first[d], w[d], dw[d]);
    });
  }
  /// The same from the grid's origin (global node 0) with local node 0 the global node
  /// `first_node`: the weights do not depend on where the patch starts (NodeGrid).
  KOKKOS_INLINE_FUNCTION ParticleWeights(const double* x, const double* origin, const double* inv_h,
                                         const int* first_node, const double* half_width) {
    unrolled_for<3>([&](int d) {
      Shape::weights((x[d] - origin[d]) * inv_h[d], half_width[d], inv_h[d], first[d], w[d], dw[d]);
      first[d] -= first_node[d];
    });
  }
  KOKKOS_INLINE_FUNCTION double weight(int a, int b, int c) const { return w[0][a] * w[1][b] * w[2][c]; }
  KOKKOS_INLINE_FUNCTION void gradient(int a, int b, int c, double* g) const {
    g[0] = dw[0][a] * w[1][b] * w[2][c];
    g[1] = w[0][a] * dw[1][b] * w[2][c];
    g[2] = w[0][a] * w[1][b] * dw[2][c];
  }
  /// The same for node i = (a n + b) n + c of the window (n = Shape::nodes), the order
  /// of NodeStencil::steps.
  KOKKOS_INLINE_FUNCTION double weight(int i) const {
    constexpr int n = Shape::nodes;
    return weight(i / (n * n), i / n % n, i % n);
  }
  KOKKOS_INLINE_FUNCTION void gradient(int i, double* g) const {
    constexpr int n = Shape::nodes;
    gradient(i / (n * n), i / n % n, i % n, g);
  }
};

}  // namespace mpmice
