#include "diagnostics.hpp"

#include <cmath>
#include <algorithm>
#include <cstdio>

#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/conserved_totals.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/errors.hpp>

namespace mpmice {
namespace {

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

namespace {

// Keep the header and the rows of steps <= `step` of a CSV file (through a temporary
// file); false if the file does not exist.
bool truncate_after(const std::string& path, long step) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line, kept;
  std::getline(in, line);
  kept = line + "\n";
  while (std::getline(in, line))
    if (std::atol(line.c_str()) <= step) kept += line + "\n";
  in.close();
  const std::string tmp = path + ".tmp";
  std::ofstream(tmp) << kept;
  std::rename(tmp.c_str(), path.c_str());
  return true;
}

}  // namespace

Diagnostics::Diagnostics(const Problem& pb, const std::string& dir, long restart_step) {
  MPI_Comm_rank(pb.decomposition->comm(), &m_rank);
  const Patch& p = pb.patch();
  for (const auto& probe : pb.input.probes) {
    ProbeCell pc;
    bool mine = true;
    for (int d = 0; d < 3; ++d) {
      int g = int(std::floor((probe.position[d] - p.grid.lower[d]) / p.grid.spacing[d]));
      g = std::min(std::max(g, 0), p.grid.cells[d] - 1);
      mine = mine && g >= p.lo[d] && g < p.hi[d];
      pc.cell[d] = p.local_index(g, d);
    }
    pc.mine = mine;
    m_probe_cells.push_back(pc);
  }
  if (m_rank != 0) return;
  if (restart_step >= 0 && truncate_after(dir + "/history.csv", restart_step) &&
      truncate_after(dir + "/probes.csv", restart_step)) {
    m_history.open(dir + "/history.csv", std::ios::app);
    m_probes.open(dir + "/probes.csv", std::ios::app);
    if (!m_history || !m_probes)
      throw InputError("--output-dir", "cannot append to history.csv and probes.csv in '" + dir + "'");
    return;
  }
  m_history.open(dir + "/history.csv");
  m_probes.open(dir + "/probes.csv");
  if (!m_history || !m_probes)
    throw InputError("--output-dir", "cannot write history.csv and probes.csv in '" + dir + "'");
  m_history << "step,time,dt";
  std::vector<std::string> names;
  for (const auto& m : pb.input.materials) names.push_back(m.name);
  names.push_back("total");
  for (const auto& name : names)
    for (const char* q : {"mass", "momentum_x", "momentum_y", "momentum_z", "energy"})
      m_history << "," << q << ":" << name;
  // With reactions the energy balance needs the solids' internal energy (the reactant's
  // m c_v T goes to the products) and the heat of reaction released so far.
  if (!pb.reactions.empty()) m_history << ",thermal_energy:solids,chemical_energy_released";
  m_history << "\n";
  m_probes << "step,time,probe,quantity,material,value\n";
  m_history.flush();
  m_probes.flush();
}

std::vector<std::array<double, 5>> Diagnostics::totals(const Problem& pb) {
  const Patch& p = pb.patch();
  const int n = int(pb.input.materials.size());
  std::vector<double> all(5 * (n + 1), 0.0);
  for (int r : pb.ice) {  // fluids from their cells, solids from their particles
    const VectorField4 vel = vector_field(pb.fields, "vel_CC");
    const MaterialTotals t = ice_totals(p.owned_cells(), p.grid.cell_volume(), r, pb.materials.eos[r].cv,
                                        pb.fields.get<Field4>("rho_CC"), pb.fields.get<Field4>("temp_CC"),
                                        ConstVectorField4{vel[0], vel[1], vel[2]});
    for (int q = 0; q < 5; ++q) all[5 * r + q] = t.value[q];
  }
  for (int s = 0; s < pb.solid_count(); ++s) {
    const MaterialTotals t = particle_totals(long(pb.particles[s].size()), pb.particles[s].data(), pb.solids[s]);
    for (int q = 0; q < 5; ++q) all[5 * pb.mpm[s] + q] = t.value[q];
  }
  global_sum(pb.decomposition->comm(), all);
  std::vector<std::array<double, 5>> out(n + 1);
  for (int m = 0; m < n; ++m)
    for (int q = 0; q < 5; ++q) {
      out[m][q] = all[5 * m + q];
      out[n][q] += all[5 * m + q];
    }
  return out;
}

void Diagnostics::write_fields_csv(const Problem& pb, const std::string& path) {
  const Patch& p = pb.patch();
  const int n = pb.material_count();
  MPI_Comm comm = pb.decomposition->comm();
  const HostState st = host_state(pb);
  const auto &rho = st.rho, &temp = st.temp, &spv = st.sp_vol;
  const auto& press = st.press;
  const auto& vel = st.vel;
  // Row: i, j, k, m, x, y, z, density, velocity_x, velocity_y, velocity_z,
  // temperature, specific_volume, volume_fraction, pressure.
  constexpr int width = 15;
  std::vector<double> rows;
  const IndexBox own = p.owned_cells();
  for (int i = own.lo[0]; i < own.hi[0]; ++i)
    for (int j = own.lo[1]; j < own.hi[1]; ++j)
      for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int m = 0; m < n; ++m) {
          const double row[width] = {double(p.global_index(i, 0)), double(p.global_index(j, 1)),
                                     double(p.global_index(k, 2)), double(m), p.cell_center(i, 0),
                                     p.cell_center(j, 1), p.cell_center(k, 2), rho(m, i, j, k),
                                     vel[0](m, i, j, k), vel[1](m, i, j, k), vel[2](m, i, j, k),
                                     temp(m, i, j, k), spv(m, i, j, k), rho(m, i, j, k) * spv(m, i, j, k),
                                     press(i, j, k)};
          rows.insert(rows.end(), row, row + width);
        }
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int mine = int(rows.size());
  std::vector<int> counts(size), displs(size, 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  std::vector<double> all;
  if (rank == 0) {
    for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    all.resize(std::size_t(displs[size - 1]) + counts[size - 1]);
  }
  MPI_Gatherv(rows.data(), mine, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, comm);
  if (rank != 0) return;
  const std::size_t nrows = all.size() / width;
  std::vector<std::size_t> order(nrows);
  for (std::size_t r = 0; r < nrows; ++r) order[r] = r;
  auto key = [&](std::size_t r) {
    const double* x = &all[r * width];
    return std::array<double, 4>{x[2], x[1], x[0], x[3]};
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw InputError("--output-dir", "cannot write '" + tmp + "'");
    out << "i,j,k,material,x,y,z,density,velocity_x,velocity_y,velocity_z,temperature,"
           "specific_volume,volume_fraction,pressure\n";
    for (std::size_t r : order) {
      const double* x = &all[r * width];
      out << long(x[0]) << "," << long(x[1]) << "," << long(x[2]) << "," << pb.input.materials[int(x[3])].name;
      for (int c = 4; c < width; ++c) out << "," << number(x[c]);
      out << "\n";
    }
    if (!out.flush()) throw InvariantError("writing '" + tmp + "' failed");
  }
  std::rename(tmp.c_str(), path.c_str());
}

void Diagnostics::record(const Problem& pb, double dt) {
  const long step = pb.step;
  if (step % pb.input.output.history_interval == 0 || step == 0) {
    const auto t = totals(pb);
    double thermal = 0;
    if (!pb.reactions.empty()) {
      for (int s = 0; s < pb.solid_count(); ++s)
        thermal += particle_thermal_energy(long(pb.particles[s].size()), pb.particles[s].data(),
                                           pb.materials.eos[pb.mpm[s]].cv);
      thermal = global_sum(pb.decomposition->comm(), thermal);
    }
    if (m_rank == 0) {
      m_history << step << "," << number(pb.time) << "," << number(dt);
      for (const auto& row : t)
        for (double v : row) m_history << "," << number(v);
      if (!pb.reactions.empty())
        m_history << "," << number(thermal) << "," << number(pb.chemical_energy_released);
      m_history << "\n";
      m_history.flush();
    }
  }
  if (pb.input.probes.empty() || !pb.has_cells() ||
      (step % pb.input.output.probe_interval != 0 && step != 0))
    return;
  // Each probe's values come from the rank owning its cell; a sum collects them.
  const int n = pb.material_count();
  const auto& quantities = probe_quantities();
  const std::size_t per_probe = quantities.size() * std::size_t(n);
  std::vector<double> values(pb.input.probes.size() * per_probe, 0.0);
  auto at = [](const auto& view, auto... idx) {
    double v = 0;
    Kokkos::deep_copy(v, Kokkos::subview(view, idx...));
    return v;
  };
  const Field4 rho = pb.fields.get<Field4>("rho_CC"), temp = pb.fields.get<Field4>("temp_CC"),
               spv = pb.fields.get<Field4>("sp_vol_CC");
  const VectorField4 vel = vector_field(pb.fields, "vel_CC");
  const Field3 press = pb.fields.get<Field3>("press_CC");
  for (std::size_t pr = 0; pr < m_probe_cells.size(); ++pr) {
    const ProbeCell& pc = m_probe_cells[pr];
    if (!pc.mine) continue;
    const int i = pc.cell[0], j = pc.cell[1], k = pc.cell[2];
    for (std::size_t q = 0; q < quantities.size(); ++q)
      for (int m = 0; m < n; ++m) {
        const std::string& name = quantities[q];
        double v = 0;
        if (name == "pressure") v = at(press, i, j, k);
        else if (name == "density") v = at(rho, m, i, j, k);
        else if (name == "velocity_x") v = at(vel[0], m, i, j, k);
        else if (name == "velocity_y") v = at(vel[1], m, i, j, k);
        else if (name == "velocity_z") v = at(vel[2], m, i, j, k);
        else if (name == "temperature") v = at(temp, m, i, j, k);
        else if (name == "specific_volume") v = at(spv, m, i, j, k);
        else if (name == "volume_fraction") v = at(rho, m, i, j, k) * at(spv, m, i, j, k);  // (E5)
        values[pr * per_probe + q * n + m] = v;
      }
  }
  global_sum(pb.decomposition->comm(), values);
  if (m_rank != 0) return;
  for (std::size_t pr = 0; pr < pb.input.probes.size(); ++pr) {
    const ProbeInput& probe = pb.input.probes[pr];
    for (const auto& name : probe.quantities) {
      std::size_t q = 0;
      while (quantities[q] != name) ++q;
      const bool shared = name == "pressure";
      for (int m = 0; m < (shared ? 1 : n); ++m)
        m_probes << step << "," << number(pb.time) << "," << probe.name << "," << name << ","
                 << (shared ? std::string("all") : pb.input.materials[m].name) << ","
                 << number(values[pr * per_probe + q * n + m]) << "\n";
    }
  }
  m_probes.flush();
}

}  // namespace mpmice
