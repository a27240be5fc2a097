#pragma once
// Collective reads and writes of one block of an HDF5 dataset through MPI-IO, for the
// field output and the checkpoints: every rank calls with its own block (possibly
// empty) of a dataset of `global` dimensions.
#include <hdf5.h>
#include <mpi.h>

#include <string>
#include <vector>

namespace mpmice {

/// Create (write) or open (read) dataset `name` of doubles with dimensions `global`,
/// and move this rank's block of `count` entries starting at `start` (C order, data
/// in `data`). Returns false if a read finds no such dataset.
bool collective_block_io(hid_t file, const std::string& name, bool write, const std::vector<hsize_t>& global,
                         const std::vector<hsize_t>& start, const std::vector<hsize_t>& count, double* data);

/// An HDF5 file opened (or created) for parallel access by every rank of `comm`;
/// id < 0 if that failed. Closed on scope exit.
struct ParallelH5File {
  hid_t id = -1;
  ParallelH5File(const std::string& path, MPI_Comm comm, bool create);
  ~ParallelH5File() { close(); }
  /// Close now (collective), e.g. before renaming the file.
  void close();
  ParallelH5File(const ParallelH5File&) = delete;
  ParallelH5File& operator=(const ParallelH5File&) = delete;
};

}  // namespace mpmice
