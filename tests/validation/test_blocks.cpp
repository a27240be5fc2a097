// Homogeneous deformation of a block (problems/block_*.yaml): pushed slowly to 5%
// uniaxial strain, every particle has F_xx = 0.95 to 1% and the other components of
// F at their undeformed values; each stress is the model's closed form (E53) of its F,
// and the plastic block lies on its hardened yield surface (E54).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/solid_models.hpp>

#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

namespace {

void check_block(const std::string& problem, bool plastic) {
  auto pb = run_problem(problem, {}, MPI_COMM_SELF, scratch_dir(problem));
  const SolidModel& model = pb->solids[0];
  const ParticleSet& ps = pb->particles[0];
  auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  double fmin = 1e9, fmax = 0, worst_offdiag = 0, worst_stress = 0, worst_yield = 0;
  for (std::size_t q = 0; q < ps.size(); ++q) {
    const Mat3 F = load_tensor(data, long(q), ParticleField::F00);
    fmin = std::min(fmin, F(0, 0));
    fmax = std::max(fmax, F(0, 0));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i + j > 0) worst_offdiag = std::max(worst_offdiag, std::abs(F(i, j) - (i == j ? 1.0 : 0.0)));
    const Mat3 sigma = load_tensor(data, long(q), ParticleField::s00);
    if (!plastic) {
      const Mat3 closed = neo_hookean_stress(F, model.bulk_modulus, model.shear_modulus);
      worst_stress = std::max(worst_stress, (sigma - closed).norm() / closed.norm());
    } else {
      // On the yield surface: sqrt(3/2) |dev(J sigma)| = sigma_y + H eps_p.
      const double eps = data(q, column(ParticleField::plastic_strain));
      const double vm = std::sqrt(1.5) * (F.det() * sigma).deviator().norm();
      worst_yield = std::max(worst_yield, std::abs(vm - (model.yield_stress + model.hardening_modulus * eps)) /
                                              model.yield_stress);
      EXPECT_GT(eps, 0.0);
    }
  }
  std::printf("%s: F_xx in [%.5f, %.5f], |other F - I| <= %.2e, stress vs closed form %.2e, off the yield "
              "surface %.2e\n", problem.c_str(), fmin, fmax, worst_offdiag, worst_stress, worst_yield);
  EXPECT_NEAR(fmin, 0.95, 0.01);
  EXPECT_NEAR(fmax, 0.95, 0.01);
  EXPECT_LE(worst_offdiag, 1e-12);
  EXPECT_LE(worst_stress, 1e-10);
  EXPECT_LE(worst_yield, 1e-10);
}

}  // namespace

TEST(Blocks, NeoHookean) { check_block("block_neo_hookean.yaml", false); }
TEST(Blocks, Plastic) { check_block("block_plastic.yaml", true); }
