#include "cli.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include "version_info.hpp"

namespace mpmice {

int run_cli(int argc, char* argv[]) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  CLI::App app{
      "mpmice: the MPM-ICE fluid-structure interaction mini-app (Kokkos + MPI).\n"
      "Run it directly or under mpiexec. Kokkos takes its own --kokkos-* options\n"
      "(--kokkos-threads=N, --kokkos-help, ...)."};
  app.name("mpmice");
  bool version = false;
  app.add_flag("--version", version, "Print the versions of mpmice, Kokkos (backends, threads) and MPI");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    if (rank == 0) app.exit(e);
    return 0;
  } catch (const CLI::ParseError& e) {
    if (rank == 0) app.exit(e);
    return 2;  // a bad command line is an input error
  }

  if (version) {
    if (rank == 0) fmt::print("{}", version_info());
    return 0;
  }
  if (rank == 0) fmt::print("{}", app.help());
  return 0;
}

}  // namespace mpmice
