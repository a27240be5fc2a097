// The cycle: its steps in order, the timestep limit, and the table of the steps.
#include "cycle.hpp"

#include <algorithm>
#include <string>

#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/node_to_cell.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/stress_update.hpp>
#include <mpmice/kernels/timestep.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

Cycle::Cycle(Problem& pb) : m_pb(pb), m_runner(*pb.halo, pb.fields) {
  const Patch& p = pb.patch();
  if (pb.has_cells()) {
    for (int d = 0; d < 3; ++d) {
      m_grad[d] = make_field("advection_gradient", p, Location::cell);
      m_mass_grad[d] = make_field("advection_mass_gradient", p, Location::cell);
    }
    m_adv_mass = make_field("advected_mass", p, Location::cell, pb.material_count());
    m_adv_q = make_field("advected_quantity", p, Location::cell, pb.material_count());
    m_face_flux = make_face_fluxes("advection_face_flux", p);
    m_ke = make_field("specific_kinetic_energy", p, Location::cell, pb.material_count());
  }
  for (int s = 0; s < pb.solid_count(); ++s) {
    // A rigid body's particle masses never change: one mass unit for the whole run, the
    // same on every rank (rigid_particle_to_cell).
    const double heaviest = global_max(pb.decomposition->comm(),
                                       max_particle_mass(long(pb.particles[s].size()), pb.particles[s].data()));
    m_rigid_mass_quantum.push_back((heaviest > 0 ? heaviest : 1.0) * 0x1p-40);
    // Every particle mass a multiple of one power of two, so that the scatters' sums and
    // a burn's transfers are exact whatever their order (quanta.hpp): 2^-41 relative at
    // most, once. Masses only decrease, by multiples of the same quantum.
    const double q = quantum_for(heaviest);
    m_mass_quantum.push_back(q);
    const auto mass = pb.particles[s].get(ParticleField::mass);
    Kokkos::parallel_for(
        "mpmice::mass_on_grid", Kokkos::RangePolicy<ExecSpace>(0, long(pb.particles[s].size())),
        KOKKOS_LAMBDA(long p) { mass(p) = on_grid(mass(p), q); });
  }
  if (pb.solid_count() > 0) {
    // The first step's limit from the initial particles (stress from F = I: zero).
    const NodeGrid grid = node_grid(p);
    for (int s = 0; s < pb.solid_count(); ++s)
      m_mpm_dt_limit = std::min(m_mpm_dt_limit, stress_update(grid, long(pb.particles[s].size()),
                                                              pb.particles[s].data(), pb.solids[s], 0.0));
  }
  const bool cells = pb.has_cells(), solids = pb.solid_count() > 0;
  if (!pb.reactions.empty()) add_burn_step();
  if (solids) add_particle_to_grid_steps();
  if (cells && solids) add_node_to_cell_step();
  if (cells) add_pressure_steps();
  if (solids) add_force_steps();
  if (cells) add_lagrangian_steps();
  if (solids) add_particle_update_steps();
  if (cells) add_advection_steps();
  for (const auto& s : m_steps) m_runner.validate(s);
}

SumQuanta Cycle::scatter_quanta(int s) const {
  MPI_Comm comm = m_pb.decomposition->comm();
  const ParticleSet& ps = m_pb.particles[s];
  const SumQuanta bound = particle_scatter_bounds(long(ps.size()), ps.data());
  std::vector<double> largest{bound.momentum, bound.heat, bound.volume, bound.external_force};
  global_max(comm, largest);  // one allreduce for the four
  SumQuanta global;
  global.momentum = largest[0];
  global.heat = largest[1];
  global.volume = largest[2];
  global.external_force = largest[3];
  SumQuanta q = quanta_for(global);
  q.mass = m_mass_quantum[s];
  return q;
}

std::string steps_table(const std::vector<Step>& steps) {
  // A vector's three components are listed once, as name_*.
  auto display = [](const std::string& n) {
    const bool component = n.size() > 2 && n[n.size() - 2] == '_' && (n.back() == 'x' || n.back() == 'y' || n.back() == 'z');
    return component ? n.substr(0, n.size() - 1) + "*" : n;
  };
  auto join = [](const std::vector<std::string>& items) {
    std::vector<std::string> seen;
    std::string s;
    for (const auto& item : items) {
      if (std::find(seen.begin(), seen.end(), item) != seen.end()) continue;
      seen.push_back(item);
      s += (s.empty() ? "" : ", ") + item;
    }
    return s.empty() ? std::string("-") : s;
  };
  std::string table = "| # | step | reads (ghost layers) | writes (+: summed into owners) |\n|---:|---|---|---|\n";
  int i = 0;
  for (const Step& step : steps) {
    std::vector<std::string> reads, writes;
    for (const auto& r : step.reads) reads.push_back(display(r.field) + ":" + std::to_string(r.ghosts));
    for (const auto& w : step.writes) writes.push_back(display(w.field) + (w.sum_ghosts ? "+" : ""));
    table += "| " + std::to_string(++i) + " | `" + step.name + "` | " + join(reads) + " | " + join(writes) + " |\n";
  }
  return table;
}

void Cycle::advance(double time, double dt) {
  m_dt = dt;
  m_time = time;
  if (!m_pb.has_cells()) {
    for (const Step& s : m_steps) m_runner.run(s);
    return;
  }
  for (const Step& s : m_steps) m_runner.run(s);
  // The new state becomes the old: t^{n+1} -> t^n.
  for (const std::string name : {"rho_CC", "temp_CC", "sp_vol_CC", "press_CC"})
    m_pb.fields.swap(name, name + "_new");
  const auto c = components("vel_CC");
  const auto c_new = components("vel_CC_new");
  for (int d = 0; d < 3; ++d) m_pb.fields.swap(c[d], c_new[d]);
}

double Cycle::stable_timestep() const {
  const Patch& p = m_pb.patch();
  const double solid_limit = m_pb.input.time.cfl * global_min(m_pb.decomposition->comm(), m_mpm_dt_limit);
  if (!m_pb.has_cells()) return solid_limit;
  const VectorField4 vel = vector_field(m_pb.fields, "vel_CC");
  const double dt = ice_timestep(p.owned_cells(), p.grid.spacing_array(),
                                 m_pb.input.time.cfl, m_pb.materials, m_pb.fields.get<Field4>("rho_CC"),
                                 m_pb.fields.get<Field4>("sp_vol_CC"),
                                 m_pb.fields.get<Field4>("temp_CC"), ConstVectorField4{vel[0], vel[1], vel[2]});
  return std::min(global_min(m_pb.decomposition->comm(), dt), solid_limit);
}

}  // namespace mpmice
