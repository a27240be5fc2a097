#pragma once
/// \file specific_volume.hpp
/// \brief Step 18: the material volume carried through advection, from the
///        specific-volume evolution (E32, seed eq. 4), as the specific value
///        VL_r / mL_r that compatible advection transports.
#include <limits>

#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// VL_r = rho_r V v_r - theta_r kappa_r V dP_dil + dt V (theta_r alpha_r Tdot_r -
/// ftheta_r X), X = sum_s theta_s alpha_s Tdot_s (E32), with a reaction's mass sources
/// dm_r (`mass_source`, may be empty) also + dm_r v_new,r - theta_r kappa_r V dP_mx
/// (`source_sp_vol`: the new gas's specific volume, new_gas_specific_volume). Writes
/// sp_vol_L = VL/mL on `cells`, mL the Lagrangian mass (`mass_L`, E29/E30: rho_r V plus
/// a reaction's product mass; advection multiplies sp_vol_L by it again, so dividing by
/// rho_r V instead would scale the volume of a gas that gains mass by (m + dm)/m).
/// With `clamp` (ClampSpecificVolume) VL_r >= TINY_RHO V v_r. Returns the number of
/// cells where some VL_r <= 0 (the step must be redone).
/// Inputs of `lagrangian_specific_volume` (E32), in the order of its terms.
struct SpecificVolumeInputs {
  ConstField4 rho;            ///< rho_r^n, kg/m^3
  ConstField4 mass_L;         ///< mL_r (E29/E30), kg
  ConstField4 sp_vol;         ///< v_r at p_eq (E16), m^3/kg
  ConstField4 vol_frac;       ///< theta_r (E16)
  ConstField4 kappa;          ///< kappa_r (E16), 1/Pa
  ConstField3 sum_kappa;      ///< SK (E16), 1/Pa
  ConstField3 del_p_dilatate; ///< dP_dil (E20), Pa
  ConstField4 temp;           ///< T_r^n, K
  ConstField4 temp_rate;      ///< Tdot_r (E31), K/s
  ConstField4 mass_source;    ///< a reaction's dm_r, kg (empty: no reactions)
  ConstField4 source_sp_vol;  ///< the new gas's specific volume, m^3/kg
  ConstField3 del_p_mass;     ///< dP_mx (E20), Pa
};

namespace detail {

// lagrangian_specific_volume() for N materials, with or without mass sources: no
// branch is left in a cell, so the loop over cells vectorises.
template <int N, bool WithMass>
long lagrangian_specific_volume_n(const IndexBox& cells, double cell_volume, double dt, bool clamp,
                                  const MaterialTable& mats, const SpecificVolumeInputs& in,
                                  const Field4& sp_vol_L) {
  // Thermal expansivity (eos_alpha): gas_r / T with gas_r = 1 for an ideal gas, 0 for
  // the solid's law (a product, exact; a select on it kept the loop scalar).
  Kokkos::Array<double, N> gas;
  for (int r = 0; r < N; ++r) gas[r] = eos_alpha(mats.eos[r], 1.0, 1.0);
  // VL_r >= floor_scale v_r: TINY_RHO V with ClampSpecificVolume, else no floor.
  const double floor_scale = clamp ? tiny_rho * cell_volume : -std::numeric_limits<double>::infinity();
  const double bad = reduce_over_index<Reduction::sum>(
      "mpmice::lagrangian_specific_volume", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double alpha[N];
        unrolled_for<N>([&](int s) { alpha[s] = gas[s] * (1.0 / in.temp(s, i, j, k)); });
        double x = 0;
        unrolled_for<N>([&](int s) { x += in.vol_frac(s, i, j, k) * alpha[s] * in.temp_rate(s, i, j, k); });
        const double sk = in.sum_kappa(i, j, k), dp = in.del_p_dilatate(i, j, k);
        bool ok = true;
        unrolled_for<N>([&](int r) {
          const double theta = in.vol_frac(r, i, j, k), kap = in.kappa(r, i, j, k);
          const double v = in.sp_vol(r, i, j, k);
          const double mass = in.rho(r, i, j, k) * cell_volume;
          double vl = mass * v - theta * kap * cell_volume * dp +
                      dt * cell_volume * (theta * alpha[r] * in.temp_rate(r, i, j, k) - theta * kap / sk * x);
          // A reaction's new mass takes dm_r v_new, and every material gives up its share
          // of that volume by the increment dP_mx it causes (E20): sum_r of both is zero.
          if (WithMass)
            vl += in.mass_source(r, i, j, k) * in.source_sp_vol(r, i, j, k) -
                  theta * kap * cell_volume * in.del_p_mass(i, j, k);
          const double floor = floor_scale * v;
          vl = vl < floor ? floor : vl;
          ok = ok & (vl > 0.0);
          sp_vol_L(r, i, j, k) = vl / in.mass_L(r, i, j, k);
        });
        return ok ? 0.0 : 1.0;
      });
  return long(bad);
}

}  // namespace detail

/// VL_r = rho_r V v_r - theta_r kappa_r V dP_dil + dt V (theta_r alpha_r Tdot_r -
/// ftheta_r X), X = sum_s theta_s alpha_s Tdot_s (E32), with a reaction's mass sources
/// dm_r (`in.mass_source`, may be empty) also + dm_r v_new,r - theta_r kappa_r V dP_mx
/// (`in.source_sp_vol`: the new gas's specific volume, new_gas_specific_volume). Writes
/// sp_vol_L = VL/mL on `cells`, mL the Lagrangian mass (`in.mass_L`, E29/E30: rho_r V plus
/// a reaction's product mass; advection multiplies sp_vol_L by it again, so dividing by
/// rho_r V instead would scale the volume of a gas that gains mass by (m + dm)/m).
/// With `clamp` (ClampSpecificVolume) VL_r >= TINY_RHO V v_r. Returns the number of
/// cells where some VL_r <= 0 (the step must be redone).
inline long lagrangian_specific_volume(const IndexBox& cells, double cell_volume, double dt, bool clamp,
                                       const MaterialTable& mats, const SpecificVolumeInputs& in,
                                       const Field4& sp_vol_L) {
  long bad = 0;
  const bool with_mass = in.mass_source.data() != nullptr;
  with_material_count(mats.count, [&](auto n) {
    constexpr int N = decltype(n)::value;
    with_flag(with_mass, [&](auto mass) {
      bad = detail::lagrangian_specific_volume_n<N, decltype(mass)::value>(cells, cell_volume, dt, clamp, mats, in,
                                                                           sp_vol_L);
    });
  });
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
