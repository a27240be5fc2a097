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

}  // namespace mpmice::math
