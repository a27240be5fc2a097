#pragma once
/// \file math.hpp
/// \brief Device math that compiles with Kokkos 3.4 (Kokkos::Experimental::) and
///        4.x (Kokkos::). Kernels call these, never std:: functions.
#include <cstdint>
#include <cstring>

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

/// The bits of x, and the double of bits b: a copy of the bytes, which vectorises and
/// breaks no aliasing rule.
KOKKOS_FORCEINLINE_FUNCTION std::uint64_t as_bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
KOKKOS_FORCEINLINE_FUNCTION double from_bits(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

/// x^(-1/3) for x in [1e-14, 1e13], within 4 ulp, in plain arithmetic: no library call,
/// so a particle loop around it vectorises (pow does not, without -ffast-math). x is
/// brought into [1/4, 2) by exact factors of 8, in binary steps of 8^8, 8^4, 8^2 and 8
/// each way (any x in [2^-47, 2^46)); then u = 2^m x lies in [1, 2) (m = 0, 1 or 2), a
/// quartic fitted to u^(-1/3) there (relative error 3.8e-5) times 2^(m/3) gives y, and
/// two Newton steps on y^-3 = x the rest (each takes the error e to about 2 e^2). The
/// big and the small steps are separate loops: chosen in one nested `?:`, GCC 12 no
/// longer vectorised the stress update's loop. This took the elastic stress update 1.4x
/// faster than 16 steps of 8, a parabola and five Newton steps (docs/performance.md,
/// session 34).
KOKKOS_INLINE_FUNCTION double inverse_cube_root(double x) {
  double scale = 1.0;
  const double eight_s[4] = {0x1p24, 0x1p12, 0x1p6, 0x1p3}, two_s[4] = {0x1p8, 0x1p4, 0x1p2, 0x1p1};
  for (int r = 0; r < 4; ++r) {
    const bool big = x >= 0.25 * eight_s[r];  // x / 8^s >= 1/4
    x = big ? x * (1.0 / eight_s[r]) : x;
    scale = big ? scale * (1.0 / two_s[r]) : scale;
  }
  for (int r = 0; r < 4; ++r) {
    const bool small = x * eight_s[r] < 2.0;  // x 8^s < 2
    x = small ? x * eight_s[r] : x;
    scale = small ? scale * two_s[r] : scale;
  }
  const bool below_half = x < 0.5, below_one = x < 1.0;
  const double u = below_half ? 4.0 * x : below_one ? 2.0 * x : x;
  const double root = below_half ? 1.5874010519681994 : below_one ? 1.2599210498948732 : 1.0;
  double y = 1.67000381 + u * (-1.17287342 + u * (0.69547707 + u * (-0.22123598 + u * 0.02859082)));
  y *= root;
  for (int k = 0; k < 2; ++k) y += y * (1.0 - x * y * y * y) * (1.0 / 3.0);
  return scale * y;
}

}  // namespace mpmice::math
