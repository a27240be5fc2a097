#pragma once
/// \file exchange.hpp
/// \brief Step 17: implicit momentum and heat exchange among all materials of a cell
///        (E31). Because mL_r v_r = theta_r TMV, mL_r beta_rs is symmetric and the
///        solve conserves total momentum and sum m c_v T to round-off for any K, H.
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/small_solve.hpp>

namespace mpmice {

namespace detail {

// exchange() for N materials, N known at compile time: every loop in a cell is
// written out, so the loop over cells vectorises.
template <int N>
void exchange_n(const IndexBox& cells, double dt, const MaterialTable& mats, const ConstField4& mass_L,
                const ConstVectorField4& mom_L, const ConstField4& int_eng_L, const ConstField4& sp_vol,
                const ConstField4& vol_frac, const ConstField4& temp_old, const VectorField4& vel_me,
                const Field4& temp_me, const Field4& temp_rate) {
  // Per pair, the coefficients without the cell's state: K_rs and H_rs / c_v,r.
  Kokkos::Array<double, N * N> K, H_cv;
  for (int r = 0; r < N; ++r)
    for (int s = 0; s < N; ++s) {
      K[r * N + s] = mats.K(r, s);
      H_cv[r * N + s] = mats.H(r, s) / mats.eos[r].cv;
    }
  Kokkos::Array<double, N> cv, inv_cv;
  for (int r = 0; r < N; ++r) {
    cv[r] = mats.eos[r].cv;
    inv_cv[r] = 1.0 / cv[r];
  }
  const double inv_dt = 1.0 / dt;
  for_each_index(
      "mpmice::exchange", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double u[3 * N], t[N], mass[N], heat_cap[N], dt_v[N], theta[N];
        unrolled_for<N>([&](int r) {
          mass[r] = mass_L(r, i, j, k);
          heat_cap[r] = mass[r] * cv[r];
          const double inv_mass = 1.0 / mass[r];
          unrolled_for<3>([&](int d) { u[d * N + r] = mom_L[d](r, i, j, k) * inv_mass; });
          t[r] = int_eng_L(r, i, j, k) * inv_mass * inv_cv[r];  // multiplications: divisions cost 10-20 times more
          dt_v[r] = dt * sp_vol(r, i, j, k);
          theta[r] = vol_frac(r, i, j, k);
        });
        if (N > 1) {
          double beta[N * N];
          unrolled_for<N>([&](int r) {
            unrolled_for<N>([&](int s) { beta[r * N + s] = r == s ? 0.0 : dt_v[r] * theta[s] * K[r * N + s]; });
          });
          implicit_exchange<N, 3>(beta, u, mass);
          unrolled_for<N>([&](int r) {
            unrolled_for<N>([&](int s) { beta[r * N + s] = r == s ? 0.0 : dt_v[r] * theta[s] * H_cv[r * N + s]; });
          });
          implicit_exchange<N, 1>(beta, t, heat_cap);
        }
        unrolled_for<N>([&](int r) {
          unrolled_for<3>([&](int d) { vel_me[d](r, i, j, k) = u[d * N + r]; });
          temp_me(r, i, j, k) = t[r];
          temp_rate(r, i, j, k) = (t[r] - temp_old(r, i, j, k)) * inv_dt;
        });
      });
}

}  // namespace detail

/// u_r = PL_r/mL_r, T_r = EL_r/(mL_r c_v,r); momentum: beta_rs = dt v_r theta_s K_rs,
/// heat: beta_rs = dt v_r theta_s H_rs / c_v,r; out: the exchanged velocity and
/// temperature and Tdot_r = (T_r - T_r^n)/dt (E31).
inline void exchange(const IndexBox& cells, double dt, const MaterialTable& mats,
                     const ConstField4& mass_L, const ConstVectorField4& mom_L,
                     const ConstField4& int_eng_L, const ConstField4& sp_vol,
                     const ConstField4& vol_frac, const ConstField4& temp_old,
                     const VectorField4& vel_me, const Field4& temp_me, const Field4& temp_rate) {
  with_material_count(mats.count, [&](auto n) {
    detail::exchange_n<decltype(n)::value>(cells, dt, mats, mass_L, mom_L, int_eng_L, sp_vol, vol_frac, temp_old,
                                           vel_me, temp_me, temp_rate);
  });
}

}  // namespace mpmice
