#pragma once
/// \file lagrangian_values.hpp
/// \brief Step 16: the ICE materials' mass, momentum and internal energy after the
///        Lagrangian phase, before exchange (E29), and a reaction's products (E30).
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// mL_r = rho_r V on `cells_with_extra` (advection reads the extra cells' mass).
inline void lagrangian_mass(const IndexBox& cells_with_extra, double cell_volume, int materials,
                            const ConstField4& rho, const Field4& mass_L) {
  Kokkos::parallel_for(
      "mpmice::lagrangian_mass", cells_with_extra.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int m = 0; m < materials; ++m) mass_L(m, i, j, k) = rho(m, i, j, k) * cell_volume;
      });
}

/// PL_r = mL_r u_r^n + Q_r, EL_r = mL_r c_v T_r^n + W_r on `cells` (E29).
inline void lagrangian_momentum_energy(const IndexBox& cells, const MaterialTable& mats,
                                       const ConstField4& mass_L, const ConstVectorField4& vel,
                                       const ConstField4& temp, const ConstVectorField4& mom_source,
                                       const ConstField4& int_eng_source,
                                       const VectorField4& mom_L, const Field4& int_eng_L) {
  Kokkos::parallel_for(
      "mpmice::lagrangian_momentum_energy", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int m = 0; m < mats.count; ++m) {
          const double mass = mass_L(m, i, j, k);
          for (int d = 0; d < 3; ++d)
            mom_L[d](m, i, j, k) = mass * vel[d](m, i, j, k) + mom_source[d](m, i, j, k);
          int_eng_L(m, i, j, k) = mass * mats.eos[m].cv * temp(m, i, j, k) + int_eng_source(m, i, j, k);
        }
      });
}

/// (E30) for the products of a reaction: mL_r += dm_r, PL_r += dP_r, EL_r += dE_r on
/// `cells` for every material (the sources are zero but in the products' slots). The
/// products only gain (dm_r >= 0), so (E30)'s floors at TINY_RHO V never act; the
/// reactant lost its share on its particles (particle_burn.hpp), not here.
/// Also writes `temp_mixed`: T^n, or where a material gained mass, the temperature of
/// the old gas mixed with the new, (m c_v T^n + dE)/((m + dm) c_v). The exchange's Tdot
/// and (E32)'s alpha start from it: the new gas's volume is already counted
/// (new_gas_specific_volume), so mixing it in must not count again as a heating of
/// the old gas at constant pressure.
inline void add_product_sources(const IndexBox& cells, const MaterialTable& mats, const ConstField4& mass_source,
                                const ConstVectorField4& mom_source, const ConstField4& energy_source,
                                const ConstField4& temp, const Field4& mass_L, const VectorField4& mom_L,
                                const Field4& int_eng_L, const Field4& temp_mixed) {
  Kokkos::parallel_for(
      "mpmice::add_product_sources", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int m = 0; m < mats.count; ++m) {
          const double dm = mass_source(m, i, j, k), de = energy_source(m, i, j, k);
          const double old_mass = mass_L(m, i, j, k), cv = mats.eos[m].cv, t = temp(m, i, j, k);
          mass_L(m, i, j, k) = old_mass + dm;
          for (int d = 0; d < 3; ++d) mom_L[d](m, i, j, k) += mom_source[d](m, i, j, k);
          int_eng_L(m, i, j, k) += de;
          temp_mixed(m, i, j, k) = dm > 0 ? (old_mass * cv * t + de) / ((old_mass + dm) * cv) : t;
        }
      });
}

}  // namespace mpmice
