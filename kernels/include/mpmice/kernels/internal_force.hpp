#pragma once
/// \file internal_force.hpp
/// \brief Step 12: internal force on the nodes from the particle stresses,
///        f_int_i = - sum_p V_p (sigma_p + (pp_p - q_p) I) . grad S_ip (E24).
#include <algorithm>

#include <mpmice/kernels/p2g.hpp>

namespace mpmice {

namespace detail {
/// The stress a particle's nodes feel: sigma_p + (pp_p - q_p) I (E24).
KOKKOS_FORCEINLINE_FUNCTION Mat3 force_stress(const ParticleData& data, long p) {
  Mat3 stress = load_tensor(data, p, ParticleField::s00);
  const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
  for (int d = 0; d < 3; ++d) stress(d, d) += iso;
  return stress;
}

/// internal_force's scatter particle by particle, node by node: the reference that
/// internal_force_window_runs, which internal_force takes, must match (the tests compare
/// them). GIMP took this path until session 41.
template <class Shape>
void internal_force_each_particle(const NodeGrid& grid, long count, const ParticleData& data,
                                  const NodeScatter& scatter, const NodeStencil<Shape::nodes>& rows,
                                  const Quantum& quantum, const Quantum& mass_quantum) {
  constexpr int n = Shape::nodes;
  scatter_from_particles("mpmice::internal_force", count, KOKKOS_LAMBDA(long p) {
    const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
    const long first = rows.at(wt.first);
    const Mat3 stress = force_stress(data, p);
    // V in units of force (Quantum::whole_units), the mass in kg (rounded as p2g rounds it).
    const double vol_units = data(p, column(ParticleField::volume)) * quantum.scale;
    const double mp = data(p, column(ParticleField::mass));
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
            const double units = vol_units * (stress(d, 0) * g[0] + stress(d, 1) * g[1] + stress(d, 2) * g[2]);
            const double f = quantum.whole_units(units);  // in units, as the scatter holds it
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
}

/// internal_force's scatter by runs of particles of one window: as p2g_window_runs, a
/// run adds its particles' forces counted in quanta (Quantum::in_units), and into the
/// scatter once per node. A block's particles find their forces first, in one vector
/// loop over the particles (over_window_run_blocks); a particle's node of largest
/// weight is found in the nodes' order, and a node whose share of the mass rounds to
/// zero gets no force, as in internal_force_each_particle. That one also skips a node
/// of no gradient; such a node of weight is one a GIMP particle sits exactly on (dw = 0
/// along all three directions), and then the forces on its other nodes cancel in pairs
/// (opposite gradients, exactly), so the remainder `given` is 0 and which node takes it
/// does not matter. With quanta the sums are exact, so they do not depend on how the
/// particles split into runs or threads, and built with MPMICE_REPRODUCIBLE they are
/// bit for bit those of internal_force_each_particle. Without it GCC may fuse a
/// different product of sigma . grad S into an FMA in the vector loop than in the
/// scalar one, so a force within an ulp of half a quantum can round to the other
/// neighbour (one contribution in a 300-step container run with linear shapes). Without
/// quanta the sums' order differs too (a node gets given - f, not -f then + given), so
/// they change at round-off. With `Counted` (a quantum, as in the driver) the run sums
/// the forces' units as integers (UnitCount, as p2g_window_runs: 1.0-1.2x on 1 thread,
/// docs/performance.md, session 38), else as doubles; the same sums either way.
/// Tests: `InternalForce.LinearWindowRunsAddAsOneParticleAtATime`,
/// `InternalForce.GimpWindowRunsAddAsOneParticleAtATime`.
template <class Shape, bool Counted>
void internal_force_window_runs(const NodeGrid& grid, long count, const ParticleData& data,
                                const NodeScatter& scatter, const NodeStencil<Shape::nodes>& rows,
                                const Quantum& quantum, const Quantum& mass_quantum) {
  constexpr int n = Shape::nodes, N = n * n * n, B = window_run_block;
  using Sums = UnitSums<Counted>;
  using Sum = typename Sums::Sum;
  scatter_from_particle_runs("mpmice::internal_force", count, KOKKOS_LAMBDA(long lo, long hi) {
    auto node = scatter.access();
    // The run's sums of minus the forces, in units; counted: of the bits of t = x +
    // magic, so that the sum of k particles' is -(force) + k magic (UnitCount).
    Sum minus[3][N] = {};
    std::uint64_t added = 0;  // particles in the run so far
    // What each particle of the block adds to minus the forces, node by node.
    alignas(64) Sum block_terms[3][N][B];
    long block_first[B];
    // The block's particles in one vector loop (lanes are particles, the nodes written
    // out): the forces in quanta, t = x + magic; a node left out gets x = 0.
    const auto weigh = [&](long p, long i) {
      const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
      block_first[i] = rows.at(wt.first);
      const Mat3 stress = force_stress(data, p);
      const double vol_units = data(p, column(ParticleField::volume)) * quantum.scale;  // as each_particle
      const double mp = data(p, column(ParticleField::mass));
      double kept_weight[N], force[3][N];
      unrolled_for<N>([&](int a) {
        const double S = wt.weight(a);
        double g[3];
        wt.gradient(a, g);
        const double kept = mass_quantum.in_units(S * mp) + mass_quantum.unrounded;
        const double f0 = vol_units * (stress(0, 0) * g[0] + stress(0, 1) * g[1] + stress(0, 2) * g[2]);
        const double f1 = vol_units * (stress(1, 0) * g[0] + stress(1, 1) * g[1] + stress(1, 2) * g[2]);
        const double f2 = vol_units * (stress(2, 0) * g[0] + stress(2, 1) * g[1] + stress(2, 2) * g[2]);
        kept_weight[a] = kept != 0.0 ? S : 0.0;
        force[0][a] = (kept != 0.0 ? f0 : 0.0) + quantum.magic;
        force[1][a] = (kept != 0.0 ? f1 : 0.0) + quantum.magic;
        force[2][a] = (kept != 0.0 ? f2 : 0.0) + quantum.magic;
      });
      const auto term = [&](double t) { return Sums::term(t, quantum.magic); };
      // The particle's forces sum to zero: its kept node of largest weight, the first
      // in the nodes' order, also gets the sum of all (internal_force_each_particle).
      long heaviest = -1;
      double largest = 0;
      Sum given0 = 0, given1 = 0, given2 = 0;
      unrolled_for<N>([&](int a) {
        // Arithmetic, not selects: GCC made the selects branches, which mispredict.
        const long larger = kept_weight[a] > largest;
        heaviest += larger * (a - heaviest);
        largest = kept_weight[a] > largest ? kept_weight[a] : largest;
        given0 += term(force[0][a]);
        given1 += term(force[1][a]);
        given2 += term(force[2][a]);
      });
      given0 = Sums::count(given0, N);
      given1 = Sums::count(given1, N);
      given2 = Sums::count(given2, N);
      unrolled_for<N>([&](int a) {
        block_terms[0][a][i] = term(force[0][a]) - Sums::only_where(a == heaviest, given0);
        block_terms[1][a][i] = term(force[1][a]) - Sums::only_where(a == heaviest, given1);
        block_terms[2][a][i] = term(force[2][a]) - Sums::only_where(a == heaviest, given2);
      });
    };
    const auto add = [&](int i) {
      unrolled_for<3>([&](int d) { unrolled_for<N>([&](int a) { minus[d][a] += block_terms[d][a][i]; }); });
      ++added;
    };
    // Adds the run's sums into its nodes and zeroes them.
    const auto add_run = [&](long run_first) {
      if (added == 0) return;
      unrolled_for<N>([&](int a) {
        const long row = run_first + rows.steps[a];
        for (int d = 0; d < 3; ++d) node(row, d) -= Sums::total(minus[d][a], added);
      });
      for (int d = 0; d < 3; ++d)
        for (int a = 0; a < N; ++a) minus[d][a] = 0;
      added = 0;
    };
    over_window_run_blocks(lo, hi, block_first, weigh, add, add_run);
  });
}

/// `fint` from internal_force's scatter, whose forces are counted in the quantum `q`.
inline void add_force_scatter_into(const NodeScatter& scatter, const VectorField4& fint, int m, const Quantum& q) {
  add_scatter_into<3>(scatter, {fint[0], fint[1], fint[2]}, m, {0, 0, 0}, {q.unit, q.unit, q.unit});
}
}  // namespace detail

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
  if (quantum.q > 0)
    detail::internal_force_window_runs<Shape, true>(grid, count, data, scatter, rows, quantum, mass_quantum);
  else
    detail::internal_force_window_runs<Shape, false>(grid, count, data, scatter, rows, quantum, mass_quantum);
  detail::add_force_scatter_into(scatter, fint, m, quantum);
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
