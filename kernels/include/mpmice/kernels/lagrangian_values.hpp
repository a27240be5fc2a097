#pragma once
/// \file lagrangian_values.hpp
/// \brief Step 16: the ICE materials' mass, momentum and internal energy after the
///        Lagrangian phase, before exchange (E29), and a reaction's products (E30).
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

namespace detail {

/// A box of at least this many cells runs the Lagrangian values one material per pass.
/// Their materials are independent and each streams its own 13 (momentum and energy) or
/// 17 (a reaction's products) arrays: in one pass 4 materials stream 52 arrays, which
/// ran at 43% of the triad at 128^3 cells, against 105% for one material's 13
/// (docs/performance.md, session 33). Smaller boxes stay in cache, where a launch per
/// material would cost more than it saves. face_velocity_n splits its materials the
/// same way, inline, with its own thresholds (face_velocity_split_faces): its materials
/// share the pressure gradient, read once per face in one pass.
constexpr long lagrangian_split_cells = 1L << 15;

/// body(m, i, j, k) for every material m < N and index of `cells`: in one pass with the
/// materials written out (the loop over cells vectorises), or one pass per material
/// from `lagrangian_split_cells` cells on. Every (m, i, j, k) gets the same arithmetic
/// either way.
template <int N, class Body>
void for_each_material_and_index(const std::string& label, const IndexBox& cells, const Body& body) {
  if constexpr (N > 1) {
    if (cells.size() >= lagrangian_split_cells) {
      for (int m = 0; m < N; ++m)
        for_each_index(label, cells, KOKKOS_LAMBDA(long i, long j, long k) { body(m, i, j, k); });
      return;
    }
  }
  for_each_index(label, cells, KOKKOS_LAMBDA(long i, long j, long k) {
    unrolled_for<N>([&](int m) { body(m, i, j, k); });
  });
}

// lagrangian_mass() and lagrangian_momentum_energy() for N materials: the loop over
// materials written out, so the loop over cells vectorises.
template <int N>
void lagrangian_mass_n(const IndexBox& cells_with_extra, double cell_volume, const ConstField4& rho,
                       const Field4& mass_L) {
  for_each_index(
      "mpmice::lagrangian_mass", cells_with_extra, KOKKOS_LAMBDA(long i, long j, long k) {
        unrolled_for<N>([&](int m) { mass_L(m, i, j, k) = rho(m, i, j, k) * cell_volume; });
      });
}

template <int N>
void lagrangian_momentum_energy_n(const IndexBox& cells, const MaterialTable& mats, const ConstField4& mass_L,
                                  const ConstVectorField4& vel, const ConstField4& temp,
                                  const ConstVectorField4& mom_source, const ConstField4& int_eng_source,
                                  const VectorField4& mom_L, const Field4& int_eng_L) {
  Kokkos::Array<double, N> cv;
  for (int m = 0; m < N; ++m) cv[m] = mats.eos[m].cv;
  for_each_material_and_index<N>(
      "mpmice::lagrangian_momentum_energy", cells, KOKKOS_LAMBDA(int m, long i, long j, long k) {
        const double mass = mass_L(m, i, j, k);
        unrolled_for<3>([&](int d) { mom_L[d](m, i, j, k) = mass * vel[d](m, i, j, k) + mom_source[d](m, i, j, k); });
        int_eng_L(m, i, j, k) = mass * cv[m] * temp(m, i, j, k) + int_eng_source(m, i, j, k);
      });
}

}  // namespace detail

/// mL_r = rho_r V on `cells_with_extra` (advection reads the extra cells' mass).
inline void lagrangian_mass(const IndexBox& cells_with_extra, double cell_volume, int materials,
                            const ConstField4& rho, const Field4& mass_L) {
  with_material_count(materials, [&](auto n) {
    detail::lagrangian_mass_n<decltype(n)::value>(cells_with_extra, cell_volume, rho, mass_L);
  });
}

/// PL_r = mL_r u_r^n + Q_r, EL_r = mL_r c_v T_r^n + W_r on `cells` (E29).
inline void lagrangian_momentum_energy(const IndexBox& cells, const MaterialTable& mats,
                                       const ConstField4& mass_L, const ConstVectorField4& vel,
                                       const ConstField4& temp, const ConstVectorField4& mom_source,
                                       const ConstField4& int_eng_source,
                                       const VectorField4& mom_L, const Field4& int_eng_L) {
  with_material_count(mats.count, [&](auto n) {
    detail::lagrangian_momentum_energy_n<decltype(n)::value>(cells, mats, mass_L, vel, temp, mom_source,
                                                             int_eng_source, mom_L, int_eng_L);
  });
}

namespace detail {
template <int N>
void add_product_sources_n(const IndexBox& cells, const MaterialTable& mats, const ConstField4& mass_source,
                           const ConstVectorField4& mom_source, const ConstField4& energy_source,
                           const ConstVectorField4& vel, const ConstField4& temp, const Field4& mass_L,
                           const VectorField4& mom_L, const Field4& int_eng_L, const Field4& temp_mixed) {
  for_each_material_and_index<N>(
      "mpmice::add_product_sources", cells, KOKKOS_LAMBDA(int m, long i, long j, long k) {
        const double dm = mass_source(m, i, j, k);
        const double old_mass = mass_L(m, i, j, k), cv = mats.eos[m].cv, t = temp(m, i, j, k);
        double kinetic_gain = 0;
        unrolled_for<3>([&](int d) {
          const double dp = mom_source[d](m, i, j, k), p_old = old_mass * vel[d](m, i, j, k);
          const double gain = 0.5 * ((p_old + dp) * (p_old + dp) / (old_mass + dm) - p_old * vel[d](m, i, j, k));
          kinetic_gain += dm > 0 ? gain : 0.0;
          mom_L[d](m, i, j, k) += dp;
        });
        const double de = energy_source(m, i, j, k) - kinetic_gain;
        mass_L(m, i, j, k) = old_mass + dm;
        int_eng_L(m, i, j, k) += de;
        const double mixed = (old_mass * cv * t + de) / ((old_mass + dm) * cv);
        temp_mixed(m, i, j, k) = dm > 0 ? mixed : t;
      });
}
}  // namespace detail

/// (E30) for the products of a reaction: mL_r += dm_r, PL_r += dP_r, EL_r += dE_r on
/// `cells` for every material (the sources are zero but in the products' slots). The
/// products only gain (dm_r >= 0), so (E30)'s floors at TINY_RHO V never act; the
/// reactant lost its share on its particles (particle_burn.hpp), not here.
/// dE_r is the burned solid's whole energy, kinetic included; the gas's kinetic energy
/// grows by |m u^n + dP|^2 / (2 (m + dm)) - m |u^n|^2 / 2 as it takes the momentum, and
/// the rest of dE_r (at least its internal part, by Cauchy-Schwarz) is internal energy:
/// the burned solid merges with the gas inelastically, and the kinetic energy of their
/// relative motion becomes heat. (Without it a whole burn of problems/burn_box.yaml
/// lost 13% of its initial energy at cfl 0.4 and 37% at cfl 0.1: the burning particles'
/// velocities differ within a cell, and their spread was lost; docs/design.md,
/// "Reactions".)
/// Also writes `temp_mixed`: T^n, or where a material gained mass, the temperature of
/// the old gas mixed with the new, (m c_v T^n + dE_int)/((m + dm) c_v). The exchange's Tdot
/// and (E32)'s alpha start from it: the new gas's volume is already counted
/// (new_gas_specific_volume), so mixing it in must not count again as a heating of
/// the old gas at constant pressure.
inline void add_product_sources(const IndexBox& cells, const MaterialTable& mats, const ConstField4& mass_source,
                                const ConstVectorField4& mom_source, const ConstField4& energy_source,
                                const ConstVectorField4& vel, const ConstField4& temp, const Field4& mass_L,
                                const VectorField4& mom_L, const Field4& int_eng_L, const Field4& temp_mixed) {
  with_material_count(mats.count, [&](auto n) {
    detail::add_product_sources_n<decltype(n)::value>(cells, mats, mass_source, mom_source, energy_source, vel, temp,
                                                      mass_L, mom_L, int_eng_L, temp_mixed);
  });
}

}  // namespace mpmice
