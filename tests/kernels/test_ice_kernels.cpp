// Pointwise and per-cell ICE kernels against closed forms and conservation laws.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <mpmice/kernels/advection.hpp>
#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/conserved_to_primitive.hpp>
#include <mpmice/kernels/equilibrate_pressure.hpp>
#include <mpmice/kernels/exchange.hpp>
#include <mpmice/kernels/face_exchange.hpp>
#include <mpmice/kernels/face_velocity.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/pressure_work_heat.hpp>
#include <mpmice/kernels/timestep.hpp>

using namespace mpmice;

TEST(IdealGas, InverseAndSoundSpeed) {
  Eos air{EosType::ideal_gas, 1.4, 716.0};
  for (double T : {200.0, 300.0, 1500.0})
    for (double p : {1.0e3, 101325.0, 5.0e7}) {
      const double rho = eos_density(air, p, T);
      // Round trip to a few ulps.
      EXPECT_NEAR(eos_pressure(air, rho, T), p, 4e-16 * p);
      EXPECT_NEAR(eos_sound_speed_squared(air, rho, T), 1.4 * 0.4 * 716.0 * T, 1e-12 * T * 716);
    }
}

TEST(SmallSolve, MatchesKnownSolution) {
  // A x = b with a 3x3 system of the exchange's kind (no pivoting): diagonally
  // dominant by rows, off-diagonal entries negative and far from symmetric.
  double a[3 * 3] = {};
  const double rows[3][3] = {{1.5, -0.25, -0.25}, {-40, 61, -20}, {-1e3, -2e3, 3001}};
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) a[r * 3 + s] = rows[r][s];
  const double x[3] = {1.5, -2.0, 0.25};
  double b[3] = {};
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) b[r] += rows[r][s] * x[s];
  solve_dense<3, 1>(a, b);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(b[r], x[r], 1e-14);
}

// The implicit exchange with m_r beta_rs symmetric conserves sum m_r q_r to round-off
// for any coefficient, and a huge coefficient equalises the velocities: for n materials
// (2: the closed form, 3 and 4: elimination).
template <int n>
void check_exchange_conserves_and_equalises() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.1, 2.0);
  for (double K : {1.0, 1e5, 1e15}) {
    double mass[n], q[n], beta[n * n];
    double before = 0, scale = 0;
    for (int r = 0; r < n; ++r) {
      mass[r] = u(rng);
      q[r] = 100 * (u(rng) - 1.0);
      before += mass[r] * q[r];
      scale += mass[r] * std::abs(q[r]);
    }
    // beta_rs = K w_rs / m_r with w symmetric: m_r beta_rs symmetric, as in (E31).
    for (int r = 0; r < n; ++r)
      for (int s = 0; s < n; ++s) beta[r * n + s] = r == s ? 0 : K * (1.0 + r + s) / mass[r] * 1e-3;
    implicit_exchange<n, 1>(beta, q, mass);
    double after = 0;
    for (int r = 0; r < n; ++r) after += mass[r] * q[r];
    // Elimination with N=4 loses a few ulps of the largest term per operation.
    EXPECT_NEAR(after, before, 1e-13 * scale) << n << " materials, K " << K;
    if (K >= 1e15)
      for (int r = 1; r < n; ++r) EXPECT_NEAR(q[r], q[0], 1e-9 * scale) << n << " materials";
  }
}

TEST(SmallSolve, ExchangeConservesAndEqualises) {
  check_exchange_conserves_and_equalises<2>();
  check_exchange_conserves_and_equalises<3>();
  check_exchange_conserves_and_equalises<4>();
}

// implicit_exchange for n materials (2: the closed form, 3 and 4: elimination of
// A (q + dq) = q) against the system as (E31) writes it, A dq = sum_s beta_rs (q_s - q_r),
// solved by elimination in long double, plus the uniform shift that keeps
// sum_r w_r q_r, for weights that do not make w_r beta_rs symmetric (the shift is then
// not round-off). Coefficients up to K = 1e3: beyond, the reference's elimination
// cancels products of size K^2 down to K and long double no longer resolves them to
// 1e-15 (stiff coefficients: ExchangeConservesAndEqualises).
template <int n>
void check_exchange_solves_the_system() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.1, 2.0);
  for (double K : {1e-3, 1.0, 1e3})
    for (int draw = 0; draw < 20; ++draw) {
      constexpr int NQ = 3;
      double beta[n * n], weight[n], q[NQ * n];
      for (int r = 0; r < n; ++r) {
        weight[r] = u(rng);
        for (int s = 0; s < n; ++s) beta[r * n + s] = r == s ? 0.0 : K * u(rng);
      }
      for (double& v : q) v = 100 * (u(rng) - 1.0);
      long double expect[NQ * n];
      for (int k = 0; k < NQ; ++k) {
        long double a[n][n + 1];  // the matrix and the right side
        for (int r = 0; r < n; ++r) {
          a[r][r] = 1;
          a[r][n] = 0;
          for (int s = 0; s < n; ++s)
            if (s != r) {
              a[r][r] += beta[r * n + s];
              a[r][s] = -beta[r * n + s];
              a[r][n] += beta[r * n + s] * ((long double)q[k * n + s] - q[k * n + r]);
            }
        }
        for (int c = 0; c < n; ++c)
          for (int r = c + 1; r < n; ++r) {
            const long double f = a[r][c] / a[c][c];
            for (int s = c; s <= n; ++s) a[r][s] -= f * a[c][s];
          }
        long double dq[n], wsum = 0, wdq = 0;
        for (int r = n - 1; r >= 0; --r) {
          dq[r] = a[r][n];
          for (int s = r + 1; s < n; ++s) dq[r] -= a[r][s] * dq[s];
          dq[r] /= a[r][r];
          wsum += weight[r];
          wdq += weight[r] * dq[r];
        }
        for (int r = 0; r < n; ++r) expect[k * n + r] = q[k * n + r] + dq[r] - wdq / wsum;
      }
      double scale[NQ] = {};
      for (int k = 0; k < NQ; ++k)
        for (int r = 0; r < n; ++r) scale[k] += std::abs(q[k * n + r]);
      implicit_exchange<n, NQ>(beta, q, weight);
      // A few roundings per operation of values no larger than sum_r |q_r|; elimination
      // with 4 materials takes a few dozen operations.
      for (int i = 0; i < NQ * n; ++i)
        EXPECT_NEAR(q[i], double(expect[i]), 1e-14 * scale[i / n]) << n << " materials, K " << K << ", entry " << i;
    }
}

TEST(SmallSolve, ExchangeSolvesTheSystem) {
  check_exchange_solves_the_system<2>();
  check_exchange_solves_the_system<3>();
  check_exchange_solves_the_system<4>();
}

// The equilibration's inputs for `n` materials on the cells of `p`, filled on the host
// (rh, th, vh, ph) and copied to the device by `copied()`.
struct EquilibrationInputs {
  Field4 rho, temp, sp_vol;
  Field3 press;
  Field4::HostMirror rh, th, vh;
  Field3::HostMirror ph;
  EquilibrationInputs(const Patch& p, int n)
      : rho(make_field("rho", p, Location::cell, n)), temp(make_field("t", p, Location::cell, n)),
        sp_vol(make_field("v", p, Location::cell, n)), press(make_field("p", p, Location::cell)),
        rh(Kokkos::create_mirror_view(rho)), th(Kokkos::create_mirror_view(temp)),
        vh(Kokkos::create_mirror_view(sp_vol)), ph(Kokkos::create_mirror_view(press)) {}
  EquilibrationIn copied() const {
    Kokkos::deep_copy(rho, rh);
    Kokkos::deep_copy(temp, th);
    Kokkos::deep_copy(sp_vol, vh);
    Kokkos::deep_copy(press, ph);
    return {rho, temp, sp_vol, press};
  }
};

// equilibrate_pressure on the owned cells of `p` from `in`, its outputs copied to the host.
using HostField3 = decltype(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Field3()));
using HostField4 = decltype(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Field4()));
struct EquilibratedOnHost {
  HostField3 press;
  HostField4 theta, v, c, kappa;
  HostField3 sum_kappa, tmv;
};
EquilibratedOnHost equilibrate_on_host(const Patch& p, double cell_volume, const MaterialTable& mats,
                                       const EquilibrationIn& in) {
  const int n = mats.count;
  const EquilibrationOut out{make_field("peq", p, Location::cell), make_field("th", p, Location::cell, n),
                             make_field("v", p, Location::cell, n), make_field("c", p, Location::cell, n),
                             make_field("k", p, Location::cell, n), make_field("sk", p, Location::cell),
                             make_field("tmv", p, Location::cell)};
  EXPECT_FALSE(equilibrate_pressure(p.owned_cells(), cell_volume, mats, in, out).failed);
  const auto host = [](const auto& f) { return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f); };
  return {host(out.press_eq), host(out.vol_frac), host(out.sp_vol),   host(out.speed_sound),
          host(out.kappa),    host(out.sum_kappa), host(out.tmv)};
}

// Two ideal gases at different temperatures: the equilibrated pressure is the EOS
// pressure of each material at its new micro density, and the volume fractions sum to 1.
TEST(Equilibration, TwoGasesShareOnePressure) {
  Grid g;
  g.cells = {4, 1, 1};
  const Patch p = whole_grid_patch(g, 1);
  MaterialTable mats;
  mats.count = 2;
  mats.eos[0] = Eos{EosType::ideal_gas, 1.4, 716.0};
  mats.eos[1] = Eos{EosType::ideal_gas, 1.67, 3116.0};
  const EquilibrationInputs in(p, 2);
  const auto &rh = in.rh, &th = in.th, &vh = in.vh;
  const auto &ph = in.ph;
  for (int i = 0; i < p.extent(Location::cell, 0); ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        // Volume fractions 0.3/0.7 at quite different pressures; guess far off.
        const double p0 = 1e5 * (1 + i), p1 = 3e5;
        th(0, i, j, k) = 300;
        th(1, i, j, k) = 900;
        vh(0, i, j, k) = 1.0 / eos_density(mats.eos[0], p0, 300);
        vh(1, i, j, k) = 1.0 / eos_density(mats.eos[1], p1, 900);
        rh(0, i, j, k) = 0.3 / vh(0, i, j, k);
        rh(1, i, j, k) = 0.7 / vh(1, i, j, k);
        ph(i, j, k) = 1e4;
      }
  const auto [peq, theta, v, c, kappa, sum_kappa, tmv] = equilibrate_on_host(p, g.cell_volume(), mats, in.copied());
  const IndexBox own = p.owned_cells();
  for (int i = own.lo[0]; i < own.hi[0]; ++i) {
    const double P = peq(i, 1, 1);
    EXPECT_NEAR(theta(0, i, 1, 1) + theta(1, i, 1, 1), 1.0, 1e-13);
    double sk = 0, volume = 0;
    for (int r = 0; r < 2; ++r) {
      const double vr = v(r, i, 1, 1), T = th(r, i, 1, 1);
      EXPECT_NEAR(eos_pressure(mats.eos[r], 1.0 / vr, T), P, 1e-12 * P);
      // (E16) at the new state, each value from the EOS's own functions; a few roundings
      // apart from the kernel's (1e-13 relative: 100 ulps).
      const double c2 = eos_sound_speed_squared(mats.eos[r], 1.0 / vr, T);
      EXPECT_NEAR(c(r, i, 1, 1), std::sqrt(c2), 1e-13 * std::sqrt(c2));
      EXPECT_NEAR(kappa(r, i, 1, 1), vr / c2, 1e-13 * vr / c2);
      EXPECT_NEAR(theta(r, i, 1, 1), rh(r, i, 1, 1) * g.cell_volume() * vr / tmv(i, 1, 1), 1e-13);
      sk += theta(r, i, 1, 1) * vr / c2;
      volume += rh(r, i, 1, 1) * g.cell_volume() * vr;
    }
    EXPECT_NEAR(sum_kappa(i, 1, 1), sk, 1e-13 * sk);
    EXPECT_NEAR(tmv(i, 1, 1), volume, 1e-13 * volume);
    // The mixture lies between the two initial pressures.
    EXPECT_GT(P, 1e5 * std::min(1 + i - 1, 3) * 0.99);
  }
}

// Two gases and two solids as in the container (copper with the law in tension, E52;
// PBX without), equilibrated by the Newton iteration (E15) from starts as a step leaves
// them: the gases' specific volumes from another pressure, the solids' from their EOS at
// the given pressure (Step 2), that pressure off by up to 3x. Pressures from below the
// solids' reference pressure (copper in tension) to 500 MPa. Every material must end at
// the one pressure by eos.hpp's own functions, with (E16) from them.
TEST(Equilibration, GasesAndSolidsShareOnePressure) {
  Grid g;
  g.cells = {8, 1, 1};
  const Patch p = whole_grid_patch(g, 1);
  const double V = g.cell_volume();
  MaterialTable mats;
  mats.count = 4;
  mats.eos[0] = Eos{EosType::ideal_gas, 1.4, 716.0};
  mats.eos[1] = Eos{EosType::solid, 1.4, 383.0, 8930.0, 136.35e9, 101325.0, true};
  mats.eos[2] = Eos{EosType::ideal_gas, 1.3, 1000.0};
  mats.eos[3] = Eos{EosType::solid, 1.4, 996.0, 1840.0, 5.72e9, 101325.0, false};
  const EquilibrationInputs in(p, 4);
  const auto &rh = in.rh, &th = in.th, &vh = in.vh;
  const auto &ph = in.ph;
  const double p_eq[10] = {3e5, 5e4, 9e4, 101325.0, 2e5, 1e6, 3e7, 1e8, 5e8, 1e6};
  const double guess[10] = {1.0, 1.0, 3.0, 0.9, 0.34, 1.0, 2.0, 0.5, 1.1, 1.0};
  // Volume fractions: mixed, or nearly one material with traces of the others (1e-9).
  const double fractions[4][4] = {
      {0.4, 0.2, 0.3, 0.1}, {1.0, 1e-9, 1e-9, 1e-9}, {1e-9, 1.0, 1e-9, 1e-9}, {0.1, 0.45, 0.0, 0.45}};
  for (int i = 0; i < p.extent(Location::cell, 0); ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const double start = p_eq[i] * guess[i];
        for (int r = 0; r < 4; ++r) {
          th(r, i, j, k) = 300.0 + 100.0 * r + 10.0 * i;
          const double rho_micro = eos_density(mats.eos[r], p_eq[i], th(r, i, j, k));
          rh(r, i, j, k) = fractions[i % 4][r] * rho_micro;
          const bool solid = mats.eos[r].type == EosType::solid;
          vh(r, i, j, k) = 1.0 / eos_density(mats.eos[r], solid ? start : 1.5 * p_eq[i], th(r, i, j, k));
        }
        ph(i, j, k) = start;
      }
  const auto [peq, theta, v, c, kappa, sum_kappa, tmv] = equilibrate_on_host(p, V, mats, in.copied());
  const IndexBox own = p.owned_cells();
  for (int i = own.lo[0]; i < own.hi[0]; ++i) {
    const double P = peq(i, 1, 1);
    double sum = 0, sk = 0, volume = 0, start_volume = 0;
    for (int r = 0; r < 4; ++r) start_volume += rh(r, i, 1, 1) * V * vh(r, i, 1, 1);
    for (int r = 0; r < 4; ++r) {
      const double vr = v(r, i, 1, 1), T = th(r, i, 1, 1);
      // A material's pressure from its specific volume: a few roundings of v (1e-15
      // relative) move a gas's by as much; a solid's, p_ref - K/2 (J - 1/J), by a few
      // K eps (K = 136 GPa: 1e-4 Pa); under copper's law in tension (p ~
      // rhoM^(K/p_ref)) 1.3e6 times as much as a gas's. So 1e-12 relative, plus 16 K
      // eps for a solid, and 1e-8 relative in tension, for the pressure and for c^2.
      const bool solid = mats.eos[r].type == EosType::solid;
      const bool tension = eos_has_tension_law(mats.eos[r]) && 1.0 / vr < mats.eos[r].rho0;
      const double tol = tension ? 1e-8 : 1e-12;
      const double solid_eps = solid && !tension ? 16 * std::numeric_limits<double>::epsilon() * mats.eos[r].bulk : 0;
      EXPECT_NEAR(eos_pressure(mats.eos[r], 1.0 / vr, T), P, tol * P + solid_eps)
          << "cell " << i << " material " << r;
      const double c2 = eos_sound_speed_squared(mats.eos[r], 1.0 / vr, T);
      EXPECT_NEAR(c(r, i, 1, 1), std::sqrt(c2), tol * std::sqrt(c2)) << "cell " << i << " material " << r;
      EXPECT_NEAR(kappa(r, i, 1, 1), vr / c2, tol * vr / c2);
      // (E14): theta = rhoB v with the bulk density held, m / TMV^n.
      EXPECT_NEAR(theta(r, i, 1, 1), rh(r, i, 1, 1) * V * vr / start_volume, 1e-13);
      sum += theta(r, i, 1, 1);
      sk += theta(r, i, 1, 1) * kappa(r, i, 1, 1);
      volume += rh(r, i, 1, 1) * V * vr;
    }
    // Converged: |sum theta - 1| < 100 ulps (equilibration_tolerance).
    EXPECT_NEAR(sum, 1.0, 1e-13) << "cell " << i;
    EXPECT_NEAR(sum_kappa(i, 1, 1), sk, 1e-13 * sk);
    EXPECT_NEAR(tmv(i, 1, 1), volume, 1e-13 * volume);
  }
}

// A periodic row of 16 cells (h = 0.1 m, two ghost layers) with one material's field q
// and its face velocities U, all zero.
struct AdvectionRow {
  Patch p;
  Field4 q;
  VectorField4 U;
  AdvectionRow() {
    Grid g;
    g.cells = {16, 1, 1};
    g.spacing = {0.1, 0.1, 0.1};
    p = whole_grid_patch(g, 2);
    q = make_field("q", p, Location::cell, 1);
    const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
    for (int d = 0; d < 3; ++d) U[d] = make_field("U", p, faces[d], 1);
  }
  // The periodic image (0..15) of local cell index i.
  static int owned_image(int i) { return ((i - 2) % 16 + 16) % 16; }
  // A rough profile over the owned images: a ramp with a step of 3 on cells 5-8.
  static double rough(int gi) { return 1.0 + (gi > 4 && gi < 9 ? 3.0 : 0.0) + 0.1 * gi; }
  GradientField gradient() const {
    return {make_field("gx", p, Location::cell), make_field("gy", p, Location::cell),
            make_field("gz", p, Location::cell)};
  }
};

// Uniform flow of a uniform field: no change in the interior, first and second order;
// and on a periodic row the changes sum to zero (conservation) for any field.
TEST(Advection, UniformFieldIsUnchangedAndTotalsAreConserved) {
  AdvectionRow row;
  const Patch& p = row.p;
  const int nx = p.extent(Location::cell, 0);
  Field4 q = row.q;
  VectorField4 U = row.U;
  Kokkos::deep_copy(U[0], 50.0);
  const double dt = 1e-4;
  const Kokkos::Array<double, 3> h{0.1, 0.1, 0.1};
  ConstVectorField4 Uc{U[0], U[1], U[2]};
  for (bool second : {false, true})
    for (int shape = 0; shape < 2; ++shape) {
      auto qh = Kokkos::create_mirror_view(q);
      for (int i = 0; i < nx; ++i)
        for (int j = 0; j < 5; ++j)
          for (int k = 0; k < 5; ++k)
            qh(0, i, j, k) = shape == 0 ? 2.5 : AdvectionRow::rough(AdvectionRow::owned_image(i));
      Kokkos::deep_copy(q, qh);
      GradientField grad = row.gradient();
      if (second) limited_gradient(p.ghosted_cells(1), h, q, 0, ConstField4(), GradientField(), grad);
      Field4 change = make_field("chg", p, Location::cell, 1);
      advection_change(p.owned_cells(), h, dt, Uc, 0, q, ConstField4(), second, grad, GradientField(),
                       change);
      auto ch = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), change);
      double sum = 0, scale = 0;
      for (int i = 2; i < 18; ++i) {
        sum += ch(0, i, 2, 2);
        scale += std::abs(ch(0, i, 2, 2));
        if (shape == 0) EXPECT_NEAR(ch(0, i, 2, 2), 0.0, 1e-15);
      }
      EXPECT_NEAR(sum, 0.0, 1e-14 * (scale + 1));
    }
}

// face_fluxes gives each face once, and advection_change is their difference: on a
// periodic row with a rough field and face velocities of both signs, what enters a cell
// through its x faces minus what leaves is V Adv[q] of the cell, first and second order
// (to round-off of the terms), and the fluxes are not all zero.
TEST(Advection, FaceFluxesAddUpToTheChange) {
  AdvectionRow row;
  const Patch& p = row.p;
  const int nx = p.extent(Location::cell, 0);
  Field4 q = row.q;
  VectorField4 U = row.U;
  auto qh = Kokkos::create_mirror_view(q);
  auto uh = Kokkos::create_mirror_view(U[0]);
  for (int i = 0; i < nx + 1; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const int gi = AdvectionRow::owned_image(i);
        uh(0, i, j, k) = 80.0 * std::sin(2 * M_PI * gi / 16.0) + 10.0;
        if (i < nx) qh(0, i, j, k) = AdvectionRow::rough(gi);
      }
  Kokkos::deep_copy(q, qh);
  Kokkos::deep_copy(U[0], uh);
  const double dt = 2e-4;
  const Kokkos::Array<double, 3> h{0.1, 0.1, 0.1};
  const double V = 1e-3;
  const ConstVectorField4 Uc{U[0], U[1], U[2]};
  for (bool second : {false, true}) {
    GradientField grad = row.gradient();
    if (second) limited_gradient(p.ghosted_cells(1), h, q, 0, ConstField4(), GradientField(), grad);
    Field4 change = make_field("chg", p, Location::cell, 1);
    advection_change(p.owned_cells(), h, dt, Uc, 0, q, ConstField4(), second, grad, GradientField(), change);
    const FaceFluxes flux = make_face_fluxes("flux", p);
    face_fluxes(p.owned_cells(), h, dt, Uc, 0, q, ConstField4(), second, grad, GradientField(), flux);
    auto ch = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), change);
    auto fh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flux[0]);
    double moved = 0;
    for (int i = 2; i < 18; ++i) {
      const double net_in = fh(i, 2, 2) - fh(i + 1, 2, 2);
      EXPECT_NEAR(net_in, V * ch(0, i, 2, 2), 1e-15 * (std::abs(fh(i, 2, 2)) + std::abs(fh(i + 1, 2, 2))));
      moved += std::abs(fh(i, 2, 2));
    }
    EXPECT_GT(moved, 0.0);  // something moved
  }
}

namespace {
// A field of `materials` slots at `where` on patch p, every entry uniform in [lo, hi).
Field4 random_values(const Patch& p, Location where, int materials, double lo, double hi, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(lo, hi);
  const Field4 f = make_field("f", p, where, materials);
  auto fh = Kokkos::create_mirror_view(f);
  for (size_t n = 0; n < fh.size(); ++n) fh.data()[n] = value(rng);
  Kokkos::deep_copy(f, fh);
  return f;
}

// A 6 x 7 x 9 patch of unequal cell sizes with random cell values around 1 (q, its
// mass), random gradients and face velocities of both signs in every direction.
struct RandomBox {
  Patch p;
  Field4 q, mass;
  VectorField4 U;
  GradientField grad, mass_grad;
  Kokkos::Array<double, 3> h{1e-3, 2e-3, 1.5e-3};
  double dt = 2e-6;

  RandomBox() {
    Grid g;
    g.cells = {6, 7, 9};
    g.spacing = {h[0], h[1], h[2]};
    p = whole_grid_patch(g, 2);
    std::mt19937 rng(11);
    auto random_field = [&](Location where, double lo, double hi) { return random_values(p, where, 1, lo, hi, rng); };
    q = random_field(Location::cell, 0.5, 1.5);
    mass = random_field(Location::cell, 0.5, 1.5);
    const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
    for (int d = 0; d < 3; ++d) {
      U[d] = random_field(faces[d], -40.0, 60.0);
      // Gradients up to 100 /m: slab values within 10% of the cell's.
      auto slot = [](const Field4& f) { return Kokkos::subview(f, 0, Kokkos::ALL, Kokkos::ALL, Kokkos::ALL); };
      grad[d] = slot(random_field(Location::cell, -100.0, 100.0));
      mass_grad[d] = slot(random_field(Location::cell, -100.0, 100.0));
    }
  }
  ConstVectorField4 velocities() const { return {U[0], U[1], U[2]}; }
};
}  // namespace

// The face exchange (E19) on the x faces of the owned cells, for 1 and 2 materials, on
// a patch small enough that a copy of its faces runs on the calling thread
// (for_each_index_light) and on one large enough to run in parallel. One material: the
// velocity is copied, and nothing outside the faces is written. Two: the exchange
// conserves each face's momentum sum_r rho_r U_r (rho_r = thetaf_r / vh_r, the face
// densities the solve is symmetric in) and brings the two velocities closer without
// reversing their order. 1e-12: the conserved sum is formed from four products and a
// 2 x 2 solve of values around 1, a few ulps each; a wrong density or coefficient
// misses by the exchange's size, 1e-2 here.
TEST(FaceExchange, CopiesOneMaterialAndConservesMomentumOfTwo) {
  for (int n : {12, 36}) {
    Grid g;
    g.cells = {n, n, n};
    g.spacing = {1e-3, 1e-3, 1e-3};
    const Patch p = whole_grid_patch(g, 2);
    IndexBox faces = p.owned_cells();
    faces.hi[0] += 1;
    EXPECT_EQ(faces.size() < detail::light_serial_indices, n == 12);
    std::mt19937 rng(5);
    for (int mats : {1, 2}) {
      MaterialTable t;
      t.count = mats;
      t.momentum_exchange[1] = t.momentum_exchange[max_materials] = 1e5;  // K_01 = K_10, kg/m^3/s
      const Field4 theta = random_values(p, Location::cell, mats, 0.2, 0.8, rng),
                   v = random_values(p, Location::cell, mats, 0.5, 2.0, rng),  // m^3/kg
          face_vel = random_values(p, Location::x_face, mats, -3.0, 3.0, rng),
                   out = make_field("U_me", p, Location::x_face, mats);
      Kokkos::deep_copy(out, -1e30);
      const double dt = 1e-7;
      face_exchange(faces, 0, dt, t, theta, v, face_vel, out);
      const auto th = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), theta);
      const auto vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
      const auto u = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), face_vel);
      const auto um = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
      long wrong = 0, untouched = 0, outside = 0;
      double worst = 0;
      for (int i = 0; i < int(u.extent(1)); ++i)
        for (int j = 0; j < int(u.extent(2)); ++j)
          for (int k = 0; k < int(u.extent(3)); ++k) {
            if (!faces.contains(i, j, k)) {
              ++outside;
              for (int r = 0; r < mats; ++r) untouched += um(r, i, j, k) == -1e30;
              continue;
            }
            if (mats == 1) {
              wrong += um(0, i, j, k) != u(0, i, j, k);
              continue;
            }
            double rho[2], before = 0, after = 0, scale = 0;
            for (int r = 0; r < 2; ++r) {
              const double vl = vh(r, i - 1, j, k), vr = vh(r, i, j, k);
              rho[r] = 0.5 * (th(r, i - 1, j, k) + th(r, i, j, k)) / (2.0 * vl * vr / (vl + vr));
              before += rho[r] * u(r, i, j, k);
              after += rho[r] * um(r, i, j, k);
              scale += rho[r] * std::abs(u(r, i, j, k));
            }
            worst = std::max(worst, std::abs(after - before) / scale);
            const double gap = u(0, i, j, k) - u(1, i, j, k), gap_me = um(0, i, j, k) - um(1, i, j, k);
            wrong += !(std::abs(gap_me) < std::abs(gap) && gap_me * gap >= 0);
          }
      EXPECT_EQ(wrong, 0) << mats << " materials, " << n << "^3 cells";
      EXPECT_EQ(untouched, outside * mats) << mats << " materials, " << n << "^3 cells";
      EXPECT_LT(worst, 1e-12) << n << "^3 cells";
    }
  }
}

// The face velocity (E18) on the faces of each direction, for 3 materials of which the
// second is rigid (no pressure or gravity term), against the formula evaluated here; and
// for 4 materials in a box of more faces than detail::face_velocity_split_faces, which
// face_velocity takes one material per pass. A wrong material slot, cell offset or term
// misses by the term's size: the states are random, the pressure term dt vh dp/h is
// about 1 m/s against velocities up to 3 m/s, and even the gravity term (1e-6 m/s) is
// over 1e6 times the tolerance. 1e-13: both sides form the same few products and
// quotients of values of order 1, a few ulps apart at most if the compiler orders them
// differently. Faces outside the box are not written.
TEST(FaceVelocity, MatchesTheFormulaForEveryMaterialAndDirection) {
  const auto check = [](std::array<int, 3> cells, int mats) {
    Grid g;
    g.cells = cells;
    g.spacing = {1e-3, 2e-3, 1.5e-3};
    const Patch p = whole_grid_patch(g, 2);
    std::mt19937 rng(17);
    MaterialTable t;
    t.count = mats;
    t.kind[1] = rigid_material;
    const Field4 rho = random_values(p, Location::cell, mats, 0.5, 2.0, rng),  // kg/m^3
                 v = random_values(p, Location::cell, mats, 0.5, 2.0, rng),    // m^3/kg
                 press_slot = random_values(p, Location::cell, 1, 9e4, 1.1e5, rng);  // Pa
    const Field3 press = Kokkos::subview(press_slot, 0, Kokkos::ALL, Kokkos::ALL, Kokkos::ALL);
    const auto rh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rho);
    const auto vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    const auto ph = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), press);
    const Location where[3] = {Location::x_face, Location::y_face, Location::z_face};
    const double dt = 1e-7, gravity = -9.81;
    for (int d = 0; d < 3; ++d) {
      const Field4 u = random_values(p, Location::cell, mats, -3.0, 3.0, rng);  // m/s
      const Field4 out = make_field("U", p, where[d], mats);
      Kokkos::deep_copy(out, -1e30);
      IndexBox faces = p.owned_cells();
      faces.hi[d] += 1;
      face_velocity(faces, d, g.spacing[d], dt, gravity, t, press, rho, v, u, out);
      const auto uh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), u);
      const auto oh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
      long wrong = 0, written_outside = 0;
      for (int m = 0; m < mats; ++m)
        for (int i = 0; i < int(oh.extent(1)); ++i)
          for (int j = 0; j < int(oh.extent(2)); ++j)
            for (int k = 0; k < int(oh.extent(3)); ++k) {
              if (!faces.contains(i, j, k)) {
                written_outside += oh(m, i, j, k) != -1e30;
                continue;
              }
              const int il = i - (d == 0), jl = j - (d == 1), kl = k - (d == 2);
              const double rl = rh(m, il, jl, kl), rr = rh(m, i, j, k);
              const double vl = vh(m, il, jl, kl), vr = vh(m, i, j, k);
              const double u_avg = (rl * uh(m, il, jl, kl) + rr * uh(m, i, j, k)) / (rl + rr);
              const double push = -dt * (2.0 * vl * vr / (vl + vr)) * (ph(i, j, k) - ph(il, jl, kl)) /
                                      g.spacing[d] + dt * gravity;
              const double expected = m == 1 ? u_avg : u_avg + push;
              wrong += !(std::abs(oh(m, i, j, k) - expected) <= 1e-13 * (std::abs(u_avg) + std::abs(push)));
            }
      EXPECT_EQ(wrong, 0) << mats << " materials, faces normal to " << d << ", " << faces.size() << " faces";
      EXPECT_EQ(written_outside, 0) << mats << " materials, faces normal to " << d;
    }
  };
  check({5, 6, 7}, 3);
  // 40 x 48 x 70 cells: 136,320 to 137,760 faces in each direction.
  static_assert(40L * 48 * 70 >= detail::face_velocity_split_faces, "a box that takes one material per pass");
  static_assert(detail::face_velocity_split_materials <= 4, "a box that takes one material per pass");
  check({40, 48, 70}, 4);
}

// The Lagrangian momentum and energy (E29) and a reaction's products (E30) run the
// materials in one pass in small boxes and one material per pass in large ones
// (lagrangian_split_cells): both must give every material of every owned cell its
// formula and leave the other cells alone. The arithmetic is a product and a sum per
// value (1e-15 relative: an ulp of either term, should the compiler fuse them); a wrong
// material or cell is off by the random values' whole size.
TEST(LagrangianValues, EveryMaterialAndCellInOnePassAndPerMaterial) {
  const auto check = [](std::array<int, 3> cells, int mats) {
    Grid g;
    g.cells = cells;
    const Patch p = whole_grid_patch(g, 2);
    std::mt19937 rng(29);
    MaterialTable t;
    t.count = mats;
    for (int m = 0; m < mats; ++m) t.eos[m].cv = 700.0 + 10 * m;
    const Field4 mass = random_values(p, Location::cell, mats, 1e-9, 2e-9, rng),  // kg
        temp = random_values(p, Location::cell, mats, 300, 900, rng),                // K
        work = random_values(p, Location::cell, mats, -1e-4, 1e-4, rng);             // J
    VectorField4 u, q, mom;
    for (int d = 0; d < 3; ++d) {
      u[d] = random_values(p, Location::cell, mats, -10, 10, rng);       // m/s
      q[d] = random_values(p, Location::cell, mats, -1e-9, 1e-9, rng);   // kg m/s
      mom[d] = make_field("PL", p, Location::cell, mats);
      Kokkos::deep_copy(mom[d], -1e30);
    }
    const Field4 eng = make_field("EL", p, Location::cell, mats);
    Kokkos::deep_copy(eng, -1e30);
    const IndexBox owned = p.owned_cells();
    lagrangian_momentum_energy(owned, t, mass, {u[0], u[1], u[2]}, temp, {q[0], q[1], q[2]}, work, mom, eng);
    auto host = [](const Field4& f) { return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f); };
    const auto mh = host(mass), th = host(temp), wh = host(work), eh = host(eng);
    long wrong = 0, written_outside = 0;
    for (int d = 0; d < 3; ++d) {
      const auto uh = host(u[d]), qh = host(q[d]), ph = host(mom[d]);
      for (int m = 0; m < mats; ++m)
        for (int i = 0; i < int(ph.extent(1)); ++i)
          for (int j = 0; j < int(ph.extent(2)); ++j)
            for (int k = 0; k < int(ph.extent(3)); ++k) {
              if (!owned.contains(i, j, k)) {
                written_outside += (ph(m, i, j, k) != -1e30) + (d == 0 && eh(m, i, j, k) != -1e30);
                continue;
              }
              const double p_lag = mh(m, i, j, k) * uh(m, i, j, k);
              wrong += !(std::abs(ph(m, i, j, k) - (p_lag + qh(m, i, j, k))) <=
                         1e-15 * (std::abs(p_lag) + std::abs(qh(m, i, j, k))));
              if (d != 0) continue;
              const double e_lag = mh(m, i, j, k) * t.eos[m].cv * th(m, i, j, k);
              wrong += !(std::abs(eh(m, i, j, k) - (e_lag + wh(m, i, j, k))) <=
                         1e-15 * (std::abs(e_lag) + std::abs(wh(m, i, j, k))));
            }
    }
    EXPECT_EQ(wrong, 0) << mats << " materials, " << owned.size() << " cells";
    EXPECT_EQ(written_outside, 0) << mats << " materials, " << owned.size() << " cells";

    // A reaction's products over the whole box and over boxes of a quarter of it in x
    // and y (small enough for one pass): the same values.
    const Field4 dm = random_values(p, Location::cell, mats, 0.0, 1e-10, rng),
                 de = random_values(p, Location::cell, mats, 0.0, 1e-4, rng);
    struct State {
      Field4 mass, eng, mixed;
      VectorField4 mom;
    };
    auto state = [&]() {
      State s{make_field("mL", p, Location::cell, mats), make_field("EL", p, Location::cell, mats),
              make_field("Tmix", p, Location::cell, mats), {}};
      Kokkos::deep_copy(s.mass, mass);
      Kokkos::deep_copy(s.eng, eng);
      for (int d = 0; d < 3; ++d) {
        s.mom[d] = make_field("PL", p, Location::cell, mats);
        Kokkos::deep_copy(s.mom[d], mom[d]);
      }
      return s;
    };
    auto products = [&](const IndexBox& box, const State& s) {
      add_product_sources(box, t, dm, {q[0], q[1], q[2]}, de, {u[0], u[1], u[2]}, temp, s.mass,
                          {s.mom[0], s.mom[1], s.mom[2]}, s.eng, s.mixed);
    };
    const State whole = state(), parts = state();
    products(owned, whole);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        IndexBox part = owned;
        part.lo[0] = owned.lo[0] + a * owned.extent(0) / 4;
        part.hi[0] = owned.lo[0] + (a + 1) * owned.extent(0) / 4;
        part.lo[1] = owned.lo[1] + b * owned.extent(1) / 4;
        part.hi[1] = owned.lo[1] + (b + 1) * owned.extent(1) / 4;
        ASSERT_LT(part.size(), detail::lagrangian_split_cells);
        products(part, parts);
      }
    auto differ = [&](const Field4& a, const Field4& b) {
      const auto ah = host(a), bh = host(b);
      long n = 0;
      for (size_t e = 0; e < ah.size(); ++e)
        n += !(std::abs(ah.data()[e] - bh.data()[e]) <= 1e-15 * std::abs(bh.data()[e]));
      return n;
    };
    long differing = differ(whole.mass, parts.mass) + differ(whole.eng, parts.eng) + differ(whole.mixed, parts.mixed);
    for (int d = 0; d < 3; ++d) differing += differ(whole.mom[d], parts.mom[d]);
    EXPECT_EQ(differing, 0) << mats << " materials, " << owned.size() << " cells";
  };
  check({5, 6, 7}, 3);
  static_assert(32L * 32 * 33 >= detail::lagrangian_split_cells, "a box that takes one material per pass");
  check({32, 32, 33}, 3);
}

// First order, advection_change makes the change in one pass, each cell computing its
// six faces' fluxes itself: it must equal flux_difference of face_fluxes, for cell
// totals and for compatible (mass-weighted) values. The two differ only in rounding:
// the one pass may fuse a flux's last product into the cell's sum (an FMA, half an ulp
// of that flux) and adds six terms as the other does (an ulp of the partial sums at
// most each), so |a - b| <= 8 eps sum|flux| / V; 2e-15 is 9 eps. A wrong face, sign or
// donor changes a cell by a whole flux.
TEST(Advection, FirstOrderInOnePassMatchesTheStoredFluxes) {
  const RandomBox box;
  const Patch& p = box.p;
  const Kokkos::Array<double, 3> h = box.h;
  const ConstVectorField4 U = box.velocities();
  for (const ConstField4& m : {ConstField4(), ConstField4(box.mass)}) {
    const Field4 one_pass = make_field("a", p, Location::cell, 1), two_pass = make_field("b", p, Location::cell, 1);
    advection_change(p.owned_cells(), h, box.dt, U, 0, box.q, m, false, GradientField(), GradientField(), one_pass);
    const FaceFluxes flux = make_face_fluxes("flux", p);
    face_fluxes(p.owned_cells(), h, box.dt, U, 0, box.q, m, false, GradientField(), GradientField(), flux);
    flux_difference(p.owned_cells(), 1.0 / (h[0] * h[1] * h[2]), flux, 0, two_pass);
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), one_pass);
    auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), two_pass);
    auto fx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flux[0]);
    auto fy = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flux[1]);
    auto fz = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flux[2]);
    const IndexBox cells = p.owned_cells();
    const double V = h[0] * h[1] * h[2];
    long nonzero = 0;
    for (long i = cells.lo[0]; i < cells.hi[0]; ++i)
      for (long j = cells.lo[1]; j < cells.hi[1]; ++j)
        for (long k = cells.lo[2]; k < cells.hi[2]; ++k) {
          const double scale = std::abs(fx(i, j, k)) + std::abs(fx(i + 1, j, k)) + std::abs(fy(i, j, k)) +
                               std::abs(fy(i, j + 1, k)) + std::abs(fz(i, j, k)) + std::abs(fz(i, j, k + 1));
          EXPECT_NEAR(a(0, i, j, k), b(0, i, j, k), 2e-15 * scale / V) << "cell " << i << " " << j << " " << k;
          nonzero += a(0, i, j, k) != 0;
        }
    EXPECT_EQ(nonzero, cells.size());  // random values and speeds: every cell changes
  }
}

// Second order, against (E39), (E42) and (E43) written out here cell by cell: each
// face's flux is its donor's slab (the cell the velocity leaves), its value at the
// slab's centroid r, q_c + G . r (or, compatible, (m_c + G_m . r) q_c + m_c G . r),
// times the slab's volume. advection_change and flux_difference of face_fluxes must
// both give it, and equal each other bit for bit (the same fluxes, the same sums).
// Each face is written by one of its cells only (donor_face_fluxes): every seventh
// face velocity here is exactly 0, a face without a donor, and the face arrays start
// as NaN, so that a face no cell writes spoils its cells. The reference associates
// differently: each of the 12 terms carries at most ~10 roundings either way and the
// sum 12 more, so 1e-14 (45 eps) of the sum of |terms| / V bounds the difference; a
// wrong centroid, donor or face is a whole term.
TEST(Advection, SecondOrderMatchesTheSlabFormula) {
  const RandomBox box;
  const Patch& p = box.p;
  const Kokkos::Array<double, 3> h = box.h;
  const double dt = box.dt, V = h[0] * h[1] * h[2];
  const double area[3] = {h[1] * h[2], h[0] * h[2], h[0] * h[1]};
  auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.q);
  auto mh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.mass);
  std::vector<decltype(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.U[0]))> uh;
  std::vector<decltype(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.grad[0]))> gh, gmh;
  VectorField4 Uz;  // box.U with every seventh face velocity 0
  long zero_faces = 0;
  for (int d = 0; d < 3; ++d) {
    Uz[d] = Field4("U", box.U[d].extent(0), box.U[d].extent(1), box.U[d].extent(2), box.U[d].extent(3));
    uh.push_back(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.U[d]));
    for (size_t n = 0; n < uh[d].size(); n += 7, ++zero_faces) uh[d].data()[n] = 0.0;
    Kokkos::deep_copy(Uz[d], uh[d]);
    gh.push_back(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.grad[d]));
    gmh.push_back(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.mass_grad[d]));
  }
  // The outflux distances of cell c (E39): d[2 dir] low face, d[2 dir + 1] high face.
  auto distances = [&](const long c[3], double d[6]) {
    for (int dir = 0; dir < 3; ++dir) {
      long hi[3] = {c[0], c[1], c[2]};
      hi[dir] += 1;
      const double lo_u = uh[dir](0, c[0], c[1], c[2]), hi_u = uh[dir](0, hi[0], hi[1], hi[2]);
      d[2 * dir] = std::max(0.0, -lo_u * dt);
      d[2 * dir + 1] = std::max(0.0, hi_u * dt);
    }
  };
  // What cell c sends out through its face f (E42, E43).
  auto outflux = [&](const long c[3], int f, bool compatible) {
    double d[6];
    distances(c, d);
    const int dir = f / 2;
    double r[3];
    for (int e = 0; e < 3; ++e) r[e] = 0.5 * (d[2 * e] - d[2 * e + 1]);
    r[dir] = f % 2 ? 0.5 * (h[dir] - d[f]) : 0.5 * (d[f] - h[dir]);
    double gq = 0, gm = 0;
    for (int e = 0; e < 3; ++e) {
      gq += gh[e](c[0], c[1], c[2]) * r[e];
      gm += gmh[e](c[0], c[1], c[2]) * r[e];
    }
    const double qc = qh(0, c[0], c[1], c[2]), mc = mh(0, c[0], c[1], c[2]);
    const double slab = compatible ? (mc + gm) * qc + mc * gq : qc + gq;
    return slab * d[f] * area[dir];
  };
  const ConstVectorField4 U{Uz[0], Uz[1], Uz[2]};
  EXPECT_GT(zero_faces, 100);
  const IndexBox cells = p.owned_cells();
  auto nan_fluxes = [&](const char* name) {
    const FaceFluxes flux = make_face_fluxes(name, p);
    for (int d = 0; d < 3; ++d) Kokkos::deep_copy(flux[d], std::numeric_limits<double>::quiet_NaN());
    return flux;
  };
  for (bool compatible : {false, true}) {
    const ConstField4 m = compatible ? ConstField4(box.mass) : ConstField4();
    const Field4 change = make_field("a", p, Location::cell, 1), two_pass = make_field("b", p, Location::cell, 1);
    advection_change(cells, h, dt, U, 0, box.q, m, true, box.grad, box.mass_grad, change, nan_fluxes("scratch"));
    const FaceFluxes flux = nan_fluxes("flux");
    face_fluxes(cells, h, dt, U, 0, box.q, m, true, box.grad, box.mass_grad, flux);
    flux_difference(cells, 1.0 / V, flux, 0, two_pass);
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), change);
    auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), two_pass);
    for (long i = cells.lo[0]; i < cells.hi[0]; ++i)
      for (long j = cells.lo[1]; j < cells.hi[1]; ++j)
        for (long k = cells.lo[2]; k < cells.hi[2]; ++k) {
          const long c[3] = {i, j, k};
          double net = 0, scale = 0;
          for (int f = 0; f < 6; ++f) {
            long nb[3] = {i, j, k};
            nb[f / 2] += f % 2 ? 1 : -1;
            const double in = outflux(nb, f ^ 1, compatible), out = outflux(c, f, compatible);
            net += in - out;
            scale += std::abs(in) + std::abs(out);
          }
          EXPECT_NEAR(a(0, i, j, k), net / V, 1e-14 * scale / V) << "cell " << i << " " << j << " " << k;
          EXPECT_EQ(a(0, i, j, k), b(0, i, j, k)) << "cell " << i << " " << j << " " << k;
          EXPECT_GT(scale, 0.0);
        }
  }
}

// limited_advection_change must give what limited_gradient and then advection_change
// give, both in its one pass (the gradient limited where the outfluxes are made; forced
// here by inline_from = 0) and in its two passes (small boxes), for cell totals and
// for compatible values: bit for bit without fused multiply-adds (MPMICE_REPRODUCIBLE),
// as the same operations in the same order. With them the compiler may fuse the
// gradient's products differently in the two loops, moving a slab value by a few ulps:
// 1e-13 of the largest change (which is about one flux over V; q varies by 100% from
// cell to cell, so the limiter acts) bounds that, and a wrong gradient, limiter or slab
// misses by a sizeable part of a flux.
TEST(Advection, GradientLimitedInTheOutfluxPassMatchesTheStoredOne) {
  const RandomBox box;
  const Patch& p = box.p;
  const IndexBox cells = p.owned_cells();
  const ConstVectorField4 U = box.velocities();
  for (const ConstField4& m : {ConstField4(), ConstField4(box.mass)}) {
    GradientField grad;
    for (int d = 0; d < 3; ++d) grad[d] = make_field("g", p, Location::cell);
    const Field4 stored = make_field("a", p, Location::cell, 1);
    limited_gradient(p.ghosted_cells(1), box.h, box.q, 0, m, box.mass_grad, grad);
    advection_change(cells, box.h, box.dt, U, 0, box.q, m, true, grad, box.mass_grad, stored);
    const auto expected = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), stored);
    double largest = 0;
    long phi_below_one = 0;  // the limiter acted (its gradient differs from the central one)
    const auto gh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), grad[0]);
    const auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), box.q);
    for (long i = cells.lo[0]; i < cells.hi[0]; ++i)
      for (long j = cells.lo[1]; j < cells.hi[1]; ++j)
        for (long k = cells.lo[2]; k < cells.hi[2]; ++k) {
          largest = std::max(largest, std::abs(expected(0, i, j, k)));
          phi_below_one += gh(i, j, k) != (qh(0, i + 1, j, k) - qh(0, i - 1, j, k)) / (2.0 * box.h[0]);
        }
    EXPECT_GT(phi_below_one, cells.size() / 2);
    for (long inline_from : {0L, cells.size() + 1}) {
      const Field4 change = make_field("b", p, Location::cell, 1);
      limited_advection_change(cells, box.h, box.dt, U, 0, box.q, m, box.mass_grad, change, FaceFluxes(),
                               GradientField(), inline_from);
      const auto got = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), change);
      long differing = 0;
      double worst = 0;
      for (long i = cells.lo[0]; i < cells.hi[0]; ++i)
        for (long j = cells.lo[1]; j < cells.hi[1]; ++j)
          for (long k = cells.lo[2]; k < cells.hi[2]; ++k) {
            differing += got(0, i, j, k) != expected(0, i, j, k);
            worst = std::max(worst, std::abs(got(0, i, j, k) - expected(0, i, j, k)));
          }
      const std::string what = std::string(m.data() ? "compatible" : "totals") + ", inline_from " +
                               std::to_string(inline_from);
#if defined(MPMICE_REPRODUCIBLE)
      EXPECT_EQ(differing, 0) << what << ", largest difference " << worst;
#else
      EXPECT_LE(worst, 1e-13 * largest) << what << ", " << differing << " cells differ";
#endif
      EXPECT_GT(largest, 0.0) << what;
    }
  }
}

namespace {
// A row of 8 cells of 1 cm with one ghost layer: the pressure work tests fill the
// ghosts with the periodic images themselves.
Patch row_of_eight_cells() {
  Grid g;
  g.cells = {8, 1, 1};
  g.spacing = {0.01, 0.01, 0.01};
  return whole_grid_patch(g, 1);
}
}  // namespace

// pressure_work_heat's flux form telescopes: on a periodic row of one gas (no solid) the
// heats add up to minus what (E23) charged minus the kinetic energy the step made, and the
// cells' c_v T rises by exactly their heat. A face flux booked on the wrong face, or with
// the wrong sign, leaves the sum of -p^f Phi^f nonzero and fails this.
TEST(PressureWorkHeat, FluxFormTelescopes) {
  const Patch p = row_of_eight_cells();
  MaterialTable mats;
  mats.count = 1;
  mats.eos[0] = Eos{EosType::ideal_gas, 1.4, 716.0};
  const int nx = p.extent(Location::cell, 0);
  const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
  PressureWorkInputs in;
  Field3 pf[3], phi[3];
  for (int d = 0; d < 3; ++d) {
    pf[d] = make_field("pf", p, faces[d]);
    phi[d] = make_field("phi", p, faces[d]);
    in.press_face[d] = pf[d];
    in.face_flux[d] = phi[d];
  }
  auto cell4 = [&](const char* name, double value) {
    Field4 f = make_field(name, p, Location::cell, 1);
    Kokkos::deep_copy(f, value);
    return f;
  };
  Field4 work = cell4("w", 0.0), mass = cell4("m", 1e-6), temp = cell4("t", 300.0), tdot = cell4("td", 0.0);
  VectorField4 mom_L, mom_src, vel;
  for (int d = 0; d < 3; ++d) {
    mom_L[d] = cell4("pl", 0.0);
    mom_src[d] = cell4("q", 0.0);
    vel[d] = cell4("u", 0.0);
  }
  auto pfh = Kokkos::create_mirror_view(pf[0]);
  auto phih = Kokkos::create_mirror_view(phi[0]);
  auto wh = Kokkos::create_mirror_view(work);
  auto plh = Kokkos::create_mirror_view(mom_L[0]);
  auto qh = Kokkos::create_mirror_view(mom_src[0]);
  auto uh = Kokkos::create_mirror_view(vel[0]);
  for (int i = 0; i < nx + 1; ++i) {
    const int gi = ((i - 1) % 8 + 8) % 8;  // faces and cells: periodic images
    pfh(i, 1, 1) = 1e5 * (1.0 + 0.3 * gi - 0.05 * gi * gi);
    phih(i, 1, 1) = 1e-9 * (gi % 3 - 1.0) + 2e-10 * gi;
    if (i < nx) {
      wh(0, i, 1, 1) = 1e-4 * (gi - 3.5);
      plh(0, i, 1, 1) = 1e-6 * (0.5 + 0.1 * gi);  // before the kick: m u^n
      qh(0, i, 1, 1) = 1e-8 * (gi - 4.0);
      plh(0, i, 1, 1) += qh(0, i, 1, 1);
      uh(0, i, 1, 1) = plh(0, i, 1, 1) / 1e-6;
    }
  }
  Kokkos::deep_copy(pf[0], pfh);
  Kokkos::deep_copy(phi[0], phih);
  Kokkos::deep_copy(work, wh);
  Kokkos::deep_copy(mom_L[0], plh);
  Kokkos::deep_copy(mom_src[0], qh);
  Kokkos::deep_copy(vel[0], uh);
  Field3 no_solid[3];
  for (int d = 0; d < 3; ++d) {
    no_solid[d] = make_field("phi_s", p, faces[d]);
    in.solid_face_flux[d] = no_solid[d];
  }
  in.vol_frac = cell4("th", 1.0);
  in.work = work;
  in.kappa = cell4("k", 1e-5);
  Field3 sum_kappa = make_field("sk", p, Location::cell);
  Kokkos::deep_copy(sum_kappa, 1e-5);
  in.sum_kappa = sum_kappa;
  in.rho = cell4("rho", 1.0);
  in.mass_L = mass;
  in.mom_L = ConstVectorField4{mom_L[0], mom_L[1], mom_L[2]};
  in.mom_source = ConstVectorField4{mom_src[0], mom_src[1], mom_src[2]};
  in.vel_me = ConstVectorField4{vel[0], vel[1], vel[2]};
  const double total = pressure_work_heat(p.owned_cells(), {0.01, 0.01, 0.01}, 1e-6, {0, 0, 0}, mats, in, temp, tdot);
  auto th = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), temp);
  double charged = 0, kinetic = 0, heated = 0, scale = 0;
  for (int i = 1; i < 9; ++i) {
    charged += wh(0, i, 1, 1);
    const double before = plh(0, i, 1, 1) - qh(0, i, 1, 1);
    kinetic += 0.5 * 1e-6 * uh(0, i, 1, 1) * uh(0, i, 1, 1) - 0.5 * before * before / 1e-6;
    heated += 1e-6 * 716.0 * (th(0, i, 1, 1) - 300.0);
    scale += std::abs(pfh(i, 1, 1) * phih(i, 1, 1)) + std::abs(wh(0, i, 1, 1));
  }
  // Round-off of the sums only: 1e-12 of the largest terms.
  EXPECT_NEAR(total, -charged - kinetic, 1e-12 * scale);
  EXPECT_NEAR(heated, total, 1e-12 * scale);
  EXPECT_GT(std::abs(total), 1e-6 * scale);  // the case is not trivial
}

// The solids' push in flux form telescopes: on a periodic row of a gas (material 0) and
// a solid (material 1) whose volume flows through the faces, with nothing else going on,
// each cell's fluids gain or lose s^f p^f Phi_s^f through its faces, and the heats add
// up to zero over the row while single cells' are not. A share taken from one cell only
// instead of the face's two (or a face booked with the wrong sign) fails the sum.
TEST(PressureWorkHeat, SolidPushTelescopes) {
  const Patch p = row_of_eight_cells();
  MaterialTable mats;
  mats.count = 2;
  mats.eos[0] = Eos{EosType::ideal_gas, 1.4, 716.0};
  mats.eos[1] = Eos{EosType::ideal_gas, 1.4, 996.0};  // the law is not read here
  mats.kind[1] = mpm_material;
  const int nx = p.extent(Location::cell, 0);
  const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
  PressureWorkInputs in;
  Field3 pf[3], phi[3], phi_s[3];
  for (int d = 0; d < 3; ++d) {
    pf[d] = make_field("pf", p, faces[d]);
    phi[d] = make_field("phi", p, faces[d]);
    phi_s[d] = make_field("phi_s", p, faces[d]);
    in.press_face[d] = pf[d];
    in.face_flux[d] = phi[d];
    in.solid_face_flux[d] = phi_s[d];
  }
  auto cell4 = [&](const char* name, double value) {
    Field4 f = make_field(name, p, Location::cell, 2);
    Kokkos::deep_copy(f, value);
    return f;
  };
  Field4 theta = cell4("th", 0.0), kappa = cell4("k", 0.0), temp = cell4("t", 300.0), tdot = cell4("td", 0.0);
  Field3 sum_kappa = make_field("sk", p, Location::cell);
  auto pfh = Kokkos::create_mirror_view(pf[0]);
  auto phih = Kokkos::create_mirror_view(phi_s[0]);
  auto thh = Kokkos::create_mirror_view(theta);
  auto kh = Kokkos::create_mirror_view(kappa);
  auto skh = Kokkos::create_mirror_view(sum_kappa);
  for (int i = 0; i < nx + 1; ++i) {
    const int gi = ((i - 1) % 8 + 8) % 8;  // faces and cells: periodic images
    pfh(i, 1, 1) = 1e6 * (1.0 + 0.3 * gi - 0.05 * gi * gi);
    phih(i, 1, 1) = 1e-9 * (gi % 3 - 1.0) + 2e-10 * gi;
    if (i < nx) {
      thh(1, i, 1, 1) = 0.1 + 0.1 * gi;  // the solid's fraction, 0.1 to 0.8
      thh(0, i, 1, 1) = 1.0 - thh(1, i, 1, 1);
      kh(0, i, 1, 1) = 1e-5;
      kh(1, i, 1, 1) = 1e-10;
      skh(i, 1, 1) = thh(0, i, 1, 1) * kh(0, i, 1, 1) + thh(1, i, 1, 1) * kh(1, i, 1, 1);
    }
  }
  Kokkos::deep_copy(pf[0], pfh);
  Kokkos::deep_copy(phi_s[0], phih);
  Kokkos::deep_copy(theta, thh);
  Kokkos::deep_copy(kappa, kh);
  Kokkos::deep_copy(sum_kappa, skh);
  in.vol_frac = theta;
  in.kappa = kappa;
  in.sum_kappa = sum_kappa;
  in.work = cell4("w", 0.0);
  in.rho = cell4("rho", 1.0);
  in.mass_L = cell4("m", 1e-6);
  const Field4 zero = cell4("zero", 0.0);
  in.mom_L = ConstVectorField4{zero, zero, zero};
  in.mom_source = ConstVectorField4{zero, zero, zero};
  in.vel_me = ConstVectorField4{zero, zero, zero};
  const double total = pressure_work_heat(p.owned_cells(), {0.01, 0.01, 0.01}, 1e-6, {0, 0, 0}, mats, in, temp, tdot);
  auto th = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), temp);
  double scale = 0, largest = 0;
  for (int i = 1; i < 9; ++i) {
    scale += std::abs(pfh(i, 1, 1) * phih(i, 1, 1));
    largest = std::max(largest, std::abs(th(0, i, 1, 1) - 300.0));
  }
  // Round-off of the sums only: 1e-12 of the largest terms.
  EXPECT_NEAR(total, 0.0, 1e-12 * scale);
  EXPECT_GT(largest * 1e-6 * 716.0, 1e-3 * scale);  // single cells were heated or cooled
}

// The solid's bulk law (E51) and its tension form (E52): inverse, p_ref at rho_0, and
// the compressive branch's dp/drho against a centred difference.
TEST(SolidEos, InverseAndDerivative) {
  for (bool modified : {false, true}) {
    Eos cu;
    cu.type = EosType::solid;
    cu.rho0 = 8930;
    cu.bulk = 136.35e9;
    cu.modified = modified;
    EXPECT_DOUBLE_EQ(eos_pressure(cu, cu.rho0, 300), cu.p_ref);
    for (double p : {5e4, 101325.0, 1e7, 1e9, 2e10}) {
      if (!modified && p < 1e5) continue;
      const double rho = eos_density(cu, p, 300);
      EXPECT_NEAR(eos_pressure(cu, rho, 300), p, 1e-9 * std::max(p, cu.p_ref)) << p;
      // (E52) is stiff: p changes by a factor e per relative density change p_ref/K.
      const double h = 1e-10 * rho;
      const double fd = (eos_pressure(cu, rho + h, 300) - eos_pressure(cu, rho - h, 300)) / (2 * h);
      EXPECT_NEAR(eos_dp_drho(cu, rho, 300), fd, 1e-4 * fd) << p;
    }
  }
}

// fill_extra_cells of several fields in one launch per face gives what filling them one
// by one gives, and each kind of condition its closed form: a Dirichlet face its value,
// a Neumann face the adjacent inside cell plus gradient x distance, a symmetry face the
// mirror image with the normal component's sign changed. Fields of two materials, of
// one material slot, and material-independent.
TEST(BoundaryConditions, ExtraCellsOfSeveralFieldsInOneLaunch) {
  Grid g;
  g.cells = {4, 3, 5};
  g.spacing = {0.1, 0.2, 0.3};
  const Patch patch = whole_grid_patch(g, 2);
  const int G = patch.ghosts;
  FaceBcs bcs;
  bcs[0].kind = BcKind::dirichlet;  // x-
  bcs[0].value[0] = 7.0;
  bcs[0].value[1] = 8.0;
  bcs[1].kind = BcKind::neumann;  // x+: gradient 2 (and 3 for component 1)
  bcs[1].value[0] = 2.0;
  bcs[1].value[1] = 3.0;
  bcs[2].kind = BcKind::symmetry;  // y-
  bcs[4].kind = BcKind::symmetry;  // z-
  bcs[5].kind = BcKind::dirichlet;  // z+
  bcs[5].value[0] = -1.0;
  bcs[5].value[1] = -2.0;
  const Field4 a = make_field("a", patch, Location::cell, 2), vy = make_field("vy", patch, Location::cell, 3);
  const Field3 p = make_field("p", patch, Location::cell);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto randomise = [&](auto field) {
    auto h = Kokkos::create_mirror_view(field);
    for (std::size_t i = 0; i < h.span(); ++i) h.data()[i] = u(rng);
    Kokkos::deep_copy(field, h);
  };
  randomise(a);
  randomise(vy);
  randomise(p);
  auto copy = [](auto field) {
    auto c = decltype(field)("copy", field.layout());
    Kokkos::deep_copy(c, field);
    return c;
  };
  const Field4 a1 = copy(a), vy1 = copy(vy);
  const Field3 p1 = copy(p);
  // p has its own conditions: zero gradient everywhere but a Dirichlet z+ of -1.
  FaceBcs p_bcs;
  p_bcs[5].kind = BcKind::dirichlet;
  p_bcs[5].value[0] = -1.0;
  // Slot 1 of vy only: slots 0 and 2 must keep their random extra cells.
  fill_extra_cells(Kokkos::Array<ExtraCellFill, 3>{ExtraCellFill(a, bcs, -1), ExtraCellFill(vy, 1, bcs, 1),
                                                   ExtraCellFill(p, p_bcs, -1)},
                   patch);
  fill_extra_cells(a1, patch, bcs, -1);
  fill_extra_cells(vy1, 1, patch, bcs, 1);
  fill_extra_cells(p1, patch, p_bcs, -1);
  auto host = [](auto field) { return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), field); };
  const auto ha = host(a), ha1 = host(a1), hv = host(vy), hv1 = host(vy1);
  const auto hp = host(p), hp1 = host(p1);
  for (std::size_t i = 0; i < ha.span(); ++i) ASSERT_EQ(ha.data()[i], ha1.data()[i]) << i;
  for (std::size_t i = 0; i < hv.span(); ++i) ASSERT_EQ(hv.data()[i], hv1.data()[i]) << i;
  for (std::size_t i = 0; i < hp.span(); ++i) ASSERT_EQ(hp.data()[i], hp1.data()[i]) << i;

  const int nx = g.cells[0], j = G + 1, k = G + 2;  // a row through the inside in y and z
  for (int l = 1; l <= G; ++l) {
    for (int m = 0; m < 2; ++m) {
      EXPECT_EQ(ha(m, G - l, j, k), 7.0);                                                   // x- Dirichlet
      EXPECT_DOUBLE_EQ(ha(m, G + nx - 1 + l, j, k), ha(m, G + nx - 1, j, k) + 2.0 * 0.1 * l);  // x+ Neumann
      EXPECT_EQ(ha(m, G + 1, G - l, k), ha(m, G + 1, G - 1 + l, k));                        // y- mirror
    }
    EXPECT_EQ(hv(1, G - l, j, k), 8.0);  // the component's own value
    EXPECT_DOUBLE_EQ(hv(1, G + nx - 1 + l, j, k), hv(1, G + nx - 1, j, k) + 3.0 * 0.1 * l);
    EXPECT_EQ(hv(1, G + 1, G - l, k), -hv(1, G + 1, G - 1 + l, k));  // normal component: sign changes
    EXPECT_EQ(hv(1, G + 1, j, G - l), hv(1, G + 1, j, G - 1 + l));   // tangential at z-: mirrored
    EXPECT_EQ(hp(G + 1, j, G + g.cells[2] - 1 + l), -1.0);           // z+ Dirichlet
    EXPECT_EQ(hp(G - l, j, k), hp(G, j, k));                          // its own x-: zero gradient
    EXPECT_EQ(hv(0, G - l, j, k), hv1(0, G - l, j, k));               // other slots untouched
  }
  // Edges: x is swept first, then y over x's extra cells. The x- Dirichlet value reaches
  // the y- extra cells by the mirror, with the sign of the normal component changed.
  for (int l = 1; l <= G; ++l)
    for (int e = 1; e <= G; ++e) {
      EXPECT_EQ(ha(0, G - l, G - e, k), 7.0);
      EXPECT_EQ(hv(1, G - l, G - e, k), -8.0);
    }
  // The other slots of vy kept their random extra cells.
  long kept = 0;
  for (std::size_t i = 0; i < hv.extent(1); ++i) kept += hv(0, i, j, k) == hv1(0, i, j, k);
  EXPECT_EQ(kept, long(hv.extent(1)));
}

// The per-step reductions: the time step (a minimum), the outflux limit (a maximum,
// rows of vector loops) and the search for bad states (a count in rows of vector
// loops, then where). Each must equal a plain host loop over the same fields exactly:
// a minimum, a maximum and a count of cells do not depend on the order.
namespace {
struct ReductionBox {
  Patch p;
  MaterialTable mats;
  Field4 rho, temp, sp_vol;
  VectorField4 vel, U;

  ReductionBox() {
    Grid g;
    g.cells = {6, 5, 9};
    g.spacing = {1e-3, 2e-3, 1.5e-3};
    p = whole_grid_patch(g, 1);
    mats.count = 3;
    mats.eos[0] = Eos{EosType::ideal_gas, 1.4, 716.0};
    mats.eos[1] = Eos{EosType::ideal_gas, 1.4, 716.0};
    mats.kind[1] = mpm_material;  // not an ICE material: it does not limit the step
    mats.eos[2] = Eos{EosType::ideal_gas, 1.67, 3116.0};
    std::mt19937 rng(17);
    auto random_field = [&](Location where, double lo, double hi) {
      return random_values(p, where, mats.count, lo, hi, rng);
    };
    rho = random_field(Location::cell, 0.5, 1.5);
    temp = random_field(Location::cell, 200.0, 2000.0);
    sp_vol = random_field(Location::cell, 0.5, 1.5);
    const Location faces[3] = {Location::x_face, Location::y_face, Location::z_face};
    for (int d = 0; d < 3; ++d) {
      vel[d] = random_field(Location::cell, -300.0, 300.0);
      U[d] = random_field(faces[d], -300.0, 300.0);
    }
  }
  ConstVectorField4 cell_velocities() const { return {vel[0], vel[1], vel[2]}; }
  ConstVectorField4 face_velocities() const { return {U[0], U[1], U[2]}; }
};
}  // namespace

TEST(Reductions, TimestepAndOutfluxLimitEqualHostLoops) {
  ReductionBox b;
  // Material 2 absent (rho v below 1e-6) in one cell and the solid (material 1) in
  // another, both at 1e6 m/s: counted, either would set the step.
  auto rh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.rho);
  rh(2, 3, 2, 4) = 1e-9;
  Kokkos::deep_copy(b.rho, rh);
  auto vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.sp_vol);
  auto th = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.temp);
  Kokkos::Array<decltype(vh), 3> uh, Uh;
  for (int d = 0; d < 3; ++d) {
    uh[d] = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.vel[d]);
    Uh[d] = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.U[d]);
  }
  uh[0](2, 3, 2, 4) = 1e6;
  uh[1](1, 2, 3, 3) = -1e6;
  Kokkos::deep_copy(b.vel[0], uh[0]);
  Kokkos::deep_copy(b.vel[1], uh[1]);
  const IndexBox cells = b.p.owned_cells();
  const Kokkos::Array<double, 3> h{b.p.grid.spacing[0], b.p.grid.spacing[1], b.p.grid.spacing[2]};
  const double dt = 1e-6;
  double dt_host = std::numeric_limits<double>::max(), outflux_host = 0;
  for (int i = cells.lo[0]; i < cells.hi[0]; ++i)
    for (int j = cells.lo[1]; j < cells.hi[1]; ++j)
      for (int k = cells.lo[2]; k < cells.hi[2]; ++k)
        for (int m = 0; m < b.mats.count; ++m) {
          if (b.mats.is_ice(m) && rh(m, i, j, k) * vh(m, i, j, k) >= 1e-6) {
            const double c = std::sqrt(eos_sound_speed_squared(b.mats.eos[m], 1.0 / vh(m, i, j, k), th(m, i, j, k)));
            for (int d = 0; d < 3; ++d) dt_host = std::min(dt_host, h[d] / (c + std::abs(uh[d](m, i, j, k)) + 1e-100));
          }
          double d[6];
          outflux_distances(ConstVectorField4{Uh[0], Uh[1], Uh[2]}, m, i, j, k, dt, d);
          outflux_host = std::max(outflux_host, (d[0] + d[1]) / h[0] + (d[2] + d[3]) / h[1] + (d[4] + d[5]) / h[2]);
        }
  ASSERT_GT(dt_host, 1e-3 / 1e6 * 10);  // neither fast cell counted
  EXPECT_EQ(ice_timestep(cells, h, 0.5, b.mats, b.rho, b.sp_vol, b.temp, b.cell_velocities()), 0.5 * dt_host);
  EXPECT_EQ(max_outflux_fraction(cells, h, dt, b.mats.count, b.face_velocities()), outflux_host);
  // No fluid present anywhere: nothing limits the step.
  MaterialTable solids = b.mats;
  for (int m = 0; m < solids.count; ++m) solids.kind[m] = mpm_material;
  EXPECT_EQ(ice_timestep(cells, h, 1.0, solids, b.rho, b.sp_vol, b.temp, b.cell_velocities()),
            std::numeric_limits<double>::max());
}

TEST(Reductions, BadStatesAreCountedAndTheLastIsNamed) {
  ReductionBox b;
  const IndexBox cells = b.p.owned_cells();
  const ConstVectorField4 vel = b.cell_velocities();
  EXPECT_EQ(find_bad_states(cells, b.mats.count, b.rho, b.temp, b.sp_vol, vel).count, 0);
  auto set = [&](const Field4& f, int m, int i, int j, int k, double value) {
    auto fh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f);
    const double old = fh(m, i, j, k);
    fh(m, i, j, k) = value;
    Kokkos::deep_copy(f, fh);
    return old;
  };
  // One value at a time: density and temperature must be positive and finite, the
  // specific volume positive (E38 allows it infinite), a velocity finite.
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const Field4 fields[6] = {b.rho, b.temp, b.sp_vol, b.vel[0], b.vel[1], b.vel[2]};
  for (int q = 0; q < 6; ++q)
    for (double value : {nan, inf, -inf, 0.0, -0.0, -1.0}) {
      const bool bad = q < 2 ? true : q == 2 ? !(value > 0) || std::isnan(value) : !std::isfinite(value);
      const double old = set(fields[q], 2, 3, 2, 5, value);
      const BadState found = find_bad_states(cells, b.mats.count, b.rho, b.temp, b.sp_vol, vel);
      set(fields[q], 2, 3, 2, 5, old);
      ASSERT_EQ(found.count, bad ? 1 : 0) << "quantity " << q << ", value " << value;
      if (!bad) continue;
      EXPECT_EQ(found.quantity, q < 3 ? q : 3);
      EXPECT_EQ(found.material, 2);
      EXPECT_EQ(found.cell[0], 3);
      EXPECT_EQ(found.cell[1], 2);
      EXPECT_EQ(found.cell[2], 5);
    }
  // Bad values in four cells and in an extra cell (not in `cells`, not counted): the
  // last cell in index order, (4, 4, 7), is named, with its material and quantity.
  set(b.rho, 0, 1, 1, 1, -1.0);
  set(b.temp, 2, 2, 3, 1, nan);
  set(b.sp_vol, 1, 3, 1, 5, 0.0);
  set(b.vel[1], 2, 4, 4, 7, inf);
  set(b.rho, 1, 0, 0, 0, -1.0);
  const BadState bad = find_bad_states(cells, b.mats.count, b.rho, b.temp, b.sp_vol, vel);
  EXPECT_EQ(bad.count, 4);
  EXPECT_EQ(bad.cell[0], 4);
  EXPECT_EQ(bad.cell[1], 4);
  EXPECT_EQ(bad.cell[2], 7);
  EXPECT_EQ(bad.material, 2);
  EXPECT_EQ(bad.quantity, 3);
}
