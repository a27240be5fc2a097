// Simple Burn (E44-E46): the burning area of planar surfaces against geometry, the
// rate against dt A B (p/p0)^n, the thresholds and the cap at the reactant's mass;
// the particles' transfer gives the product exactly what the particles lose (mass,
// momentum, c_v T) plus dm dh, and burned-out particles are removed; the new gas takes
// its volume at the cell's pressure, (E32) keeps the cell's volume with it, and the
// compression work of dP_mx is paid by the new gas.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/particle_burn.hpp>
#include <mpmice/kernels/simple_burn.hpp>
#include <mpmice/kernels/sources.hpp>
#include <mpmice/kernels/specific_volume.hpp>

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
      vol_frac{"vol_frac", 2, 1, 1, 1}, node_mass{"node_mass", 1, 2, 2, 2}, dm{"dm", 2, 1, 1, 1};
  Field3 weight{"weight", 2, 2, 2}, press{"press", 1, 1, 1};
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
    return burn_rate(cell, h, dt, 2, burn, weight, node_mass, rho, temp, vol_frac, press, dm);
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

TEST(SimpleBurn, RateThresholdsAndCap) {
  const double dt = 1e-6, p = 2.0e6;
  BurnCell cell(500.0, p, 1800.0);
  const double burned = cell.run(dt);
  // The planar x surface: A = hy hz; dm = dt A B (p/p0)^n (round-off of pow: 1e-15).
  const double dm = dt * h[1] * h[2] * 75.3 * std::pow(p / 101325.0, 0.778);
  EXPECT_NEAR(burned, dm, 1e-15 * dm);
  EXPECT_NEAR(cell.at(cell.dm, 0), dm, 1e-15 * dm);
  EXPECT_EQ(cell.at(cell.dm, 1), 0.0);  // only the reactant's slot

  BurnCell cold(440.0, p, 1800.0);  // below T_thr
  EXPECT_EQ(cold.run(dt), 0.0);
  BurnCell low(500.0, 4.0e4, 1800.0);  // below p_thr
  EXPECT_EQ(low.run(dt), 0.0);
  // A reactant with less mass in the cell than one step would burn loses all of it.
  BurnCell last(500.0, p, 1e-6);
  const double all = 1e-6 * h[0] * h[1] * h[2];
  EXPECT_NEAR(last.run(1e-3), all, 1e-15 * all);
}

// Particles of the reactant (material 0) in two cells of a 2 x 1 x 1 patch: cell 0 burns
// a third of its particles' mass, cell 1 more than it has. The product (material 1)
// gains in each cell exactly what that cell's particles lost: mass, momentum, and energy
// (thermal, chemical, kinetic, and the strain energy of the stretched particles).
TEST(SimpleBurn, ParticlesGiveTheProductWhatTheyLose) {
  const int np = 6;
  ParticleSet ps("reactant", np);
  ps.resize(np);
  auto d = Kokkos::create_mirror_view(ps.data());
  auto id = Kokkos::create_mirror_view(ps.id());
  const double x[np] = {0.002, 0.004, 0.008, 0.012, 0.016, 0.019};  // cells 0, 0, 0, 1, 1, 1 (hx = 0.01)
  double cell_mass[2] = {0, 0};
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < particle_field_count; ++c) d(p, c) = 0;
    d(p, column(ParticleField::x)) = x[p];
    d(p, column(ParticleField::y)) = 0.01;
    d(p, column(ParticleField::z)) = 0.0025;
    d(p, column(ParticleField::mass)) = 1e-3 * (p + 1);
    d(p, column(ParticleField::volume)) = 1e-3 * (p + 1) / 1800.0;
    d(p, column(ParticleField::vx)) = 1.0 + p;
    d(p, column(ParticleField::vy)) = -0.5 * p;
    d(p, column(ParticleField::vz)) = 0.25;
    d(p, column(ParticleField::temperature)) = 500.0 + 10 * p;
    // F = diag(1 + 0.01 p, 1, 1): particle 0 unstrained, the others stretched.
    for (int k = 0; k < 3; ++k) d(p, column(ParticleField::F00) + 4 * k) = k == 0 ? 1.0 + 0.01 * p : 1.0;
    id(p) = p;
    cell_mass[x[p] < 0.01 ? 0 : 1] += 1e-3 * (p + 1);
  }
  Kokkos::deep_copy(ps.data(), d);
  Kokkos::deep_copy(ps.id(), id);
  Field4 dm("dm", 2, 2, 1, 1);
  auto dm_h = Kokkos::create_mirror_view(dm);
  dm_h(0, 0, 0, 0) = cell_mass[0] / 3;
  dm_h(0, 1, 0, 0) = 2 * cell_mass[1];
  Kokkos::deep_copy(dm, dm_h);
  ProductSources src{Field4("m", 2, 2, 1, 1), {Field4("px", 2, 2, 1, 1), Field4("py", 2, 2, 1, 1), Field4("pz", 2, 2, 1, 1)},
                     Field4("e", 2, 2, 1, 1)};
  SimpleBurn burn;
  burn.reactant = 0;
  burn.reactant_slot = 0;
  burn.product = 1;
  const double cv = 1000.0;
  NodeGrid grid{{0, 0, 0}, {h[0], h[1], h[2]}, {1 / h[0], 1 / h[1], 1 / h[2]}};
  SolidModel pbx;
  pbx.density = 1800.0;
  pbx.bulk_modulus = 5.7e9;
  pbx.shear_modulus = 2.6e9;
  // The strain energy of particle p before the burn (E53, by its own formula here).
  auto strain_energy = [&](int p) {
    const double s = 1.0 + 0.01 * p, j13 = std::cbrt(1.0 / s);
    Mat3 bbar = Mat3::zero();
    bbar(0, 0) = j13 * j13 * s * s;
    bbar(1, 1) = bbar(2, 2) = j13 * j13;
    return neo_hookean_energy(s, bbar, pbx.bulk_modulus, pbx.shear_modulus) * 1e-3 * (p + 1) / pbx.density;
  };
  EXPECT_GT(strain_energy(3), 1e-10 * 1e-3 * 4 * cv * 530);  // far above the 1e-14 tolerance of the sums below
  const double burned = burn_particles(grid, np, ps.data(), cv, pbx, burn, dm, Field3("scratch", 2, 1, 1), src);
  const double expected = cell_mass[0] / 3 + cell_mass[1];
  EXPECT_NEAR(burned, expected, 1e-15 * expected);

  auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  auto m_src = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), src.mass);
  auto e_src = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), src.energy);
  double lost_m[2] = {0, 0}, lost_e[2] = {0, 0}, lost_p[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int p = 0; p < np; ++p) {
    const int c = x[p] < 0.01 ? 0 : 1;
    const double m0 = 1e-3 * (p + 1), m1 = after(p, column(ParticleField::mass));
    // Cell 0: every particle keeps 2/3 of its mass and volume; cell 1 burns out.
    EXPECT_NEAR(m1, c == 0 ? m0 * 2 / 3 : 0.0, 1e-15 * m0) << p;
    EXPECT_NEAR(after(p, column(ParticleField::volume)) * 1800.0, m1, 1e-15 * m0) << p;
    const double lost = m0 - m1;
    lost_m[c] += lost;
    double speed2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double v = after(p, column(ParticleField::vx) + k);
      lost_p[c][k] += lost * v;
      speed2 += v * v;
    }
    lost_e[c] += lost * (cv * after(p, column(ParticleField::temperature)) + burn.enthalpy + 0.5 * speed2) +
                 (lost / m0) * strain_energy(p);
  }
  for (int c = 0; c < 2; ++c) {
    // Same sums in another order: equal to a few ulps.
    EXPECT_NEAR(m_src(1, c, 0, 0), lost_m[c], 1e-15 * lost_m[c]) << c;
    EXPECT_EQ(m_src(0, c, 0, 0), 0.0);  // the reactant's slot: its loss is on its particles
    EXPECT_NEAR(e_src(1, c, 0, 0), lost_e[c], 1e-14 * lost_e[c]) << c;
    for (int k = 0; k < 3; ++k) {
      auto p_src = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), src.momentum[k]);
      EXPECT_NEAR(p_src(1, c, 0, 0), lost_p[c][k], 1e-14 * std::abs(lost_p[c][0])) << c << k;
    }
  }
  // The three burned-out particles go; the others keep their order and ids.
  EXPECT_EQ(remove_massless_particles(ps), 3);
  ASSERT_EQ(ps.size(), 3u);
  auto ids = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
  for (int p = 0; p < 3; ++p) EXPECT_EQ(ids(p), p);
  EXPECT_EQ(remove_massless_particles(ps), 0);
}

// The products take the burned solid's momentum and energy in one cell (E30). Total
// energy is kept: the gas's internal energy plus the kinetic energy of its momentum
// after = before + dE, where dE carries the burned solid's kinetic energy; what the
// merged momentum does not hold as kinetic energy is heat, never negative.
TEST(ReactionSources, ProductKeepsTheEnergyItIsGiven) {
  MaterialTable mats;
  mats.count = 2;
  for (int m = 0; m < 2; ++m) {
    mats.eos[m].type = EosType::ideal_gas;
    mats.eos[m].gamma = 1.4;
    mats.eos[m].cv = 716.0;
  }
  IndexBox cell;
  cell.hi[0] = cell.hi[1] = cell.hi[2] = 1;
  auto f4 = [](const char* name) { return Field4(std::string(name), 2, 1, 1, 1); };
  Field4 dm = f4("dm"), de = f4("de"), temp = f4("T"), mass = f4("mL"), eng = f4("EL"), mixed = f4("Tmix");
  Kokkos::Array<Field4, 3> dp = {f4("dpx"), f4("dpy"), f4("dpz")}, vel = {f4("ux"), f4("uy"), f4("uz")},
                           mom = {f4("px"), f4("py"), f4("pz")};
  const double M = 2e-6, T = 900.0, u[3] = {10.0, -5.0, 2.0}, kick[3] = {1e-6, 0.0, -2e-7};
  const double dmass = 5e-7, v[3] = {300.0, 40.0, 0.0}, internal = dmass * (996.0 * 600.0 + 2e6);
  const double burned_kinetic = 0.5 * dmass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  auto set = [](const Field4& f, double value) {
    auto h = Kokkos::create_mirror_view(f);
    Kokkos::deep_copy(h, 0.0);
    h(1, 0, 0, 0) = value;
    Kokkos::deep_copy(f, h);
  };
  set(dm, dmass);
  set(de, internal + burned_kinetic);
  set(temp, T);
  set(mass, M);
  set(eng, M * 716.0 * T);
  for (int d = 0; d < 3; ++d) {
    set(dp[d], dmass * v[d]);
    set(vel[d], u[d]);
    set(mom[d], M * u[d] + kick[d]);
  }
  add_product_sources(cell, mats, dm, {dp[0], dp[1], dp[2]}, de, {vel[0], vel[1], vel[2]}, temp, mass,
                      {mom[0], mom[1], mom[2]}, eng, mixed);
  auto at = [](const Field4& f) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f);
    return h(1, 0, 0, 0);
  };
  const double mass_after = at(mass);
  EXPECT_DOUBLE_EQ(mass_after, M + dmass);
  double kinetic_before = 0, kinetic_after = 0;
  for (int d = 0; d < 3; ++d) {
    const double p_after = at(mom[d]) - kick[d];  // the momentum before the kick, with the product's
    EXPECT_NEAR(p_after, M * u[d] + dmass * v[d], 1e-15 * M * 300.0) << d;
    kinetic_before += 0.5 * M * u[d] * u[d];
    kinetic_after += 0.5 * p_after * p_after / mass_after;
  }
  const double before = M * 716.0 * T + kinetic_before + internal + burned_kinetic;
  const double after = at(eng) + kinetic_after;
  // Sums of numbers of one sign: a few ulps of the total.
  EXPECT_NEAR(after, before, 1e-14 * before);
  // The relative motion (290 m/s) became heat: the gas gained more than the solid's
  // internal and chemical energy, by (1/2) mu |v - u|^2 with mu = M dm / (M + dm).
  const double mu = M * dmass / (M + dmass);
  double relative2 = 0;
  for (int d = 0; d < 3; ++d) relative2 += (v[d] - u[d]) * (v[d] - u[d]);
  EXPECT_NEAR(at(eng) - M * 716.0 * T - internal, 0.5 * mu * relative2, 1e-9 * 0.5 * mu * relative2);
  EXPECT_NEAR(at(mixed), at(eng) / (mass_after * 716.0), 1e-12 * T);
}

namespace {

// One cell of two ideal gases: air (material 0) and products (material 1, gaining mass).
struct GasCell {
  MaterialTable mats;
  IndexBox cell;
  static constexpr double V = 1e-9;
  GasCell() {
    mats.count = 2;
    for (int m = 0; m < 2; ++m) {
      mats.eos[m].type = EosType::ideal_gas;
      mats.eos[m].gamma = 1.4;
      mats.eos[m].cv = 716.0;
    }
    cell.hi[0] = cell.hi[1] = cell.hi[2] = 1;
  }
  static Field4 pair(const char* name, double a, double b) {
    Field4 f(std::string(name), 2, 1, 1, 1);
    auto h = Kokkos::create_mirror_view(f);
    h(0, 0, 0, 0) = a;
    h(1, 0, 0, 0) = b;
    Kokkos::deep_copy(f, h);
    return f;
  }
  static Field3 one(const char* name, double v) {
    Field3 f(std::string(name), 1, 1, 1);
    Kokkos::deep_copy(f, v);
    return f;
  }
  static double at(const Field4& f, int m) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f);
    return h(m, 0, 0, 0);
  }
};

}  // namespace

// The new gas at the cell's pressure and its own temperature: v = (gamma - 1) c_v T / p
// (ideal gas), T = dE / (dm c_v); 0 for a material that gained nothing.
TEST(ReactionVolume, NewGasAtTheCellPressure) {
  GasCell c;
  const double dm = 2e-9, t_new = 3600.0, p = 2.0e6;
  Field4 v("v", 2, 1, 1, 1);
  new_gas_specific_volume(c.cell, c.mats, GasCell::pair("dm", 0.0, dm), GasCell::pair("de", 0.0, dm * 716.0 * t_new),
                          GasCell::one("p", p), v);
  EXPECT_NEAR(GasCell::at(v, 1), 0.4 * 716.0 * t_new / p, 1e-14);
  EXPECT_EQ(GasCell::at(v, 0), 0.0);
}

// (E32) with a mass source: the new gas takes dm v_new, every material gives up
// theta kappa V dP_mx with dP_mx = dm v_new / (V SK), so the cell's total volume is as
// without the source; sp_vol_L is the volume per Lagrangian mass (m + dm).
TEST(ReactionVolume, NewGasVolumeKeepsTheCellVolume) {
  GasCell c;
  const double V = GasCell::V, p = 1e6, t = 1000.0;
  const double v = 0.4 * 716.0 * t / p, kappa = v / (1.4 * p * v);  // kappa = v/c^2 = 1/(gamma p)
  const double theta[2] = {0.7, 0.3}, dm = 1e-12, v_new = 0.4 * 716.0 * 3000.0 / p;
  const double sk = (theta[0] + theta[1]) * kappa, dp_mx = dm * v_new / (V * sk);
  const Field4 rho = GasCell::pair("rho", theta[0] / v, theta[1] / v);
  const Field4 zero = GasCell::pair("zero", 0.0, 0.0);
  Field4 out("out", 2, 1, 1, 1);
  auto run = [&](bool with_source) {
    const double ml1 = theta[1] / v * V + (with_source ? dm : 0.0);
    const SpecificVolumeInputs in{rho, GasCell::pair("mL", theta[0] / v * V, ml1), GasCell::pair("v", v, v),
                                  GasCell::pair("theta", theta[0], theta[1]), GasCell::pair("kappa", kappa, kappa),
                                  GasCell::one("sk", sk), GasCell::one("dpd", 0.0), GasCell::pair("T", t, t), zero,
                                  with_source ? GasCell::pair("dm", 0.0, dm) : ConstField4(),
                                  GasCell::pair("vnew", 0.0, v_new), GasCell::one("dpmx", dp_mx)};
    lagrangian_specific_volume(c.cell, V, 1e-7, false, c.mats, in, out);
    return std::array<double, 2>{GasCell::at(out, 0) * theta[0] / v * V, GasCell::at(out, 1) * ml1};
  };
  const auto plain = run(false), burning = run(true);
  // Volumes of 1e-9 m^3; round-off of the sums: 1e-22.
  EXPECT_NEAR(plain[0] + plain[1], V, 1e-22);
  EXPECT_NEAR(burning[0] + burning[1], V, 1e-22);
  EXPECT_GT(burning[1], plain[1]);  // the products grew, the air gave up volume
  EXPECT_LT(burning[0], plain[0]);
}

// The compression work of dP_mx: each fluid present gains TMV theta kappa p dP_mx, the
// material that gained mass pays the sum; the cell's energy source sums to what it was.
TEST(ReactionVolume, CompressionWorkIsPaidByTheNewGas) {
  GasCell c;
  const double p = 1e6, dp_mx = 5e4, kappa = 1.0 / (1.4 * p), tmv = GasCell::V;
  Field4 w = GasCell::pair("w", 1.5e-3, -2.0e-3);
  Kokkos::Array<int, max_materials> fluids;
  for (int m = 0; m < max_materials; ++m) fluids[m] = 1;
  mass_exchange_work(c.cell, 2, fluids, GasCell::one("tmv", tmv), GasCell::pair("theta", 0.6, 0.4),
                     GasCell::pair("kappa", kappa, kappa), GasCell::one("p", p), GasCell::one("dpmx", dp_mx),
                     GasCell::pair("dm", 0.0, 1e-12), w);
  const double gain_air = tmv * 0.6 * kappa * p * dp_mx;
  EXPECT_NEAR(GasCell::at(w, 0), 1.5e-3 + gain_air, 1e-18);
  EXPECT_NEAR(GasCell::at(w, 0) + GasCell::at(w, 1), 1.5e-3 - 2.0e-3, 1e-18);
}
