#pragma once
#include <mpi.h>

#include <memory>
#include <string>

#include "input.hpp"

namespace mpmice {

struct RunOptions {
  std::string output_dir = "mpmice_output";
  long max_steps = -1;    // < 0: the input's time.max_steps
  double end_time = -1;   // < 0: the input's time.end
  bool progress = true;   // a progress line at most every second
  bool report = true;     // the header, the per-step timing table and the summary
  std::string restart;    // a checkpoint file, "latest" (in output_dir), or empty
};

struct Problem;

/// Set up the problem on `comm` and run it to the end time; returns the final state.
/// Throws InputError (exit 2) or InvariantError (exit 3).
std::unique_ptr<Problem> run(const Input& input, const RunOptions& options,
                             MPI_Comm comm = MPI_COMM_WORLD);

}  // namespace mpmice
