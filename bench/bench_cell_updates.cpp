// The ICE cell kernels between the big ones (steps 8, 9, 16 and the extra cells' fill),
// at 16^3 .. 128^3 cells and 1..4 materials. Bytes per item (the least a
// structure-of-arrays kernel must move, 8 B per double, per material unless said):
//  face_pressure (x):           reads p, sum rho per cell (each once); writes p^f per
//                               face (material-independent)                   -> 24
//  momentum_source:             reads p^f (3 directions, a face read once, shared),
//                               theta, rho; writes Q (3)                      -> 40 N + 24
//  lagrangian_momentum_energy:  reads mL, u (3), T, Q (3), W; writes PL (3), EL -> 104 N
//  fill_extra_cells (one field, zero gradient on the six faces; an item is an extra
//                               cell): writes the extra cell, reads the inside cell next
//                               to its face once for the two layers            -> 12 N
#include <benchmark/benchmark.h>

#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/face_pressure.hpp>
#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/sources.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

void BM_face_pressure(benchmark::State& state) {
  const int n = int(state.range(0));
  const Patch p = cube_patch(n);
  const Field3 press = cell_scalar(p, 101325, 0.05, 1), sum_rho = cell_scalar(p, 1.2, 0.1, 2);
  const Field3 out = make_field("p_f", p, Location::x_face);
  const IndexBox faces = faces_of_owned_cells(p, 0);
  for (auto _ : state) state.SetIterationTime(timed([&] { face_pressure(faces, 0, press, sum_rho, out); }));
  report(state, p.grid.cell_count(), 24.0);
}

void BM_momentum_source(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const Field4 theta = cell_field(p, mats, 1.0 / mats, 0.1, 1), rho = cell_field(p, mats, 1.0, 0.1, 2);
  // The face pressures on cell-shaped arrays: the kernel reads face i + 1 at most one
  // past the owned cells, inside the ghost layers.
  const Kokkos::Array<ConstField3, 3> press_face{cell_scalar(p, 101325, 0.05, 3), cell_scalar(p, 101325, 0.05, 4),
                                                 cell_scalar(p, 101325, 0.05, 5)};
  const VectorField4 out{make_field("qx", p, Location::cell, mats), make_field("qy", p, Location::cell, mats),
                         make_field("qz", p, Location::cell, mats)};
  Kokkos::Array<int, max_materials> gravity_on;
  for (int m = 0; m < max_materials; ++m) gravity_on[m] = 1;
  const Kokkos::Array<double, 3> gravity{0, -9.81, 0};
  for (auto _ : state)
    state.SetIterationTime(timed(
        [&] { momentum_source(p.owned_cells(), p, 1e-7, mats, gravity, gravity_on, theta, rho, press_face, out); }));
  report(state, p.grid.cell_count(), 40.0 * mats + 24.0);
}

void BM_lagrangian_momentum_energy(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  const Field4 mass = cell_field(p, mats, 1e-9, 0.1, 1), temp = cell_field(p, mats, 300, 0.1, 2),
               w = cell_field(p, mats, 0.0, 1e-12, 3);
  const ConstVectorField4 u{cell_field(p, mats, 1.0, 0.5, 4), cell_field(p, mats, 1.0, 0.5, 5),
                            cell_field(p, mats, 1.0, 0.5, 6)};
  const ConstVectorField4 q{cell_field(p, mats, 0.0, 1e-12, 7), cell_field(p, mats, 0.0, 1e-12, 8),
                            cell_field(p, mats, 0.0, 1e-12, 9)};
  const VectorField4 mom{make_field("px", p, Location::cell, mats), make_field("py", p, Location::cell, mats),
                         make_field("pz", p, Location::cell, mats)};
  const Field4 eng = make_field("e", p, Location::cell, mats);
  for (auto _ : state)
    state.SetIterationTime(
        timed([&] { lagrangian_momentum_energy(p.owned_cells(), t, mass, u, temp, q, w, mom, eng); }));
  report(state, p.grid.cell_count(), 104.0 * mats);
}

void BM_fill_extra_cells(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const Field4 q = cell_field(p, mats, 1.0, 0.1, 1);
  const FaceBcs zero_gradient{};  // Neumann, 0, on every face
  const long extra = p.cells_with_extra().size() - p.owned_cells().size();
  for (auto _ : state) state.SetIterationTime(timed([&] { fill_extra_cells(q, p, zero_gradient, -1); }));
  report(state, extra, 12.0 * mats);
}

}  // namespace

BENCHMARK(BM_face_pressure)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_momentum_source)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_lagrangian_momentum_energy)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_fill_extra_cells)->Apply(cell_sizes)->UseManualTime();
