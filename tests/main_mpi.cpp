// GoogleTest main for tests that use MPI: owns MPI and Kokkos. Rank 0 prints the
// full test log, the other ranks only their failures (gtest's brief mode); a failure
// on any rank fails every rank's exit status.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>

int main(int argc, char* argv[]) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int failed = 0;
  {
    Kokkos::ScopeGuard kokkos(argc, argv);
    ::testing::InitGoogleTest(&argc, argv);
    if (rank != 0) GTEST_FLAG_SET(brief, true);
    failed = RUN_ALL_TESTS() != 0;
    int any = 0;
    MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (any && !failed && rank == 0) std::fprintf(stderr, "a test failed on another rank\n");
    failed = any;
  }
  MPI_Finalize();
  return failed;
}
