#pragma once
/// \file trilinear.hpp
/// \brief A node field over one cell as the interpolant of the linear shape (E6, E7):
///        sum_i S_ip f_i = f(r), with r the particle's place in its cell in cell units,
///        in the form c0 + c1 x + c2 y + c3 z + c4 xy + c5 yz + c6 xz + c7 xyz.
///
/// The coefficients depend on the cell alone, so particles of one cell (sorted by cell)
/// share them: each evaluates f in 14 operations and its slopes in 8 more, instead of
/// forming 8 weights and 24 gradient factors and 32 products per field (g2p, E35, E36).
/// Evaluated in this form, a uniform field gives its value and zero slopes exactly.
/// Coefficient j of a cell is at c[j * Stride]: the coefficients of several cells can be
/// kept side by side, a cell's every Stride-th value (g2p forms them for 4 cells at once).
#include <Kokkos_Core.hpp>

namespace mpmice::trilinear {

/// The coefficients c from the values at the cell's nodes: f[4a + 2b + c] at node
/// (a, b, c) of the cell, a along x, b along y, c along z.
template <int Stride = 1>
KOKKOS_FORCEINLINE_FUNCTION void coefficients(const double* f, double* c) {
  c[0] = f[0];
  c[1 * Stride] = f[4] - f[0];
  c[2 * Stride] = f[2] - f[0];
  c[3 * Stride] = f[1] - f[0];
  c[4 * Stride] = (f[6] - f[2]) - c[1 * Stride];
  c[5 * Stride] = (f[3] - f[1]) - c[2 * Stride];
  c[6 * Stride] = (f[5] - f[1]) - c[1 * Stride];
  c[7 * Stride] = ((f[7] - f[3]) - (f[5] - f[1])) - c[4 * Stride];
}

/// f at (x, y, z) in the cell, cell units, and, with `slope`, its derivatives there
/// along x, y and z per cell (times 1/h for the gradient).
template <int Stride = 1>
KOKKOS_FORCEINLINE_FUNCTION double value(const double* c, double x, double y, double z, double* slope = nullptr) {
  const double along_y = c[2 * Stride] + z * c[5 * Stride], cross = c[4 * Stride] + z * c[7 * Stride];
  const double along_x = c[1 * Stride] + z * c[6 * Stride] + y * cross;
  if (slope) {
    slope[0] = along_x;
    slope[1] = along_y + x * cross;
    slope[2] = c[3 * Stride] + y * c[5 * Stride] + x * (c[6 * Stride] + y * c[7 * Stride]);
  }
  return c[0] + z * c[3 * Stride] + y * along_y + x * along_x;
}

}  // namespace mpmice::trilinear
