// Cell kernels of the ICE half at 16^3 .. 128^3 cells and 1..4 materials. Bytes per
// item (the least a structure-of-arrays kernel must move per cell, 8 B per double,
// counted per material unless said):
//  equilibrate_pressure: reads rho, T, v (3), p (shared, 1); writes theta, v, c,
//                        kappa (4), p_eq, SK, TMV (shared, 3)             -> 56 N + 32
//                        (the same with solids among the gases: the Newton
//                        iteration, as every MPMICE problem takes it)
//  face_velocity (x):    reads rho, v, u per cell (3), p (shared); writes U^f (1)
//                        per face (each cell's values are read once)        -> 32 N + 8
//  face_exchange (x):    reads theta, v per cell (2), U^f per face (1); writes
//                        U^f after the exchange (1)                        -> 32 N
//                        (one material: the face velocity copied           -> 16)
//  exchange:             reads mL, PL (3), EL, v, theta, T^n (8); writes u (3), T,
//                        Tdot (5)                                          -> 104 N
//  pressure_update (no mass sources): reads Adv[theta] (1), SK, p_eq (shared, 2);
//                        writes dP_dil, dP_mx, p (shared, 3)               -> 8 N + 40
//  pressure_work_heat (fluids only): reads theta, kappa, W, rho, mL, PL (3), Q (3),
//                        u^ME (3) (14), reads and writes T^ME, Tdot (4); reads p^f,
//                        Phi^f, Phi_s^f (3 each, a face read once) and SK (shared, 10)
//                                                                          -> 144 N + 80
//  advection_change (1st order, one material): reads q, 3 face velocities;
//                        writes the change                                 -> 40
//  advection_change (2nd order, compatible, as the driver moves momentum and
//                        energy): reads q, m, grad q (3), grad m (3), 3 face
//                        velocities; writes the change                     -> 96
//  limited_gradient (compatible, as the driver's second order uses it): reads q, m,
//                        grad m (3); writes grad q (3)                     -> 64
//  limited_advection (limited_advection_change, compatible: both of the above as the
//                        driver moves each mass-specific quantity, one pass from
//                        2^17 cells on): reads q, m, grad m (3), 3 face velocities;
//                        writes the change                                 -> 72
#include <benchmark/benchmark.h>

#include <mpmice/kernels/advection.hpp>
#include <mpmice/kernels/equilibrate_pressure.hpp>
#include <mpmice/kernels/exchange.hpp>
#include <mpmice/kernels/face_exchange.hpp>
#include <mpmice/kernels/face_velocity.hpp>
#include <mpmice/kernels/pressure_update.hpp>
#include <mpmice/kernels/pressure_work_heat.hpp>

#include "bench_setup.hpp"

using namespace mpmice;
using namespace mpmice::bench;

namespace {

/// 16^3 to 128^3 cells with a gas and a solid, or two of each.
void solid_cell_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"cells", "mats"});
  for (int n : {16, 32, 64, 128})
    for (int m : {2, 4}) b->Args({n, m});
}

/// The equilibration's outputs for `mats` materials on the cells of `p`.
EquilibrationOut equilibration_out(const Patch& p, int mats) {
  return {make_field("p", p, Location::cell), make_field("t", p, Location::cell, mats),
          make_field("v", p, Location::cell, mats), make_field("c", p, Location::cell, mats),
          make_field("k", p, Location::cell, mats), make_field("s", p, Location::cell),
          make_field("m", p, Location::cell)};
}

void BM_equilibrate_pressure(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  const Field4 rho = cell_field(p, mats, 1.0 / mats, 0.1, 1), temp = cell_field(p, mats, 300, 0.1, 2);
  Field4 v = cell_field(p, mats, 0.8, 0.05, 3);
  const Field3 press = cell_scalar(p, 101325, 0.05, 4);
  const EquilibrationOut out = equilibration_out(p, mats);
  const EquilibrationIn in{rho, temp, v, press};
  for (auto _ : state)
    state.SetIterationTime(timed([&] { equilibrate_pressure(p.owned_cells(), 1e-9, t, in, out); }));
  report(state, p.grid.cell_count(), 56.0 * mats + 32.0);
}

/// Gases and solids as the container's (materials 0, 2: gases; 1: copper, with the
/// law in tension; 3: PBX), each cell near equilibrium as a run's last step left it.
MaterialTable gas_and_solid_table(int materials) {
  MaterialTable t = gas_table(materials);
  const double rho0[2] = {8930.0, 1840.0}, bulk[2] = {136.35e9, 5.72e9};
  for (int m = 1; m < materials; m += 2) {
    Eos& e = t.eos[m];
    e.type = EosType::solid;
    e.rho0 = rho0[m / 2];
    e.bulk = bulk[m / 2];
    e.modified = m == 1;
  }
  return t;
}

/// The equilibration's inputs in cell (i, j, k): a random equilibrium (pressure from
/// 50 kPa to 100 MPa, about one cell in 11 below the solids' reference pressure, where
/// copper takes its law in tension; random temperatures and volume fractions) whose
/// pressure and gases' specific volumes are then moved by up to 1e-3, as by one step.
/// A solid's specific volume is its EOS's at that pressure, as node_to_cell sets it
/// (pitfall P1 in mpmice-algorithm.md).
struct NearEquilibrium {
  MaterialTable mats;
  double cell_volume;
  Field4 rho, temp, sp_vol;
  Field3 press;
  KOKKOS_INLINE_FUNCTION void operator()(int i, int j, int k) const {
    const std::uint64_t cell = (std::uint64_t(i) * rho.extent(2) + std::uint64_t(j)) * rho.extent(3) + k;
    const auto u = [&](int r) { return uniform01(7, cell * 16 + std::uint64_t(r)); };
    const auto nudge = [&](int r) { return 1.0 + 1e-3 * (2.0 * u(r) - 1.0); };
    const double p = 5e4 * math::pow(2000.0, u(0));
    double theta[max_materials], sum = 0;
    for (int r = 0; r < mats.count; ++r) sum += theta[r] = 0.05 + u(1 + r);
    const double start = p * nudge(13);
    press(i, j, k) = start;
    for (int r = 0; r < mats.count; ++r) {
      const double T = 300.0 + 400.0 * u(5 + r), rho_micro = eos_density(mats.eos[r], p, T);
      temp(r, i, j, k) = T;
      rho(r, i, j, k) = theta[r] / sum * rho_micro;
      sp_vol(r, i, j, k) = mats.eos[r].type == EosType::solid ? 1.0 / eos_density(mats.eos[r], start, T)
                                                              : nudge(9 + r) / rho_micro;
    }
  }
};

void BM_equilibrate_pressure_solids(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const NearEquilibrium in{gas_and_solid_table(mats), 1e-9, make_field("rho", p, Location::cell, mats),
                           make_field("T", p, Location::cell, mats), make_field("v", p, Location::cell, mats),
                           make_field("p", p, Location::cell)};
  const long ni = long(in.rho.extent(1)), nj = long(in.rho.extent(2)), nk = long(in.rho.extent(3));
  Kokkos::parallel_for("mpmice::bench::near_equilibrium",
                       Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<3>>({0, 0, 0}, {ni, nj, nk}), in);
  Kokkos::fence();
  const EquilibrationOut out = equilibration_out(p, mats);
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      if (equilibrate_pressure(p.owned_cells(), in.cell_volume, in.mats, {in.rho, in.temp, in.sp_vol, in.press}, out)
              .failed)
        state.SkipWithError("equilibration failed");
    }));
  report(state, p.grid.cell_count(), 56.0 * mats + 32.0);
}

void BM_face_velocity(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  const Field4 rho = cell_field(p, mats, 1.0, 0.1, 1), v = cell_field(p, mats, 0.8, 0.05, 2),
               u = cell_field(p, mats, 10, 0.5, 3);
  const Field3 press = cell_scalar(p, 101325, 0.05, 4);
  const Field4 out = make_field("U", p, Location::x_face, mats);
  IndexBox faces = p.owned_cells();
  faces.hi[0] += 1;
  for (auto _ : state)
    state.SetIterationTime(timed([&] { face_velocity(faces, 0, 1e-3, 1e-7, 0.0, t, press, rho, v, u, out); }));
  report(state, p.grid.cell_count(), 32.0 * mats + 8.0);
}

void BM_face_exchange(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  const Field4 theta = cell_field(p, mats, 1.0 / mats, 0.1, 1), v = cell_field(p, mats, 0.8, 0.05, 2);
  const Field4 face_vel = randomised(make_field("U", p, Location::x_face, mats), 1.0, 2.0, 3),
               out = make_field("U_me", p, Location::x_face, mats);
  IndexBox faces = p.owned_cells();
  faces.hi[0] += 1;
  for (auto _ : state)
    state.SetIterationTime(timed([&] { face_exchange(faces, 0, 1e-7, t, theta, v, face_vel, out); }));
  report(state, p.grid.cell_count(), mats == 1 ? 16.0 : 32.0 * mats);
}

void BM_exchange(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  const Field4 mass = cell_field(p, mats, 1e-9, 0.1, 1), eng = cell_field(p, mats, 2e-4, 0.1, 2),
               v = cell_field(p, mats, 0.8, 0.05, 3), theta = cell_field(p, mats, 1.0 / mats, 0.1, 4),
               temp = cell_field(p, mats, 300, 0.1, 5);
  const VectorField4 mom{cell_field(p, mats, 1e-8, 1, 6), cell_field(p, mats, 1e-8, 1, 7), cell_field(p, mats, 1e-8, 1, 8)};
  const VectorField4 vel{make_field("u", p, Location::cell, mats), make_field("v", p, Location::cell, mats),
                         make_field("w", p, Location::cell, mats)};
  const Field4 t_me = make_field("T", p, Location::cell, mats), tdot = make_field("Td", p, Location::cell, mats);
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      exchange(p.owned_cells(), 1e-7, t, mass, ConstVectorField4{mom[0], mom[1], mom[2]}, eng, v, theta, temp, vel,
               t_me, tdot);
    }));
  report(state, p.grid.cell_count(), 104.0 * mats);
}

void BM_pressure_update(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const Field4 adv = cell_field(p, mats, 1e-4, 1.0, 1), v = cell_field(p, mats, 0.8, 0.05, 2);
  const Field3 sum_kappa = cell_scalar(p, 7e-6, 0.1, 3), press_eq = cell_scalar(p, 101325, 0.05, 4);
  const Field3 dp_dil = make_field("dp_dil", p, Location::cell), dp_mx = make_field("dp_mx", p, Location::cell),
               press = make_field("p", p, Location::cell);
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      pressure_update(p.owned_cells(), 1e-9, mats, adv, ConstField4(), v, sum_kappa, press_eq, dp_dil, dp_mx, press);
    }));
  report(state, p.grid.cell_count(), 8.0 * mats + 40.0);
}

void BM_pressure_work_heat(benchmark::State& state) {
  const int n = int(state.range(0)), mats = int(state.range(1));
  const Patch p = cube_patch(n);
  const MaterialTable t = gas_table(mats);
  // Magnitudes of a gas cell of 1 mm at 1 bar moving at about 1 m/s with dt = 1e-7 s,
  // the volume fluxes of random sign: the heat is at most about 5e-5 of a cell's thermal
  // energy, so the temperatures the kernel changes in place move little per iteration
  // (and the work per cell does not depend on them).
  const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
  PressureWorkInputs in;
  for (int d = 0; d < 3; ++d) {
    in.press_face[d] = randomised(make_field("pf", p, faces[d]), 101325, 0.05, 1 + d);
    in.face_flux[d] = randomised(make_field("phi", p, faces[d]), 1e-13, 2.0, 4 + d);
    in.solid_face_flux[d] = randomised(make_field("phi_s", p, faces[d]), 1e-14, 2.0, 7 + d);
  }
  in.vol_frac = cell_field(p, mats, 1.0 / mats, 0.1, 10);
  in.work = cell_field(p, mats, 1e-9, 2.0, 11);
  in.kappa = cell_field(p, mats, 7e-6, 0.1, 12);
  in.sum_kappa = cell_scalar(p, 7e-6, 0.1, 13);
  in.rho = cell_field(p, mats, 1.0 / mats, 0.1, 14);
  in.mass_L = cell_field(p, mats, 1e-9 / mats, 0.1, 15);
  in.mom_L = {cell_field(p, mats, 1e-9, 2.0, 16), cell_field(p, mats, 1e-9, 2.0, 17),
              cell_field(p, mats, 1e-9, 2.0, 18)};
  in.mom_source = {cell_field(p, mats, 1e-12, 2.0, 19), cell_field(p, mats, 1e-12, 2.0, 20),
                   cell_field(p, mats, 1e-12, 2.0, 21)};
  in.vel_me = {cell_field(p, mats, 1.0, 2.0, 22), cell_field(p, mats, 1.0, 2.0, 23),
               cell_field(p, mats, 1.0, 2.0, 24)};
  const Field4 temp = cell_field(p, mats, 300, 0.1, 25), rate = make_field("Tdot", p, Location::cell, mats);
  const Kokkos::Array<double, 3> h{1e-3, 1e-3, 1e-3}, gravity{0, 0, 0};
  for (auto _ : state)
    state.SetIterationTime(timed([&] { pressure_work_heat(p.owned_cells(), h, 1e-7, gravity, t, in, temp, rate); }));
  report(state, p.grid.cell_count(), 144.0 * mats + 80.0);
}

// Face velocities of random sign, -1 to 3 m/s (a quarter of the faces carry inflow),
// on cell-shaped arrays: the kernel reads U[d](m, i+1) at most one past the owned
// cells, inside the ghost layers.
ConstVectorField4 face_velocities(const Patch& p) {
  return {cell_field(p, 1, 1.0, 2.0, 2), cell_field(p, 1, 1.0, 2.0, 3), cell_field(p, 1, 1.0, 2.0, 4)};
}

void BM_advection_first_order(benchmark::State& state) {
  const int n = int(state.range(0));
  const Patch p = cube_patch(n);
  const Field4 q = cell_field(p, 1, 1.0, 0.1, 1), change = make_field("dq", p, Location::cell, 1);
  const ConstVectorField4 U = face_velocities(p);
  const Kokkos::Array<double, 3> h{1e-3, 1e-3, 1e-3};
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      advection_change(p.owned_cells(), h, 1e-7, U, 0, q, ConstField4(), false, GradientField(), GradientField(),
                       change);
    }));
  report(state, p.grid.cell_count(), 40.0);
}

// A quantity q and its mass around 1 and 1e-9 (+-10%), the mass's limited gradient,
// room for q's, face velocities and the change: what the driver's second-order,
// compatible advection works with, on a cube of n^3 cells.
struct CompatibleFields {
  Patch p;
  Kokkos::Array<double, 3> h{1e-3, 1e-3, 1e-3};
  Field4 q, mass, change;
  GradientField mass_grad, grad;
  ConstVectorField4 U;
  FaceFluxes scratch;

  explicit CompatibleFields(int n)
      : p(cube_patch(n)), q(cell_field(p, 1, 1.0, 0.1, 1)), mass(cell_field(p, 1, 1e-9, 0.1, 5)),
        change(make_field("dq", p, Location::cell, 1)), U(face_velocities(p)),
        scratch(make_face_fluxes("flux", p)) {
    for (int d = 0; d < 3; ++d) {
      mass_grad[d] = make_field("gm", p, Location::cell);
      grad[d] = make_field("gq", p, Location::cell);
    }
    limited_gradient(p.ghosted_cells(1), h, mass, 0, ConstField4(), GradientField(), mass_grad);
  }
};

void BM_advection_second_order(benchmark::State& state) {
  const CompatibleFields f(int(state.range(0)));
  limited_gradient(f.p.ghosted_cells(1), f.h, f.q, 0, f.mass, f.mass_grad, f.grad);
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      advection_change(f.p.owned_cells(), f.h, 1e-7, f.U, 0, f.q, f.mass, true, f.grad, f.mass_grad, f.change,
                       f.scratch);
    }));
  report(state, f.p.grid.cell_count(), 96.0);
}

void BM_limited_gradient(benchmark::State& state) {
  const CompatibleFields f(int(state.range(0)));
  for (auto _ : state)
    state.SetIterationTime(
        timed([&] { limited_gradient(f.p.owned_cells(), f.h, f.q, 0, f.mass, f.mass_grad, f.grad); }));
  report(state, f.p.grid.cell_count(), 64.0);
}

void BM_limited_advection(benchmark::State& state) {
  const CompatibleFields f(int(state.range(0)));
  for (auto _ : state)
    state.SetIterationTime(timed([&] {
      limited_advection_change(f.p.owned_cells(), f.h, 1e-7, f.U, 0, f.q, f.mass, f.mass_grad, f.change, f.scratch,
                               f.grad);
    }));
  report(state, f.p.grid.cell_count(), 72.0);
}

}  // namespace

BENCHMARK(BM_equilibrate_pressure)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_equilibrate_pressure_solids)->Apply(solid_cell_sizes)->UseManualTime();
BENCHMARK(BM_face_velocity)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_face_exchange)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_exchange)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_pressure_update)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_pressure_work_heat)->Apply(cell_sizes)->UseManualTime();
BENCHMARK(BM_advection_first_order)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_advection_second_order)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_limited_gradient)->Apply(cube_sizes)->UseManualTime();
BENCHMARK(BM_limited_advection)->Apply(cube_sizes)->UseManualTime();
