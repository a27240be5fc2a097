#pragma once
/// \file trilinear.hpp
/// \brief A node field over one cell as the interpolant of the linear shape (E6, E7):
///        sum_i S_ip f_i = f(r), with r the particle's place in its cell in cell units,
///        in the form c0 + c1 x + c2 y + c3 z + c4 xy + c5 yz + c6 xz + c7 xyz.
///
/// The coefficients depend on the cell alone, so particles of one cell (sorted by cell)
/// share them: each evaluates f in 14 operations and its gradient in 8 more, instead of
/// forming 8 weights and 24 gradient factors and 32 products per field (g2p, E35, E36).
/// Evaluated in this form, a uniform field gives its value and a zero gradient exactly.
#include <Kokkos_Core.hpp>

namespace mpmice {

struct Trilinear {
  double c[8];

  /// The coefficients from the values at the cell's nodes: f[4a + 2b + c] at node
  /// (a, b, c) of the cell, a along x, b along y, c along z.
  KOKKOS_FORCEINLINE_FUNCTION static Trilinear of(const double* f) {
    Trilinear t;
    t.c[0] = f[0];
    t.c[1] = f[4] - f[0];
    t.c[2] = f[2] - f[0];
    t.c[3] = f[1] - f[0];
    t.c[4] = (f[6] - f[2]) - t.c[1];
    t.c[5] = (f[3] - f[1]) - t.c[2];
    t.c[6] = (f[5] - f[1]) - t.c[1];
    t.c[7] = ((f[7] - f[3]) - (f[5] - f[1])) - t.c[4];
    return t;
  }

  /// f at (x, y, z) in the cell, cell units.
  KOKKOS_FORCEINLINE_FUNCTION double value(double x, double y, double z) const {
    const double along_y = c[2] + z * c[5], cross = c[4] + z * c[7];
    const double along_x = c[1] + z * c[6] + y * cross;
    return c[0] + z * c[3] + y * along_y + x * along_x;
  }

  /// f at (x, y, z) and its derivatives there along x, y and z per cell (times 1/h for
  /// the gradient).
  KOKKOS_FORCEINLINE_FUNCTION double value_and_slopes(double x, double y, double z, double* slope) const {
    const double along_y = c[2] + z * c[5], cross = c[4] + z * c[7];
    const double along_x = c[1] + z * c[6] + y * cross;
    slope[0] = along_x;
    slope[1] = along_y + x * cross;
    slope[2] = c[3] + y * c[5] + x * (c[6] + y * c[7]);
    return c[0] + z * c[3] + y * along_y + x * along_x;
  }
};

}  // namespace mpmice
