#pragma once
/// \file internal_force.hpp
/// \brief Step 12: internal force on the nodes from the particle stresses,
///        f_int_i = - sum_p V_p (sigma_p + (pp_p - q_p) I) . grad S_ip (E24).
#include <algorithm>

#include <mpmice/kernels/p2g.hpp>

namespace mpmice {

/// Resets `fint` (material slot m) over the patch, then scatters (E24). The gas gauge
/// pressure pp_p is added to the stress (MPMICE, pitfall P5); 0 for MPM alone. With
/// quanta `q` (quanta.hpp) each contribution is rounded to q.internal_force, and nodes
/// whose share of the particle's mass rounds to zero (no mass from it in p2g) get none.
template <class Shape>
void internal_force(const NodeGrid& grid, long count, const ParticleData& data, int m,
                    const VectorField4& fint, const SumQuanta& q = SumQuanta()) {
  const double quantum = q.internal_force, mass_quantum = q.mass;
  const Kokkos::Array<NodeSlot, 3> slot = {material_slot(fint[0], m), material_slot(fint[1], m),
                                            material_slot(fint[2], m)};
  const NodeBlock block = node_block("mpmice::internal_force", slot[0], 3);
  const NodeScatter scatter(block);
  Kokkos::parallel_for(
      "mpmice::internal_force", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
        Mat3 stress = load_tensor(data, p, ParticleField::s00);
        const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
        for (int d = 0; d < 3; ++d) stress(d, d) += iso;
        const double vol = data(p, column(ParticleField::volume)), mp = data(p, column(ParticleField::mass));
        auto node = scatter.access();
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c) {
              double g[3];
              wt.gradient(a, b, c, g);
              if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) continue;
              if (mass_quantum > 0 && on_grid(wt.weight(a, b, c) * mp, mass_quantum) == 0.0) continue;
              const int i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + c;
              node(i, j, k, 0) -= on_grid(vol * (stress(0, 0) * g[0] + stress(0, 1) * g[1] + stress(0, 2) * g[2]), quantum);
              node(i, j, k, 1) -= on_grid(vol * (stress(1, 0) * g[0] + stress(1, 1) * g[1] + stress(1, 2) * g[2]), quantum);
              node(i, j, k, 2) -= on_grid(vol * (stress(2, 0) * g[0] + stress(2, 1) * g[1] + stress(2, 2) * g[2]), quantum);
            }
      });
  unpack_block<3>(block, scatter, slot, {0, 0, 0});
}

/// A bound on any one contribution of `internal_force`: max_p V_p |sigma_p + (pp_p - q_p)
/// I|_max times 3 max_d 1/h_d (|dS/dx_d| <= 1/h_d for the linear and GIMP weights).
inline double internal_force_bound(const NodeGrid& grid, long count, const ParticleData& data) {
  double largest = 0;
  Kokkos::parallel_reduce(
      "mpmice::internal_force_bound", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& mx) {
        const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
        double s = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const double v = math::abs(data(p, tensor_column(ParticleField::s00, a, b)) + (a == b ? iso : 0.0));
            s = v > s ? v : s;
          }
        const double f = data(p, column(ParticleField::volume)) * s;
        mx = f > mx ? f : mx;
      },
      Kokkos::Max<double>(largest));
  const double inv_h = std::max(grid.inv_h[0], std::max(grid.inv_h[1], grid.inv_h[2]));
  return 3.0 * inv_h * largest;
}

}  // namespace mpmice
