#pragma once
/// \file face_velocity.hpp
/// \brief Step 5: face-centred normal velocities from the cell state and the
///        pressure gradient across the face (E18).
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// Faces of the patch's cells and one ghost layer of cells around them: the faces
/// second-order advection needs. `d` is the face normal.
inline IndexBox faces_around_cells(const Patch& patch, int d) {
  IndexBox b = patch.ghosted_cells(1);
  b.hi[d] += 1;
  return b;
}

/// U_r^f = (rho_L u_L + rho_R u_R)/(rho_L + rho_R) - dt vh (p_R - p_L)/h_d + dt g_d,
/// vh = 2 v_L v_R/(v_L + v_R), for every material and every face in `faces` with
/// normal d (E18). Cells L = face - e_d and R = face. A rigid material has neither
/// the pressure nor the gravity term.
inline void face_velocity(const IndexBox& faces, int d, double spacing, double dt, double gravity,
                          const MaterialTable& mats, const ConstField3& press, const ConstField4& rho,
                          const ConstField4& sp_vol, const ConstField4& vel_d,
                          const Field4& face_vel) {
  const int di = d == 0, dj = d == 1, dk = d == 2;
  Kokkos::parallel_for(
      "mpmice::face_velocity", faces.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const int il = i - di, jl = j - dj, kl = k - dk;
        const double dpdx = (press(i, j, k) - press(il, jl, kl)) / spacing;
        for (int m = 0; m < mats.count; ++m) {
          const double rl = rho(m, il, jl, kl), rr = rho(m, i, j, k);
          const double vl = sp_vol(m, il, jl, kl), vr = sp_vol(m, i, j, k);
          const double vh = 2.0 * vl * vr / (vl + vr);
          const double u_avg = (rl * vel_d(m, il, jl, kl) + rr * vel_d(m, i, j, k)) / (rl + rr);
          face_vel(m, i, j, k) = mats.is_rigid(m) ? u_avg : u_avg - dt * vh * dpdx + dt * gravity;
        }
      });
}

}  // namespace mpmice
