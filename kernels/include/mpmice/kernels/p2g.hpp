#pragma once
/// \file p2g.hpp
/// \brief Step 1: particle-to-grid of mass, momentum, m T, volume and external force
///        (E12), and the node velocity and temperature from them.
///
/// Particles add into the nodes through a NodeScatter (node_scatter.hpp).
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/node_scatter.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/shape.hpp>

namespace mpmice {

/// Node sums of one MPM material, indexed (m, i, j, k) on the patch's nodes.
struct NodeSums {
  Field4 mass;      ///< sum S m_p, kg (starts at 1e-200)
  VectorField4 mom; ///< sum S m_p v_p, kg m/s
  Field4 heat;      ///< sum S m_p T_p, kg K
  Field4 volume;    ///< sum S V_p, m^3 (starts at 1e-200)
  VectorField4 fext;///< sum S f_ext,p, N
};

namespace detail {
/// What particle p gives its nodes, times their weight (E12): mass, momentum (3), m T,
/// volume, external force (3); all but the mass in their units of `quanta`, scaled once
/// for all nodes (Quantum::whole_units: one product fewer per node and field, the same
/// rounded values). The mass stays in kg: its share rounds as internal_force rounds it.
constexpr int p2g_fields = 9;
KOKKOS_FORCEINLINE_FUNCTION void p2g_values(const ParticleData& data, long p, const QuantumArray<p2g_fields>& quanta,
                                            double* value) {
  const double mp = data(p, column(ParticleField::mass));
  value[0] = mp;
  value[1] = mp * data(p, column(ParticleField::vx));
  value[2] = mp * data(p, column(ParticleField::vy));
  value[3] = mp * data(p, column(ParticleField::vz));
  value[4] = mp * data(p, column(ParticleField::temperature));
  value[5] = data(p, column(ParticleField::volume));
  value[6] = data(p, column(ParticleField::fext_x));
  value[7] = data(p, column(ParticleField::fext_y));
  value[8] = data(p, column(ParticleField::fext_z));
  for (int f = 1; f < p2g_fields; ++f) value[f] *= quanta.scale[f];
}

/// The quantum of each of p2g_values.
inline Kokkos::Array<Quantum, p2g_fields> p2g_quanta(const SumQuanta& q) {
  return {q.mass, q.momentum, q.momentum, q.momentum, q.heat, q.volume, q.external_force, q.external_force,
          q.external_force};
}

/// p2g's scatter particle by particle, node by node, a node's 8 fields after the mass as
/// one vector operation: the reference that p2g_window_runs, which p2g takes, must
/// match (the tests compare them). A node whose share of the mass rounds to zero gets
/// nothing at all, so that no node has momentum or force without mass (internal_force,
/// with quanta, skips it too). GIMP took this path until session 41.
template <class Shape>
void p2g_each_particle(const NodeGrid& grid, long count, const ParticleData& data, const NodeScatter& scatter,
                       const NodeStencil<Shape::nodes>& rows, const Kokkos::Array<Quantum, p2g_fields>& quantum) {
  constexpr int n = Shape::nodes, F = p2g_fields;
  const QuantumArray<F> quanta(quantum);
  scatter_from_particles("mpmice::p2g", count, KOKKOS_LAMBDA(long p) {
    double value[F];
    const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
    const long first = rows.at(wt.first);
    p2g_values(data, p, quanta, value);
    auto node = scatter.access();
    unrolled_for<n>([&](int a) {
      unrolled_for<n>([&](int b) {
        unrolled_for<n>([&](int c) {
          const double S = wt.weight(a, b, c);
          const double mass = quantum[0].in_units(S * value[0]);
          if (mass == 0.0) return;
          const long row = first + rows.step(a, b, c);
          node(row, 0) += mass;  // in units, as every field here (add_scatter_into)
          // The other 8 fields: one 8-wide vector operation where the CPU has it.
          MPMICE_PRAGMA_SIMD
          for (int f = 1; f < F; ++f) node(row, f) += quanta.whole_units(f, S * value[f]);
        });
      });
    });
  });
}

/// Particles per block of `over_window_run_blocks`: on the host 32 (16 and 64 ran
/// 0.92-1.0x as fast in p2g), on a GPU 1 (a thread takes one particle, and its block
/// arrays stay small).
#if defined(MPMICE_DEVICE_BACKEND)
constexpr int window_run_block = 1;
#else
constexpr int window_run_block = 32;
#endif

/// The particle loop of a scatter by window runs (p2g_window_runs,
/// internal_force_window_runs) over particles [lo, hi), a block of `window_run_block`
/// particles at a time. First, in one vector loop over the block's particles (lanes are
/// particles), `weigh(p, i)` stores what particle p, the block's i-th, adds into the
/// nodes of its window, and its first node's row in `block_first[i]`. Then, particle by
/// particle, `add(i)` adds the block's particle i into the run's sums, and
/// `add_run(first)` adds them into the nodes from row `first` (and zeroes them) after
/// the last particle of the run's window, which may come in a later block. Until
/// session 41 one loop did both for each particle in turn (and GIMP scattered particle by
/// particle): a particle's weights fed the run's sums in a chain of some 60 cycles, which
/// out-of-order execution overlapped for only two or three particles (on 1 thread p2g
/// 1.35x and internal_force 1.7x faster apart with the linear shape, 2.1x and 2.1x with
/// GIMP, docs/performance.md, session 41). The run's inner loop calls nothing else, so
/// the compiler keeps the run's sums in registers through it.
template <class Weigh, class Add, class AddRun>
KOKKOS_FORCEINLINE_FUNCTION void over_window_run_blocks(long lo, long hi, long* block_first, const Weigh& weigh,
                                                        const Add& add, const AddRun& add_run) {
  long run_first = -1;  // no run yet: add_run with nothing added adds nothing
  for (long b0 = lo; b0 < hi; b0 += window_run_block) {
    const int n = int(hi - b0 < window_run_block ? hi - b0 : window_run_block);
#if defined(MPMICE_DEVICE_BACKEND)
    for (int i = 0; i < n; ++i) weigh(b0 + i, long(i));
#else
    // The place in the block as a long: as an int, GCC 12 left this loop scalar.
    simd_run([&](long p) { weigh(p, p - b0); }, b0, b0 + n);
#endif
    int i = 0;
    while (i < n) {
      const long first = block_first[i];
      if (first != run_first) {
        add_run(run_first);
        run_first = first;
      }
      do add(i);
      while (++i < n && block_first[i] == first);
    }
  }
  add_run(run_first);
}

/// Whether p2g_window_runs counts the mass in integers too, as the other fields (with
/// `Counted`, given a mass quantum): with GIMP's 27 nodes 1.06-1.31x on 1 thread (its 27
/// additions a particle leave the floating-point pipes), with the linear shape's 8
/// 0.82-1.17x, no gain (medians of alternating rounds in four comparisons, AMD Zen 3;
/// docs/performance.md, session 47).
template <class Shape>
constexpr bool p2g_counts_mass = Shape::nodes == 3;

/// p2g's scatter by runs of particles of one window, the nodes their shape reaches (the
/// linear shape's 8 around a cell, GIMP's 27 around a node). Sorted by window
/// (particle_sort.hpp), particles come in such runs: a run adds its particles'
/// contributions in registers (or, GIMP's 27 nodes, in the stack's first cache lines)
/// and adds the sums into the scatter once per node (8 particles per cell: 1/8 of the
/// adds), a node's 8 fields after the mass as one vector over the fields (as they lie
/// in the node's row of the scatter). Unsorted particles make runs of one; they take
/// the same path (GIMP particles in cell order, runs of 1-2: 1.1x p2g_each_particle on
/// 1 thread). A block's particles are weighed first (over_window_run_blocks): each
/// node's weight kept (0 for a node whose share of the mass rounds to zero: it gets
/// nothing, as in p2g_each_particle) and that share, stored node by node (a run reads
/// one particle's as a scalar, broadcast), and the values of the other fields, stored
/// particle by particle (read as a vector over them). The run counts each contribution
/// in its quantum, as the scatter holds them (add_scatter_into): with `Counted` (every
/// field after the mass has a quantum, and the mass too where `p2g_counts_mass`, as in
/// the driver) in 64-bit integers, the bits of x + magic added (UnitCount: 1.1-1.4x
/// against the rounded doubles on 1 thread, docs/performance.md, session 38), and back
/// to doubles in the run's vector over the fields (UnitCount::total_in_vector: on AVX2
/// the conversion had made that loop scalar, session 49); the linear shape's mass, and
/// every field without quanta, as the doubles (x + magic) - magic.
/// The sums' order differs from p2g_each_particle's: without quanta a node's value
/// changes at round-off; with quanta, as in the driver, not at all.
template <class Shape, bool Counted>
void p2g_window_runs(const NodeGrid& grid, long count, const ParticleData& data, const NodeScatter& scatter,
                     const NodeStencil<Shape::nodes>& rows, const Kokkos::Array<Quantum, p2g_fields>& quantum) {
  constexpr int n = Shape::nodes, N = n * n * n, F = p2g_fields, B = window_run_block;
  using Sums = UnitSums<Counted>;
  using MassSums = UnitSums<Counted && p2g_counts_mass<Shape>>;
  const QuantumArray<F> quanta(quantum);
  scatter_from_particle_runs("mpmice::p2g", count, KOKKOS_LAMBDA(long lo, long hi) {
    auto node = scatter.access();
    typename MassSums::Sum mass_units[N] = {};
    typename Sums::Sum units[N][F - 1] = {};
    std::uint64_t added = 0;  // particles in the run so far
    alignas(64) double block_kept[N][B], block_value[B][F - 1];
    alignas(64) typename MassSums::Sum block_mass[N][B];
    long block_first[B];
    const auto weigh = [&](long p, long i) {
      const ParticleWeights<Shape> wt = particle_weights<Shape>(grid, data, p);
      block_first[i] = rows.at(wt.first);
      double value[F];
      p2g_values(data, p, quanta, value);
      unrolled_for<F - 1>([&](int f) { block_value[i][f] = value[f + 1]; });
      unrolled_for<N>([&](int a) {
        const double S = wt.weight(a);
        // quantum[0].in_units(S m_p) + magic: the mass's count, as `term` adds it.
        const double t = (S * value[0]) * quanta.scale[0] + quanta.magic[0];
        block_kept[a][i] = t - quanta.magic[0] != 0.0 ? S : 0.0;
        block_mass[a][i] = MassSums::term(t, quanta.magic[0]);
      });
    };
    // A node left out adds x = 0: the magic number alone, counted as 0.
    const auto add = [&](int i) {
      unrolled_for<N>([&](int a) { mass_units[a] += block_mass[a][i]; });
      unrolled_for<N>([&](int a) {
        MPMICE_PRAGMA_SIMD
        for (int f = 1; f < F; ++f)
          units[a][f - 1] += Sums::term(block_kept[a][i] * block_value[i][f - 1] + quanta.magic[f], quanta.magic[f]);
      });
      ++added;
    };
    // Adds the run's sums into its nodes (those that got mass) and zeroes them.
    const auto add_run = [&](long run_first) {
      if (added == 0) return;
      unrolled_for<N>([&](int a) {
        if (MassSums::count(mass_units[a], added) != 0) {
          const long row = run_first + rows.steps[a];
          node(row, 0) += MassSums::total(mass_units[a], added);
          MPMICE_PRAGMA_SIMD
          for (int f = 1; f < F; ++f) node(row, f) += Sums::total_in_vector(units[a][f - 1], added);
        }
        mass_units[a] = 0;
        for (int f = 0; f < F - 1; ++f) units[a][f] = 0;
      });
      added = 0;
    };
    over_window_run_blocks(lo, hi, block_first, weigh, add, add_run);
  });
}

/// The node sums from p2g's scatter, whose fields are counted in `quantum`. Mass and
/// volume start at 1e-200 so that no node divides by zero.
inline void add_p2g_scatter_into(const NodeScatter& scatter, const NodeSums& sums, int m,
                                 const Kokkos::Array<Quantum, p2g_fields>& quantum) {
  constexpr int F = p2g_fields;
  add_scatter_into<F>(scatter,
                      {sums.mass, sums.mom[0], sums.mom[1], sums.mom[2], sums.heat, sums.volume, sums.fext[0],
                       sums.fext[1], sums.fext[2]},
                      m, {1e-200, 0, 0, 0, 0, 1e-200, 0, 0, 0}, QuantumArray<F>(quantum).unit);
}
}  // namespace detail

/// (E12) for the `count` particles of `data` into material slot m of `sums` (which the
/// call first resets over the whole patch, ghost nodes included). With quanta `q` each
/// contribution is rounded to them (quanta.hpp: sums independent of their order).
/// `scratch` holds the scatter's copies between calls.
template <class Shape>
void p2g(const NodeGrid& grid, long count, const ParticleData& data, int m, const NodeSums& sums,
         const SumQuanta& q, ScatterScratch& scratch) {
  const NodeScatter& scatter = scratch.zeroed("mpmice::p2g", sums.mass, detail::p2g_fields);
  const NodeStencil<Shape::nodes> rows = block_stencil<Shape::nodes>(sums.mass);
  const Kokkos::Array<Quantum, detail::p2g_fields> quantum = detail::p2g_quanta(q);
  if (QuantumArray<detail::p2g_fields>(quantum).counted_from(detail::p2g_counts_mass<Shape> ? 0 : 1))
    detail::p2g_window_runs<Shape, true>(grid, count, data, scatter, rows, quantum);
  else
    detail::p2g_window_runs<Shape, false>(grid, count, data, scatter, rows, quantum);
  detail::add_p2g_scatter_into(scatter, sums, m, quantum);
}

/// The same with copies of its own.
template <class Shape>
void p2g(const NodeGrid& grid, long count, const ParticleData& data, int m, const NodeSums& sums,
         const SumQuanta& q = SumQuanta()) {
  ScatterScratch scratch;
  p2g<Shape>(grid, count, data, m, sums, q, scratch);
}

/// Node velocity v = sum S m v / m and temperature T = sum S m T / m (E12) on `nodes`.
inline void node_velocity_temperature(const IndexBox& nodes, int m, const ConstField4& mass,
                                      const ConstVectorField4& mom, const ConstField4& heat,
                                      const VectorField4& vel, const Field4& temp) {
  for_each_index("mpmice::node_velocity_temperature", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const double inv = 1.0 / mass(m, i, j, k);
    for (int d = 0; d < 3; ++d) vel[d](m, i, j, k) = mom[d](m, i, j, k) * inv;
    temp(m, i, j, k) = heat(m, i, j, k) * inv;
  });
}

}  // namespace mpmice
