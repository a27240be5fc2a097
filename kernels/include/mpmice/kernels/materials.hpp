#pragma once
/// \file materials.hpp
/// \brief The material table that cell kernels capture by value: count, equations of
///        state, and the exchange coefficients K_rs, H_rs (mpmice-algorithm.md 2).
#include <mpmice/kernels/eos.hpp>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

struct MaterialTable {
  int count = 0;
  Kokkos::Array<Eos, max_materials> eos;
  /// Momentum exchange coefficients K_rs, kg/m^3/s, symmetric, zero diagonal.
  Kokkos::Array<double, max_materials * max_materials> momentum_exchange;
  /// Heat exchange coefficients H_rs, W/m^3/K, symmetric, zero diagonal.
  Kokkos::Array<double, max_materials * max_materials> heat_exchange;

  MaterialTable() {
    for (int i = 0; i < max_materials * max_materials; ++i)
      momentum_exchange[i] = heat_exchange[i] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION double K(int r, int s) const { return momentum_exchange[r * max_materials + s]; }
  KOKKOS_INLINE_FUNCTION double H(int r, int s) const { return heat_exchange[r * max_materials + s]; }
};

}  // namespace mpmice
