#pragma once
/// \file kinetic_energy_fix.hpp
/// \brief Total-energy consistency of the advection (an addition to
///        mpmice-algorithm.md, see docs/design.md): advection of momentum averages
///        velocities and so removes kinetic energy, which the internal-energy form of
///        ICE would lose. The specific kinetic energy k = |u|^2/2 is advected with the
///        same compatible fluxes as momentum; what it carries beyond 1/2 m |u_new|^2 is
///        the kinetic energy the averaging dissipated, and becomes heat (DeBar's remap
///        correction of Lagrange-remap codes).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>

namespace mpmice {

/// k_r = |u_r|^2 / 2 over `cells`.
inline void specific_kinetic_energy(const IndexBox& cells, int materials,
                                    const ConstVectorField4& vel, const Field4& k_out) {
  // One vector loop per material (a loop over a run-time count of materials inside the
  // cell loop would keep it scalar).
  for (int m = 0; m < materials; ++m)
    for_each_index(
        "mpmice::specific_kinetic_energy", cells, KOKKOS_LAMBDA(long i, long j, long k) {
          const double ux = vel[0](m, i, j, k), uy = vel[1](m, i, j, k), uz = vel[2](m, i, j, k);
          k_out(m, i, j, k) = 0.5 * (ux * ux + uy * uy + uz * uz);
        });
}

/// T^{n+1} += (K_advected - 1/2 m^{n+1} |u^{n+1}|^2) / (m^{n+1} c_v), with
/// K_advected = mL k_L + Adv[mL k] for material m.
inline void kinetic_energy_to_heat(const IndexBox& cells, double cell_volume, int m, double cv,
                                   const ConstField4& mass_L, const ConstField4& k_L,
                                   const ConstField4& adv_k, const ConstField4& rho_new,
                                   const ConstVectorField4& vel_new, const Field4& temp_new) {
  for_each_index(
      "mpmice::kinetic_energy_to_heat", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        const double mass = rho_new(m, i, j, k) * cell_volume;
        const double ux = vel_new[0](m, i, j, k), uy = vel_new[1](m, i, j, k), uz = vel_new[2](m, i, j, k);
        const double carried = mass_L(m, i, j, k) * k_L(m, i, j, k) + adv_k(m, i, j, k);
        const double kept = 0.5 * mass * (ux * ux + uy * uy + uz * uz);
        temp_new(m, i, j, k) += (carried - kept) / (mass * cv);
      });
}

}  // namespace mpmice
