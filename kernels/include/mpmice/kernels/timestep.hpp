#pragma once
/// \file timestep.hpp
/// \brief The ICE acoustic timestep limit (E57, explicit pressure, knob = 1).
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// min over cells, ICE (fluid) materials and directions of h_d / (c + |u_d|), times `cfl`.
/// c from the EOS at rhoM = 1/v and T (E47). A material with a volume fraction
/// rho v below `present` in a cell is absent there: its state carries no mass and
/// does not limit the step (an addition to (E57), see docs/design.md).
inline double ice_timestep(const IndexBox& cells, const Kokkos::Array<double, 3> h, double cfl,
                           const MaterialTable& mats, const ConstField4& rho, const ConstField4& sp_vol,
                           const ConstField4& temp, const ConstVectorField4& vel, double present = 1e-6) {
  double dt = 1.0e300;
  Kokkos::parallel_reduce(
      "mpmice::ice_timestep", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, double& lim) {
        for (int m = 0; m < mats.count; ++m) {
          if (!mats.is_ice(m)) continue;  // solids limit the step through (E58)
          if (rho(m, i, j, k) * sp_vol(m, i, j, k) < present) continue;
          const double c = math::sqrt(
              eos_sound_speed_squared(mats.eos[m], 1.0 / sp_vol(m, i, j, k), temp(m, i, j, k)));
          for (int d = 0; d < 3; ++d) {
            const double t = h[d] / (c + math::abs(vel[d](m, i, j, k)) + 1.0e-100);
            if (t < lim) lim = t;
          }
        }
      },
      Kokkos::Min<double>(dt));
  return cfl * dt;
}

}  // namespace mpmice
