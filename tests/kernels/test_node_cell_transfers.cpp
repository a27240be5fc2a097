// node_to_cell (E13): each cell's mass, velocity, temperature, density and specific
// volume from its 8 nodes, against the same sums written out on the host; and the
// solid's modified law in tension (E52), which node_to_cell applies in a second pass
// over the cells below p_ref.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/node_to_cell.hpp>

using namespace mpmice;

namespace {

// Copper as problems/container.yaml has it: the modified law below p_ref, or not.
Eos copper(bool modified = true) {
  Eos e;
  e.type = EosType::solid;
  e.rho0 = 8930;
  e.bulk = 136.35e9;
  e.p_ref = 101325;
  e.modified = modified;
  return e;
}

// A 5 x 4 x 6 patch with random node masses (slot 0, from 1e-5 kg down to nearly
// nothing), velocities, temperatures and weights, random cell temperatures, and cell
// pressures from `low` to `high`.
struct Transfer {
  Patch patch;
  Field3 weight, press;
  Field4 node_mass, node_temp, rho, temp, sp_vol;
  VectorField4 node_vel, vel;

  Transfer(double low, double high) {
    Grid g;
    g.cells = {5, 4, 6};
    g.spacing = {1e-3, 2e-3, 5e-4};
    patch = whole_grid_patch(g, 2);
    const auto node = [&](const char* label) { return make_field(label, patch, Location::node, 1); };
    const auto cell = [&](const char* label) { return make_field(label, patch, Location::cell, 1); };
    weight = make_field("weight", patch, Location::node);
    press = make_field("press", patch, Location::cell);
    node_mass = node("node_mass");
    node_temp = node("node_temp");
    node_vel = {node("node_u"), node("node_v"), node("node_w")};
    rho = cell("rho");
    temp = cell("temp");
    sp_vol = cell("sp_vol");
    vel = {cell("u"), cell("v"), cell("w")};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto fill = [&](auto view, double lo, double hi) {
      auto h = Kokkos::create_mirror_view(view);
      for (std::size_t q = 0; q < h.size(); ++q) h.data()[q] = lo + (hi - lo) * u(rng);
      Kokkos::deep_copy(view, h);
    };
    fill(weight, 0.125, 0.25);
    fill(node_mass, 0.0, 1e-5);
    // Lighter by 10^-4 per node layer along x: the cells of local i = 4 hold about
    // m_small (1e-21 kg), those beyond less, so the blend with T^n matters there.
    auto mass = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), node_mass);
    for (std::size_t i = 0; i < mass.extent(1); ++i)
      for (std::size_t j = 0; j < mass.extent(2); ++j)
        for (std::size_t k = 0; k < mass.extent(3); ++k) mass(0, i, j, k) *= std::pow(1e-4, double(i));
    Kokkos::deep_copy(node_mass, mass);
    fill(node_temp, 280, 600);
    for (int d = 0; d < 3; ++d) fill(node_vel[d], -5, 5);
    fill(temp, 290, 310);
    fill(press, low, high);
  }

  void run(const Eos& eos) {
    node_to_cell(patch.owned_cells(), patch.grid.cell_volume(), 0, 0, eos, weight, node_mass,
                 ConstVectorField4{node_vel[0], node_vel[1], node_vel[2]}, node_temp, press, rho, vel, temp, sp_vol);
  }
};

template <class View>
auto on_host(const View& v) {
  return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
}

// f(i, j, k) for every owned cell of `t`; returns how many.
template <class F>
int for_each_owned_cell(const Transfer& t, const F& f) {
  const IndexBox cells = t.patch.owned_cells();
  int count = 0;
  for (int i = cells.lo[0]; i < cells.hi[0]; ++i)
    for (int j = cells.lo[1]; j < cells.hi[1]; ++j)
      for (int k = cells.lo[2]; k < cells.hi[2]; ++k, ++count) f(i, j, k);
  return count;
}

}  // namespace

TEST(NodeToCell, CellValuesFromTheirEightNodes) {
  Transfer t(1.1e5, 2e5);  // above p_ref only: every cell takes the first pass's law
  // A copy (create_mirror, not create_mirror_view: on the host that would be t.temp).
  const auto temp_before = Kokkos::create_mirror(Kokkos::HostSpace(), t.temp);
  Kokkos::deep_copy(temp_before, t.temp);
  t.run(copper());
  const auto w = on_host(t.weight), p = on_host(t.press);
  const auto nm = on_host(t.node_mass), nt = on_host(t.node_temp);
  const auto rho = on_host(t.rho), temp = on_host(t.temp), sp_vol = on_host(t.sp_vol);
  const auto nu = on_host(t.node_vel[0]), nv = on_host(t.node_vel[1]), nw = on_host(t.node_vel[2]);
  const auto u = on_host(t.vel[0]), v = on_host(t.vel[1]), ww = on_host(t.vel[2]);
  const double V = t.patch.grid.cell_volume(), m_small = tiny_rho * V;
  const int checked = for_each_owned_cell(t, [&](int i, int j, int k) {
    double mass = m_small, mom[3] = {0, 0, 0}, heat = 0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const double wm = w(i + a, j + b, k + c) * nm(0, i + a, j + b, k + c);
          mass += wm;
          mom[0] += wm * nu(0, i + a, j + b, k + c);
          mom[1] += wm * nv(0, i + a, j + b, k + c);
          mom[2] += wm * nw(0, i + a, j + b, k + c);
          heat += wm * nt(0, i + a, j + b, k + c);
        }
    const double z = (mass - m_small) / mass;
    const double T = (1.0 - z) * temp_before(0, i, j, k) + z * heat / mass;
    // The kernel may fuse other products into FMAs than this loop: a few roundings
    // (1.1e-16 each) of sums of 8 positive terms, so 1e-14 relative; the
    // velocities' sums mix signs, so theirs is 1e-14 of the largest speed, 5 m/s.
    const double tol = 1e-14;
    const std::string cell = std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(k);
    EXPECT_NEAR(rho(0, i, j, k), mass / V, tol * mass / V) << cell;
    EXPECT_NEAR(temp(0, i, j, k), T, tol * T) << cell;
    EXPECT_NEAR(u(0, i, j, k), mom[0] / mass, tol * 5) << cell;
    EXPECT_NEAR(v(0, i, j, k), mom[1] / mass, tol * 5) << cell;
    EXPECT_NEAR(ww(0, i, j, k), mom[2] / mass, tol * 5) << cell;
    const double expected = 1.0 / eos_density(copper(), p(i, j, k), temp(0, i, j, k));
    EXPECT_NEAR(sp_vol(0, i, j, k), expected, tol * expected) << cell;
  });
  EXPECT_EQ(checked, 5 * 4 * 6);
}

// Pressures on both sides of p_ref: the cells in tension must get the modified law
// (pow), which differs from the bulk law there by far more than round-off.
TEST(NodeToCell, CellsInTensionTakeTheModifiedLaw) {
  Transfer t(2e4, 2e5);
  const Eos eos = copper();
  t.run(eos);
  const auto p = on_host(t.press);
  const auto temp = on_host(t.temp), sp_vol = on_host(t.sp_vol);
  int tension = 0, compression = 0;
  for_each_owned_cell(t, [&](int i, int j, int k) {
    const double pc = p(i, j, k), T = temp(0, i, j, k);
    const bool in_tension = pc < eos.p_ref;
    (in_tension ? tension : compression) += 1;
    // The same functions of the same values. Outside tension within 4 ulps, should a
    // compiler fuse x^2 + 1 into an FMA in the vector loop and not here; in tension
    // the same pow on the host, so to the last bit (a GPU's pow may differ by ulps).
    const double expected = 1.0 / eos_density(eos, pc, T);
#if !defined(MPMICE_DEVICE_BACKEND)
    if (in_tension) EXPECT_EQ(sp_vol(0, i, j, k), expected) << i << " " << j << " " << k;
#endif
    EXPECT_DOUBLE_EQ(sp_vol(0, i, j, k), expected) << i << " " << j << " " << k;
    if (in_tension) {
      // The laws differ by about (p_ref/K) d^2/2 relative, d = p/p_ref - 1: by more
      // than 3.7e-9 below 0.9 p_ref, where 4 ulps are 1e-15.
      const double bulk_law = 1.0 / eos_density_outside_tension(eos, pc, T);
      if (pc < 0.9 * eos.p_ref) EXPECT_GT(std::abs(sp_vol(0, i, j, k) - bulk_law), 1e-10 * bulk_law);
    }
  });
  EXPECT_GT(tension, 10);
  EXPECT_GT(compression, 10);
}

// A solid without the modified law keeps the bulk law below p_ref too (node_to_cell's
// second pass is for the modified law only).
TEST(NodeToCell, UnmodifiedSolidKeepsTheBulkLawInTension) {
  Transfer t(2e4, 2e5);
  const Eos eos = copper(false);
  t.run(eos);
  const auto p = on_host(t.press);
  const auto temp = on_host(t.temp), sp_vol = on_host(t.sp_vol);
  int tension = 0;
  for_each_owned_cell(t, [&](int i, int j, int k) {
    const double pc = p(i, j, k), T = temp(0, i, j, k);
    tension += pc < eos.p_ref ? 1 : 0;
    // Within 4 ulps, as in CellsInTensionTakeTheModifiedLaw; the modified law would
    // differ by more than 3.7e-9 below 0.9 p_ref.
    EXPECT_DOUBLE_EQ(sp_vol(0, i, j, k), 1.0 / eos_density_outside_tension(eos, pc, T)) << i << " " << j << " " << k;
  });
  EXPECT_GT(tension, 10);
}
