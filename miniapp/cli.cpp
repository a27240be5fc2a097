#include "cli.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <iostream>

#include <mpmice/kernels/errors.hpp>

#include "input.hpp"
#include "cycle.hpp"
#include "input_echo.hpp"
#include "problem.hpp"
#include "run.hpp"
#include "version_info.hpp"

namespace mpmice {

int run_cli(int argc, char* argv[]) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  CLI::App app{
      "mpmice: the MPM-ICE fluid-structure interaction mini-app (Kokkos + MPI).\n"
      "Runs the problem in INPUT (YAML; see problems/) and writes history.csv and\n"
      "probes.csv to the output directory. Run it directly or under mpiexec. Kokkos\n"
      "takes its own --kokkos-* options (--kokkos-threads=N, --kokkos-help, ...).\n"
      "Exit status: 0 done, 2 bad input or command line, 3 the run broke an invariant."};
  app.name("mpmice");
  bool version = false;
  std::string input_file;
  RunOptions options;
  std::vector<std::string> overrides;
  app.add_flag("--version", version, "Print the versions of mpmice, Kokkos (backends, threads) and MPI");
  app.add_option("input", input_file, "Problem input (YAML)");
  app.add_option("--output-dir,-o", options.output_dir, "Directory for history.csv and probes.csv")
      ->capture_default_str();
  app.add_option("--max-steps", options.max_steps, "Stop after this many steps")->check(CLI::NonNegativeNumber);
  app.add_option("--end-time", options.end_time, "Stop at this time, s (overrides time.end)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--set", overrides, "Override an input value: key.path=value (repeatable), e.g. "
                                     "--set grid.cells=[200,1,1]");
  app.add_flag("!--no-progress", options.progress, "No progress lines");
  app.add_option("--restart", options.restart,
                 "Continue from a checkpoint: a checkpoint_NNNNNN.h5 file, or 'latest' (the newest in the "
                 "output directory)");
  bool check = false;
  app.add_flag("--check", check,
               "Validate INPUT (and its set-up on this many ranks) without running it; print the "
               "configuration with every default filled in");
  bool list_steps = false;
  app.add_flag("--steps", list_steps,
               "Print the timestep's steps for INPUT (declared reads with ghost layers, writes) as a "
               "markdown table, and exit");

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
  if (input_file.empty()) {
    if (rank == 0) fmt::print("{}", app.help());
    return 0;
  }
  try {
    const Input input = load_input(input_file, overrides);
    if (check) {
      auto problem = make_problem(input, MPI_COMM_WORLD);  // set-up errors too
      if (rank == 0) fmt::print("# {}: valid\n{}", input_file, resolved_yaml(input));
      return 0;
    }
    if (list_steps) {
      auto problem = make_problem(input, MPI_COMM_WORLD);
      Cycle cycle(*problem);
      if (rank == 0) fmt::print("{}", steps_table(cycle.steps()));
      return 0;
    }
    run(input, options);
  } catch (const InputError& e) {
    if (rank == 0) {
      const std::string where = e.line() > 0 ? input_file + ":" + std::to_string(e.line()) + ": " : input_file + ": ";
      std::cerr << "mpmice: input error: " << where << e.what() << "\n";
    }
    return 2;
  } catch (const InvariantError& e) {
    // The ranks that saw the failure carry its description; the others are empty.
    if (std::string(e.what()).size() > 0)
      std::cerr << "mpmice: stopped (rank " << rank << "): " << e.what() << "\n";
    else if (rank == 0)
      std::cerr << "mpmice: stopped: another rank found a broken invariant\n";
    return 3;
  }
  return 0;
}

}  // namespace mpmice
