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
///
/// A particle's forces must sum to zero (sum_i grad S_ip = 0): its stress cannot push
/// itself. Skipping a node breaks that (and the rounding does, by a few quanta), so the
/// particle's node with the largest weight also gets minus the sum of what the others
/// got; the sum is then exactly zero. Without it a burning particle of a trace of its
/// mass, whose far nodes are skipped, pushed itself and the grid: a whole burn of
/// problems/burn_box.yaml made z-momentum of 1.8e-7 of sqrt(M E) from nothing.
/// `scratch` holds the scatter's copies between calls.
template <class Shape>
void internal_force(const NodeGrid& grid, long count, const ParticleData& data, int m,
                    const VectorField4& fint, const SumQuanta& q, ScatterScratch& scratch) {
  constexpr int n = Shape::nodes;
  const Quantum quantum(q.internal_force), mass_quantum(q.mass);
  const NodeStencil<n> rows = block_stencil<n>(fint[0]);
  const NodeScatter& scatter = scratch.zeroed("mpmice::internal_force", fint[0], 3);
  scatter_from_particles("mpmice::internal_force", count, KOKKOS_LAMBDA(long p) {
    double x[3], half[3];
    particle_position(data, p, x, half);
    const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    const long first = rows.at(wt.first);
    Mat3 stress = load_tensor(data, p, ParticleField::s00);
    const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
    for (int d = 0; d < 3; ++d) stress(d, d) += iso;
    const double vol = data(p, column(ParticleField::volume)), mp = data(p, column(ParticleField::mass));
    auto node = scatter.access();
    double given[3] = {0, 0, 0}, heaviest = 0;
    long heaviest_row = -1;
    unrolled_for<n>([&](int a) {
      unrolled_for<n>([&](int b) {
        unrolled_for<n>([&](int c) {
          double g[3];
          wt.gradient(a, b, c, g);
          if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) return;
          const double S = wt.weight(a, b, c);
          if (mass_quantum.q > 0 && mass_quantum.round(S * mp) == 0.0) return;
          const long row = first + rows.step(a, b, c);
          for (int d = 0; d < 3; ++d) {
            const double f = quantum.round(vol * (stress(d, 0) * g[0] + stress(d, 1) * g[1] + stress(d, 2) * g[2]));
            node(row, d) -= f;
            given[d] += f;
          }
          heaviest_row = S > heaviest ? row : heaviest_row;
          heaviest = S > heaviest ? S : heaviest;
        });
      });
    });
    // Sums of multiples of the quantum are exact: the particle's total is then 0.
    if (heaviest_row >= 0)
      for (int d = 0; d < 3; ++d) node(heaviest_row, d) += given[d];
  });
  add_scatter_into<3>(scatter, {fint[0], fint[1], fint[2]}, m, {0, 0, 0});
}

/// The same with copies of its own.
template <class Shape>
void internal_force(const NodeGrid& grid, long count, const ParticleData& data, int m,
                    const VectorField4& fint, const SumQuanta& q = SumQuanta()) {
  ScatterScratch scratch;
  internal_force<Shape>(grid, count, data, m, fint, q, scratch);
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
