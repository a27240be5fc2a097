#pragma once
// Checkpoints: the whole persistent state (every material's cell state and pressure,
// every particle with all its components and id, time, step, the next dt) in one HDF5
// file written by all ranks through MPI-IO, under a temporary name renamed when
// complete, so that a run killed at any moment leaves its previous checkpoint usable.
// A restart on the same ranks continues bit for bit; on other ranks, each rank takes
// the particles in its patch (the sums then differ in round-off).
#include <string>

#include "problem.hpp"

namespace mpmice {

/// Write DIR/checkpoint_<step>.h5 (collective) and delete all but the newest `keep`.
void write_checkpoint(const Problem& problem, double next_dt, const std::string& dir, int keep);

/// The newest complete checkpoint in `dir`, or InputError if there is none.
std::string latest_checkpoint(const std::string& dir);

/// Load `file` into `problem` (set up from a compatible input; InputError naming what
/// differs otherwise). Returns the dt of the next step.
double read_checkpoint(Problem& problem, const std::string& file);

}  // namespace mpmice
