#pragma once
/// \file pressure_update.hpp
/// \brief Step 7: the pressure at the end of the step from the volume that flows into
///        each cell (E20; seed eq. 9 with the sign that makes inflow raise pressure).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

namespace detail {

// pressure_update() and sum_density() for N materials, with or without mass sources:
// the loops over materials written out, so the loop over cells vectorises.
template <int N, bool WithMass>
void pressure_update_n(const IndexBox& cells, double cell_volume, const ConstField4& adv_vol_frac,
                       const ConstField4& mass_source, const ConstField4& sp_vol, const ConstField3& sum_kappa,
                       const ConstField3& press_eq, const Field3& del_p_dilatate, const Field3& del_p_mass,
                       const Field3& press) {
  for_each_index<Rows::longest>(
      "mpmice::pressure_update", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double adv = 0, mx = 0;
        unrolled_for<N>([&](int m) {
          adv += adv_vol_frac(m, i, j, k);
          if (WithMass) mx += mass_source(m, i, j, k) * sp_vol(m, i, j, k);
        });
        const double sk = sum_kappa(i, j, k);
        const double dp_dil = adv / sk;
        const double dp_mx = mx / (cell_volume * sk);
        const double p = press_eq(i, j, k) + dp_dil + dp_mx;
        del_p_dilatate(i, j, k) = dp_dil;
        del_p_mass(i, j, k) = dp_mx;
        press(i, j, k) = p > 1.0e-12 ? p : 1.0e-12;
      });
}

template <int N>
void sum_density_n(const IndexBox& cells, const ConstField4& rho, const Field3& sum_rho) {
  for_each_index(
      "mpmice::sum_density", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double s = 0;
        unrolled_for<N>([&](int m) { s += rho(m, i, j, k); });
        sum_rho(i, j, k) = s;
      });
}

}  // namespace detail

/// dP_dil = sum_r Adv[theta_r] / SK, dP_mx = (sum_r dm_r v_r / V) / SK,
/// p^{n+1} = max(p_eq + dP_dil + dP_mx, 1e-12) on `cells` (E20). `adv_vol_frac`
/// holds Adv[theta_r]; `mass_source` may be empty (no reactions).
inline void pressure_update(const IndexBox& cells, double cell_volume, int materials,
                            const ConstField4& adv_vol_frac, const ConstField4& mass_source,
                            const ConstField4& sp_vol, const ConstField3& sum_kappa,
                            const ConstField3& press_eq, const Field3& del_p_dilatate,
                            const Field3& del_p_mass, const Field3& press) {
  const bool with_mass = mass_source.data() != nullptr;
  with_material_count(materials, [&](auto n) {
    constexpr int N = decltype(n)::value;
    with_flag(with_mass, [&](auto mass) {
      detail::pressure_update_n<N, decltype(mass)::value>(cells, cell_volume, adv_vol_frac, mass_source, sp_vol,
                                                          sum_kappa, press_eq, del_p_dilatate, del_p_mass, press);
    });
  });
}

/// Srho = sum_r rho_r (E20, last line), on `cells` (extra cells included).
inline void sum_density(const IndexBox& cells, int materials, const ConstField4& rho,
                        const Field3& sum_rho) {
  with_material_count(materials, [&](auto n) { detail::sum_density_n<decltype(n)::value>(cells, rho, sum_rho); });
}

}  // namespace mpmice
