// Sod shock tube (problems/sod.yaml) against the exact Riemann solution computed here:
// the L1 density error at 400 cells, its convergence from 100 to 400 cells, and the
// same tube along x, y and z agreeing to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "exact_riemann.hpp"
#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

namespace {

// L1 norm of (rho - rho_exact) over the tube, per unit length (classic Sod, t = 0.2).
double density_l1_error(int cells) {
  auto pb = run_problem("sod.yaml", {"grid.cells=[" + std::to_string(cells) + ",1,1]"}, MPI_COMM_SELF,
                        scratch_dir("sod_" + std::to_string(cells)));
  EXPECT_NEAR(pb->time, 0.2, 1e-12);
  const ExactRiemann exact({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
  const auto rho = profile(*pb, "rho_CC", 0, 0);
  const double dx = 1.0 / cells;
  double l1 = 0;
  for (int i = 0; i < cells; ++i) {
    const double x = (i + 0.5) * dx;
    l1 += std::abs(rho[i] - exact.sample((x - 0.5) / 0.2).rho) * dx;
  }
  return l1;
}

}  // namespace

TEST(Sod, ExactStarState) {
  // The solver of the test itself, against the values in mpmice-algorithm.md 11.4.
  const ExactRiemann classic({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
  EXPECT_NEAR(classic.p_star, 0.30313, 1e-5);
  EXPECT_NEAR(classic.u_star, 0.92745, 1e-5);
  const ExactRiemann si({1.1768293, 0.0, 101325}, {0.11768293, 0.0, 10132.5}, 1.4);
  EXPECT_NEAR(si.p_star, 28859, 1.0);
  EXPECT_NEAR(si.u_star, 285.11, 0.01);
}

TEST(Sod, DensityErrorAndConvergence) {
  const int cells[3] = {100, 200, 400};
  double err[3];
  for (int r = 0; r < 3; ++r) {
    err[r] = density_l1_error(cells[r]);
    std::printf("Sod: %4d cells  L1(rho - exact) = %.5f\n", cells[r], err[r]);
  }
  // Acceptance of the ICE issue: at 400 cells the L1 error is within 1% of the left
  // density (rho_L = 1).
  EXPECT_LE(err[2], 0.01);
  // Least-squares slope of log(err) against log(h) over the three resolutions; with a
  // shock and a contact the best a consistent scheme reaches is about 1 (shock) and
  // 1/2 to 2/3 (contact, smeared); 0.6 is the bound.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int r = 0; r < 3; ++r) {
    const double x = std::log(1.0 / cells[r]), y = std::log(err[r]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double order = (3 * sxy - sx * sy) / (3 * sxx - sx * sx);
  std::printf("Sod: observed order %.3f\n", order);
  EXPECT_GE(order, 0.6);
  EXPECT_LT(err[1], err[0]);
  EXPECT_LT(err[2], err[1]);
}

TEST(Sod, SameAlongXYZ) {
  const int n = 200;
  const std::string cells = std::to_string(n);
  auto x = run_problem("sod.yaml", {"grid.cells=[" + cells + ",1,1]"}, MPI_COMM_SELF, scratch_dir("sod_x"));
  auto y = run_problem("sod_y.yaml", {"grid.cells=[1," + cells + ",1]"}, MPI_COMM_SELF, scratch_dir("sod_y"));
  auto z = run_problem("sod_z.yaml", {"grid.cells=[1,1," + cells + "]"}, MPI_COMM_SELF, scratch_dir("sod_z"));
  for (const char* field : {"rho_CC", "temp_CC", "press_CC"}) {
    const auto px = profile(*x, field, 0, 0), py = profile(*y, field, 0, 1), pz = profile(*z, field, 0, 2);
    double worst = 0;
    for (int i = 0; i < n; ++i)
      worst = std::max({worst, std::abs(px[i] - py[i]) / std::abs(px[i]), std::abs(px[i] - pz[i]) / std::abs(px[i])});
    // Round-off: the three runs do the same arithmetic in a different direction.
    EXPECT_LE(worst, 1e-13) << field;
  }
  const auto ux = profile(*x, "vel_CC_x", 0, 0), uy = profile(*y, "vel_CC_y", 0, 1),
             uz = profile(*z, "vel_CC_z", 0, 2);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(ux[i], uy[i], 1e-13);
    EXPECT_NEAR(ux[i], uz[i], 1e-13);
  }
}
