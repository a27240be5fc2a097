// The same problem on 1 rank and on all ranks of the job gives the same history.csv
// to 1e-12 relative (per column, against the column's largest magnitude): the cells
// compute the same arithmetic on any decomposition; only the global sums of the
// history are added in another order.
#include <gtest/gtest.h>

#include <cstdio>

#include "validation_util.hpp"

using namespace mpmice;
using namespace mpmice::validation;

namespace {

void compare(const std::string& problem, const std::vector<std::string>& sets, double tolerance = 1e-12) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string tag = problem.substr(0, problem.find('.'));
  const std::string many = scratch_dir(tag + "_np" + std::to_string(size));
  run_problem(problem, sets, MPI_COMM_WORLD, many);
  double diff = 0;
  if (rank == 0) {
    const std::string one = scratch_dir(tag + "_np1_reference");
    run_problem(problem, sets, MPI_COMM_SELF, one);
    diff = max_relative_difference(read_csv(one + "/history.csv"), read_csv(many + "/history.csv"));
    std::printf("%s: 1 vs %d ranks, largest relative difference in history.csv %.3e\n", problem.c_str(),
                size, diff);
  }
  MPI_Bcast(&diff, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  EXPECT_LE(diff, tolerance) << problem;
}

}  // namespace

TEST(Ranks, SodX) { compare("sod.yaml", {"grid.cells=[100,1,1]"}); }
TEST(Ranks, SodY) { compare("sod_y.yaml", {"grid.cells=[1,100,1]"}); }
TEST(Ranks, SodZ) { compare("sod_z.yaml", {"grid.cells=[1,1,100]"}); }
TEST(Ranks, Interface) { compare("interface.yaml", {}); }
TEST(Ranks, HotBlob) { compare("hot_blob.yaml", {"time.max_steps=100"}); }
// Particles cross the rank boundary: the bar vibrates across x = 0.625, the disks
// travel through the centre of the box.
TEST(Ranks, Bar) { compare("bar.yaml", {}); }
TEST(Ranks, Disks) { compare("disks.yaml", {}); }
// The coupled cycle: the piston crosses the rank boundary at y = 0.125 m (the whole
// compression, 5300 steps); the block travels across both patches of the periodic
// box. The rigid piston's cells come from exact integer particle sums and its
// prescribed velocity (rigid_particle_to_cell), so nothing depends on the order in
// which ranks add: measured 3e-15 to 5e-15 (the history's own sums,
// whose thread order varies from run to run).
TEST(Ranks, Piston) { compare("piston.yaml", {"grid.cells=[1,100,1]"}); }
TEST(Ranks, BlockInGas) { compare("block_in_gas.yaml", {"time.max_steps=200"}); }
