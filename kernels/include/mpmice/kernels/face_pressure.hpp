#pragma once
/// \file face_pressure.hpp
/// \brief Step 8: face pressure with crossed density weights (E21).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>

namespace mpmice {

/// p^f = (p_R Srho_L + p_L Srho_R)/(Srho_L + Srho_R) on faces with normal d (E21).
inline void face_pressure(const IndexBox& faces, int d, const ConstField3& press,
                          const ConstField3& sum_rho, const Field3& press_face) {
  const long di = d == 0, dj = d == 1, dk = d == 2;
  for_each_index<Rows::longest>(
      "mpmice::face_pressure", faces, KOKKOS_LAMBDA(long i, long j, long k) {
        const double rl = sum_rho(i - di, j - dj, k - dk), rr = sum_rho(i, j, k);
        press_face(i, j, k) = (press(i, j, k) * rl + press(i - di, j - dj, k - dk) * rr) / (rl + rr);
      });
}

/// Faces of the owned cells with normal d (both sides of every owned cell).
inline IndexBox faces_of_owned_cells(const Patch& patch, int d) { return faces_of(patch.owned_cells(), d); }

}  // namespace mpmice
