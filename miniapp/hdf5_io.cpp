#include "hdf5_io.hpp"

namespace mpmice {

bool collective_block_io(hid_t file, const std::string& name, bool write, const std::vector<hsize_t>& global,
                         const std::vector<hsize_t>& start, const std::vector<hsize_t>& count, double* data) {
  const int rank = int(global.size());
  hid_t dset, filespace;
  if (write) {
    filespace = H5Screate_simple(rank, global.data(), nullptr);
    dset = H5Dcreate2(file, name.c_str(), H5T_NATIVE_DOUBLE, filespace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  } else {
    dset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    if (dset < 0) return false;
    filespace = H5Dget_space(dset);
  }
  hid_t memspace = H5Screate_simple(rank, count.data(), nullptr);
  hsize_t total = 1;
  for (auto c : count) total *= c;
  if (total == 0) {
    H5Sselect_none(filespace);
    H5Sselect_none(memspace);
  } else {
    H5Sselect_hyperslab(filespace, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
  }
  hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
  if (write)
    H5Dwrite(dset, H5T_NATIVE_DOUBLE, memspace, filespace, xfer, data);
  else
    H5Dread(dset, H5T_NATIVE_DOUBLE, memspace, filespace, xfer, data);
  H5Pclose(xfer);
  H5Sclose(memspace);
  H5Sclose(filespace);
  H5Dclose(dset);
  return true;
}

ParallelH5File::ParallelH5File(const std::string& path, MPI_Comm comm, bool create) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  id = create ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl) : H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
}

void ParallelH5File::close() {
  if (id >= 0) H5Fclose(id);
  id = -1;
}

}  // namespace mpmice
