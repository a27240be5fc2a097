// Two elastic disks collide (problems/disks.yaml): total momentum, zero at the start,
// stays zero through the collision to the round-off of the order-independent sums, and
// both disks rebound (each disk's momentum along the approach direction changes sign).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <mpmice/kernels/particle_grid.hpp>

#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

TEST(Disks, MomentumConservedAndBothRebound) {
  const std::string dir = scratch_dir("disks");
  auto pb = run_problem("disks.yaml", {}, MPI_COMM_SELF, dir);
  const auto history = read_csv(dir + "/history.csv").rows;
  const double mass = history.front()[3];
  const double scale = mass * std::sqrt(0.1 * 0.1 + 0.1 * 0.1);
  double worst = 0;
  for (const auto& row : history)
    for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(row[4 + d]) / scale);
  // The bound: every particle's contribution to a node sum is rounded to a quantum of
  // 2^-40 of the largest contribution (quanta.hpp), about 2^-40 m |v0| for momentum and
  // likewise for the internal force's impulse. With N particles, up to 27 nodes each,
  // both scatters and all steps, these independent roundings (standard deviation
  // q / sqrt(12) each) add up to sigma = sqrt(2 27 N steps / 12) 2^-40 / N of M |v0|
  // (1.6e-12 here; measured: 0.7e-12 before the weights' rounding changed in session 8,
  // 1.4e-12 then, 1.9e-13 in session 16). The test allows 10 sigma: a real leak of momentum,
  // such as a node force without mass, is orders of magnitude larger.
  const double n = double(pb->particles[0].size()), steps = double(history.size() - 1);
  const double sigma = std::sqrt(2.0 * 27.0 * n * steps / 12.0) * std::ldexp(1.0, -40) / n;
  std::printf("disks: largest |total momentum| / (M |v0|) = %.3e over %.0f steps (rounding sigma %.2e)\n", worst,
              steps, sigma);
  EXPECT_LE(worst, 10 * sigma);

  // Each disk's momentum along (1, 1)/sqrt(2): the lower-left disk started at +,
  // the upper-right one at -; after the rebound both have changed sign.
  const ParticleSet& ps = pb->particles[0];
  auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  double p_lower = 0, p_upper = 0;
  for (std::size_t q = 0; q < ps.size(); ++q) {
    const double along = (data(q, column(ParticleField::vx)) + data(q, column(ParticleField::vy))) / std::sqrt(2.0);
    const double m = data(q, column(ParticleField::mass));
    if (data(q, column(ParticleField::x)) + data(q, column(ParticleField::y)) < 1.0)
      p_lower += m * along;
    else
      p_upper += m * along;
  }
  std::printf("disks: momentum along the approach after the collision: lower %.4f, upper %.4f kg m/s "
              "(initially %+.4f, %+.4f)\n", p_lower, p_upper, 0.5 * scale, -0.5 * scale);
  EXPECT_LT(p_lower, -0.1 * 0.5 * scale);
  EXPECT_GT(p_upper, 0.1 * 0.5 * scale);
}
