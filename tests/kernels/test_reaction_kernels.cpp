// Simple Burn (E44-E46): the burning area of planar surfaces against geometry, the
// rate against dt A B (p/p0)^n, the thresholds and the cap at the reactant's mass,
// and the sources conserving mass, momentum and volume exactly and adding dm dh of
// energy; the volume fractions after the reaction (E17) still sum to one.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include <mpmice/kernels/simple_burn.hpp>

using namespace mpmice;

namespace {

const double h[3] = {0.01, 0.02, 0.005};

// Corner masses of a cell cut by a plane normal to direction `d`: `full` on the low
// side's corners, `part` on the high side's.
void planar(int d, double full, double part, double M[2][2][2]) {
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) M[a][b][c] = (d == 0 ? a : d == 1 ? b : c) ? part : full;
}

// One cell (0,0,0) of two materials, reactant 0 (node slot 0) and product 1.
struct BurnCell {
  Field4 rho{"rho", 2, 1, 1, 1}, temp{"temp", 2, 1, 1, 1}, sp_vol{"sp_vol", 2, 1, 1, 1},
      vol_frac{"vol_frac", 2, 1, 1, 1}, node_mass{"node_mass", 1, 2, 2, 2};
  VectorField4 vel{Field4("u", 2, 1, 1, 1), Field4("v", 2, 1, 1, 1), Field4("w", 2, 1, 1, 1)};
  Field3 weight{"weight", 2, 2, 2}, press{"press", 1, 1, 1};
  ReactionSources src{Field4("dm", 2, 1, 1, 1),
                      {Field4("dpx", 2, 1, 1, 1), Field4("dpy", 2, 1, 1, 1), Field4("dpz", 2, 1, 1, 1)},
                      Field4("de", 2, 1, 1, 1), Field4("dv", 2, 1, 1, 1)};
  SimpleBurn burn;

  // Reactant fills 60% of the cell, cut normal to x; both materials at `t` K, p Pa.
  BurnCell(double t, double p, double reactant_density) {
    burn.reactant = 0;
    burn.reactant_slot = 0;
    burn.product = 1;
    Kokkos::deep_copy(weight, 0.125);
    auto nm = Kokkos::create_mirror_view(node_mass);
    double M[2][2][2];
    planar(0, 8.0, 3.0, M);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) nm(0, a, b, c) = M[a][b][c];
    Kokkos::deep_copy(node_mass, nm);
    set(rho, {reactant_density, 2.0});
    set(temp, {t, t});
    set(sp_vol, {1 / 1800.0, 0.5});
    set(vol_frac, {0.6, 0.4});
    set(vel[0], {3.0, -1.0});
    set(vel[1], {-2.0, 0.5});
    set(vel[2], {0.25, 0.0});
    Kokkos::deep_copy(press, p);
  }
  static void set(const Field4& f, std::array<double, 2> v) {
    auto m = Kokkos::create_mirror_view(f);
    m(0, 0, 0, 0) = v[0];
    m(1, 0, 0, 0) = v[1];
    Kokkos::deep_copy(f, m);
  }
  double run(double dt) {
    IndexBox cell;
    cell.hi[0] = cell.hi[1] = cell.hi[2] = 1;
    const ConstVectorField4 u{vel[0], vel[1], vel[2]};
    return simple_burn(cell, h, dt, 2, burn, 1500.0, weight, node_mass, rho, u, temp, sp_vol, vol_frac, press, src);
  }
  double at(const Field4& f, int m) {
    auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f);
    return host(m, 0, 0, 0);
  }
};

}  // namespace

TEST(SimpleBurn, PlanarSurfaceAreaIsTheCellFace) {
  double M[2][2][2];
  for (int d = 0; d < 3; ++d) {
    // A plane normal to d: A = V / h_d, the cell's face across d (n = e_d, max |n| = 1).
    planar(d, 1.0, 0.5, M);
    EXPECT_NEAR(burn_area(M, h), h[0] * h[1] * h[2] / h[d], 1e-15) << d;
    planar(d, 0.5, 1.0, M);  // facing the other way
    EXPECT_NEAR(burn_area(M, h), h[0] * h[1] * h[2] / h[d], 1e-15) << d;
  }
  planar(0, 1.0, 1.0, M);  // full cell: no surface
  EXPECT_EQ(burn_area(M, h), 0.0);
  planar(0, 1.0, 0.7, M);  // spread 0.3 <= 0.4: interior
  EXPECT_EQ(burn_area(M, h), 0.0);
  planar(0, 1.0, 0.0, M);  // spread 1: the reactant's last corner cells do not burn
  EXPECT_EQ(burn_area(M, h), 0.0);
  planar(0, 1e-13, 5e-14, M);  // no reactant
  EXPECT_EQ(burn_area(M, h), 0.0);
}

TEST(SimpleBurn, RateThresholdsAndConservation) {
  const double dt = 1e-6, p = 2.0e6;
  BurnCell cell(500.0, p, 1800.0);
  const double burned = cell.run(dt);
  // The planar x surface: A = hy hz; dm = dt A B (p/p0)^n.
  const double dm = dt * h[1] * h[2] * 75.3 * std::pow(p / 101325.0, 0.778);
  EXPECT_NEAR(burned, dm, 1e-15 * dm);
  EXPECT_NEAR(cell.at(cell.src.mass, 1), dm, 1e-15 * dm);
  // Exactly what the reactant loses the product gains; energy gains dm dh.
  EXPECT_EQ(cell.at(cell.src.mass, 0) + cell.at(cell.src.mass, 1), 0.0);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(cell.at(cell.src.momentum[d], 0) + cell.at(cell.src.momentum[d], 1), 0.0);
    const double u[3] = {3.0, -2.0, 0.25};
    EXPECT_NEAR(cell.at(cell.src.momentum[d], 1), dm * u[d], 1e-15);
  }
  EXPECT_EQ(cell.at(cell.src.volume, 0) + cell.at(cell.src.volume, 1), 0.0);
  EXPECT_NEAR(cell.at(cell.src.energy, 0) + cell.at(cell.src.energy, 1), dm * cell.burn.enthalpy,
              1e-12 * dm * cell.burn.enthalpy);
  EXPECT_NEAR(cell.at(cell.src.energy, 1), dm * (1500.0 * 500.0 + cell.burn.enthalpy), 1e-9);

  BurnCell cold(440.0, p, 1800.0);  // below T_thr
  EXPECT_EQ(cold.run(dt), 0.0);
  BurnCell low(500.0, 4.0e4, 1800.0);  // below p_thr
  EXPECT_EQ(low.run(dt), 0.0);
  // A reactant with less mass in the cell than one step would burn loses all of it.
  BurnCell last(500.0, p, 1e-6);
  const double all = 1e-6 * h[0] * h[1] * h[2];
  EXPECT_NEAR(last.run(1e-3), all, 1e-15 * all);
  EXPECT_NEAR(last.at(last.src.mass, 0), -all, 1e-15 * all);
}

TEST(SimpleBurn, VolumeFractionsStillFillTheCell) {
  Field4 rho("rho", 2, 1, 1, 1), sp("sp", 2, 1, 1, 1), kappa("kappa", 2, 1, 1, 1), dV("dV", 2, 1, 1, 1),
      theta("theta", 2, 1, 1, 1);
  Field3 sk("sk", 1, 1, 1);
  auto set = [](const Field4& f, double a, double b) {
    auto m = Kokkos::create_mirror_view(f);
    m(0, 0, 0, 0) = a;
    m(1, 0, 0, 0) = b;
    Kokkos::deep_copy(f, m);
  };
  const double V = 1e-6;
  // Solid 1800 kg/m^3 at v = 1/1800 filling 60%, gas 2 kg/m^3 at v = 0.2 filling 40%.
  set(rho, 1080.0, 0.8);
  set(sp, 1 / 1800.0, 0.5);
  set(theta, 0.6, 0.4);
  set(kappa, 1e-10, 1e-5);
  set(dV, -1e-8, 1e-8);  // 1% of the cell's volume moves from the solid to the gas
  IndexBox cell;
  cell.hi[0] = cell.hi[1] = cell.hi[2] = 1;
  volume_fraction_after_reaction(cell, V, 2, rho, sp, kappa, dV, theta, sk);
  auto t = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), theta);
  auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sk);
  EXPECT_NEAR(t(0, 0, 0, 0), 0.59, 1e-14);
  EXPECT_NEAR(t(1, 0, 0, 0), 0.41, 1e-14);
  EXPECT_NEAR(s(0, 0, 0), 0.59 * 1e-10 + 0.41 * 1e-5, 1e-20);
}
