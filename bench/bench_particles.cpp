// Particle kernels of the MPM half, 1e4 .. 4e6 particles, 8 per cell, sorted as the
// driver sorts them (by their shape's window: the cell for the linear shape, the
// nearest node for GIMP). p2g and internal_force round their contributions to quanta as the
// driver does (quanta.hpp; `driver_quanta` below). Bytes per particle (the least a structure-of-arrays kernel moves;
// node fields are few and stay in cache, so they are not counted):
//  p2g:            reads x (3), size (3), mass, volume, v (3), T, f_ext (3) -> 15 x 8 = 120
//  internal_force: reads x (3), size (3), volume, stress (9), gas pressure,
//                  bulk viscosity                                          -> 18 x 8 = 144
//  g2p:            reads x (3), size (3), v (3), F (9), volume; writes v (3),
//                  x (3), F (9), L (9), volume, T                          -> 44 x 8 = 352
//  g2p_mpmice:     g2p as MPMICE runs it (the nodes' heat rate and the transfers'
//                  terms, TransferHeat): + mass, gas pressure, bulk viscosity -> 47 x 8 = 376
//  stress_update (neo-Hookean): reads F (9), v (3); writes stress (9)     -> 21 x 8 = 168
//  stress_update (J2 plastic): + L (9), bbar_e (9 read, 9 write), eps_p (2) -> 50 x 8 = 400
#include <benchmark/benchmark.h>

#include <mpmice/kernels/g2p.hpp>
#include <mpmice/kernels/internal_force.hpp>
#include <mpmice/kernels/p2g.hpp>
#include <mpmice/kernels/particle_sort.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/stress_update.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

// A cube holding `particles` at 8 per cell.
Patch patch_for(long particles) {
  int n = 1;
  while (8L * n * n * n < particles) ++n;
  return cube_patch(n);
}

// `count` particles of `p` (particles_in) sorted by Shape's window (particle_sort.hpp),
// one set for every kernel of that count and shape (kept): p2g and internal_force read
// them, and g2p, run with dt = 0, leaves them in place.
template <class Shape>
const ParticleSet& sorted_particles_in(const Patch& p, long count) {
  return kept<ParticleSet>("sorted particles " + std::to_string(count) + " " + std::to_string(Shape::nodes), [&] {
    ParticleSet ps = particles_in(p, count, 1);
    sort_particles_by_window<Shape>(p, ps);
    return ps;
  });
}

// The quanta the driver's p2g and internal_force use (miniapp/cycle.cpp and
// cycle_particles.cpp): 2^-40 of the largest contribution of each kind, the mass's from
// the heaviest particle.
SumQuanta driver_quanta(const NodeGrid& grid, long count, const ParticleData& data) {
  SumQuanta bound = particle_scatter_bounds(count, data);
  Kokkos::parallel_reduce(
      "heaviest", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& mx) { mx = std::max(mx, data(p, column(ParticleField::mass))); },
      Kokkos::Max<double>(bound.mass));
  bound.internal_force = internal_force_bound(grid, count, data);
  return quanta_for(bound);
}

NodeSums node_sums(const Patch& p) {
  auto node = [&](const char* name) { return make_field(name, p, Location::node, 1); };
  return NodeSums{node("m"), {node("px"), node("py"), node("pz")}, node("mT"), node("V"),
                  {node("fx"), node("fy"), node("fz")}};
}

template <class Shape>
void BM_p2g(benchmark::State& state) {
  const long n = state.range(0);
  const Patch p = patch_for(n);
  const NodeGrid grid = node_grid(p);
  const ParticleSet& ps = sorted_particles_in<Shape>(p, n);
  const NodeSums sums = node_sums(p);
  const SumQuanta q = driver_quanta(grid, n, ps.data());
  // The scratch is kept between steps, as the driver keeps it: a first, untimed call
  // allocates it (and faults its pages in), which a run pays once, not every step.
  ScatterScratch scratch;
  p2g<Shape>(grid, n, ps.data(), 0, sums, q, scratch);
  for (auto _ : state) state.SetIterationTime(timed([&] { p2g<Shape>(grid, n, ps.data(), 0, sums, q, scratch); }));
  report(state, n, 120.0);
}

template <class Shape>
void BM_internal_force(benchmark::State& state) {
  const long n = state.range(0);
  const Patch p = patch_for(n);
  const NodeGrid grid = node_grid(p);
  const ParticleSet& ps = sorted_particles_in<Shape>(p, n);
  const NodeSums sums = node_sums(p);
  const SumQuanta q = driver_quanta(grid, n, ps.data());
  ScatterScratch scratch;  // kept between steps, as in BM_p2g
  internal_force<Shape>(grid, n, ps.data(), 0, sums.fext, q, scratch);
  for (auto _ : state)
    state.SetIterationTime(timed([&] { internal_force<Shape>(grid, n, ps.data(), 0, sums.fext, q, scratch); }));
  report(state, n, 144.0);
}

// g2p; with `Mpmice`, with the heat rate and the transfers' terms as MPMICE's cycle
// calls it (the node fields' values are the sums' zeros).
template <class Shape, bool Mpmice>
void BM_g2p(benchmark::State& state) {
  const long n = state.range(0);
  const Patch p = patch_for(n);
  const NodeGrid grid = node_grid(p);
  const ParticleSet& ps = sorted_particles_in<Shape>(p, n);
  const NodeSums sums = node_sums(p);
  const ConstVectorField4 vs{sums.mom[0], sums.mom[1], sums.mom[2]}, acc{sums.fext[0], sums.fext[1], sums.fext[2]};
  const Field4 temp_rate = Mpmice ? sums.heat : Field4();  // empty: not given (g2p)
  const TransferHeat transfer{Mpmice ? sums.volume : Field4(), 1000.0};
  // dt = 0: the particles stay in place, so every iteration does the same work.
  for (auto _ : state)
    state.SetIterationTime(
        timed([&] { g2p<Shape>(grid, n, ps.data(), 0, 0.0, 0.0, false, {0, 0, 0}, vs, acc, temp_rate, transfer); }));
  report(state, n, Mpmice ? 376.0 : 352.0);
}

void BM_stress_update(benchmark::State& state) {
  const long n = state.range(0);
  const bool plastic = state.range(1) != 0;
  const Patch p = patch_for(n);
  const NodeGrid grid = node_grid(p);
  // Unsorted, shared by the elastic and the plastic model (kept; the elastic update
  // leaves the plastic state alone).
  const ParticleSet& ps = kept<ParticleSet>("particles " + std::to_string(n), [&] { return particles_in(p, n, 4); });
  SolidModel model;
  model.type = plastic ? SolidModelType::neo_hookean_plastic : SolidModelType::neo_hookean;
  model.yield_stress = 1e8;
  for (auto _ : state) state.SetIterationTime(timed([&] { stress_update(grid, n, ps.data(), model, 1e-9); }));
  report(state, n, plastic ? 400.0 : 168.0);
}

}  // namespace

// Registered count by count, so that the kernels of one count and shape follow one
// another and share their particles (sorted_particles_in).
const bool particle_benchmarks = [] {
  for (long n : {10000L, 100000L, 1000000L, 4000000L}) {
    auto add = [n](const char* name, void (*bm)(benchmark::State&)) {
      benchmark::RegisterBenchmark(name, bm)->ArgName("particles")->Arg(n)->UseManualTime();
    };
    add("BM_p2g<LinearShape>", BM_p2g<LinearShape>);
    add("BM_internal_force<LinearShape>", BM_internal_force<LinearShape>);
    add("BM_g2p<LinearShape>", BM_g2p<LinearShape, false>);
    add("BM_p2g<GimpShape>", BM_p2g<GimpShape>);
    add("BM_internal_force<GimpShape>", BM_internal_force<GimpShape>);
    add("BM_g2p<GimpShape>", BM_g2p<GimpShape, false>);
    add("BM_g2p_mpmice<GimpShape>", BM_g2p<GimpShape, true>);  // MPMICE's problems use GIMP
  }
  return true;
}();
BENCHMARK(BM_stress_update)
    ->ArgNames({"particles", "plastic"})
    ->Args({10000, 0})->Args({10000, 1})->Args({1000000, 0})->Args({1000000, 1})
    ->UseManualTime();
