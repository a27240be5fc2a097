#pragma once
/// \file face_exchange.hpp
/// \brief Step 6: implicit momentum exchange among the materials on each face (E19).
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/small_solve.hpp>

namespace mpmice {

namespace detail {

// face_exchange() for N materials, N known at compile time: every loop in a face is
// written out, so the loop over faces vectorises. One material: a copy, which small
// boxes make on the calling thread (for_each_index_light).
template <int N>
void face_exchange_n(const IndexBox& faces, int d, double dt, const MaterialTable& mats,
                     const ConstField4& vol_frac, const ConstField4& sp_vol, const ConstField4& face_vel,
                     const Field4& face_vel_me) {
  if constexpr (N == 1) {  // the velocity copied
    for_each_index_light("mpmice::face_exchange", faces, KOKKOS_LAMBDA(long i, long j, long k) {
      face_vel_me(0, i, j, k) = face_vel(0, i, j, k);
    });
    return;
  }
  const long di = d == 0, dj = d == 1, dk = d == 2;
  // K_rs copied out of the table: the loop reads them from registers.
  Kokkos::Array<double, N * N> K;
  for (int r = 0; r < N; ++r)
    for (int s = 0; s < N; ++s) K[r * N + s] = mats.K(r, s);
  for_each_index<Rows::longest>(
      "mpmice::face_exchange", faces, KOKKOS_LAMBDA(long i, long j, long k) {
        double q[N];
        unrolled_for<N>([&](int r) { q[r] = face_vel(r, i, j, k); });
        const long il = i - di, jl = j - dj, kl = k - dk;
        double vh[N], thetaf[N], beta[N * N], face_density[N];
        unrolled_for<N>([&](int r) {
          const double vl = sp_vol(r, il, jl, kl), vr = sp_vol(r, i, j, k);
          vh[r] = 2.0 * vl * vr / (vl + vr);
          thetaf[r] = 0.5 * (vol_frac(r, il, jl, kl) + vol_frac(r, i, j, k));
          face_density[r] = thetaf[r] / vh[r];  // makes face_density_r beta_rs symmetric
        });
        unrolled_for<N>([&](int r) {
          unrolled_for<N>([&](int s) { beta[r * N + s] = r == s ? 0.0 : dt * vh[r] * thetaf[s] * K[r * N + s]; });
        });
        implicit_exchange<N, 1>(beta, q, face_density);
        unrolled_for<N>([&](int r) { face_vel_me(r, i, j, k) = q[r]; });
      });
}

}  // namespace detail

/// beta_rs = dt vh_r thetaf_s K_rs with thetaf the mean volume fraction of the two
/// cells and vh_r the harmonic mean specific volume; solves the N x N system of
/// (E19) per face. With one material the velocity is copied.
inline void face_exchange(const IndexBox& faces, int d, double dt, const MaterialTable& mats,
                          const ConstField4& vol_frac, const ConstField4& sp_vol,
                          const ConstField4& face_vel, const Field4& face_vel_me) {
  with_material_count(mats.count, [&](auto n) {
    detail::face_exchange_n<decltype(n)::value>(faces, d, dt, mats, vol_frac, sp_vol, face_vel, face_vel_me);
  });
}

}  // namespace mpmice
