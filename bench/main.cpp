// Benchmark main: MPI (for the halo benchmarks, on one rank) and Kokkos live for the
// whole run; the context records what ran.
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <mpmice/kernels/version.hpp>

#include "bench_setup.hpp"
#include "git_revision.hpp"  // generated: MPMICE_GIT_REVISION

namespace {

int run_benchmarks(int argc, char* argv[]) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  benchmark::AddCustomContext("mpmice", MPMICE_VERSION_STRING);
  benchmark::AddCustomContext("git", MPMICE_GIT_REVISION);
  benchmark::AddCustomContext("kokkos_execution_space", Kokkos::DefaultExecutionSpace::name());
  benchmark::AddCustomContext("kokkos_threads",
                              std::to_string(Kokkos::DefaultExecutionSpace().concurrency()));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  mpmice::bench::release_kept();
  benchmark::Shutdown();
  return 0;
}

}  // namespace

int main(int argc, char* argv[]) {
  MPI_Init(&argc, &argv);
  const int status = run_benchmarks(argc, argv);
  MPI_Finalize();
  return status;
}
