// A hot gas disc in a closed box (problems/hot_blob.yaml), two materials, 500 steps:
// every material's mass is conserved to 1e-12 relative (round-off: the walls let
// nothing through and advection only moves mass between cells), and each material's
// momentum, zero by the problem's mirror symmetry, stays below 1e-12 of M c (mass
// times the largest sound speed, the scale momentum errors would have). The energy
// drift (ICE's internal-energy form does not conserve total energy exactly) is printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "diagnostics.hpp"
#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

TEST(HotBlob, ConservesMassAndMomentum) {
  const std::string dir = scratch_dir("hot_blob");
  auto pb = run_problem("hot_blob.yaml", {}, MPI_COMM_SELF, dir);
  ASSERT_EQ(pb->step, 500);
  const auto history = read_csv(dir + "/history.csv").rows;
  ASSERT_EQ(history.size(), 501u);
  const auto& first = history.front();
  const auto& last = history.back();
  const double c_max = std::sqrt(1.4 * 0.4 * 717.5 * 900.0);
  for (int m = 0; m < 3; ++m) {  // air, hot, total
    const int col = 3 + 5 * m;
    const double mass0 = first[col];
    double worst_mass = 0, worst_mom = 0;
    for (const auto& row : history) {
      worst_mass = std::max(worst_mass, std::abs(row[col] - mass0) / mass0);
      for (int d = 1; d <= 3; ++d) worst_mom = std::max(worst_mom, std::abs(row[col + d]) / (mass0 * c_max));
    }
    EXPECT_LE(worst_mass, 1e-12) << "material column " << col;
    EXPECT_LE(worst_mom, 1e-12) << "material column " << col;
  }
  const double e0 = first[3 + 5 * 2 + 4], e1 = last[3 + 5 * 2 + 4];
  std::printf("hot blob: total energy %.6e J -> %.6e J over 500 steps (drift %+.3f%%)\n", e0, e1,
              100 * (e1 - e0) / e0);
}
