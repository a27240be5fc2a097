#include "checkpoint.hpp"

#include "hdf5_io.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <mpmice/kernels/errors.hpp>

namespace mpmice {
namespace {

// The state fields a checkpoint holds (cell fields exist with fluids).
const char* cell_fields[] = {"rho_CC", "temp_CC", "sp_vol_CC", "vel_CC_x", "vel_CC_y", "vel_CC_z"};

// The state fields of this problem: with reactions also what Step 4 decided to burn in
// the next step.
std::vector<std::string> state_fields(const Problem& pb) {
  std::vector<std::string> names(std::begin(cell_fields), std::end(cell_fields));
  if (!pb.reactions.empty()) names.push_back("burn_dm_CC");
  return names;
}

std::string material_list(const Problem& pb) {
  std::string s;
  for (const auto& m : pb.input.materials) s += m.name + (m.is_solid ? "(solid);" : "(fluid);");
  return s;
}

void put_attr(hid_t obj, const char* name, const std::vector<double>& v) {
  hsize_t n = v.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t a = H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  H5Sclose(space);
}
std::vector<double> get_attr(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) return {};
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t space = H5Aget_space(a);
  std::vector<double> v(std::size_t(H5Sget_simple_extent_npoints(space)));
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Sclose(space);
  H5Aclose(a);
  return v;
}
void put_string(hid_t obj, const char* name, const std::string& s) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, s.size() + 1);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, type, s.c_str());
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
}
std::string get_string(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) return {};
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  hid_t type = H5Aget_type(a);
  std::string s(H5Tget_size(type), '\0');
  H5Aread(a, type, s.data());
  H5Tclose(type);
  H5Aclose(a);
  return std::string(s.c_str());
}

// Collective write or read of a 2D block [rows x cols] at row `offset` of a dataset
// with `total` rows.
void block_io(hid_t file, const std::string& name, bool write, hsize_t total, hsize_t cols, hsize_t offset,
              hsize_t rows, double* data) {
  if (!collective_block_io(file, name, write, {total, cols}, {offset, 0}, {rows, cols}, data))
    throw InputError("--restart", "the checkpoint has no dataset '" + name + "'");
}

hsize_t dataset_rows(hid_t file, const std::string& name) {
  hid_t dset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (dset < 0) throw InputError("--restart", "the checkpoint has no dataset '" + name + "'");
  hid_t space = H5Dget_space(dset);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  H5Dclose(dset);
  return dims[0];
}

// Cells as rows: every global cell, x slowest (global index order), one column per
// material. This rank's owned cells are the rows of its patch, so the block is not
// contiguous: read and write go through a strided hyperslab per (i, j) column of k.
void cell_io(hid_t file, const Problem& pb, const std::string& name, bool write, double* local_block,
             int columns) {
  const Patch& p = pb.patch();
  const std::vector<hsize_t> global{hsize_t(p.grid.cells[0]), hsize_t(p.grid.cells[1]), hsize_t(p.grid.cells[2]),
                                    hsize_t(columns)};
  const std::vector<hsize_t> start{hsize_t(p.lo[0]), hsize_t(p.lo[1]), hsize_t(p.lo[2]), 0};
  const std::vector<hsize_t> count{hsize_t(p.owned_cells(0)), hsize_t(p.owned_cells(1)), hsize_t(p.owned_cells(2)),
                                   hsize_t(columns)};
  if (!collective_block_io(file, name, write, global, start, count, local_block))
    throw InputError("--restart", "the checkpoint has no dataset '" + name + "'");
}

}  // namespace

void write_checkpoint(const Problem& pb, double next_dt, const std::string& dir, int keep) {
  MPI_Comm comm = pb.decomposition->comm();
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  char name[64];
  std::snprintf(name, sizeof name, "checkpoint_%06ld.h5", pb.step);
  const std::string path = dir + "/" + name, tmp = path + ".tmp";
  ParallelH5File file(tmp, comm, true);
  if (file.id < 0) throw InvariantError("cannot create the checkpoint '" + tmp + "'");
  const hid_t f = file.id;
  const Grid& g = pb.patch().grid;
  put_attr(f, "time_step_dt", {pb.time, double(pb.step), next_dt, double(pb.particles_left_domain)});
  put_attr(f, "reactions", {pb.chemical_energy_released, double(pb.particles_burned_out)});
  put_attr(f, "grid", {double(g.cells[0]), double(g.cells[1]), double(g.cells[2]), g.lower[0], g.lower[1],
                       g.lower[2], g.spacing[0], g.spacing[1], g.spacing[2]});
  put_attr(f, "ranks", {double(size), double(pb.decomposition->dims()[0]), double(pb.decomposition->dims()[1]),
                        double(pb.decomposition->dims()[2])});
  put_string(f, "materials", material_list(pb));
  const Patch& p = pb.patch();
  const IndexBox own = p.owned_cells();
  const int n = pb.material_count();
  if (pb.has_cells()) {
    std::vector<double> block(std::size_t(own.size()) * n);
    auto pack = [&](auto&& value) {
      std::size_t q = 0;
      for (int i = own.lo[0]; i < own.hi[0]; ++i)
        for (int j = own.lo[1]; j < own.hi[1]; ++j)
          for (int k = own.lo[2]; k < own.hi[2]; ++k)
            for (int m = 0; m < n; ++m) block[q++] = value(m, i, j, k);
    };
    for (const std::string& field : state_fields(pb)) {
      auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pb.fields.get<Field4>(field));
      pack([&](int m, int i, int j, int k) { return h(m, i, j, k); });
      cell_io(f, pb, "/" + field, true, block.data(), n);
    }
    auto press = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pb.fields.get<Field3>("press_CC"));
    std::vector<double> pblock(std::size_t(own.size()));
    std::size_t q = 0;
    for (int i = own.lo[0]; i < own.hi[0]; ++i)
      for (int j = own.lo[1]; j < own.hi[1]; ++j)
        for (int k = own.lo[2]; k < own.hi[2]; ++k) pblock[q++] = press(i, j, k);
    cell_io(f, pb, "/press_CC", true, pblock.data(), 1);
  }
  // Particles: each rank's rows in rank order, so that the same ranks read back the
  // same particles in the same order. The per-rank counts are kept too.
  for (int s = 0; s < pb.solid_count(); ++s) {
    const ParticleSet& ps = pb.particles[s];
    const long mine = long(ps.size());
    std::vector<long> counts(size);
    MPI_Allgather(&mine, 1, MPI_LONG, counts.data(), 1, MPI_LONG, comm);
    long before = 0, total = 0;
    for (int r = 0; r < size; ++r) (r < rank ? before : total) += counts[r];
    total += before;
    const int nc = particle_field_count;
    auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
    std::vector<double> rows(std::size_t(mine) * (nc + 1));
    for (long q = 0; q < mine; ++q) {
      for (int c = 0; c < nc; ++c) rows[q * (nc + 1) + c] = data(q, c);
      rows[q * (nc + 1) + nc] = double(id(q));  // ids < 2^53
    }
    const std::string base = "/particles_" + std::to_string(s);
    block_io(f, base, true, hsize_t(total), hsize_t(nc + 1), hsize_t(before), hsize_t(mine), rows.data());
    std::vector<double> c(counts.begin(), counts.end());
    hid_t dset = H5Dopen2(f, base.c_str(), H5P_DEFAULT);
    put_attr(dset, "rank_counts", c);
    H5Dclose(dset);
  }
  file.close();
  MPI_Barrier(comm);
  if (rank == 0) {
    std::rename(tmp.c_str(), path.c_str());
    // Keep the newest `keep`.
    std::vector<std::string> all;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      const std::string fname = e.path().filename().string();
      if (fname.rfind("checkpoint_", 0) == 0 && fname.size() > 3 && fname.substr(fname.size() - 3) == ".h5")
        all.push_back(e.path().string());
    }
    std::sort(all.begin(), all.end());
    for (std::size_t i = 0; keep > 0 && i + std::size_t(keep) < all.size(); ++i) std::filesystem::remove(all[i]);
  }
  MPI_Barrier(comm);
}

std::string latest_checkpoint(const std::string& dir) {
  std::vector<std::string> all;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string fname = e.path().filename().string();
    if (fname.rfind("checkpoint_", 0) == 0 && fname.size() > 3 && fname.substr(fname.size() - 3) == ".h5")
      all.push_back(e.path().string());
  }
  if (all.empty()) throw InputError("--restart", "no checkpoint_*.h5 in '" + dir + "' to restart from");
  std::sort(all.begin(), all.end());
  return all.back();
}

double read_checkpoint(Problem& pb, const std::string& file) {
  MPI_Comm comm = pb.decomposition->comm();
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // our own messages instead of HDF5's stack
  ParallelH5File h5(file, comm, false);
  if (h5.id < 0) throw InputError("--restart", "cannot open the checkpoint '" + file + "'");
  const hid_t f = h5.id;
  const auto tsd = get_attr(f, "time_step_dt");
  const auto grid = get_attr(f, "grid");
  const auto ranks = get_attr(f, "ranks");
  if (tsd.size() != 4 || grid.size() != 9 || ranks.size() != 4) {
    throw InputError("--restart", "'" + file + "' is not an mpmice checkpoint");
  }
  const Grid& g = pb.patch().grid;
  for (int d = 0; d < 3; ++d)
    if (int(grid[d]) != g.cells[d] || grid[3 + d] != g.lower[d] || grid[6 + d] != g.spacing[d]) {
      throw InputError("--restart", "the checkpoint '" + file + "' was written for another grid (grid.cells, "
                                    "grid.lower or grid.upper differ from the input)");
    }
  if (get_string(f, "materials") != material_list(pb)) {
    throw InputError("--restart", "the checkpoint '" + file + "' was written for other materials (" +
                                      get_string(f, "materials") + " against " + material_list(pb) + ")");
  }
  pb.time = tsd[0];
  pb.step = long(tsd[1]);
  pb.particles_left_domain = long(tsd[3]);
  const auto reactions = get_attr(f, "reactions");
  if (reactions.size() == 2) {
    pb.chemical_energy_released = reactions[0];
    pb.particles_burned_out = long(reactions[1]);
  }
  const Patch& p = pb.patch();
  const IndexBox own = p.owned_cells();
  const int n = pb.material_count();
  if (pb.has_cells()) {
    std::vector<double> block(std::size_t(own.size()) * n);
    for (const std::string& field : state_fields(pb)) {
      cell_io(f, pb, "/" + field, false, block.data(), n);
      Field4 view = pb.fields.get<Field4>(field);
      auto h = Kokkos::create_mirror_view(view);
      Kokkos::deep_copy(h, view);
      std::size_t q = 0;
      for (int i = own.lo[0]; i < own.hi[0]; ++i)
        for (int j = own.lo[1]; j < own.hi[1]; ++j)
          for (int k = own.lo[2]; k < own.hi[2]; ++k)
            for (int m = 0; m < n; ++m) h(m, i, j, k) = block[q++];
      Kokkos::deep_copy(view, h);
    }
    std::vector<double> pblock(std::size_t(own.size()));
    cell_io(f, pb, "/press_CC", false, pblock.data(), 1);
    Field3 press = pb.fields.get<Field3>("press_CC");
    auto h = Kokkos::create_mirror_view(press);
    Kokkos::deep_copy(h, press);
    std::size_t q = 0;
    for (int i = own.lo[0]; i < own.hi[0]; ++i)
      for (int j = own.lo[1]; j < own.hi[1]; ++j)
        for (int k = own.lo[2]; k < own.hi[2]; ++k) h(i, j, k) = pblock[q++];
    Kokkos::deep_copy(press, h);
    fill_state_extra_cells(pb, "");
  }
  const bool same_ranks = int(ranks[0]) == size && int(ranks[1]) == pb.decomposition->dims()[0] &&
                          int(ranks[2]) == pb.decomposition->dims()[1] && int(ranks[3]) == pb.decomposition->dims()[2];
  const int nc = particle_field_count;
  for (int s = 0; s < pb.solid_count(); ++s) {
    const std::string base = "/particles_" + std::to_string(s);
    const hsize_t total = dataset_rows(f, base);
    hsize_t offset = 0, rows = total;
    if (same_ranks) {  // this rank's own rows, in their order
      hid_t dset = H5Dopen2(f, base.c_str(), H5P_DEFAULT);
      const auto counts = get_attr(dset, "rank_counts");
      H5Dclose(dset);
      offset = 0;
      for (int r = 0; r < rank; ++r) offset += hsize_t(counts[r]);
      rows = hsize_t(counts[rank]);
    }
    std::vector<double> data(rows * (nc + 1));
    block_io(f, base, false, total, hsize_t(nc + 1), offset, rows, data.data());
    // Keep the rows in this patch (all of them when the ranks are the same).
    std::vector<long> keep;
    for (hsize_t q = 0; q < rows; ++q) {
      bool inside = true;
      for (int d = 0; d < 3 && !same_ranks; ++d) {
        const double x = data[q * (nc + 1) + column(ParticleField::x) + d];
        inside = inside && x >= p.owned_lower(d) && x < p.owned_upper(d);
      }
      if (inside) keep.push_back(long(q));
    }
    ParticleSet ps(pb.particles[s].label(), keep.size());
    ps.resize(keep.size());
    auto h = Kokkos::create_mirror_view(ps.data());
    auto id = Kokkos::create_mirror_view(ps.id());
    for (std::size_t q = 0; q < keep.size(); ++q) {
      for (int c = 0; c < nc; ++c) h(q, c) = data[keep[q] * (nc + 1) + c];
      id(q) = std::int64_t(data[keep[q] * (nc + 1) + nc]);
    }
    Kokkos::deep_copy(ps.data(), h);
    Kokkos::deep_copy(ps.id(), id);
    pb.particles[s] = std::move(ps);
  }
  h5.close();
  for (const auto& name : pb.fields.names())
    if (name != "NC_CCweight") pb.fields.set_valid_ghosts(name, 0);
  return tsd[2];
}

}  // namespace mpmice
