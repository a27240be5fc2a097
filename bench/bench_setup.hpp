#pragma once
// Realistic inputs for the kernel benchmarks: a cube of cells with gas states, and
// particles on a lattice with random jitter, all on one patch.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <string>

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

/// A uniform number in [0, 1) made from `seed` and `index` alone (the splitmix64 hash),
/// so that a parallel fill gives the same values on any number of threads.
KOKKOS_INLINE_FUNCTION double uniform01(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + index + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return double(z >> 11) * 0x1.0p-53;
}

/// Fill every entry of `f` with values around `base`, varying by +-`spread`. In
/// parallel: the largest inputs are 2 GB, and a serial fill was most of the benchmarks'
/// set-up.
template <class View>
View randomised(View f, double base, double spread, unsigned seed) {
  const auto flat = Kokkos::View<typename View::value_type*, typename View::memory_space,
                                 Kokkos::MemoryTraits<Kokkos::Unmanaged>>(f.data(), f.span());
  Kokkos::parallel_for(
      "mpmice::bench::randomised", Kokkos::RangePolicy<ExecSpace>(0, long(f.span())), KOKKOS_LAMBDA(long i) {
        flat(i) = base * (1.0 + spread * (2.0 * uniform01(seed, std::uint64_t(i)) - 1.0));
      });
  Kokkos::fence();
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
/// benchmarks sort them by their shape's window, as the driver does), F = I, small random
/// velocities. Filled in parallel, as `randomised`.
inline ParticleSet particles_in(const Patch& p, long count, unsigned seed) {
  ParticleSet ps("bench", std::size_t(count));  // zeroed
  ps.resize(std::size_t(count));
  const ParticleData h = ps.data();
  const long cells = p.grid.cell_count();
  const long ny = p.grid.cells[1], nz = p.grid.cells[2];
  const Kokkos::Array<double, 3> h_cell = p.grid.spacing_array();
  Kokkos::parallel_for(
      "mpmice::bench::particles_in", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long q) {
        // 15 random numbers a particle: position (3), velocity (3), velocity gradient (9).
        auto u = [&](int r) { return uniform01(seed, std::uint64_t(q) * 15 + std::uint64_t(r)); };
        const long cell = q * cells / count;  // in cell order
        const long idx[3] = {cell / (ny * nz), (cell / nz) % ny, cell % nz};
        for (int d = 0; d < 3; ++d) {
          h(q, column(ParticleField::x) + d) = (double(idx[d]) + 0.05 + 0.9 * u(d)) * h_cell[d];
          h(q, column(ParticleField::vx) + d) = u(3 + d) - 0.5;
          h(q, column(ParticleField::size_x) + d) = 0.5;
          h(q, tensor_column(ParticleField::F00, d, d)) = 1.0;
          h(q, tensor_column(ParticleField::be00, d, d)) = 1.0;
          for (int e = 0; e < 3; ++e) h(q, tensor_column(ParticleField::L00, d, e)) = 10.0 * (u(6 + 3 * d + e) - 0.5);
        }
        h(q, column(ParticleField::mass)) = 1e-6;
        h(q, column(ParticleField::volume)) = 1e-10;
        h(q, column(ParticleField::temperature)) = 300;
      });
  Kokkos::fence();
  return ps;
}

/// The input that `make()` returns for `key`, kept until a call with another key, so
/// that consecutive benchmarks (and Google Benchmark's repeated calls of one benchmark
/// while it sizes its iterations) share their largest inputs instead of making them
/// again: 4e6 particles are 2.2 GB, and making them was most of `ci/bench`'s time. One
/// input is kept at a time, of any type; `key` must name the type as well as the
/// values. For inputs the benchmarks read, or write without changing the work.
/// `release_kept()` frees it before Kokkos is finalised (bench/main.cpp).
struct KeptInput {
  std::string key;
  std::shared_ptr<void> value;
};

inline KeptInput& kept_input() {
  static KeptInput slot;
  return slot;
}

template <class T, class Make>
const T& kept(const std::string& key, Make&& make) {
  KeptInput& slot = kept_input();
  if (!slot.value || slot.key != key) {
    slot = {};  // the old input is freed before the new one is made
    slot.value = std::make_shared<T>(make());
    slot.key = key;
  }
  return *static_cast<const T*>(slot.value.get());
}

inline void release_kept() { kept_input() = {}; }

/// The cube sizes of the cell and node benchmarks: 16^3 to 128^3 cells.
inline void cube_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("cells");
  for (int n : {16, 32, 64, 128}) b->Arg(n);
}

/// The sizes of the cell benchmarks with materials: 16^3 to 128^3 cells, 1, 2 and 4
/// materials.
inline void cell_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"cells", "mats"});
  for (int n : {16, 32, 64, 128})
    for (int m : {1, 2, 4}) b->Args({n, m});
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
