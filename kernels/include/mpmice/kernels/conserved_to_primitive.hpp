#pragma once
/// \file conserved_to_primitive.hpp
/// \brief Steps 25-26: the advected totals back to density, velocity, temperature and
///        specific volume (E37, E38).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// m^{n+1} = mL + Adv[m], rho^{n+1} = m^{n+1}/V (E37, E38).
inline void advance_density(const IndexBox& cells, double cell_volume, int m,
                            const ConstField4& mass_L, const ConstField4& adv_mass,
                            const Field4& rho_new) {
  Kokkos::parallel_for(
      "mpmice::advance_density", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        rho_new(m, i, j, k) = (mass_L(m, i, j, k) + adv_mass(m, i, j, k)) / cell_volume;
      });
}

/// A mass-specific quantity after advection: q^{n+1} = (mL q_L + Adv[mL q])/m^{n+1}
/// (E37, E38), with m^{n+1} = rho^{n+1} V.
inline void advance_specific(const IndexBox& cells, double cell_volume, int m,
                             const ConstField4& mass_L, const ConstField4& q_L,
                             const ConstField4& adv_q, const ConstField4& rho_new,
                             const Field4& q_new) {
  Kokkos::parallel_for(
      "mpmice::advance_specific", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        q_new(m, i, j, k) = (mass_L(m, i, j, k) * q_L(m, i, j, k) + adv_q(m, i, j, k)) /
                            (rho_new(m, i, j, k) * cell_volume);
      });
}

/// Cells (local index) where rho, T or v is not positive or a velocity not finite
/// after the step (E38's stop condition); returns how many.
inline long count_bad_states(const IndexBox& cells, int materials, const ConstField4& rho,
                             const ConstField4& temp, const ConstField4& sp_vol,
                             const ConstVectorField4& vel) {
  long bad = 0;
  Kokkos::parallel_reduce(
      "mpmice::count_bad_states", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, long& n) {
        for (int m = 0; m < materials; ++m) {
          const bool ok = rho(m, i, j, k) > 0 && temp(m, i, j, k) > 0 && sp_vol(m, i, j, k) > 0 &&
                          math::isfinite(vel[0](m, i, j, k)) && math::isfinite(vel[1](m, i, j, k)) &&
                          math::isfinite(vel[2](m, i, j, k)) && math::isfinite(rho(m, i, j, k)) &&
                          math::isfinite(temp(m, i, j, k));
          if (!ok) {
            ++n;
            return;
          }
        }
      },
      bad);
  return bad;
}

}  // namespace mpmice
