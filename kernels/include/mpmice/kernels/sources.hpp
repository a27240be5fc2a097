#pragma once
/// \file sources.hpp
/// \brief Steps 9 and 10: momentum and internal-energy sources over the step from
///        the pressure force, gravity and the p dV work (E22, E23).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

namespace detail {
template <int N>
void momentum_source_n(const IndexBox& cells, const Patch& patch, double dt, const Kokkos::Array<double, 3> gravity,
                       const Kokkos::Array<int, max_materials> gravity_on, const ConstField4& vol_frac,
                       const ConstField4& rho, const Kokkos::Array<ConstField3, 3>& press_face,
                       const VectorField4& mom_source) {
  const double ax = patch.grid.face_area(0), ay = patch.grid.face_area(1), az = patch.grid.face_area(2),
               vol = patch.grid.cell_volume();
  // Gravity's factor per material, V or 0: a select on the captured flags kept the
  // loop scalar.
  Kokkos::Array<double, max_materials> gravity_volume;
  for (int m = 0; m < max_materials; ++m) gravity_volume[m] = gravity_on[m] ? vol : 0.0;
  for_each_index("mpmice::momentum_source", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    const double fx = (press_face[0](i + 1, j, k) - press_face[0](i, j, k)) * ax;
    const double fy = (press_face[1](i, j + 1, k) - press_face[1](i, j, k)) * ay;
    const double fz = (press_face[2](i, j, k + 1) - press_face[2](i, j, k)) * az;
    unrolled_for<N>([&](int m) {
      const double theta = vol_frac(m, i, j, k);
      const double w = rho(m, i, j, k) * gravity_volume[m];
      mom_source[0](m, i, j, k) = dt * (-theta * fx + w * gravity[0]);
      mom_source[1](m, i, j, k) = dt * (-theta * fy + w * gravity[1]);
      mom_source[2](m, i, j, k) = dt * (-theta * fz + w * gravity[2]);
    });
  });
}

template <int N>
void energy_source_n(const IndexBox& cells, const Kokkos::Array<int, max_materials> work_on, const ConstField3& tmv,
                     const ConstField4& vol_frac, const ConstField4& kappa, const ConstField3& press,
                     const ConstField3& del_p_dilatate, const Field4& int_eng_source) {
  for_each_index("mpmice::energy_source", cells, KOKKOS_LAMBDA(long i, long j, long k) {
    const double pdp = tmv(i, j, k) * press(i, j, k) * del_p_dilatate(i, j, k);
    unrolled_for<N>([&](int m) {
      const double theta = vol_frac(m, i, j, k);
      const double work = pdp * theta * kappa(m, i, j, k);
      int_eng_source(m, i, j, k) = work_on[m] && theta > 1e-6 ? work : 0.0;
    });
  });
}
}  // namespace detail

/// Q_r = dt [ -theta_r (p^f_+ - p^f_-) A_d + rho_r V g_d ] per component d (E22);
/// gravity acts on the materials whose `gravity_on[m]` is set (ICE materials).
inline void momentum_source(const IndexBox& cells, const Patch& patch, double dt,
                            int materials, const Kokkos::Array<double, 3> gravity,
                            const Kokkos::Array<int, max_materials> gravity_on,
                            const ConstField4& vol_frac, const ConstField4& rho,
                            const Kokkos::Array<ConstField3, 3>& press_face,
                            const VectorField4& mom_source) {
  with_material_count(materials, [&](auto n) {
    detail::momentum_source_n<decltype(n)::value>(cells, patch, dt, gravity, gravity_on, vol_frac, rho, press_face,
                                                  mom_source);
  });
}

/// W_r = TMV theta_r kappa_r p^{n+1} dP_dil (E23): the work of compression, for the
/// materials with `work_on[m]` set (ICE materials; MPM materials get 0).
inline void energy_source(const IndexBox& cells, int materials,
                          const Kokkos::Array<int, max_materials> work_on, const ConstField3& tmv,
                          const ConstField4& vol_frac, const ConstField4& kappa,
                          const ConstField3& press, const ConstField3& del_p_dilatate,
                          const Field4& int_eng_source) {
  with_material_count(materials, [&](auto n) {
    detail::energy_source_n<decltype(n)::value>(cells, work_on, tmv, vol_frac, kappa, press, del_p_dilatate,
                                                int_eng_source);
  });
}

/// With a reaction (departure from P8, docs/design.md "Reactions"): the new gas's
/// volume dm v compresses the cell by dP_mx (E20, E32). Each fluid present
/// (`work_on`, theta > 1e-6) gains that compression work, TMV theta_r kappa_r p^{n+1}
/// dP_mx, and the materials that gained mass (mass_source > 0) pay it, in proportion to
/// their dm: the new gas is created at the cell's pressure (isobaric, its energy
/// dm (c_v,s T_s + dh) - p dm v), and the cell's total energy is unchanged.
inline void mass_exchange_work(const IndexBox& cells, int materials, const Kokkos::Array<int, max_materials> work_on,
                               const ConstField3& tmv, const ConstField4& vol_frac, const ConstField4& kappa,
                               const ConstField3& press, const ConstField3& del_p_mass,
                               const ConstField4& mass_source, const Field4& int_eng_source) {
  Kokkos::parallel_for(
      "mpmice::mass_exchange_work", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double gained = 0;
        for (int m = 0; m < materials; ++m) gained += mass_source(m, i, j, k) > 0 ? mass_source(m, i, j, k) : 0.0;
        if (!(gained > 0)) return;
        const double pdp = tmv(i, j, k) * press(i, j, k) * del_p_mass(i, j, k);
        double work = 0;
        for (int m = 0; m < materials; ++m) {
          const double theta = vol_frac(m, i, j, k);
          if (!work_on[m] || !(theta > 1e-6)) continue;
          const double w = pdp * theta * kappa(m, i, j, k);
          int_eng_source(m, i, j, k) += w;
          work += w;
        }
        for (int m = 0; m < materials; ++m)
          if (mass_source(m, i, j, k) > 0) int_eng_source(m, i, j, k) -= work * mass_source(m, i, j, k) / gained;
      });
}

}  // namespace mpmice
