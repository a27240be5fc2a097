#pragma once
/// \file materials.hpp
/// \brief The material table that cell kernels capture by value: count, equations of
///        state, and the exchange coefficients K_rs, H_rs (mpmice-algorithm.md 2).
#include <type_traits>

#include <mpmice/kernels/eos.hpp>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

/// What kind of material a cell-field slot holds.
enum MaterialKind : int {
  ice_material = 0,    ///< fluid: cell fields, advected
  mpm_material = 1,    ///< solid: particles; cell fields rebuilt from nodes each step
  rigid_material = 2   ///< solid with prescribed motion: no pressure force on it
};

struct MaterialTable {
  int count = 0;
  Kokkos::Array<Eos, max_materials> eos;
  Kokkos::Array<int, max_materials> kind;
  /// Momentum exchange coefficients K_rs, kg/m^3/s, symmetric, zero diagonal.
  Kokkos::Array<double, max_materials * max_materials> momentum_exchange;
  /// Heat exchange coefficients H_rs, W/m^3/K, symmetric, zero diagonal.
  Kokkos::Array<double, max_materials * max_materials> heat_exchange;

  MaterialTable() {
    for (int i = 0; i < max_materials * max_materials; ++i)
      momentum_exchange[i] = heat_exchange[i] = 0.0;
    for (int m = 0; m < max_materials; ++m) kind[m] = ice_material;
  }
  KOKKOS_INLINE_FUNCTION bool is_ice(int m) const { return kind[m] == ice_material; }
  KOKKOS_INLINE_FUNCTION bool is_rigid(int m) const { return kind[m] == rigid_material; }
  KOKKOS_INLINE_FUNCTION double K(int r, int s) const { return momentum_exchange[r * max_materials + s]; }
  KOKKOS_INLINE_FUNCTION double H(int r, int s) const { return heat_exchange[r * max_materials + s]; }
};

/// Calls f(std::integral_constant<int, N>{}) with N = n, for n in 1..max_materials:
/// the per-cell kernels are instantiated once per material count.
template <class F>
void with_material_count(int n, F&& f) {
  static_assert(max_materials == 8, "with_material_count lists 1..8");
  switch (n) {
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 2: f(std::integral_constant<int, 2>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 5: f(std::integral_constant<int, 5>{}); break;
    case 6: f(std::integral_constant<int, 6>{}); break;
    case 7: f(std::integral_constant<int, 7>{}); break;
    case 8: f(std::integral_constant<int, 8>{}); break;
    default: break;  // no materials: nothing to do
  }
}

/// Calls f(std::true_type{}) or f(std::false_type{}): a run-time choice (all materials
/// ideal gases, mass sources present, ...) made a template argument of a kernel.
template <class F>
void with_flag(bool flag, F&& f) {
  if (flag)
    f(std::true_type{});
  else
    f(std::false_type{});
}

/// `prefix M(N, Flag);` for every N of with_material_count and both flags of with_flag,
/// M a kernel's signature: with `extern template` or `template`, the instances of a kernel
/// compiled once for the project's own programs (kernels/instances/).
#define MPMICE_EACH_COUNT_AND_FLAG(prefix, M)                                                    \
  prefix M(1, false); prefix M(1, true); prefix M(2, false); prefix M(2, true); prefix M(3, false); \
  prefix M(3, true); prefix M(4, false); prefix M(4, true); prefix M(5, false); prefix M(5, true);  \
  prefix M(6, false); prefix M(6, true); prefix M(7, false); prefix M(7, true); prefix M(8, false); \
  prefix M(8, true);

}  // namespace mpmice
