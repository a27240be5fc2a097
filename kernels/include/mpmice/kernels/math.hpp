#pragma once
/// \file math.hpp
/// \brief Device math that compiles with Kokkos 3.4 (Kokkos::Experimental::) and
///        4.x (Kokkos::). Kernels call these, never std:: functions.
#include <Kokkos_Core.hpp>

namespace mpmice::math {

#if KOKKOS_VERSION >= 30600
namespace kmath = Kokkos;
#else
namespace kmath = Kokkos::Experimental;
#endif

KOKKOS_INLINE_FUNCTION double floor(double x) { return kmath::floor(x); }
KOKKOS_INLINE_FUNCTION double sqrt(double x) { return kmath::sqrt(x); }
KOKKOS_INLINE_FUNCTION double pow(double x, double y) { return kmath::pow(x, y); }
KOKKOS_INLINE_FUNCTION double exp(double x) { return kmath::exp(x); }
KOKKOS_INLINE_FUNCTION double log(double x) { return kmath::log(x); }
KOKKOS_INLINE_FUNCTION double abs(double x) { return x < 0 ? -x : x; }
KOKKOS_INLINE_FUNCTION bool isfinite(double x) { return kmath::isfinite(x); }

/// x^(-1/3) for x in [1e-7, 1e7], within 4 ulp, in plain arithmetic: no library call,
/// so a particle loop around it vectorises (pow does not, without -ffast-math). x is
/// brought into [1/4, 2) by exact factors of 8, a parabola through x = 1/4, 1, 2 gives
/// 11%, and five Newton steps on y^-3 = x the rest.
KOKKOS_INLINE_FUNCTION double inverse_cube_root(double x) {
  double scale = 1.0;
  for (int r = 0; r < 8; ++r) {
    const bool big = x >= 2.0;
    x = big ? 0.125 * x : x;
    scale = big ? 0.5 * scale : scale;
  }
  for (int r = 0; r < 8; ++r) {
    const bool small = x < 0.25;
    x = small ? 8.0 * x : x;
    scale = small ? 2.0 * scale : scale;
  }
  const double d = x - 1.0;
  double y = 1.0 + d * (-0.536 + 0.3297 * d);
  for (int k = 0; k < 5; ++k) y += y * (1.0 - x * y * y * y) * (1.0 / 3.0);
  return scale * y;
}

}  // namespace mpmice::math
