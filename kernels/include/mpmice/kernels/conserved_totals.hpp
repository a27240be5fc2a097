#pragma once
/// \file conserved_totals.hpp
/// \brief Per-material totals over the owned cells for the conservation history
///        (Step 27): mass, momentum and energy = internal + kinetic.
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// Totals of one material over `cells`: {mass, p_x, p_y, p_z, energy}, SI units.
struct MaterialTotals {
  double value[5] = {0, 0, 0, 0, 0};
  KOKKOS_INLINE_FUNCTION MaterialTotals& operator+=(const MaterialTotals& o) {
    for (int q = 0; q < 5; ++q) value[q] += o.value[q];
    return *this;
  }
  // Kokkos 3.x joins reductions through volatile references.
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile MaterialTotals& o) volatile {
    for (int q = 0; q < 5; ++q) value[q] += o.value[q];
  }
};

}  // namespace mpmice

namespace Kokkos {
template <>
struct reduction_identity<mpmice::MaterialTotals> {
  KOKKOS_FORCEINLINE_FUNCTION static mpmice::MaterialTotals sum() { return {}; }
};
}  // namespace Kokkos

namespace mpmice {

inline MaterialTotals ice_totals(const IndexBox& cells, double cell_volume, int m, double cv,
                                 const ConstField4& rho, const ConstField4& temp,
                                 const ConstVectorField4& vel) {
  MaterialTotals total;
  Kokkos::parallel_reduce(
      "mpmice::ice_totals", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, MaterialTotals& t) {
        const double mass = rho(m, i, j, k) * cell_volume;
        const double ux = vel[0](m, i, j, k), uy = vel[1](m, i, j, k), uz = vel[2](m, i, j, k);
        t.value[0] += mass;
        t.value[1] += mass * ux;
        t.value[2] += mass * uy;
        t.value[3] += mass * uz;
        t.value[4] += mass * (cv * temp(m, i, j, k) + 0.5 * (ux * ux + uy * uy + uz * uz));
      },
      Kokkos::Sum<MaterialTotals>(total));
  return total;
}

}  // namespace mpmice
