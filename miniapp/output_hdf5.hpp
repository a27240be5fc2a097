#pragma once
// Field output for ParaView and VisIt: at each output time one HDF5 file written by
// all ranks together through MPI-IO (cells as a structured grid, each solid's
// particles as a point cloud), an XDMF file describing it, and a time-series XDMF
// over all outputs so far. Every file is written under a temporary name and renamed
// when complete.
#include <string>
#include <vector>

#include "problem.hpp"

namespace mpmice {

class FieldOutput {
 public:
  FieldOutput(const Problem& problem, const std::string& directory);
  /// Write the state now (collective). Returns the file name written.
  std::string write(const Problem& problem);

 private:
  std::string m_dir;
  struct Entry {
    std::string file;
    double time;
    std::string grids;  // its XDMF grids, for the time series
  };
  std::vector<Entry> m_written;
};

}  // namespace mpmice
