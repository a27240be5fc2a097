#pragma once
/// \file mpm_lagrangian_values.hpp
/// \brief Steps 15 and 19 of MPMICE: the MPM materials' cell momentum and energy
///        after the Lagrangian phase from their nodes (E27), and, after the exchange,
///        the cell-centred rates the nodes have not seen yet (E33).
#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/node_to_cell.hpp>

namespace mpmice {

namespace detail {
template <bool Rigid>
void mpm_lagrangian_values_n(const IndexBox& cells, double cell_volume, int s, int m, double cv,
                             const ConstField3& weight, const ConstField4& node_mass,
                             const ConstVectorField4& node_vel_star, const ConstField4& node_temp,
                             const ConstField4& rho, const ConstVectorField4& vel, const ConstField4& temp,
                             const ConstVectorField4& mom_source, const VectorField4& mom_L, const Field4& int_eng_L) {
  const double m_small = tiny_rho * cell_volume;
  for_each_index("mpmice::mpm_lagrangian_values", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    const double mass = rho(m, i, j, k) * cell_volume;
    // A plain `if` on the template argument (folded at compile time): nvcc cannot
    // capture a variable first named inside `if constexpr`.
    if (Rigid) {  // its cell mass comes from its particles, its velocity is prescribed
      for (int d = 0; d < 3; ++d) mom_L[d](m, i, j, k) = mass * vel[d](m, i, j, k);
      int_eng_L(m, i, j, k) = mass * cv * temp(m, i, j, k);
    } else {
      double node_mass_sum = 0, p_mpm[3] = {0, 0, 0}, e_mpm = 0;  // the mass sum is not used
      add_weighted_node_sums(weight, node_mass, node_vel_star, node_temp, s, i, j, k, cv, node_mass_sum, p_mpm, e_mpm);
      const double z = (mass - m_small) / mass;
      unrolled_for<3>([&](int d) {
        mom_L[d](m, i, j, k) = (1.0 - z) * mass * vel[d](m, i, j, k) + z * (p_mpm[d] + mom_source[d](m, i, j, k));
      });
      int_eng_L(m, i, j, k) = (1.0 - z) * mass * cv * temp(m, i, j, k) + z * e_mpm;
    }
  });
}
}  // namespace detail

/// (E27) for node slot s, cell material m: P_mpm = sum_i w_i m_i v*_i + Q_r,
/// E_mpm = sum_i w_i m_i c_v T*_i (+ W_r = 0), blended with the cell's own
/// m_r u_r and m_r c_v T_r by z = (m_r - m_small)/m_r; mL = m_r. A rigid material
/// gets no Q. Overwrites slot m of mom_L and int_eng_L on `cells`.
inline void mpm_lagrangian_values(const IndexBox& cells, double cell_volume, int s, int m, double cv,
                                  bool rigid, const ConstField3& weight, const ConstField4& node_mass,
                                  const ConstVectorField4& node_vel_star, const ConstField4& node_temp,
                                  const ConstField4& rho, const ConstVectorField4& vel, const ConstField4& temp,
                                  const ConstVectorField4& mom_source, const VectorField4& mom_L,
                                  const Field4& int_eng_L) {
  with_flag(rigid, [&](auto is_rigid) {
    detail::mpm_lagrangian_values_n<decltype(is_rigid)::value>(cells, cell_volume, s, m, cv, weight, node_mass,
                                                               node_vel_star, node_temp, rho, vel, temp, mom_source,
                                                               mom_L, int_eng_L);
  });
}

namespace detail {
template <bool Rigid>
void mpm_cell_rates_n(const IndexBox& cells, double dt, int s, int m, double cv, const ConstField4& mass_L,
                      const ConstVectorField4& mom_L, const ConstField4& int_eng_L,
                      const ConstVectorField4& mom_source, const ConstVectorField4& vel_me, const ConstField4& temp_me,
                      const VectorField4& cell_acc, const Field4& cell_temp_rate) {
  for_each_index("mpmice::mpm_cell_rates", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    const double mass = mass_L(m, i, j, k);
    unrolled_for<3>([&](int d) {
      const double rate =
          (mass * vel_me[d](m, i, j, k) - (mom_L[d](m, i, j, k) - mom_source[d](m, i, j, k))) / (mass * dt);
      cell_acc[d](s, i, j, k) = Rigid ? 0.0 : rate;  // folded at compile time
    });
    cell_temp_rate(s, i, j, k) = (mass * cv * temp_me(m, i, j, k) - int_eng_L(m, i, j, k)) / (mass * cv * dt);
  });
}
}  // namespace detail

/// (E33) for cell material m into rate slot s: aV = (PME - (PL - Q))/(mL dt) (0 for a
/// rigid material), aT = (EME - (EL - W))/(mL c_v dt) with PME = mL u_ME,
/// EME = mL c_v T_ME, W = 0 for solids.
inline void mpm_cell_rates(const IndexBox& cells, double dt, int s, int m, double cv, bool rigid,
                           const ConstField4& mass_L, const ConstVectorField4& mom_L, const ConstField4& int_eng_L,
                           const ConstVectorField4& mom_source, const ConstVectorField4& vel_me,
                           const ConstField4& temp_me, const VectorField4& cell_acc, const Field4& cell_temp_rate) {
  with_flag(rigid, [&](auto is_rigid) {
    detail::mpm_cell_rates_n<decltype(is_rigid)::value>(cells, dt, s, m, cv, mass_L, mom_L, int_eng_L, mom_source,
                                                        vel_me, temp_me, cell_acc, cell_temp_rate);
  });
}

}  // namespace mpmice
