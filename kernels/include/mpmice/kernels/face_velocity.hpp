#pragma once
/// \file face_velocity.hpp
/// \brief Step 5: face-centred normal velocities from the cell state and the
///        pressure gradient across the face (E18).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// Faces of the patch's cells and one ghost layer of cells around them: the faces
/// second-order advection needs. `d` is the face normal.
inline IndexBox faces_around_cells(const Patch& patch, int d) {
  IndexBox b = patch.ghosted_cells(1);
  b.hi[d] += 1;
  return b;
}

namespace detail {

/// A box of at least this many faces takes one material per pass when it has at least
/// `face_velocity_split_materials` (face_velocity_n). One pass over all materials streams
/// 4 N + 1 arrays, and at 128^3 cells the plane i - 1 of each (135 KB) has left the 1 MB
/// L2 by the time plane i reads it; a pass per material streams 5. With 4 materials
/// that was faster from 64^3 cells on (session 31: 1.15-1.26x), slower in boxes of
/// 16^3-32^3 cells, whose arrays stay in cache (the pressure read N times, N launches;
/// session 30), and with 2 materials no faster (docs/performance.md).
constexpr long face_velocity_split_faces = 1L << 17;
constexpr int face_velocity_split_materials = 4;

/// (E18) for material m at face (i, j, k), whose cell L is (il, jl, kl), with the
/// pressure gradient dpdx across it; `pushed` is 0 for a rigid material, else 1.
KOKKOS_FORCEINLINE_FUNCTION double material_face_velocity(const ConstField4& rho, const ConstField4& sp_vol,
                                                          const ConstField4& vel_d, int m, long i, long j, long k,
                                                          long il, long jl, long kl, double dpdx, double pushed,
                                                          double dt, double gravity) {
  const double rl = rho(m, il, jl, kl), rr = rho(m, i, j, k);
  const double vl = sp_vol(m, il, jl, kl), vr = sp_vol(m, i, j, k);
  const double vh = 2.0 * vl * vr / (vl + vr);
  const double u_avg = (rl * vel_d(m, il, jl, kl) + rr * vel_d(m, i, j, k)) / (rl + rr);
  return u_avg - pushed * (dt * vh * dpdx) + pushed * (dt * gravity);
}

// face_velocity() for N materials, N known at compile time: the loop over materials
// is written out and the body has no branch, so the loop over cells vectorises. A
// large box with many materials goes one material at a time (face_velocity_split_faces),
// by the same formula (bit for bit in a build without fused multiply-adds).
template <int N>
void face_velocity_n(const IndexBox& faces, int d, double spacing, double dt, double gravity,
                     const MaterialTable& mats, const ConstField3& press, const ConstField4& rho,
                     const ConstField4& sp_vol, const ConstField4& vel_d, const Field4& face_vel) {
  const long di = d == 0, dj = d == 1, dk = d == 2;
  // 1 for a material the pressure and gravity push, 0 for a rigid one (a product,
  // not a branch, so the loop over faces vectorises; exact either way).
  Kokkos::Array<double, N> pushed;
  for (int m = 0; m < N; ++m) pushed[m] = mats.is_rigid(m) ? 0.0 : 1.0;
  if constexpr (N >= face_velocity_split_materials) {  // fewer: no per-material loops compiled
    if (faces.size() >= face_velocity_split_faces) {
      for (int m = 0; m < N; ++m) {
        const double push = pushed[m];
        for_each_index<Rows::longest>(
            "mpmice::face_velocity", faces, KOKKOS_LAMBDA(long i, long j, long k) {
              const long il = i - di, jl = j - dj, kl = k - dk;
              const double dpdx = (press(i, j, k) - press(il, jl, kl)) / spacing;
              face_vel(m, i, j, k) =
                  material_face_velocity(rho, sp_vol, vel_d, m, i, j, k, il, jl, kl, dpdx, push, dt, gravity);
            });
      }
      return;
    }
  }
  for_each_index<Rows::longest>(
      "mpmice::face_velocity", faces, KOKKOS_LAMBDA(long i, long j, long k) {
        const long il = i - di, jl = j - dj, kl = k - dk;
        const double dpdx = (press(i, j, k) - press(il, jl, kl)) / spacing;
        unrolled_for<N>([&](int m) {
          face_vel(m, i, j, k) =
              material_face_velocity(rho, sp_vol, vel_d, m, i, j, k, il, jl, kl, dpdx, pushed[m], dt, gravity);
        });
      });
}

}  // namespace detail

/// U_r^f = (rho_L u_L + rho_R u_R)/(rho_L + rho_R) - dt vh (p_R - p_L)/h_d + dt g_d,
/// vh = 2 v_L v_R/(v_L + v_R), for every material and every face in `faces` with
/// normal d (E18). Cells L = face - e_d and R = face. A rigid material has neither
/// the pressure nor the gravity term.
inline void face_velocity(const IndexBox& faces, int d, double spacing, double dt, double gravity,
                          const MaterialTable& mats, const ConstField3& press, const ConstField4& rho,
                          const ConstField4& sp_vol, const ConstField4& vel_d,
                          const Field4& face_vel) {
  with_material_count(mats.count, [&](auto n) {
    detail::face_velocity_n<decltype(n)::value>(faces, d, spacing, dt, gravity, mats, press, rho,
                                                sp_vol, vel_d, face_vel);
  });
}

}  // namespace mpmice
