#pragma once
// Running problems/ inputs in-process and reading their state, for validation tests.
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <mpmice/kernels/grid_state.hpp>

#include "input.hpp"
#include "problem.hpp"
#include "run.hpp"

namespace mpmice::validation {

inline std::string problem_path(const std::string& name) {
  return std::string(MPMICE_SOURCE_DIR) + "/problems/" + name;
}

/// Run problems/<name> with `--set` overrides on `comm`, writing into `outdir`.
inline std::unique_ptr<Problem> run_problem(const std::string& name, const std::vector<std::string>& sets,
                                            MPI_Comm comm, const std::string& outdir) {
  const Input in = load_input(problem_path(name), sets);
  RunOptions o;
  o.output_dir = outdir;
  o.progress = false;
  o.report = false;
  return run(in, o, comm);
}

/// A cell quantity of material m along direction d of a 1D problem, indexed by global
/// cell, gathered on every rank.
inline std::vector<double> profile(const Problem& pb, const std::string& field, int m, int d) {
  const Patch& p = pb.patch();
  const int n = p.grid.cells[d];
  std::vector<double> out(n, 0.0);
  const IndexBox own = p.owned_cells();
  auto copy_out = [&](auto host, auto value) {
    for (int i = own.lo[0]; i < own.hi[0]; ++i)
      for (int j = own.lo[1]; j < own.hi[1]; ++j)
        for (int k = own.lo[2]; k < own.hi[2]; ++k) {
          const int idx[3] = {i, j, k};
          out[p.global_index(idx[d], d)] = value(host, i, j, k);
        }
  };
  if (field == "press_CC") {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pb.fields.get<Field3>(field));
    copy_out(h, [](auto& v, int i, int j, int k) { return v(i, j, k); });
  } else {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pb.fields.get<Field4>(field));
    copy_out(h, [m](auto& v, int i, int j, int k) { return v(m, i, j, k); });
  }
  MPI_Allreduce(MPI_IN_PLACE, out.data(), n, MPI_DOUBLE, MPI_SUM, pb.decomposition->comm());
  return out;
}

/// A CSV file: its header names and its rows of numbers (non-numeric fields read 0).
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

inline Table read_csv(const std::string& path) {
  std::ifstream in(path);
  Table t;
  std::string line, cell;
  std::getline(in, line);
  std::stringstream hs(line);
  while (std::getline(hs, cell, ',')) t.header.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    while (std::getline(ss, cell, ',')) row.push_back(std::atof(cell.c_str()));
    t.rows.push_back(row);
  }
  return t;
}

/// Largest difference between two history.csv tables, each value relative to the
/// scale of its quantity: a column's largest magnitude, and for momentum the
/// momentum scale of the run, sqrt(total mass x total energy) (a momentum that is
/// zero by symmetry is compared with what momentum errors would be measured against).
/// +inf if the shapes differ.
inline double max_relative_difference(const Table& a, const Table& b) {
  if (a.rows.size() != b.rows.size() || a.rows.empty() || a.header != b.header) return 1e300;
  std::size_t mass_col = 0, energy_col = 0;
  for (std::size_t c = 0; c < a.header.size(); ++c) {
    if (a.header[c] == "mass:total") mass_col = c;
    if (a.header[c] == "energy:total") energy_col = c;
  }
  double momentum_scale = 0;
  for (const auto& row : a.rows)
    momentum_scale = std::max(momentum_scale, std::sqrt(std::abs(row[mass_col] * row[energy_col])));
  double worst = 0;
  for (std::size_t c = 0; c < a.header.size(); ++c) {
    double scale = 0;
    for (const auto& row : a.rows) scale = std::max(scale, std::abs(row[c]));
    if (a.header[c].rfind("momentum", 0) == 0) scale = std::max(scale, momentum_scale);
    for (std::size_t r = 0; r < a.rows.size(); ++r) {
      if (a.rows[r].size() != b.rows[r].size()) return 1e300;
      const double diff = std::abs(a.rows[r][c] - b.rows[r][c]);
      worst = std::max(worst, scale > 0 ? diff / scale : (diff > 0 ? 1e300 : 0.0));
    }
  }
  return worst;
}

inline std::string scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("mpmice_test_" + name);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace mpmice::validation
