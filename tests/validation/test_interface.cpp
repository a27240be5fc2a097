// A helium slab moving with air at uniform velocity and pressure (problems/
// interface.yaml): a contact discontinuity, exact solution of the Euler equations in
// which pressure and velocity stay uniform. After the slab has crossed 20 cells they
// must still be uniform to 1e-8 relative (the bound; what remains is round-off
// from the mixed cells' equilibration, about 1e-14 here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

TEST(Interface, PressureAndVelocityStayUniform) {
  auto pb = run_problem("interface.yaml", {}, MPI_COMM_SELF, scratch_dir("interface"));
  // 100 m/s for 2 ms over cells of 1 cm: 20 cells.
  const double crossed = 100.0 * pb->time / pb->patch().grid.spacing[0];
  EXPECT_GE(crossed, 20.0 - 1e-9);
  const auto p = profile(*pb, "press_CC", 0, 0);
  const auto theta_he = [&] {
    auto rho = profile(*pb, "rho_CC", 1, 0), v = profile(*pb, "sp_vol_CC", 1, 0);
    for (std::size_t i = 0; i < rho.size(); ++i) rho[i] *= v[i];
    return rho;
  }();
  double p_dev = 0, u_dev = 0;
  for (double x : p) p_dev = std::max(p_dev, std::abs(x - 101325.0) / 101325.0);
  for (int m = 0; m < 2; ++m)
    for (double u : profile(*pb, "vel_CC_x", m, 0)) u_dev = std::max(u_dev, std::abs(u - 100.0) / 100.0);
  std::printf("interface: max |p - p0|/p0 = %.3e, max |u - u0|/u0 = %.3e\n", p_dev, u_dev);
  EXPECT_LE(p_dev, 1e-8);
  EXPECT_LE(u_dev, 1e-8);
  // The slab moved: helium now fills x in [0.5, 0.7] (cells 50-69; the advection
  // smears each edge over about three cells).
  for (int i = 54; i < 66; ++i) EXPECT_GT(theta_he[i], 0.99) << "cell " << i;
  for (int i = 20; i < 28; ++i) EXPECT_LT(theta_he[i], 0.01) << "cell " << i;
}
