#pragma once
// Realistic inputs for the kernel benchmarks: a cube of cells with gas states, and
// particles on a lattice with random jitter, all on one patch.
#include <benchmark/benchmark.h>

#include <random>

#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice::bench {

inline Patch cube_patch(int n, int ghosts = 2) {
  Grid g;
  g.cells = {n, n, n};
  g.spacing = {1e-3, 1e-3, 1e-3};
  return whole_grid_patch(g, ghosts);
}

/// `materials` ideal gases with momentum and heat exchange among all of them.
inline MaterialTable gas_table(int materials) {
  MaterialTable t;
  t.count = materials;
  for (int m = 0; m < materials; ++m) {
    t.eos[m] = Eos{};
    t.eos[m].gamma = 1.4 + 0.05 * m;
    t.eos[m].cv = 716.0 + 100 * m;
    for (int s = 0; s < materials; ++s)
      if (s != m) {
        t.momentum_exchange[m * max_materials + s] = 1e15;
        t.heat_exchange[m * max_materials + s] = 1e5;
      }
  }
  return t;
}

/// Fill every entry of `f` with values around `base`, varying by +-`spread`.
template <class View>
View randomised(View f, double base, double spread, unsigned seed) {
  auto h = Kokkos::create_mirror_view(f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-spread, spread);
  for (std::size_t i = 0; i < h.size(); ++i) h.data()[i] = base * (1.0 + u(rng));
  Kokkos::deep_copy(f, h);
  return f;
}

/// A per-material cell field with values around `base`, varying by +-`spread`.
inline Field4 cell_field(const Patch& p, int materials, double base, double spread, unsigned seed) {
  return randomised(make_field("bench", p, Location::cell, materials), base, spread, seed);
}

inline Field3 cell_scalar(const Patch& p, double base, double spread, unsigned seed) {
  return randomised(make_field("bench", p, Location::cell), base, spread, seed);
}

/// A node field of one material slot with values around `base`, varying by +-`spread`.
inline Field4 node_field(const Patch& p, double base, double spread, unsigned seed) {
  return randomised(make_field("bench", p, Location::node, 1), base, spread, seed);
}

/// Three node fields as node_field (seeds seed, seed + 1, seed + 2).
inline VectorField4 node_vector(const Patch& p, double base, double spread, unsigned seed) {
  return {node_field(p, base, spread, seed), node_field(p, base, spread, seed + 1),
          node_field(p, base, spread, seed + 2)};
}

/// `count` particles spread over the patch's owned cells (sorted by cell; the particle
/// benchmarks sort them by their shape's window, as the driver does), F = I, small random velocities.
inline ParticleSet particles_in(const Patch& p, long count, unsigned seed) {
  ParticleSet ps("bench", std::size_t(count));
  ps.resize(std::size_t(count));
  auto h = Kokkos::create_mirror_view(ps.data());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const long cells = p.grid.cell_count();
  for (long q = 0; q < count; ++q) {
    for (int c = 0; c < particle_field_count; ++c) h(q, c) = 0.0;
    const long cell = q * cells / count;  // in cell order
    const long idx[3] = {cell / (long(p.grid.cells[1]) * p.grid.cells[2]), (cell / p.grid.cells[2]) % p.grid.cells[1],
                         cell % p.grid.cells[2]};
    for (int d = 0; d < 3; ++d) {
      h(q, column(ParticleField::x) + d) = (idx[d] + 0.05 + 0.9 * u(rng)) * p.grid.spacing[d];
      h(q, column(ParticleField::vx) + d) = u(rng) - 0.5;
      h(q, column(ParticleField::size_x) + d) = 0.5;
      h(q, tensor_column(ParticleField::F00, d, d)) = 1.0;
      h(q, tensor_column(ParticleField::be00, d, d)) = 1.0;
      for (int e = 0; e < 3; ++e) h(q, tensor_column(ParticleField::L00, d, e)) = 10.0 * (u(rng) - 0.5);
    }
    h(q, column(ParticleField::mass)) = 1e-6;
    h(q, column(ParticleField::volume)) = 1e-10;
    h(q, column(ParticleField::temperature)) = 300;
  }
  Kokkos::deep_copy(ps.data(), h);
  return ps;
}

/// The cube sizes of the cell and node benchmarks: 16^3 to 128^3 cells.
inline void cube_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("cells");
  for (int n : {16, 32, 64, 128}) b->Arg(n);
}

/// Reports `items` per iteration, each counted as `bytes_per_item` bytes (the byte
/// count documented at the top of each benchmark file), as items/s and bytes/s.
inline void report(benchmark::State& state, long items, double bytes_per_item) {
  state.SetItemsProcessed(state.iterations() * items);
  state.SetBytesProcessed(int64_t(state.iterations() * items * bytes_per_item));
  state.counters["bytes_per_item"] = bytes_per_item;
}

/// Seconds of one fenced call of f.
template <class F>
double timed(F&& f) {
  Kokkos::fence();
  Kokkos::Timer timer;
  f();
  Kokkos::fence();
  return timer.seconds();
}

}  // namespace mpmice::bench
