// Particle-to-grid scatter strategies (issue: measure, keep the fastest): mass and
// momentum (4 node fields) of particles sorted by cell at 1, 8 and 27 particles per
// cell, linear shape functions:
//  - ScatterView, duplicated per thread (the OpenMP default; what p2g uses on any host backend),
//  - ScatterView with atomics (the GPU default),
//  - plain atomic_add into the node views,
//  - gather: each node sums the particles of its 8 cells (needs the particles sorted
//    by cell and the cell offsets; no write conflicts, no atomics).
// Bytes per particle: x (3), mass, v (3) -> 56.
#include <benchmark/benchmark.h>

#include <Kokkos_ScatterView.hpp>
#include <Kokkos_Sort.hpp>

#include <mpmice/kernels/particle_sort.hpp>
#include <mpmice/kernels/shape.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

struct Case {
  Patch patch;
  NodeGrid grid;
  ParticleSet particles;
  Field4 mass, px, py, pz;
  Kokkos::View<long*> cell_start;  // particles of local cell c: [cell_start(c), cell_start(c+1))
};

Case make_case(long particles, int per_cell) {
  int n = 1;
  while (long(per_cell) * n * n * n < particles) ++n;
  Case c{cube_patch(n), {}, particles_in(cube_patch(n), particles, 5), {}, {}, {}, {}, {}};
  c.grid = node_grid(c.patch);
  sort_particles_by_cell(c.patch, c.particles);
  auto node = [&](const char* label) { return make_field(label, c.patch, Location::node, 1); };
  c.mass = node("m");
  c.px = node("px");
  c.py = node("py");
  c.pz = node("pz");
  // Cell offsets of the sorted particles (row-major local cell index).
  const int ny = c.patch.extent(Location::cell, 1), nz = c.patch.extent(Location::cell, 2);
  const long ncell = long(c.patch.extent(Location::cell, 0)) * ny * nz;
  auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.particles.data());
  Kokkos::View<long*, Kokkos::HostSpace> start("start", ncell + 1);
  for (long p = 0; p < particles; ++p) {
    int idx[3];
    for (int d = 0; d < 3; ++d)
      idx[d] = int(std::floor((data(p, column(ParticleField::x) + d) - c.grid.lower[d]) * c.grid.inv_h[d]));
    start((long(idx[0]) * ny + idx[1]) * nz + idx[2] + 1) += 1;
  }
  for (long q = 0; q < ncell; ++q) start(q + 1) += start(q);
  c.cell_start = Kokkos::create_mirror_view_and_copy(MemSpace(), start);
  return c;
}

template <class Scatter>
void scatter_with(const Case& c, long n) {
  Scatter sm(c.mass), sx(c.px), sy(c.py), sz(c.pz);
  const NodeGrid grid = c.grid;
  const ParticleData data = c.particles.data();
  Kokkos::parallel_for(
      "scatter", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<LinearShape> wt(x, grid.lower, grid.inv_h, half);
        const double m = data(p, column(ParticleField::mass));
        const double v[3] = {data(p, column(ParticleField::vx)), data(p, column(ParticleField::vy)),
                             data(p, column(ParticleField::vz))};
        auto am = sm.access();
        auto ax = sx.access();
        auto ay = sy.access();
        auto az = sz.access();
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int cc = 0; cc < 2; ++cc) {
              const double S = wt.weight(a, b, cc) * m;
              const long i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + cc;
              am(0, i, j, k) += S;
              ax(0, i, j, k) += S * v[0];
              ay(0, i, j, k) += S * v[1];
              az(0, i, j, k) += S * v[2];
            }
      });
  Field4 mass = c.mass, px = c.px, py = c.py, pz = c.pz;  // contribute takes non-const views
  Kokkos::Experimental::contribute(mass, sm);
  Kokkos::Experimental::contribute(px, sx);
  Kokkos::Experimental::contribute(py, sy);
  Kokkos::Experimental::contribute(pz, sz);
}

void scatter_atomic(const Case& c, long n) {
  const NodeGrid grid = c.grid;
  const ParticleData data = c.particles.data();
  const Field4 mass = c.mass, px = c.px, py = c.py, pz = c.pz;
  Kokkos::parallel_for(
      "scatter_atomic", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long p) {
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<LinearShape> wt(x, grid.lower, grid.inv_h, half);
        const double m = data(p, column(ParticleField::mass));
        const double v[3] = {data(p, column(ParticleField::vx)), data(p, column(ParticleField::vy)),
                             data(p, column(ParticleField::vz))};
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int cc = 0; cc < 2; ++cc) {
              const double S = wt.weight(a, b, cc) * m;
              const long i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + cc;
              Kokkos::atomic_add(&mass(0, i, j, k), S);
              Kokkos::atomic_add(&px(0, i, j, k), S * v[0]);
              Kokkos::atomic_add(&py(0, i, j, k), S * v[1]);
              Kokkos::atomic_add(&pz(0, i, j, k), S * v[2]);
            }
      });
}

// Each node owns its sums: it reads the particles of the 8 cells around it.
void gather_sorted(const Case& c) {
  const NodeGrid grid = c.grid;
  const ParticleData data = c.particles.data();
  const Field4 mass = c.mass, px = c.px, py = c.py, pz = c.pz;
  const auto start = c.cell_start;
  const int ny = c.patch.extent(Location::cell, 1), nz = c.patch.extent(Location::cell, 2);
  IndexBox nodes = c.patch.owned_nodes();
  Kokkos::parallel_for(
      "gather_sorted", nodes.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double m = 0, s[3] = {0, 0, 0};
        for (int a = -1; a <= 0; ++a)
          for (int b = -1; b <= 0; ++b)
            for (int cc = -1; cc <= 0; ++cc) {
              const long cell = (long(i + a) * ny + (j + b)) * nz + (k + cc);
              for (long p = start(cell); p < start(cell + 1); ++p) {
                double w = data(p, column(ParticleField::mass));
                const int node[3] = {i, j, k};
                for (int d = 0; d < 3; ++d)
                  w *= 1.0 - math::abs((data(p, column(ParticleField::x) + d) - grid.lower[d]) * grid.inv_h[d] - node[d]);
                m += w;
                for (int d = 0; d < 3; ++d) s[d] += w * data(p, column(ParticleField::vx) + d);
              }
            }
        mass(0, i, j, k) = m;
        px(0, i, j, k) = s[0];
        py(0, i, j, k) = s[1];
        pz(0, i, j, k) = s[2];
      });
}

using DuplicatedScatter = Kokkos::Experimental::ScatterView<double****, Kokkos::LayoutRight, ExecSpace,
                                                            Kokkos::Experimental::ScatterSum,
                                                            Kokkos::Experimental::ScatterDuplicated,
                                                            Kokkos::Experimental::ScatterNonAtomic>;
using AtomicScatter = Kokkos::Experimental::ScatterView<double****, Kokkos::LayoutRight, ExecSpace,
                                                        Kokkos::Experimental::ScatterSum,
                                                        Kokkos::Experimental::ScatterNonDuplicated,
                                                        Kokkos::Experimental::ScatterAtomic>;

void BM_scatter(benchmark::State& state) {
  const long n = state.range(0);
  const int per_cell = int(state.range(1)), method = int(state.range(2));
  // One case for the four methods (kept): each writes only the node sums.
  const Case& c = kept<Case>("scatter case " + std::to_string(n) + " " + std::to_string(per_cell),
                             [&] { return make_case(n, per_cell); });
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      if (method == 0) scatter_with<DuplicatedScatter>(c, n);
      else if (method == 1) scatter_with<AtomicScatter>(c, n);
      else if (method == 2) scatter_atomic(c, n);
      else gather_sorted(c);
    }));
  report(state, n, 56.0);
  const char* names[4] = {"scatterview_duplicated", "scatterview_atomic", "atomic_add", "sorted_gather"};
  state.SetLabel(names[method]);
}

}  // namespace

BENCHMARK(BM_scatter)
    ->ArgNames({"particles", "per_cell", "method"})
    ->Apply([](benchmark::internal::Benchmark* b) {  // the methods of one density in a row (kept)
      for (int per_cell : {1, 8, 27})
        for (int method : {0, 1, 2, 3}) b->Args({1000000, per_cell, method});
    })
    ->UseManualTime();
