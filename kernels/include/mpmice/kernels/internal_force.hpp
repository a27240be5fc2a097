#pragma once
/// \file internal_force.hpp
/// \brief Step 12: internal force on the nodes from the particle stresses,
///        f_int_i = - sum_p V_p (sigma_p + (pp_p - q_p) I) . grad S_ip (E24).
#include <mpmice/kernels/p2g.hpp>

namespace mpmice {

/// Resets `fint` (material slot m) over the patch, then scatters (E24). The gas gauge
/// pressure pp_p is added to the stress (MPMICE, pitfall P5); 0 for MPM alone.
template <class Shape>
void internal_force(const NodeGrid& grid, long count, const ParticleData& data, int m,
                    const VectorField4& fint) {
  for (int d = 0; d < 3; ++d)
    Kokkos::deep_copy(Kokkos::subview(fint[d], m, Kokkos::ALL, Kokkos::ALL, Kokkos::ALL), 0.0);
  NodeScatter s_x(fint[0]), s_y(fint[1]), s_z(fint[2]);
  Kokkos::parallel_for(
      "mpmice::internal_force", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<Shape> wt(x, grid.lower, grid.inv_h, half);
        Mat3 stress = load_tensor(data, p, ParticleField::s00);
        const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
        for (int d = 0; d < 3; ++d) stress(d, d) += iso;
        const double vol = data(p, column(ParticleField::volume));
        auto ax = s_x.access();
        auto ay = s_y.access();
        auto az = s_z.access();
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c) {
              double g[3];
              wt.gradient(a, b, c, g);
              if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) continue;
              const int i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + c;
              ax(m, i, j, k) -= vol * (stress(0, 0) * g[0] + stress(0, 1) * g[1] + stress(0, 2) * g[2]);
              ay(m, i, j, k) -= vol * (stress(1, 0) * g[0] + stress(1, 1) * g[1] + stress(1, 2) * g[2]);
              az(m, i, j, k) -= vol * (stress(2, 0) * g[0] + stress(2, 1) * g[1] + stress(2, 2) * g[2]);
            }
      });
  contribute(fint[0], s_x);
  contribute(fint[1], s_y);
  contribute(fint[2], s_z);
}

}  // namespace mpmice
