// MPM kernels: shape functions (partition of unity, linear reproduction), the
// particle-grid transfers' conservation, the particle-state check, and the
// constitutive models against closed forms under homogeneous deformation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <mpmice/kernels/bad_particles.hpp>
#include <mpmice/kernels/g2p.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/internal_force.hpp>
#include <mpmice/kernels/p2g.hpp>
#include <mpmice/kernels/particle_sort.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/stress_update.hpp>
#include <mpmice/kernels/trilinear.hpp>

using namespace mpmice;

namespace {

// A patch with 2 ghost layers over a whole grid of `cells` cells of size `spacing`.
Patch whole_patch(std::array<int, 3> cells, std::array<double, 3> spacing) {
  Grid g;
  g.cells = cells;
  g.spacing = spacing;
  return whole_grid_patch(g, 2);
}

// Node sums of one material over the patch's nodes.
NodeSums node_sums(const Patch& patch) {
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  return NodeSums{node("m"), {node("px"), node("py"), node("pz")}, node("mT"), node("V"),
                  {node("fx"), node("fy"), node("fz")}};
}

// The velocity gradient of the g2p tests, 1/s, and node velocities v = A x + b (each
// component b) on every node of the patch: a linear field, which g2p reproduces.
constexpr double velocity_gradient[3][3] = {{0.1, -0.2, 0.05}, {0.3, 0.0, -0.1}, {0.02, 0.04, -0.3}};
void fill_linear_velocity(const Patch& patch, const NodeGrid& grid, const VectorField4& vs, double b) {
  for (int d = 0; d < 3; ++d) {
    auto v = vs[d];
    const double a0 = velocity_gradient[d][0], a1 = velocity_gradient[d][1], a2 = velocity_gradient[d][2];
    Kokkos::parallel_for("linear", patch.ghosted_nodes(2).policy(), KOKKOS_LAMBDA(int i, int j, int k) {
      v(0, i, j, k) = a0 * (grid.lower[0] + i * grid.h[0]) + a1 * (grid.lower[1] + j * grid.h[1]) +
                      a2 * (grid.lower[2] + k * grid.h[2]) + b;
    });
  }
}

template <class Shape>
void check_partition_and_linear(double half_width) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(3.0, 6.0);
  const double lower[3] = {-0.2, 0.1, 0.0}, h[3] = {0.1, 0.2, 0.05};
  const double inv_h[3] = {1 / h[0], 1 / h[1], 1 / h[2]}, half[3] = {half_width, half_width, half_width};
  for (int trial = 0; trial < 2000; ++trial) {
    double x[3];
    for (int d = 0; d < 3; ++d) x[d] = lower[d] + u(rng) * h[d];
    const ParticleWeights<Shape> wt(x, lower, inv_h, half);
    // sum S = 1, sum S X_i = x, sum grad S = 0, sum X_i (x) grad S = I.
    double sum = 0, first[3] = {0, 0, 0}, gsum[3] = {0, 0, 0}, gx[3][3] = {};
    for (int a = 0; a < Shape::nodes; ++a)
      for (int b = 0; b < Shape::nodes; ++b)
        for (int c = 0; c < Shape::nodes; ++c) {
          const double S = wt.weight(a, b, c);
          double g[3];
          wt.gradient(a, b, c, g);
          const double X[3] = {lower[0] + (wt.first[0] + a) * h[0], lower[1] + (wt.first[1] + b) * h[1],
                               lower[2] + (wt.first[2] + c) * h[2]};
          sum += S;
          for (int d = 0; d < 3; ++d) {
            first[d] += S * X[d];
            gsum[d] += g[d];
            for (int e = 0; e < 3; ++e) gx[d][e] += X[d] * g[e];
          }
        }
    ASSERT_NEAR(sum, 1.0, 1e-13);
    for (int d = 0; d < 3; ++d) {
      ASSERT_NEAR(first[d], x[d], 1e-13);
      ASSERT_NEAR(gsum[d] * h[d], 0.0, 1e-13);
      for (int e = 0; e < 3; ++e) ASSERT_NEAR(gx[d][e], d == e ? 1.0 : 0.0, 1e-12);
    }
  }
}

}  // namespace

TEST(Shape, LinearPartitionOfUnityAndLinearReproduction) { check_partition_and_linear<LinearShape>(0.0); }
TEST(Shape, GimpPartitionOfUnityAndLinearReproduction) {
  for (double l : {0.25, 1.0 / 6.0, 0.5}) check_partition_and_linear<GimpShape>(l);
}

// Random particles: node mass and momentum totals equal particle totals; a grid
// velocity that is linear in x is gathered back exactly (rigid motion), and the node
// sums do not depend on the thread count beyond round-off.
template <class Shape>
void transfer_test() {
  const Patch patch = whole_patch({8, 6, 5}, {0.1, 0.1, 0.1});
  const Grid& g = patch.grid;
  const NodeGrid grid = node_grid(patch);
  const long n = 5000;
  ParticleSet ps("solid", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double mass = 0, mom[3] = {0, 0, 0};
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
    for (int d = 0; d < 3; ++d) {
      h(p, column(ParticleField::x) + d) = (0.5 + u(rng) * (g.cells[d] - 1)) * g.spacing[d];
      h(p, column(ParticleField::vx) + d) = u(rng) - 0.5;
      h(p, column(ParticleField::size_x) + d) = 0.5;
    }
    h(p, column(ParticleField::mass)) = 0.5 + u(rng);
    h(p, column(ParticleField::volume)) = 1e-4;
    mass += h(p, column(ParticleField::mass));
    for (int d = 0; d < 3; ++d) mom[d] += h(p, column(ParticleField::mass)) * h(p, column(ParticleField::vx) + d);
  }
  Kokkos::deep_copy(ps.data(), h);
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  const NodeSums sums = node_sums(patch);
  p2g<Shape>(grid, n, ps.data(), 0, sums);
  auto total = [&](const Field4& f) {
    double s = 0;
    Kokkos::parallel_reduce("sum", patch.ghosted_nodes(2).policy(),
                            KOKKOS_LAMBDA(int i, int j, int k, double& t) { t += f(0, i, j, k); }, s);
    return s;
  };
  const double nodes = double(patch.ghosted_nodes(2).size());
  EXPECT_NEAR(total(sums.mass) - nodes * 1e-200, mass, 1e-13 * mass);
  // Node by node against a serial sum on the host: whatever the thread count, the
  // scatter differs from it only by round-off.
  {
    auto node_mass = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sums.mass);
    Kokkos::View<double****, Kokkos::HostSpace> serial("serial", 1, node_mass.extent(1), node_mass.extent(2),
                                                         node_mass.extent(3));
    for (long p = 0; p < n; ++p) {
      double x[3], half[3];
      for (int d = 0; d < 3; ++d) {
        x[d] = h(p, column(ParticleField::x) + d);
        half[d] = 0.5 * h(p, column(ParticleField::size_x) + d);
      }
      const ParticleWeights<Shape> wt(x, grid.lower, grid.inv_h, half);
      for (int a = 0; a < Shape::nodes; ++a)
        for (int b = 0; b < Shape::nodes; ++b)
          for (int c = 0; c < Shape::nodes; ++c)
            serial(0, wt.first[0] + a, wt.first[1] + b, wt.first[2] + c) +=
                wt.weight(a, b, c) * h(p, column(ParticleField::mass));
    }
    double worst = 0;
    for (std::size_t i = 0; i < serial.extent(1); ++i)
      for (std::size_t j = 0; j < serial.extent(2); ++j)
        for (std::size_t k = 0; k < serial.extent(3); ++k)
          worst = std::max(worst, std::abs(node_mass(0, i, j, k) - 1e-200 - serial(0, i, j, k)));
    EXPECT_LE(worst, 1e-14 * mass) << "threads " << ExecSpace().concurrency();
  }
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(total(sums.mom[d]), mom[d], 1e-13 * mass);

  // Gather of a linear velocity field v = A x + b: particles get it exactly, and L = A.
  VectorField4 vs{node("vsx"), node("vsy"), node("vsz")}, acc{node("ax"), node("ay"), node("az")};
  const auto& A = velocity_gradient;
  fill_linear_velocity(patch, grid, vs, 1.0);
  for (long p = 0; p < n; ++p)
    for (int d = 0; d < 3; ++d) h(p, column(ParticleField::F00) + 4 * d) = 1.0;
  Kokkos::deep_copy(ps.data(), h);
  // The positions before the update (a host mirror may alias the particle data).
  std::vector<double> x0(3 * n);
  for (long p = 0; p < n; ++p)
    for (int d = 0; d < 3; ++d) x0[3 * p + d] = h(p, column(ParticleField::x) + d);
  const double dt = 1e-3;
  g2p<Shape>(grid, n, ps.data(), 0, dt, 1.0, false, {0, 0, 0}, ConstVectorField4{vs[0], vs[1], vs[2]},
             ConstVectorField4{acc[0], acc[1], acc[2]});
  auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  for (long p = 0; p < n; p += 97) {
    double x[3];
    for (int d = 0; d < 3; ++d) x[d] = x0[3 * p + d];
    for (int d = 0; d < 3; ++d) {
      const double v = A[d][0] * x[0] + A[d][1] * x[1] + A[d][2] * x[2] + 1.0;
      EXPECT_NEAR(after(p, column(ParticleField::vx) + d), v, 1e-13);  // PIC fraction 1
      EXPECT_NEAR(after(p, column(ParticleField::x) + d), x[d] + dt * v, 1e-13);
      for (int e = 0; e < 3; ++e) EXPECT_NEAR(after(p, tensor_column(ParticleField::L00, d, e)), A[d][e], 1e-11);
    }
  }
}

TEST(Transfer, LinearConservesAndReproduces) { transfer_test<LinearShape>(); }

// The interpolant over a cell (trilinear.hpp) is the linear shape's sum: at random
// points of a cell with random node values in [-1, 1], its value and slopes against
// sum_i S_i f_i and sum_i dS_i/dr f_i formed from the 1D weights (1 - r, r) and their
// derivatives (-1, 1). Both are sums of 8 terms of at most 1 with a few roundings each:
// 1e-14 is about 50 ulp of 1, and an interpolant with any coefficient wrong by a node
// value's share misses by far more. A uniform field gives its value and zero slopes
// exactly (g2p: a body at rest stays at rest without round-off).
TEST(Transfer, TrilinearIsTheLinearShapesSum) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int round = 0; round < 1000; ++round) {
    double f[8];
    for (double& value : f) value = 2 * u(rng) - 1;
    double c[8], c4[8 * 4];  // the coefficients alone, and as the third of 4 cells side by side
    trilinear::coefficients(f, c);
    trilinear::coefficients<4>(f, c4 + 2);
    const double r[3] = {u(rng), u(rng), u(rng)};
    double sum = 0, slope_sum[3] = {0, 0, 0};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const double w[3] = {a ? r[0] : 1 - r[0], b ? r[1] : 1 - r[1], c ? r[2] : 1 - r[2]};
          const double dw[3] = {a ? 1.0 : -1.0, b ? 1.0 : -1.0, c ? 1.0 : -1.0};
          const double fi = f[4 * a + 2 * b + c];
          sum += w[0] * w[1] * w[2] * fi;
          slope_sum[0] += dw[0] * w[1] * w[2] * fi;
          slope_sum[1] += w[0] * dw[1] * w[2] * fi;
          slope_sum[2] += w[0] * w[1] * dw[2] * fi;
        }
    double slope[3], slope4[3];
    const double value = trilinear::value(c, r[0], r[1], r[2], slope);
    EXPECT_EQ(trilinear::value(c, r[0], r[1], r[2]), value);
    EXPECT_EQ(trilinear::value<4>(c4 + 2, r[0], r[1], r[2], slope4), value);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(slope4[d], slope[d]);
    worst = std::max(worst, std::abs(value - sum));
    for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(slope[d] - slope_sum[d]));
  }
  EXPECT_LE(worst, 1e-14);
  const double uniform[8] = {0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3};
  double c[8], slope[3];
  trilinear::coefficients(uniform, c);
  EXPECT_EQ(trilinear::value(c, 0.1, 0.7, 0.9, slope), 0.3);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(slope[d], 0.0);
}
TEST(Transfer, GimpConservesAndReproduces) { transfer_test<GimpShape>(); }

// (E36) over n sub-steps: the vector loop decides n = 1 (one_deformation_step) without
// the integer count, so the two must agree at every |L| dt, the boundary 1 included.
TEST(Deformation, OneStepTestAgreesWithTheSubstepCount) {
  const double below_one = std::nextafter(1.0, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double s : {0.0, 0.25, 0.5, below_one, 1.0, 1.5, 2.0, 7.25, 1e6, 0x1p30, 1e150, inf, nan}) {
    Mat3 L = Mat3::zero();
    L(0, 1) = s;  // |L| dt = s with dt = 1 (sqrt(s^2) is s exactly, up to 1e150)
    EXPECT_EQ(one_deformation_step(L, 1.0), deformation_substeps(L, 1.0) == 1) << "|L| dt = " << s;
  }
  // The count itself: 2 floor(|L| dt), at least 1 and at most 10000.
  auto count = [](double s) {
    Mat3 L = Mat3::zero();
    L(2, 0) = s;
    return deformation_substeps(L, 1.0);
  };
  EXPECT_EQ(count(0.0), 1);
  EXPECT_EQ(count(nan), 1);
  EXPECT_EQ(count(below_one), 1);
  EXPECT_EQ(count(1.0), 2);
  EXPECT_EQ(count(7.25), 14);
  EXPECT_EQ(count(5000.0), 10000);
  EXPECT_EQ(count(0x1p30), 10000);
  EXPECT_EQ(count(inf), 10000);
}

// g2p's deformation in a uniform velocity gradient A (nodes v = A x): with |A| dt < 1
// one sub-step, F = I + dt L; with |A| dt = 5.5, ten (2 floor(|L| dt)),
// F = (I + dt L / 10)^10 (the second, scalar pass), and V scales by det F. L is A to
// round-off (transfer_test); F and V are compared with the same formula applied to the
// stored L, so the tolerance is the rounding of ten 3 x 3 products of entries of order
// 1 (|F| about 2 here): 1e-12 relative, some 50 times their rounding.
TEST(Deformation, LargeVelocityGradientIsSubstepped) {
  const Patch patch = whole_patch({6, 6, 6}, {0.1, 0.1, 0.1});
  const NodeGrid grid = node_grid(patch);
  const long n = 300;
  ParticleSet ps("solid", n);
  ps.resize(n);
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  VectorField4 vs{node("vsx"), node("vsy"), node("vsz")}, acc{node("ax"), node("ay"), node("az")};
  fill_linear_velocity(patch, grid, vs, 0.0);
  double norm = 0;
  for (int d = 0; d < 3; ++d)
    for (int e = 0; e < 3; ++e) norm += velocity_gradient[d][e] * velocity_gradient[d][e];
  norm = std::sqrt(norm);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(1.0, 5.0);
  for (double dt : {0.5 / norm, 5.5 / norm}) {
    auto h = Kokkos::create_mirror_view(ps.data());
    for (long p = 0; p < n; ++p) {
      for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
      for (int d = 0; d < 3; ++d) {
        h(p, column(ParticleField::x) + d) = u(rng) * 0.1;
        h(p, column(ParticleField::size_x) + d) = 0.5;
        h(p, column(ParticleField::F00) + 4 * d) = 1.0;
      }
      h(p, column(ParticleField::mass)) = 1.0;
      h(p, column(ParticleField::volume)) = 1e-4;
    }
    Kokkos::deep_copy(ps.data(), h);
    g2p<LinearShape>(grid, n, ps.data(), 0, dt, 0.0, false, {0, 0, 0}, ConstVectorField4{vs[0], vs[1], vs[2]},
                     ConstVectorField4{acc[0], acc[1], acc[2]});
    auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
    for (long p = 0; p < n; ++p) {
      Mat3 L;
      for (int d = 0; d < 3; ++d)
        for (int e = 0; e < 3; ++e) L(d, e) = after(p, tensor_column(ParticleField::L00, d, e));
      const int steps = deformation_substeps(L, dt);
      ASSERT_EQ(steps, dt * norm < 1 ? 1 : 10) << "particle " << p;
      const Mat3 F = deformation_increment(L, dt), F_one = Mat3::identity() + dt * L;
      double scale = 0, worst = 0, from_one = 0;
      for (int d = 0; d < 3; ++d)
        for (int e = 0; e < 3; ++e) {
          const double got = after(p, tensor_column(ParticleField::F00, d, e));
          scale = std::max(scale, std::abs(F(d, e)));
          worst = std::max(worst, std::abs(got - F(d, e)));
          from_one = std::max(from_one, std::abs(got - F_one(d, e)));
        }
      ASSERT_LE(worst, 1e-12 * scale) << "particle " << p << ", " << steps << " sub-steps";
      if (steps > 1) ASSERT_GT(from_one, 0.1 * scale) << "particle " << p << ": one step, not " << steps;
      EXPECT_NEAR(after(p, column(ParticleField::volume)), 1e-4 * F.det(), 1e-12 * 1e-4 * std::abs(F.det()));
    }
  }
}

// g2p takes the heat rate and the transfers' energy together (MPMICE) or neither (MPM
// alone); one without the other is refused before any particle changes.
TEST(Transfer, G2pTakesTheHeatRateAndTheTransfersTogether) {
  const Patch patch = whole_patch({4, 4, 4}, {0.1, 0.1, 0.1});
  const NodeGrid grid = node_grid(patch);
  ParticleSet ps("solid", 1);
  ps.resize(1);
  auto h = Kokkos::create_mirror_view(ps.data());
  for (int c = 0; c < particle_field_count; ++c) h(0, c) = 0.0;
  for (int d = 0; d < 3; ++d) {
    h(0, column(ParticleField::x) + d) = 0.2;
    h(0, column(ParticleField::size_x) + d) = 0.5;
    h(0, column(ParticleField::F00) + 4 * d) = 1.0;
  }
  h(0, column(ParticleField::mass)) = 1.0;
  h(0, column(ParticleField::volume)) = 1e-3;
  Kokkos::deep_copy(ps.data(), h);
  const auto before = Kokkos::create_mirror(ps.data());  // a copy, unlike a host mirror view
  Kokkos::deep_copy(before, ps.data());
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  const Field4 zero = node("zero"), one = node("one"), rate = node("rate");
  Kokkos::deep_copy(one, 1.0);  // an acceleration that a run would add into the velocity
  const ConstVectorField4 still{zero, zero, zero}, pushed{one, one, one};
  const TransferHeat transfer{node("energy"), 400.0};
  EXPECT_THROW(g2p<LinearShape>(grid, 1, ps.data(), 0, 1e-3, 0.0, false, {0, 0, 0}, still, pushed, rate),
               std::invalid_argument);
  EXPECT_THROW(g2p<GimpShape>(grid, 1, ps.data(), 0, 1e-3, 0.0, false, {0, 0, 0}, still, pushed, ConstField4(),
                              transfer),
               std::invalid_argument);
  const auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  for (int c = 0; c < particle_field_count; ++c) EXPECT_EQ(after(0, c), before(0, c)) << "column " << c;
  // Both given, it runs: v += dt a.
  EXPECT_NO_THROW(
      g2p<LinearShape>(grid, 1, ps.data(), 0, 1e-3, 0.0, false, {0, 0, 0}, still, pushed, rate, transfer));
  EXPECT_DOUBLE_EQ(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data())(0, column(ParticleField::vx)),
                   1e-3);
}

// p2g, g2p and a plain host loop must compute the same weights to the last bit (the
// momentum g2p gives back balances what p2g took only then; shape.hpp). Particles sit
// four cells apart, so a node's mass is one particle's weight times its mass of 1,
// exactly; with an acceleration of 1 on every node, g2p's velocity change with GIMP is
// its sum of weights, added in the host loop's order, direction by direction (g2p never
// forms GIMP's 3D weights; its sums over k, then j, then i of the 1D weights,
// G2pParticle::sum_by_direction). Before shape.hpp avoided it, GCC fused products into
// FMAs differently in the vectorised g2p: half the particles differed in the last bit.
// With the linear shape g2p forms no weights either: it evaluates the interpolant over
// the particle's cell (trilinear.hpp), which for a uniform field is the field's value,
// exactly 1 here; its position enters through the same 1D weights (r = w[1]).
template <class Shape>
void weights_agree_test() {
  const Patch patch = whole_patch({16, 16, 16}, {0.1, 0.2, 0.05});
  const Grid& g = patch.grid;
  const NodeGrid grid = node_grid(patch);
  const long n = 4 * 4 * 4;
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  const NodeSums sums = node_sums(patch);
  const Field4 zero = node("zero"), one = node("one");
  Kokkos::deep_copy(one, 1.0);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long mismatched_p2g = 0, mismatched_g2p = 0;
  for (int round = 0; round < 100; ++round) {
    ParticleSet ps("solid", n);
    ps.resize(n);
    auto h = Kokkos::create_mirror_view(ps.data());
    for (long p = 0; p < n; ++p) {
      for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
      const long cell[3] = {4 * (p / 16) + 1, 4 * (p / 4 % 4) + 1, 4 * (p % 4) + 1};
      for (int d = 0; d < 3; ++d) {
        h(p, column(ParticleField::x) + d) = (cell[d] + u(rng)) * g.spacing[d];
        h(p, column(ParticleField::size_x) + d) = 0.2 + 0.8 * u(rng);  // GIMP half-width 0.1 .. 0.5 cells
        h(p, column(ParticleField::F00) + 4 * d) = 1.0;
      }
      h(p, column(ParticleField::mass)) = 1.0;
    }
    Kokkos::deep_copy(ps.data(), h);
    p2g<Shape>(grid, n, ps.data(), 0, sums);
    g2p<Shape>(grid, n, ps.data(), 0, 1.0, 0.0, false, {0, 0, 0}, ConstVectorField4{zero, zero, zero},
               ConstVectorField4{one, one, one});
    auto mass = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sums.mass);
    auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
    for (long p = 0; p < n; ++p) {
      double x[3], half[3];
      for (int d = 0; d < 3; ++d) {
        x[d] = h(p, column(ParticleField::x) + d);
        half[d] = 0.5 * h(p, column(ParticleField::size_x) + d);
      }
      const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
      double sum = 0;
      bool p2g_same = true;
      for (int a = 0; a < Shape::nodes; ++a)
        for (int b = 0; b < Shape::nodes; ++b)
          for (int c = 0; c < Shape::nodes; ++c) {
            const double S = wt.weight(a, b, c);
            if (S == 0.0) continue;
            sum += S;
            p2g_same = p2g_same && mass(0, wt.first[0] + a, wt.first[1] + b, wt.first[2] + c) == 1e-200 + S;
          }
      if (Shape::nodes == 2) sum = 1.0;  // the linear shape's interpolant of a uniform field: exact
      if (Shape::nodes == 3) {
        sum = 0;
        for (int a = 0; a < Shape::nodes; ++a) {
          double over_jk = 0;
          for (int b = 0; b < Shape::nodes; ++b) {
            double over_k = 0;
            for (int c = 0; c < Shape::nodes; ++c) over_k += wt.w[2][c] * 1.0;
            over_jk += wt.w[1][b] * over_k;
          }
          sum += wt.w[0][a] * over_jk;
        }
      }
      mismatched_p2g += p2g_same ? 0 : 1;
      mismatched_g2p += after(p, column(ParticleField::vx)) == sum ? 0 : 1;
    }
  }
  EXPECT_EQ(mismatched_p2g, 0) << "of " << 100 * n << " particles";
  EXPECT_EQ(mismatched_g2p, 0) << "of " << 100 * n << " particles";
}

TEST(Transfer, LinearWeightsAgreeBetweenKernels) { weights_agree_test<LinearShape>(); }
TEST(Transfer, GimpWeightsAgreeBetweenKernels) { weights_agree_test<GimpShape>(); }

// Particles for the cell-run tests: 0 to 11 in each cell of the patch in cell order,
// 40 more in the first, the last quarter shuffled (runs of many, one and no particles,
// one longer than a block of the scatters by cell runs, and an unsorted tail).
// Every column is 0 but the position, the mass (every 7th particle a trace of 2e-12 kg,
// whose far nodes' share of the mass rounds to zero, else 0.5 to 1.5 kg) and the volume
// (0.5e-4 to 1.5e-4 m^3); `more(h, p, u)` sets particle p's other columns in the host
// copy h from uniform draws u() in [0, 1). With `around_nodes`, GIMP's windows: 0 to 11
// in the cell around each node (half a cell either side, so also in the ghost cells
// next to the patch), in node order.
template <class More>
ParticleSet cell_run_particles(const Patch& patch, std::mt19937_64& rng, const More& more, bool around_nodes = false) {
  const Grid& g = patch.grid;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto u = [&] { return uniform(rng); };
  const int extra = around_nodes ? 1 : 0;
  const double shift = around_nodes ? 0.5 : 0.0;
  std::vector<std::array<double, 3>> at;
  for (int i = 0; i < g.cells[0] + extra; ++i)
    for (int j = 0; j < g.cells[1] + extra; ++j)
      for (int k = 0; k < g.cells[2] + extra; ++k)
        for (int c = int(u() * 12) + (i + j + k == 0 ? 40 : 0); c > 0; --c)
          at.push_back({(i - shift + u()) * g.spacing[0], (j - shift + u()) * g.spacing[1],
                        (k - shift + u()) * g.spacing[2]});
  std::shuffle(at.begin() + long(at.size()) * 3 / 4, at.end(), rng);
  const long n = long(at.size());
  ParticleSet ps("solid", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
    for (int d = 0; d < 3; ++d) h(p, column(ParticleField::x) + d) = at[p][d];
    h(p, column(ParticleField::mass)) = p % 7 == 0 ? 2e-12 : 0.5 + u();
    h(p, column(ParticleField::volume)) = 1e-4 * (0.5 + u());
    more(h, p, u);
  }
  Kokkos::deep_copy(ps.data(), h);
  return ps;
}

// Particles exactly on node planes (the spacing a power of two, so their cell fraction
// is exactly 0 along some directions): the nodes beyond such a plane have a weight of
// 0 but, with the linear shape, a gradient of +-1/h along it, and L = sum v_i (x) grad
// S_ip needs them (without them a uniform velocity v gave L = -v/h along the plane's
// normal). With a linear velocity field v = A x + b on the nodes, every particle must
// get v and L = A, read in groups (runs of particles by cell, so groups take
// ReadWindows) and particle by particle. Tolerances as transfer_test's (round-off of
// sums of 8 or 27 products of entries of order 1, and for L of velocities divided by
// h = 1/8).
template <class Shape>
void expect_node_plane_gradients() {
  const Patch patch = whole_patch({8, 6, 5}, {0.125, 0.125, 0.125});
  const NodeGrid grid = node_grid(patch);
  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  VectorField4 vs{node("vsx"), node("vsy"), node("vsz")}, acc{node("ax"), node("ay"), node("az")};
  fill_linear_velocity(patch, grid, vs, 1.0);
  const auto& A = velocity_gradient;
  for (bool in_groups : {true, false}) {
    std::mt19937_64 rng(31);  // the same particles both ways
    long on_plane = 0;
    const ParticleSet ps = cell_run_particles(patch, rng, [&](auto& h, long p, auto& u) {
      bool plane = false;
      for (int d = 0; d < 3; ++d) {
        double& x = h(p, column(ParticleField::x) + d);
        const bool on = u() < 0.5;  // onto its cell's lower node plane
        x = on ? std::floor(x / 0.125) * 0.125 : x;
        plane = plane || on;
        h(p, column(ParticleField::size_x) + d) = 0.5;
        h(p, column(ParticleField::F00) + 4 * d) = 1.0;
      }
      on_plane += plane;
    });
    const long n = long(ps.size());
    ASSERT_GT(on_plane, n / 2);
    // The positions before the update (a host mirror may alias the particle data).
    auto before = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
    std::vector<double> x0(3 * n);
    for (long p = 0; p < n; ++p)
      for (int d = 0; d < 3; ++d) x0[3 * p + d] = before(p, column(ParticleField::x) + d);
    detail::g2p_deforming<Shape, false>(grid, n, ps.data(), 0, 1e-3, 1.0, ConstVectorField4{vs[0], vs[1], vs[2]},
                                        ConstVectorField4{acc[0], acc[1], acc[2]}, ConstField4(), TransferHeat(),
                                        in_groups);
    auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
    for (long p = 0; p < n; ++p) {
      const double* x = &x0[3 * p];
      for (int d = 0; d < 3; ++d) {
        const double v = A[d][0] * x[0] + A[d][1] * x[1] + A[d][2] * x[2] + 1.0;
        ASSERT_NEAR(after(p, column(ParticleField::vx) + d), v, 1e-13)
            << "particle " << p << ", in groups " << in_groups;
        for (int e = 0; e < 3; ++e)
          ASSERT_NEAR(after(p, tensor_column(ParticleField::L00, d, e)), A[d][e], 1e-11)
              << "particle " << p << " at (" << x[0] << ", " << x[1] << ", " << x[2] << "), L(" << d << ", " << e
              << "), in groups " << in_groups;
      }
    }
  }
}

TEST(Transfer, LinearNodePlaneParticlesGetTheVelocityGradient) { expect_node_plane_gradients<LinearShape>(); }
TEST(Transfer, GimpNodePlaneParticlesGetTheVelocityGradient) { expect_node_plane_gradients<GimpShape>(); }

// The number of entries where two fields differ (bit for bit; NaN never equal).
long differing_entries(const ConstField4& a, const ConstField4& b) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  auto y = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  long differing = 0;
  for (std::size_t i = 0; i < x.span(); ++i) differing += x.data()[i] != y.data()[i];
  return differing;
}

// The largest |a - b| over the entries of two fields.
double largest_difference(const ConstField4& a, const ConstField4& b) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  auto y = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  double largest = 0;
  for (std::size_t i = 0; i < x.span(); ++i) largest = std::max(largest, std::abs(x.data()[i] - y.data()[i]));
  return largest;
}

// add_scatter_into sums the scatter's copies (one per thread: 2 in the unit tests, 1
// and 4 in this file's other runs, tests/CMakeLists.txt) in thread order, scales the
// sums and leaves every copy zeroed for the next loop. The copies are set by hand to
// whole numbers below 2^20, whose sums and products with a power of two are exact, so
// the node values are compared exactly; a second call, with nothing added, gives the
// start values alone.
TEST(NodeScatter, AddsEveryCopyAndLeavesThemZeroed) {
  const Patch patch = whole_patch({5, 4, 3}, {0.1, 0.1, 0.1});
  const NodeSums sums = node_sums(patch);
  const Kokkos::Array<Field4, 3> dest{sums.mass, sums.mom[0], sums.heat};
  const Kokkos::Array<double, 3> start{1e-200, 0.0, 2.0}, unit{0.25, 1.0, 0x1p-40};
  ScatterScratch scratch;
  const NodeScatter& scatter = scratch.zeroed("test", sums.mass, 3);
  const auto copies = Kokkos::create_mirror_view(scatter.copies());
  const long count = long(copies.extent(0)), rows = long(copies.extent(1));
  ASSERT_EQ(rows, node_rows(sums.mass));
  const auto entry = [](long t, long row, int f) { return double((t + 1) * 1000 + 3 * row + f); };
  for (long t = 0; t < count; ++t)
    for (long row = 0; row < rows; ++row)
      for (int f = 0; f < 3; ++f) copies(t, row, f) = entry(t, row, f);
  Kokkos::deep_copy(scatter.copies(), copies);

  add_scatter_into<3>(scatter, dest, 0, start, unit);
  const long nj = long(sums.mass.extent(2)), nk = long(sums.mass.extent(3));
  long wrong = 0;
  for (int f = 0; f < 3; ++f) {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dest[f]);
    for (long i = 0; i < long(h.extent(1)); ++i)
      for (long j = 0; j < nj; ++j)
        for (long k = 0; k < nk; ++k) {
          double sum = 0;
          for (long t = 0; t < count; ++t) sum += entry(t, (i * nj + j) * nk + k, f);
          wrong += h(0, i, j, k) != start[f] + unit[f] * sum;
        }
  }
  EXPECT_EQ(wrong, 0) << "of " << 3 * rows << " node values, " << count << " copies";
  Kokkos::deep_copy(copies, scatter.copies());
  long left = 0;
  for (std::size_t e = 0; e < copies.span(); ++e) left += copies.data()[e] != 0.0;
  EXPECT_EQ(left, 0);

  add_scatter_into<3>(scatter, dest, 0, start, unit);
  for (int f = 0; f < 3; ++f) {
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dest[f]);
    long not_start = 0;
    for (std::size_t e = 0; e < h.span(); ++e) not_start += h.data()[e] != start[f];
    EXPECT_EQ(not_start, 0) << "field " << f;
  }
}

// p2g adds consecutive particles of one window (the nodes their shape reaches: the
// linear shape's cell, GIMP's nearest node) together before adding into the nodes
// (p2g_window_runs). With quanta every sum is exact, so node by node it must give bit for
// bit what adding one particle at a time gives (p2g_each_particle): runs of many, one and
// no particles, a run longer than a block, runs broken by an unsorted tail, and trace
// particles whose far nodes' share of the mass rounds to zero (skipped by both). Every
// field after the mass with a quantum is counted in integers, and with GIMP the mass too
// (p2g_counts_mass); with the external force unrounded (no quantum) the runs sum in
// doubles, the other fields still bit for bit and the force to round-off.
template <class Shape>
void expect_window_runs_add_as_one_particle_at_a_time(bool force_quantum) {
  constexpr int n_nodes = Shape::nodes, N = n_nodes * n_nodes * n_nodes;
  const Patch patch = whole_patch({6, 5, 4}, {0.1, 0.2, 0.1});
  const NodeGrid grid = node_grid(patch);
  std::mt19937_64 rng(23);
  const ParticleSet ps = cell_run_particles(
      patch, rng,
      [](auto& h, long p, auto& u) {
        for (int d = 0; d < 3; ++d) {
          h(p, column(ParticleField::vx) + d) = u() - 0.5;
          h(p, column(ParticleField::fext_x) + d) = u() - 0.5;
          h(p, column(ParticleField::size_x) + d) = 0.5;  // GIMP's half-width: a quarter cell
        }
        h(p, column(ParticleField::temperature)) = 300 + 100 * u();
      },
      Shape::nodes == 3);
  const long n = long(ps.size());
  SumQuanta q = quanta_for(particle_scatter_bounds(n, ps.data()));
  q.mass = quantum_for(1.5);
  if (!force_quantum) q.external_force = 0;
  ASSERT_EQ(QuantumArray<detail::p2g_fields>(detail::p2g_quanta(q)).counted_from(1), force_quantum);

  const NodeSums runs = node_sums(patch), each = node_sums(patch);
  p2g<Shape>(grid, n, ps.data(), 0, runs, q);
  ScatterScratch scratch;
  const NodeScatter& scatter = scratch.zeroed("each", each.mass, detail::p2g_fields);
  detail::p2g_each_particle<Shape>(grid, n, ps.data(), scatter, block_stencil<n_nodes>(each.mass),
                                   detail::p2g_quanta(q));
  detail::add_p2g_scatter_into(scatter, each, 0, detail::p2g_quanta(q));
  const Field4 a[9] = {runs.mass, runs.mom[0], runs.mom[1], runs.mom[2], runs.heat, runs.volume,
                       runs.fext[0], runs.fext[1], runs.fext[2]};
  const Field4 b[9] = {each.mass, each.mom[0], each.mom[1], each.mom[2], each.heat, each.volume,
                       each.fext[0], each.fext[1], each.fext[2]};
  for (int f = 0; f < (force_quantum ? 9 : 6); ++f) EXPECT_EQ(differing_entries(a[f], b[f]), 0) << "field " << f;
  // Unrounded forces summed in another order: |f_ext| < 0.5 N from at most k particles a
  // node (the windows that reach it: 8 with the linear shape, 27 with GIMP; each of up to
  // 11 particles, one of up to 51), so each sum is within (k - 1) 2^-53 (0.5 k) N of the
  // exact one (the worst case of k - 1 roundings of partial sums below 0.5 k N), and the
  // two sums within twice that of each other.
  const double k = (N - 1) * 11 + 51, bound = 2 * (k - 1) * 0x1p-53 * 0.5 * k;
  for (int f = force_quantum ? 9 : 6; f < 9; ++f) EXPECT_LE(largest_difference(a[f], b[f]), bound) << "field " << f;
  // The trace particles' far nodes were skipped: some node share of weight rounds to zero.
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  long skipped = 0;
  for (long p = 0; p < n; p += 7) {
    double x[3], half[3];
    particle_position(h, p, x, half);
    const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    for (int i = 0; i < N; ++i) {
      const double S = wt.weight(i);
      skipped += S > 0 && Quantum(q.mass).round(S * 2e-12) == 0.0;
    }
  }
  EXPECT_GT(skipped, 0);
}

TEST(Transfer, LinearWindowRunsAddAsOneParticleAtATime) {
  expect_window_runs_add_as_one_particle_at_a_time<LinearShape>(true);
}
TEST(Transfer, LinearWindowRunsWithAnUnroundedFieldAddAsOneParticleAtATime) {
  expect_window_runs_add_as_one_particle_at_a_time<LinearShape>(false);
}
TEST(Transfer, GimpWindowRunsAddAsOneParticleAtATime) {
  expect_window_runs_add_as_one_particle_at_a_time<GimpShape>(true);
}
TEST(Transfer, GimpWindowRunsWithAnUnroundedFieldAddAsOneParticleAtATime) {
  expect_window_runs_add_as_one_particle_at_a_time<GimpShape>(false);
}

#if !defined(MPMICE_DEVICE_BACKEND)
// A body for reduce_over_particle_groups that reports how particle p reads its nodes:
// 1 if through ReadWindows over `windows` distinct places (1, 2 or 3), else 0. Its
// `first` is g2p's own (G2pParticle::first).
template <class Shape>
struct WindowReads {
  detail::G2pParticle<Shape, true> g2p_body;
  int windows;
  long first(long p) const { return g2p_body.first(p); }
  double operator()(long, const ReadOwnNodes&) const { return 0.0; }
  double operator()(long, const ReadWindows<2>& read) const {
    return (read.first[0] != read.first[1] ? 2 : 1) == windows ? 1.0 : 0.0;
  }
  double operator()(long, const ReadWindows<3>& read) const {
    const bool distinct = read.first[0] != read.first[2];  // the middle one differs from both
    return (distinct ? 3 : 2) == windows ? 1.0 : 0.0;
  }
};
#endif

// g2p reads the node values of a group of 8 consecutive particles once for the group
// when their windows of nodes are one of two or three (GIMP: reduce_over_particle_groups,
// ReadWindows), else particle by particle (ReadOwnNodes); with the linear shape it forms
// the interpolants of a cell once for each run of its particles, and takes them in
// vector blocks of 4 and 2 and one by one (reduce_over_cell_runs), else each particle
// its own cell's. Either way every particle
// must get the same values, bit for bit, as reading particle by particle throughout:
// groups in one, two, three and more windows (runs of many, one and no particles, an
// unsorted tail), nodes of zero weight (GIMP's far nodes: ReadWindows reads them,
// ReadOwnNodes reads the particle's middle node instead; with the linear shape a
// particle on a node plane, whose nodes above it have a weight of exactly 0 and both
// read), and a group deep in the
// ghost cells whose windows leave the node arrays below i and above j (GIMP: they must
// read their own), with
// every node field g2p reads (the heat and the transfers' terms included).
template <class Shape>
void expect_groups_read_as_one_particle_at_a_time() {
  constexpr bool gimp = Shape::nodes == 3;
  const std::array<double, 3> h_cell = {0.125, 0.25, 0.125};  // node planes exact in binary
  const Patch patch = whole_patch({6, 5, 4}, h_cell);
  const NodeGrid grid = node_grid(patch);
  std::mt19937_64 rng(29);
  const ParticleSet grouped = cell_run_particles(
      patch, rng,
      [&](auto& h, long p, auto& u) {
        for (int d = 0; d < 3; ++d) {
          h(p, column(ParticleField::vx) + d) = u() - 0.5;
          for (int e = 0; e < 3; ++e) h(p, tensor_column(ParticleField::F00, d, e)) = (d == e) + 0.02 * (u() - 0.5);
          h(p, column(ParticleField::size_x) + d) = 0.5;  // GIMP's half-width: a quarter cell
        }
        h(p, column(ParticleField::temperature)) = 300 + 100 * u();
        h(p, column(ParticleField::gas_pressure)) = 1e5 * u();
        h(p, column(ParticleField::bulk_viscosity)) = 1e3 * u();
        if (p < 8) {
          // The first group: 0.3-0.45 cells into the outermost ghost cell along i, near
          // node (1, 1) along j and k, one window. GIMP's lowest node of it lies below
          // the node arrays, with weight 0.
          h(p, column(ParticleField::x)) = (-2.0 + 0.3 + 0.15 * u()) * h_cell[0];
          for (int d = 1; d < 3; ++d) h(p, column(ParticleField::x) + d) = (1.0 + 0.1 * u()) * h_cell[d];
        } else if (p < 16) {
          // The second: the same along j, at the top (0.55-0.7 cells into the outermost
          // ghost cell above the patch's 5 cells), near node (2, 2) along i and k. GIMP's
          // highest node of it lies above the node arrays, where a row's place is still
          // inside the block of nodes.
          h(p, column(ParticleField::x) + 1) = (5.0 + 1.55 + 0.15 * u()) * h_cell[1];
          for (int d : {0, 2}) h(p, column(ParticleField::x) + d) = (2.0 + 0.1 * u()) * h_cell[d];
        } else if (!gimp && p < 24) {
          // The third (linear): the last cell of the node arrays, the outermost ghost
          // cell above the patch along i, j and k, whose cells' batch of node values
          // (reduce_over_cell_runs) would read past the arrays' end, and starts lower.
          const int cells[3] = {6, 5, 4};
          for (int d = 0; d < 3; ++d) h(p, column(ParticleField::x) + d) = (cells[d] + 1.1 + 0.8 * u()) * h_cell[d];
        }
        // Every 4th particle onto a node plane along d: the one below it (linear), its
        // nearest (GIMP; its window stays the same). Not the second group's along j: its
        // nearest plane there is the edge of the ghost cells.
        const int d = int(p % 3);
        double& x = h(p, column(ParticleField::x) + d);
        if (p % 4 == 1 && !(p < 16 && d == 1))
          x = std::floor(x / h_cell[d] + (gimp ? 0.5 : 0.0)) * h_cell[d];
      },
      /*around_nodes=*/gimp);
  const long n = long(grouped.size());
  ParticleSet each("each", n);
  each.resize(n);
  Kokkos::deep_copy(each.data(), grouped.data());

  // Every node field g2p reads, drawn at random: v*, the acceleration, the heat rate and
  // the transfers' energy.
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto random_node_field = [&](const char* name) {
    const Field4 f = make_field(name, patch, Location::node, 1);
    auto h = Kokkos::create_mirror_view(f);
    for (std::size_t i = 0; i < h.span(); ++i) h.data()[i] = uniform(rng);
    Kokkos::deep_copy(f, h);
    return f;
  };
  const ConstVectorField4 vel{random_node_field("vx"), random_node_field("vy"), random_node_field("vz")};
  const ConstVectorField4 acc{random_node_field("ax"), random_node_field("ay"), random_node_field("az")};
  const Field4 temp_rate = random_node_field("temp_rate");
  const TransferHeat transfer{random_node_field("energy"), 400.0};
  const double dt = 1e-3;  // |L| dt < 1: no particle needs sub-steps (which only g2p does)
  const auto before = Kokkos::create_mirror(grouped.data());  // a copy: g2p moves the particles
  Kokkos::deep_copy(before, grouped.data());
  // g2p as MPMICE runs it (the heat and the transfers' terms), then as MPM alone runs it
  // (GIMP's sums are then taken direction by direction: G2pParticle::sum_by_direction).
  for (const bool transfers : {true, false}) {
    Kokkos::deep_copy(grouped.data(), before);
    Kokkos::deep_copy(each.data(), before);
    double substepped;
    if (transfers) {
      detail::g2p_deforming<Shape, true>(grid, n, grouped.data(), 0, dt, 0.25, vel, acc, temp_rate, transfer,
                                         /*in_groups=*/true);
      substepped = detail::g2p_deforming<Shape, true>(grid, n, each.data(), 0, dt, 0.25, vel, acc, temp_rate,
                                                      transfer, /*in_groups=*/false);
    } else {
      detail::g2p_deforming<Shape, false>(grid, n, grouped.data(), 0, dt, 0.25, vel, acc, Field4(), TransferHeat(),
                                          /*in_groups=*/true);
      substepped = detail::g2p_deforming<Shape, false>(grid, n, each.data(), 0, dt, 0.25, vel, acc, Field4(),
                                                       TransferHeat(), /*in_groups=*/false);
    }
    ASSERT_EQ(substepped, 0.0);
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), grouped.data());
    auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), each.data());
    long differing = 0;
    for (long p = 0; p < n; ++p)
      for (int c = 0; c < particle_field_count; ++c) differing += std::memcmp(&a(p, c), &b(p, c), sizeof(double)) != 0;
    EXPECT_EQ(differing, 0) << "of " << n * particle_field_count << " entries, transfers " << transfers;
  }

  // Both reads were taken: groups of 8 (as reduce_over_particle_groups forms them, from
  // the start of each run of detail::particle_run particles) in one window, in two, in
  // three (the first and the last particle's and one more), in more, and with a window
  // outside the node arrays (windows from the positions before g2p).
  const Kokkos::Array<long, 3> extent = {long(vel[0].extent(1)), long(vel[0].extent(2)), long(vel[0].extent(3))};
  const auto window_of = [&](long p) {
    double x[3], half[3];
    particle_position(before, p, x, half);
    const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    return std::array<long, 3>{long(wt.first[0]), long(wt.first[1]), long(wt.first[2])};
  };
  const auto inside = [&](long p) {
    const std::array<long, 3> w = window_of(p);
    for (int d = 0; d < 3; ++d)
      if (w[d] < 0 || w[d] + Shape::nodes - 1 >= extent[d]) return false;
    return true;
  };
  long in_one = 0, in_two = 0, in_three = 0, in_more = 0, outside = 0;
  for (long run = 0; run < n; run += detail::particle_run)
    for (long g = run; g + detail::particle_group <= std::min(n, run + detail::particle_run);
         g += detail::particle_group) {
      const long last = g + detail::particle_group - 1;
      // The windows of the first and the last particle, and of the others.
      const std::set<std::array<long, 3>> ends = {window_of(g), window_of(last)};
      std::set<std::array<long, 3>> others;
      bool all_inside = true;
      for (long p = g; p <= last; ++p) {
        if (ends.count(window_of(p)) == 0) others.insert(window_of(p));
        all_inside = all_inside && inside(p);
      }
      const std::size_t windows = ends.size() + others.size();
      long& kind = !all_inside       ? outside
                   : others.size() > 1 ? in_more
                   : windows == 1      ? in_one
                   : windows == 2      ? in_two
                                       : in_three;
      ++kind;
    }
  EXPECT_GT(in_one, 5);
  EXPECT_GT(in_two, 5) << in_one << " in one window, " << in_more << " in more";
  EXPECT_GT(in_three, 5);
  EXPECT_GT(in_more, 5);
  EXPECT_EQ(outside, gimp ? 2 : 0);  // the first two groups
#if !defined(MPMICE_DEVICE_BACKEND)
  // ... and reduce_over_particle_groups chose those: it gives ReadWindows to the
  // particles of exactly the groups in one, two or three windows, all inside.
  const ParticleData input = before;
  const detail::G2pParticle<Shape, true> g2p_body(grid, input, 0, dt, 0.25, vel, acc, temp_rate, transfer);
  const auto reads = [&](int windows) {
    return reduce_over_particle_groups<Reduction::sum>("reads", n, WindowReads<Shape>{g2p_body, windows});
  };
  EXPECT_EQ(reads(1), double(detail::particle_group * in_one));
  EXPECT_EQ(reads(2), double(detail::particle_group * in_two));
  EXPECT_EQ(reads(3), double(detail::particle_group * in_three));
#endif
}

TEST(Transfer, LinearG2pGroupsReadAsOneParticleAtATime) { expect_groups_read_as_one_particle_at_a_time<LinearShape>(); }
TEST(Transfer, GimpG2pGroupsReadAsOneParticleAtATime) { expect_groups_read_as_one_particle_at_a_time<GimpShape>(); }

// Quantum::round against its definition, computed here without the magic number:
// the multiple of q nearest x (ties to the even multiple), exact.
TEST(Quanta, RoundToTheNearestMultipleTiesToEven) {
  const double q = quantum_for(3.0);  // 2^-39: contributions up to 3 are below 2^41 q
  ASSERT_EQ(q, std::ldexp(1.0, -39));
  const Quantum quantum(q);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int n = 0; n < 10000; ++n) {
    const double x = n % 2 ? u(rng) : u(rng) * std::ldexp(1.0, -30 * (n % 3));  // also near 0
    const double r = quantum.round(x);
    const double k = std::nearbyint(x / q);  // x / q exact (a power of two); nearbyint: ties to even
    ASSERT_EQ(r, k * q) << "x = " << x;
    ASSERT_EQ(quantum.in_units(x), k) << "x = " << x;
    ASSERT_LE(std::abs(r - x), 0.5 * q);
  }
  // Halves go to the even multiple, on both sides of 0.
  EXPECT_EQ(quantum.round(2.5 * q), 2 * q);
  EXPECT_EQ(quantum.round(3.5 * q), 4 * q);
  EXPECT_EQ(quantum.round(-2.5 * q), -2 * q);
  EXPECT_EQ(quantum.round(0.49 * q), 0.0);
  EXPECT_EQ(quantum.round(-0.5 * q), 0.0);
  // Whole multiples stay, up to the rounding's limit 2^51 q, and halves round to even
  // there too (2^41 q is the largest contribution the quanta are made for).
  for (int e : {41, 50, 51}) {
    const double big = std::ldexp(q, e);
    EXPECT_EQ(quantum.round(big - q), big - q) << "2^" << e << " q";
    EXPECT_EQ(quantum.round(-big), -big) << "2^" << e << " q";
    EXPECT_EQ(quantum.round(big - 1.5 * q), big - 2 * q) << "2^" << e << " q";
  }
  // Without a quantum a value passes through unchanged: tiny, huge, NaN.
  const Quantum none(0.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {1e-300, -3.7e-310, 1.234567890123e200, -0.1, inf, -inf})
    EXPECT_EQ(none.round(x), x);
  EXPECT_EQ(quantum.round(inf), inf);
  EXPECT_EQ(quantum.round(-inf), -inf);
  EXPECT_TRUE(std::isnan(none.round(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_TRUE(std::isnan(quantum.round(std::numeric_limits<double>::quiet_NaN())));
}

// The reason for quanta: sums of rounded contributions do not depend on their order.
TEST(Quanta, RoundedSumsDoNotDependOnTheirOrder) {
  const Quantum quantum(quantum_for(1.0));
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> x(4096);
  for (double& v : x) v = quantum.round(u(rng) * std::ldexp(1.0, -int(rng() % 20)));
  const auto sum = [&] {
    double s = 0;
    for (double v : x) s += v;
    return s;
  };
  const double first = sum();
  for (int shuffle = 0; shuffle < 5; ++shuffle) {
    std::shuffle(x.begin(), x.end(), rng);
    EXPECT_EQ(sum(), first);
  }
}

// Whole units counted in integers (UnitCount, p2g's cell runs): the bits of x + magic
// added as integers give back exactly the sum of the whole numbers x rounds to, for
// contributions of either sign up to the quanta's 2^41 units, wrapping past 2^64 on the
// way (each pattern is about 2^62), including a contribution of 0 (a node left out).
TEST(Quanta, CountedUnitsSumExactly) {
  const Quantum quantum(quantum_for(1.0));
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int terms : {1, 2, 7, 64, 1000}) {
    std::uint64_t counted = 0;
    double rounded = 0;  // the sum of the rounded units, exact: below 2^53
    for (int t = 0; t < terms; ++t) {
      const double x = t % 5 == 4 ? 0.0 : u(rng) * std::ldexp(1.0, -int(rng() % 40));
      counted += UnitCount::bits(x * quantum.scale + quantum.magic);
      rounded += quantum.in_units(x);
    }
    EXPECT_EQ(UnitCount::total(counted, std::uint64_t(terms)), rounded) << terms << " terms";
  }
  // The largest contributions the quanta are made for, all of one sign.
  const double big = std::ldexp(1.0, 41) - 1;
  std::uint64_t counted = 0;
  for (int t = 0; t < 100; ++t) counted += UnitCount::bits(-big + quantum.magic);
  EXPECT_EQ(UnitCount::total(counted, 100), -100 * big);
  // A bound of 0 still gets a quantum (so that the kernels count), which keeps 0 as 0;
  // a bound that is no bound gets none.
  EXPECT_EQ(quantum_for(0.0), 1.0);
  EXPECT_EQ(Quantum(quantum_for(0.0)).round(0.0), 0.0);
  EXPECT_EQ(quantum_for(-1.0), 0.0);
  EXPECT_EQ(quantum_for(std::numeric_limits<double>::quiet_NaN()), 0.0);
}

// The counts' conversion for vector loops (UnitCount::total_in_vector, p2g's node sums)
// gives the bits that the conversion double(int64_t) gives, rounding included, for
// every magnitude: the edges of the two halves it splits a count into, then counts of
// random sign and length.
TEST(Quanta, CountsConvertAsTheConversionDoes) {
  const auto check = [](std::int64_t n) {
    EXPECT_EQ(math::as_bits(UnitCount::to_double(std::uint64_t(n))), math::as_bits(double(n))) << n;
  };
  const std::int64_t lowest = std::numeric_limits<std::int64_t>::min(), top = std::numeric_limits<std::int64_t>::max();
  for (std::int64_t n : {std::int64_t(0), std::int64_t(1), std::int64_t(-1), lowest, lowest + 1, top, top - 1,
                         std::int64_t(0xFFFFFFFF), std::int64_t(0x100000000), -std::int64_t(0x100000000),
                         (std::int64_t(1) << 53) + 1, -(std::int64_t(1) << 53) - 1, (std::int64_t(1) << 62) + 3})
    check(n);
  std::mt19937_64 rng(49);
  for (int t = 0; t < 200000; ++t) check(std::int64_t(rng()) >> (rng() % 64));
  // As p2g takes it: a run's sum of bit patterns back as its count.
  std::uint64_t sum = 0;
  for (int t = 1; t <= 100; ++t) {
    sum += UnitCount::bits(double(int(rng() % 2001) - 1000) + 0x1.8p52);
    EXPECT_EQ(UnitCount::total_in_vector(sum, std::uint64_t(t)), UnitCount::total(sum, std::uint64_t(t)));
  }
}

// Sorted by the window of Shape (sort_particles_by_window), every particle is kept with
// all its values, and their windows' middle nodes (the cell for the linear shape, the
// nearest node for GIMP, local indices) come in row-major order, the particles of one
// window in their order before the sort (stable: the same order on any number of
// threads); sorted again, nothing moves.
template <class Shape>
void expect_sorted_by_window() {
  Grid g;
  g.cells = {4, 4, 4};
  const Patch patch = whole_grid_patch(g, 2);
  // Enough particles (about 14 a window) that on 2 threads most windows get some from
  // each thread.
  const long n = 10000;
  ParticleSet ps("s", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  auto id = Kokkos::create_mirror_view(ps.id());
  std::mt19937 rng(2);
  // The 4 owned cells, the 2 ghost cells either side, and a little past them (sorted
  // as if on the edge: the key's clamp).
  std::uniform_real_distribution<double> u(-2.4, 6.4);
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = p + 0.001 * c;
    for (int d = 0; d < 3; ++d) h(p, column(ParticleField::x) + d) = u(rng);
    id(p) = p;
  }
  Kokkos::deep_copy(ps.data(), h);
  Kokkos::deep_copy(ps.id(), id);
  sort_particles_by_window<Shape>(patch, ps);
  auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  auto sid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
  long last_key = -1, last_id = -1, idsum = 0, out_of_their_order = 0;
  for (long q = 0; q < n; ++q) {
    const long p = sid(q);
    idsum += p;
    for (int c = 0; c < particle_field_count; ++c) ASSERT_EQ(s(q, c), h(p, c));
    long key = 0;
    const double to_middle = Shape::nodes == 3 ? 0.5 : 0.0;  // cells 1 m wide
    for (int d = 0; d < 3; ++d) {
      const long c = long(std::floor(s(q, column(ParticleField::x) + d) + to_middle)) + 2;  // 8 cells, 9 nodes
      key = key * 16 + std::clamp(c, 0L, 8L);
    }
    EXPECT_GE(key, last_key);
    out_of_their_order += key == last_key && p < last_id;
    last_key = key;
    last_id = p;
  }
  EXPECT_EQ(out_of_their_order, 0) << "particles of one window not in their order before the sort";
  EXPECT_EQ(idsum, (n - 1) * n / 2);
  // Sorted again, already in order: nothing moves, the same views are kept (no gather).
  const double* before = ps.data().data();
  sort_particles_by_window<Shape>(patch, ps);
  EXPECT_EQ(ps.data().data(), before);
  auto again = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
  for (long q = 0; q < n; ++q) ASSERT_EQ(again(q), sid(q));
}

TEST(Transfer, SortByCellKeepsEveryParticle) { expect_sorted_by_window<LinearShape>(); }
TEST(Transfer, SortByGimpWindowKeepsEveryParticle) { expect_sorted_by_window<GimpShape>(); }

// The cube root the stress update uses instead of pow (so that its loop vectorises):
// against long-double powl over J from 1e-14 to 1e13 (log-uniform: every binary step of
// its range reduction) and near 1. Bound 1e-15 relative, about 4.5 ulp: its two Newton
// steps end within 1 ulp over 2e6 values (1.7e-16), and the neo-Hookean stress needs no
// better than its inputs' rounding.
TEST(Math, InverseCubeRootWithinFourUlp) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(std::log(1e-14), std::log(1e13)), near(0.5, 2.0);
  double worst = 0;
  for (int n = 0; n < 200000; ++n) {
    const double x = n % 2 ? std::exp(u(rng)) : near(rng);
    const long double want = powl((long double)x, -1.0L / 3.0L);
    const double got = math::inverse_cube_root(x);
    worst = std::max(worst, double(std::fabs((long double)got - want) / want));
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(math::inverse_cube_root(1.0), 1.0);
  EXPECT_EQ(math::inverse_cube_root(8.0), 0.5);
}

// The particle-state check names the row and the first quantity broken, counts every
// broken particle, and passes a sound state (zero mass and volume allowed: a particle
// that burned out).
TEST(ParticleState, BadParticlesAreFoundAndNamed) {
  const long n = 50;
  ParticleSet ps("s", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  for (long p = 0; p < n; ++p)
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = 1.0;
  h(7, column(ParticleField::mass)) = 0.0;
  h(7, column(ParticleField::volume)) = 0.0;
  auto check = [&]() {
    Kokkos::deep_copy(ps.data(), h);
    return find_bad_particles(n, ps.data());
  };
  EXPECT_EQ(check().count, 0);
  const double nan = std::nan("");
  struct Case { long row; ParticleField field; double value; ParticleQuantity want; };
  const Case cases[] = {{3, ParticleField::y, nan, ParticleQuantity::position},
                        {12, ParticleField::vz, HUGE_VAL, ParticleQuantity::velocity},
                        {20, ParticleField::mass, -1e-30, ParticleQuantity::mass},
                        {21, ParticleField::volume, nan, ParticleQuantity::volume},
                        {30, ParticleField::temperature, 0.0, ParticleQuantity::temperature},
                        {40, ParticleField::F21, nan, ParticleQuantity::deformation},
                        {49, ParticleField::s02, -HUGE_VAL, ParticleQuantity::stress}};
  for (const Case& c : cases) {
    const double kept = h(c.row, column(c.field));
    h(c.row, column(c.field)) = c.value;
    const BadParticle b = check();
    EXPECT_EQ(b.count, 1) << quantity_name(c.want);
    EXPECT_EQ(b.row, c.row);
    EXPECT_EQ(b.quantity, c.want);
    h(c.row, column(c.field)) = kept;
  }
  h(5, column(ParticleField::x)) = nan;  // two broken: the count says so, the last row is named
  h(9, column(ParticleField::mass)) = -1.0;
  const BadParticle b = check();
  EXPECT_EQ(b.count, 2);
  EXPECT_EQ(b.row, 9);
  EXPECT_EQ(b.quantity, ParticleQuantity::mass);
}

// Closed forms of (E53) under uniaxial stretch F = diag(l, 1, 1) and simple shear
// F = I + g e1 e2.
TEST(Stress, NeoHookeanClosedForms) {
  const double K = 5e9, G = 2e9;
  for (double l : {0.8, 1.0, 1.3}) {
    Mat3 F = Mat3::identity();
    F(0, 0) = l;
    const Mat3 s = neo_hookean_stress(F, K, G);
    const double J = l, c = std::pow(J, -2.0 / 3.0);
    const double dev_xx = G / J * c * (l * l - (l * l + 2.0) / 3.0);
    const double dev_yy = G / J * c * (1.0 - (l * l + 2.0) / 3.0);
    const double p = 0.5 * K * (J - 1.0 / J);
    EXPECT_NEAR(s(0, 0), p + dev_xx, 1e-10 * (K + G));
    EXPECT_NEAR(s(1, 1), p + dev_yy, 1e-10 * (K + G));
    EXPECT_NEAR(s(2, 2), p + dev_yy, 1e-10 * (K + G));
    EXPECT_NEAR(s(0, 1), 0.0, 1e-10 * (K + G));
  }
  for (double g : {0.01, 0.2, 1.0}) {
    Mat3 F = Mat3::identity();
    F(0, 1) = g;
    const Mat3 s = neo_hookean_stress(F, K, G);
    // J = 1, b = [[1+g^2, g, 0], [g, 1, 0], [0, 0, 1]]: shear stress G g, normal
    // stresses G (2/3 g^2, -1/3 g^2, -1/3 g^2).
    EXPECT_NEAR(s(0, 1), G * g, 1e-10 * G);
    EXPECT_NEAR(s(1, 0), G * g, 1e-10 * G);
    EXPECT_NEAR(s(0, 0), G * 2.0 / 3.0 * g * g, 1e-10 * G);
    EXPECT_NEAR(s(1, 1), -G / 3.0 * g * g, 1e-10 * G);
    EXPECT_NEAR(s(2, 2), -G / 3.0 * g * g, 1e-10 * G);
  }
}

// The stress update as a whole (E53, E58): every particle's stress is (E53) of its F,
// and the update returns min over particles and directions of h_d / (c_dil + |v_d|),
// c_dil = sqrt((K + 4G/3) / rho) at rho = rho_0 / J, formed here in long double from the
// definition (the kernel multiplies by 1/h and takes J (K + 4G/3) / rho_0 under the
// root: a few roundings apart, so 1e-14 relative). 37 particles: the vector loop's
// remainder too; anisotropic cells, so the limiting direction matters. The J2 model
// (a plain loop) below its yield stress returns the same limit; a rigid one, 1e300.
TEST(Stress, UpdateWritesTheStressAndReturnsTheWaveLimit) {
  const Patch patch = whole_patch({4, 4, 4}, {1e-3, 2e-3, 0.5e-3});
  const NodeGrid grid = node_grid(patch);
  const long n = 37;
  SolidModel elastic;
  elastic.density = 8900.0;
  elastic.bulk_modulus = 1.4e11;
  elastic.shear_modulus = 4.6e10;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ParticleSet ps("solid", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  std::vector<Mat3> F(n);
  long double want = std::numeric_limits<long double>::max();
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
    F[p] = Mat3::identity();
    // J from 0.5 to 2 (compression and tension), with shear.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        F[p](a, b) = a == b ? std::pow(2.0, u(rng) / 3.0) : 0.15 * u(rng);
        h(p, tensor_column(ParticleField::F00, a, b)) = F[p](a, b);
        h(p, tensor_column(ParticleField::be00, a, b)) = a == b ? 1.0 : 0.0;
      }
    const long double rho = (long double)elastic.density / F[p].det();
    const long double c = std::sqrt(((long double)elastic.bulk_modulus + 4.0L * elastic.shear_modulus / 3.0L) / rho);
    for (int d = 0; d < 3; ++d) {
      const double v = 3000.0 * u(rng);
      h(p, column(ParticleField::vx) + d) = v;
      want = std::min(want, (long double)grid.h[d] / (c + std::fabs((long double)v)));
    }
  }
  const auto run = [&](const SolidModel& model) {
    Kokkos::deep_copy(ps.data(), h);
    return stress_update(grid, n, ps.data(), model, 1e-9);
  };
  const double got = run(elastic);
  EXPECT_NEAR(got / double(want), 1.0, 1e-14);
  auto out = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  for (long p = 0; p < n; ++p) {
    const Mat3 s = neo_hookean_stress(F[p], elastic.bulk_modulus, elastic.shear_modulus);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        ASSERT_NEAR(out(p, tensor_column(ParticleField::s00, a, b)), s(a, b), 1e-12 * elastic.bulk_modulus)
            << "particle " << p << " stress (" << a << ", " << b << ")";
  }
  SolidModel plastic = elastic;
  plastic.type = SolidModelType::neo_hookean_plastic;
  EXPECT_NEAR(run(plastic) / double(want), 1.0, 1e-14);
  SolidModel rigid = elastic;
  rigid.type = SolidModelType::rigid;
  EXPECT_EQ(run(rigid), 1e300);
}

// A copper-like J2 material for the plastic tests (K 100 GPa, G 40 GPa, yield 200 MPa,
// hardening 2 GPa).
namespace {
SolidModel copper_like_plastic() {
  SolidModel m;
  m.type = SolidModelType::neo_hookean_plastic;
  m.bulk_modulus = 100e9;
  m.shear_modulus = 40e9;
  m.yield_stress = 200e6;
  m.hardening_modulus = 2e9;
  return m;
}
}  // namespace

// (E54): elastic below yield (equal to neo-Hookean), on the yield surface
// sqrt(3/2)|s| = sigma_y + H eps_p once yielding, and the yield stress grows with
// the hardening modulus.
TEST(Stress, PlasticYieldsAndHardens) {
  SolidModel m = copper_like_plastic();
  Mat3 F = Mat3::identity(), be = Mat3::identity();
  double eps = 0, previous_eps = 0;
  bool yielded = false;
  for (int step = 1; step <= 400; ++step) {
    const double dg = 5e-5;  // simple shear increments
    Mat3 f = Mat3::identity();
    f(0, 1) = dg;
    F = f * F;
    const Mat3 s = neo_hookean_plastic_stress(f, F.det(), be, eps, m);
    const double vm = std::sqrt(1.5) * (F.det() * s).deviator().norm();
    if (eps == 0) {
      const Mat3 e = neo_hookean_stress(F, m.bulk_modulus, m.shear_modulus);
      EXPECT_NEAR(s(0, 1), e(0, 1), 1e-10 * m.shear_modulus);
      EXPECT_LE(vm, m.yield_stress * (1 + 1e-12));
    } else {
      yielded = true;
      EXPECT_NEAR(vm, m.yield_stress + m.hardening_modulus * eps, 1e-10 * m.yield_stress);
      EXPECT_GT(eps, previous_eps);
    }
    previous_eps = eps;
  }
  EXPECT_TRUE(yielded);
  EXPECT_GT(eps, 0.005);
}

// Energy of (E54) with `plastic_heat`: in simple shear (J = 1, tau_01 = J sigma_01) the
// work done on a material point, sum tau_01 dg (trapezoid), equals its stored energy
// plus the heat released, through yielding and hardening and past failure. Bound: one
// step's work, tau dg: the trapezoid is exact to second order while the stress is
// smooth, and errs by half a step's work in the step where the stress drops to zero.
// (Without the det-1 bbar in neo_hookean_energy the plastic work was counted twice.)
TEST(Stress, PlasticHeatClosesTheEnergyBalance) {
  SolidModel m = copper_like_plastic();
  m.failure_strain = 0.01;
  Mat3 F = Mat3::identity(), be = Mat3::identity();
  double eps = 0, work = 0, heat = 0, tau_old = 0, step_work = 0;
  const double dg = 5e-5;
  Mat3 f = Mat3::identity();
  f(0, 1) = dg;
  for (int step = 0; step < 600; ++step) {
    F = f * F;
    const double eps_old = eps;
    const Mat3 s = neo_hookean_plastic_stress(f, F.det(), be, eps, m);
    heat += plastic_heat(eps_old, eps, F.det(), be, m);
    work += 0.5 * (tau_old + F.det() * s(0, 1)) * dg;
    tau_old = F.det() * s(0, 1);
    step_work = std::max(step_work, std::abs(tau_old) * dg);
  }
  ASSERT_GE(eps, m.failure_strain);  // it yielded, hardened and failed
  const double stored = eps >= m.failure_strain ? failed_energy(F.det(), m.bulk_modulus)
                                                : neo_hookean_energy(F.det(), be, m.bulk_modulus, m.shear_modulus);
  EXPECT_GT(heat, 0.9 * work);
  EXPECT_NEAR(stored + heat, work, step_work);
}

// Failure: once the plastic strain reaches failure_strain the particle carries no shear
// and no tension, and in compression exactly its bulk law's pressure.
TEST(Stress, FailedMaterialKeepsOnlyCompression) {
  SolidModel m = copper_like_plastic();
  m.hardening_modulus = 0.0;
  m.failure_strain = 0.002;
  Mat3 F = Mat3::identity(), be = Mat3::identity();
  double eps = 0;
  Mat3 f = Mat3::identity();
  f(0, 1) = 5e-5;
  int steps = 0;
  while (eps < m.failure_strain && steps < 1000) {  // simple shear until it fails
    F = f * F;
    const Mat3 s = neo_hookean_plastic_stress(f, F.det(), be, eps, m);
    if (eps < m.failure_strain) EXPECT_GT(s(0, 1), 0.0);  // still carries shear
    ++steps;
  }
  ASSERT_GE(eps, m.failure_strain);
  for (double stretch : {0.99, 1.01}) {  // then compressed, or stretched, by 1% per side
    Mat3 g = stretch * Mat3::identity();
    g(0, 1) = 5e-5;
    const Mat3 F_new = g * F;
    Mat3 be_copy = be;
    double eps_copy = eps;
    const Mat3 s = neo_hookean_plastic_stress(g, F_new.det(), be_copy, eps_copy, m);
    const double p = neo_hookean_mean_stress(F_new.det(), m.bulk_modulus);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double want = (a == b && p < 0) ? p : 0.0;
        EXPECT_EQ(s(a, b), want) << "stretch " << stretch << " component " << a << b;
      }
    EXPECT_EQ(stretch < 1, p < 0);
  }
}

// A particle's internal forces sum to zero: its stress cannot push itself. Heavy
// particles with random stresses and gauge pressures, and one of 1e-5 of their mass
// placed so that a far node's share of its mass rounds to zero (that node gets no
// force, internal_force.hpp). With the quanta of the driver, every node value is a sum of
// multiples of the force quantum, so the total over the nodes must be exactly 0. Before
// the particle's heaviest node took the remainder, the skipped node's force (checked
// below to be many quanta) was missing from it.
TEST(InternalForce, EachParticlesForcesSumToZero) {
  const Patch patch = whole_patch({6, 6, 6}, {0.1, 0.1, 0.1});
  const NodeGrid grid = node_grid(patch);
  const long n = 40;
  ParticleSet ps("solid", n);
  ps.resize(n);
  auto h = Kokkos::create_mirror_view(ps.data());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < particle_field_count; ++c) h(p, c) = 0.0;
    const bool trace = p == n - 1;
    for (int d = 0; d < 3; ++d) {
      // The trace particle on node 2's y and z planes and 0.7501 cells past it in x:
      // node (4, 2, 2) lies 1.2499 cells away, just inside the GIMP support (1.25 cells
      // for a particle of half a cell).
      h(p, column(ParticleField::x) + d) = trace ? (d == 0 ? 2.7501 : 2.0) * 0.1 : (1.5 + 3.0 * u(rng)) * 0.1;
      h(p, column(ParticleField::size_x) + d) = 0.5;
    }
    h(p, column(ParticleField::mass)) = trace ? 1e-5 : 0.5 + u(rng);
    h(p, column(ParticleField::volume)) = h(p, column(ParticleField::mass)) / 2000.0;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        const double v = 1e8 * (u(rng) - 0.5);
        h(p, tensor_column(ParticleField::s00, a, b)) = v;
        h(p, tensor_column(ParticleField::s00, b, a)) = v;
      }
    h(p, column(ParticleField::gas_pressure)) = 1e7 * u(rng);
  }
  Kokkos::deep_copy(ps.data(), h);
  SumQuanta q;
  q.mass = quantum_for(1.5);
  q.internal_force = quantum_for(internal_force_bound(grid, n, ps.data()));
  // The case is not trivial: the trace particle has a node whose mass share rounds to
  // zero while its force there is many quanta.
  double skipped = 0;
  {
    double x[3], half[3];
    particle_position(h, n - 1, x, half);
    const ParticleWeights<GimpShape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    for (int a = 0; a < GimpShape::nodes; ++a)
      for (int b = 0; b < GimpShape::nodes; ++b)
        for (int c = 0; c < GimpShape::nodes; ++c) {
          double g[3];
          wt.gradient(a, b, c, g);
          if (Quantum(q.mass).round(wt.weight(a, b, c) * 1e-5) == 0.0)
            skipped = std::max(skipped, h(n - 1, column(ParticleField::volume)) * 1e7 *
                                            std::max(std::abs(g[0]), std::max(std::abs(g[1]), std::abs(g[2]))));
        }
  }
  EXPECT_GT(skipped, 10 * q.internal_force);
  const Kokkos::Array<Field4, 3> f = {make_field("fx", patch, Location::node, 1),
                                      make_field("fy", patch, Location::node, 1),
                                      make_field("fz", patch, Location::node, 1)};
  internal_force<GimpShape>(grid, n, ps.data(), 0, VectorField4{f[0], f[1], f[2]}, q);
  for (int d = 0; d < 3; ++d) {
    const auto fh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f[d]);
    double total = 0, largest = 0;
    for (std::size_t i = 0; i < fh.extent(1); ++i)
      for (std::size_t j = 0; j < fh.extent(2); ++j)
        for (std::size_t k = 0; k < fh.extent(3); ++k) {
          total += fh(0, i, j, k);
          largest = std::max(largest, std::abs(fh(0, i, j, k)));
        }
    EXPECT_GT(largest, 1e6 * q.internal_force) << d;  // forces were made
    EXPECT_EQ(total, 0.0) << d;
  }
}

// internal_force adds consecutive particles of one window together
// (internal_force_window_runs): random stresses and gauge pressures, runs of many, one
// and no particles, a run longer than a block and an unsorted tail, and trace particles
// whose far nodes get no force (and whose heaviest node takes the rest); with GIMP
// every fifth particle exactly on its nearest node, the node of most weight, which has
// no gradient (internal_force_each_particle skips it, the window runs do not: its
// other nodes' forces cancel in pairs, so which node takes their zero sum does not
// matter). With quanta every sum is exact. Built with
// MPMICE_REPRODUCIBLE (no fused multiply-adds, kernels/CMakeLists.txt) both compute each
// force alike: bit for bit the same. Without it the vector loop may fuse another
// product of sigma . grad S into an FMA than the scalar loop does, so a contribution
// within an ulp of half a quantum rounds the other way (seen once in a container run):
// it moves one quantum between that node and the particle's heaviest node. So then a
// few entries (at most 16) may differ, each by a few quanta (at most 4; a quantum is
// 2^-41 to 2^-40 of the bound on one force), where a real fault (a node, a sign, a lost
// remainder of a trace particle) differs by whole forces, over 1e6 quanta here. The
// forces' total over the grid is exactly zero.
template <class Shape>
void expect_internal_force_window_runs_add_as_one_particle_at_a_time() {
  constexpr bool gimp = Shape::nodes == 3;
  const std::array<double, 3> h_cell = {0.125, 0.25, 0.125};  // node positions exact in binary
  const Patch patch = whole_patch({6, 5, 4}, h_cell);
  const NodeGrid grid = node_grid(patch);
  std::mt19937_64 rng(29);
  long on_node = 0;
  const ParticleSet ps = cell_run_particles(
      patch, rng,
      [&](auto& h, long p, auto& u) {
        h(p, column(ParticleField::gas_pressure)) = 1e5 * u();
        h(p, column(ParticleField::bulk_viscosity)) = 1e3 * u();
        for (int a = 0; a < 3; ++a)
          for (int b = a; b < 3; ++b) {
            const double v = 1e8 * (u() - 0.5);
            h(p, tensor_column(ParticleField::s00, a, b)) = v;
            h(p, tensor_column(ParticleField::s00, b, a)) = v;
          }
        const bool snap = gimp && p % 5 == 1 && p % 7 != 0;  // not a trace particle
        for (int d = 0; d < 3; ++d) {
          h(p, column(ParticleField::size_x) + d) = 0.5;  // GIMP's half-width: a quarter cell
          double& x = h(p, column(ParticleField::x) + d);
          if (snap) x = std::round(x / h_cell[d]) * h_cell[d];
        }
        on_node += snap;
      },
      gimp);
  EXPECT_EQ(on_node > 0, gimp);
  const long n = long(ps.size());
  SumQuanta q;
  q.mass = quantum_for(1.5);
  q.internal_force = quantum_for(internal_force_bound(grid, n, ps.data()));

  auto node = [&](const char* name) { return make_field(name, patch, Location::node, 1); };
  const VectorField4 runs{node("fx"), node("fy"), node("fz")}, each{node("ex"), node("ey"), node("ez")};
  internal_force<Shape>(grid, n, ps.data(), 0, runs, q);
  ScatterScratch scratch;
  const NodeScatter& scatter = scratch.zeroed("each", each[0], 3);
  detail::internal_force_each_particle<Shape>(grid, n, ps.data(), scatter, block_stencil<Shape::nodes>(each[0]),
                                              Quantum(q.internal_force), Quantum(q.mass));
  detail::add_force_scatter_into(scatter, each, 0, Quantum(q.internal_force));
  for (int d = 0; d < 3; ++d) {
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), runs[d]);
    auto y = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), each[d]);
    double total = 0, largest = 0, worst = 0;
    long differing = 0;
    for (std::size_t i = 0; i < x.span(); ++i) {
      total += x.data()[i];
      largest = std::max(largest, std::abs(y.data()[i]));
      worst = std::max(worst, std::abs(x.data()[i] - y.data()[i]));
      differing += x.data()[i] != y.data()[i];
    }
    EXPECT_GT(largest, 1e6 * q.internal_force) << d;  // forces were made
#if defined(MPMICE_REPRODUCIBLE)
    EXPECT_EQ(differing, 0) << "component " << d;
#else
    EXPECT_LE(worst, 4 * q.internal_force) << "component " << d;
    EXPECT_LE(differing, 16) << "component " << d;
#endif
    EXPECT_EQ(total, 0.0) << "component " << d;
  }
}

TEST(InternalForce, LinearWindowRunsAddAsOneParticleAtATime) {
  expect_internal_force_window_runs_add_as_one_particle_at_a_time<LinearShape>();
}
TEST(InternalForce, GimpWindowRunsAddAsOneParticleAtATime) {
  expect_internal_force_window_runs_add_as_one_particle_at_a_time<GimpShape>();
}
