#pragma once
/// \file specific_volume.hpp
/// \brief Step 18: the material volume carried through advection, from the
///        specific-volume evolution (E32, seed eq. 4), as the specific value
///        VL_r / mL_r that compatible advection transports.
#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// VL_r = rho_r V v_r - theta_r kappa_r V dP_dil + dt V (theta_r alpha_r Tdot_r -
/// ftheta_r X), X = sum_s theta_s alpha_s Tdot_s (E32); writes sp_vol_L = VL/mL on
/// `cells`. With `clamp` (ClampSpecificVolume) VL_r >= TINY_RHO V v_r. Returns the
/// number of cells where some VL_r <= 0 (the step must be redone).
inline long lagrangian_specific_volume(const IndexBox& cells, double cell_volume, double dt, bool clamp,
                                       const MaterialTable& mats, const ConstField4& rho,
                                       const ConstField4& sp_vol, const ConstField4& vol_frac,
                                       const ConstField4& kappa, const ConstField3& sum_kappa,
                                       const ConstField3& del_p_dilatate, const ConstField4& temp,
                                       const ConstField4& temp_rate, const Field4& sp_vol_L) {
  long bad = 0;
  Kokkos::parallel_reduce(
      "mpmice::lagrangian_specific_volume", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, long& nbad) {
        const int n = mats.count;
        double x = 0;
        for (int s = 0; s < n; ++s)
          x += vol_frac(s, i, j, k) * eos_alpha(mats.eos[s], 1.0 / sp_vol(s, i, j, k), temp(s, i, j, k)) *
               temp_rate(s, i, j, k);
        const double sk = sum_kappa(i, j, k), dp = del_p_dilatate(i, j, k);
        bool ok = true;
        for (int r = 0; r < n; ++r) {
          const double theta = vol_frac(r, i, j, k), kap = kappa(r, i, j, k);
          const double alpha = eos_alpha(mats.eos[r], 1.0 / sp_vol(r, i, j, k), temp(r, i, j, k));
          const double mass = rho(r, i, j, k) * cell_volume;
          double vl = mass * sp_vol(r, i, j, k) - theta * kap * cell_volume * dp +
                      dt * cell_volume * (theta * alpha * temp_rate(r, i, j, k) - theta * kap / sk * x);
          const double floor = tiny_rho * cell_volume * sp_vol(r, i, j, k);
          if (clamp && vl < floor) vl = floor;
          if (!(vl > 0.0)) ok = false;
          sp_vol_L(r, i, j, k) = vl / mass;
        }
        if (!ok) ++nbad;
      },
      bad);
  return bad;
}

/// Extra cells (those of `cells_with_extra` outside `owned`): v = theta/rho, the
/// specific-volume boundary condition computeFromDensity.
inline void specific_volume_from_density(const IndexBox& cells_with_extra, const IndexBox& owned,
                                         int materials, const ConstField4& vol_frac,
                                         const ConstField4& rho, const Field4& sp_vol) {
  Kokkos::parallel_for(
      "mpmice::specific_volume_from_density", cells_with_extra.policy(),
      KOKKOS_LAMBDA(int i, int j, int k) {
        if (owned.contains(i, j, k)) return;
        for (int m = 0; m < materials; ++m) sp_vol(m, i, j, k) = vol_frac(m, i, j, k) / rho(m, i, j, k);
      });
}

}  // namespace mpmice
