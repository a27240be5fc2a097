#pragma once
/// \file exchange.hpp
/// \brief Step 17: implicit momentum and heat exchange among all materials of a cell
///        (E31). Because mL_r v_r = theta_r TMV, mL_r beta_rs is symmetric and the
///        solve conserves total momentum and sum m c_v T to round-off for any K, H.
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/small_solve.hpp>

namespace mpmice {

/// u_r = PL_r/mL_r, T_r = EL_r/(mL_r c_v,r); momentum: beta_rs = dt v_r theta_s K_rs,
/// heat: beta_rs = dt v_r theta_s H_rs / c_v,r; out: the exchanged velocity and
/// temperature and Tdot_r = (T_r - T_r^n)/dt (E31).
inline void exchange(const IndexBox& cells, double dt, const MaterialTable& mats,
                     const ConstField4& mass_L, const ConstVectorField4& mom_L,
                     const ConstField4& int_eng_L, const ConstField4& sp_vol,
                     const ConstField4& vol_frac, const ConstField4& temp_old,
                     const VectorField4& vel_me, const Field4& temp_me, const Field4& temp_rate) {
  Kokkos::parallel_for(
      "mpmice::exchange", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const int n = mats.count;
        double u[3 * max_materials], t[max_materials], mass[max_materials], heat_cap[max_materials];
        for (int r = 0; r < n; ++r) {
          mass[r] = mass_L(r, i, j, k);
          heat_cap[r] = mass[r] * mats.eos[r].cv;
          for (int d = 0; d < 3; ++d) u[d * max_materials + r] = mom_L[d](r, i, j, k) / mass[r];
          t[r] = int_eng_L(r, i, j, k) / heat_cap[r];
        }
        if (n > 1) {
          double beta[max_materials * max_materials];
          for (int r = 0; r < n; ++r)
            for (int s = 0; s < n; ++s)
              beta[r * max_materials + s] =
                  r == s ? 0.0 : dt * sp_vol(r, i, j, k) * vol_frac(s, i, j, k) * mats.K(r, s);
          implicit_exchange(n, beta, u, 3, mass);
          for (int r = 0; r < n; ++r)
            for (int s = 0; s < n; ++s)
              beta[r * max_materials + s] =
                  r == s ? 0.0
                         : dt * sp_vol(r, i, j, k) * vol_frac(s, i, j, k) * mats.H(r, s) / mats.eos[r].cv;
          implicit_exchange(n, beta, t, 1, heat_cap);
        }
        for (int r = 0; r < n; ++r) {
          for (int d = 0; d < 3; ++d) vel_me[d](r, i, j, k) = u[d * max_materials + r];
          temp_me(r, i, j, k) = t[r];
          temp_rate(r, i, j, k) = (t[r] - temp_old(r, i, j, k)) / dt;
        }
      });
}

}  // namespace mpmice
