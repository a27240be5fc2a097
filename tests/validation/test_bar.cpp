// Axial vibration of an elastic bar (problems/bar.yaml): the period of the first mode
// from the centre-of-mass velocity in history.csv within 1% of 4/c (pi c / 2 angular
// frequency), its amplitude 2 v0/pi, and the total energy (strain + kinetic) within
// 2% of the initial value over 5 periods.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

TEST(Bar, PeriodAmplitudeAndEnergy) {
  const std::string dir = scratch_dir("bar");
  auto pb = run_problem("bar.yaml", {}, MPI_COMM_SELF, dir);
  const auto history = read_csv(dir + "/history.csv").rows;
  const double c = std::sqrt(1.0e6 / 1000.0), v0 = 0.01 * c;
  const double period = 4.0 / c;  // 2 pi / (pi c / 2) for a bar of length 1
  std::vector<double> crossings;
  double vmax = 0, e0 = history.front()[7], worst_energy = 0;
  for (std::size_t r = 1; r < history.size(); ++r) {
    const double t0 = history[r - 1][1], t1 = history[r][1];
    const double v_a = history[r - 1][4] / history[r - 1][3], v_b = history[r][4] / history[r][3];
    if (v_a > 0 && v_b <= 0) crossings.push_back(t0 + (t1 - t0) * v_a / (v_a - v_b));
    vmax = std::max(vmax, std::abs(v_b));
    worst_energy = std::max(worst_energy, std::abs(history[r][7] - e0) / e0);
  }
  ASSERT_GE(crossings.size(), 6u) << "fewer than 5 periods";
  const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  std::printf("bar: period %.6f s (exact %.6f, %+.3f%%), centre-of-mass amplitude %.5f m/s (exact %.5f), "
              "largest energy change %.3f%%\n",
              measured, period, 100 * (measured - period) / period, vmax, 2 * v0 / M_PI, 100 * worst_energy);
  EXPECT_NEAR(measured, period, 0.01 * period);
  EXPECT_NEAR(vmax, 2 * v0 / M_PI, 0.01 * 2 * v0 / M_PI);
  EXPECT_LE(worst_energy, 0.02);
}
