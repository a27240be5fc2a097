// The solids' steps after the exchange: grid-to-particle, stress, migration.
#include "cycle.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include <mpmice/halo/migrate.hpp>
#include <mpmice/kernels/bad_particles.hpp>
#include <mpmice/kernels/g2p.hpp>
#include <mpmice/kernels/grid_update.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/particle_sort.hpp>
#include <mpmice/kernels/stress_update.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

namespace {
// "particle 17 of material 'pbx' (at x, y, z m)": the row's id and, when finite, where it is.
std::string particle_name(const ParticleSet& ps, long row, const std::string& material) {
  const auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(ps.id(), row));
  const auto x = Kokkos::create_mirror_view_and_copy(
      Kokkos::HostSpace(), Kokkos::subview(ps.data(), row, std::make_pair(column(ParticleField::x), column(ParticleField::x) + 3)));
  std::string name = "particle " + std::to_string(id()) + " of material '" + material + "'";
  if (std::isfinite(x(0)) && std::isfinite(x(1)) && std::isfinite(x(2)))
    name += fmt::format(" (at {:.6g}, {:.6g}, {:.6g} m)", x(0), x(1), x(2));
  return name;
}

// Stops the run when a particle's state is broken (bad_particles.hpp), naming it.
void stop_if_bad_particles(MPI_Comm comm, const Problem& pb, const char* step) {
  BadParticle bad;
  int material = 0;
  for (int s = 0; s < pb.solid_count() && bad.count == 0; ++s) {
    bad = find_bad_particles(long(pb.particles[s].size()), pb.particles[s].data());
    material = s;
  }
  std::string message;
  if (bad.count > 0) {
    const ParticleQuantity q = bad.quantity;
    const bool sign = q == ParticleQuantity::mass || q == ParticleQuantity::volume;
    message = std::string(step) + ": the " + quantity_name(q) + " of " +
              particle_name(pb.particles[material], bad.row, pb.input.materials[pb.mpm[material]].name) + " is " +
              (q == ParticleQuantity::temperature ? "not positive or " : sign ? "negative or " : "") +
              "not finite (" + std::to_string(bad.count) + " particles of that material on this rank)";
  }
  stop_if_any(comm, bad.count > 0, message);
}
}  // namespace

// Steps 20 (node conditions), 21-24, 27: the particles' update, stress, migration.
void Cycle::add_particle_update_steps() {
  const Patch& p = m_pb.patch();
  const NodeGrid grid = node_grid(p);
  const int ns = m_pb.solid_count();
  const bool gimp = m_pb.input.mpm.gimp;
  const double pic = m_pb.input.mpm.pic_fraction;
  const FaceBcs velocity_bcs = m_pb.input.boundary.velocity;
  const IndexBox nodes = p.with_extra(Location::node, p.ghosts);
  const bool heat = m_pb.has_cells();
  const double& dt = m_dt;
  Kokkos::Array<int, max_materials> deformable;  // the node conditions act on all but rigid bodies
  for (int s = 0; s < max_materials; ++s) deformable[s] = s < ns && m_pb.solids[s].type != SolidModelType::rigid;
  m_steps.push_back(Step{"node_boundary_conditions", {},
                         cat<FieldWrite>({vec_out("vel_NC"), vec_out("vel_star_NC"), vec_out("acc_NC")}),
                         [=, &dt](const StepContext& ctx) {
                           node_velocity_bcs(p, nodes, ns, deformable, dt, velocity_bcs, write_vec(ctx, "vel_NC"),
                                             write_vec(ctx, "vel_star_NC"), write_vec(ctx, "acc_NC"));
                         }});
  Reads g2p_reads = cat<FieldRead>({vec("vel_star_NC", 1), vec("acc_NC", 1)});
  if (heat) {
    g2p_reads.push_back({"temp_rate_NC", 1});
    g2p_reads.push_back({"transfer_energy_NC", 1});
  }
  m_steps.push_back(Step{"g2p", g2p_reads, {}, [=, &dt](const StepContext& ctx) {
                           const auto vel_star = read_vec(ctx, "vel_star_NC");
                           const auto acc = read_vec(ctx, "acc_NC");
                           const ConstField4 rate = heat ? ConstField4(ctx.read<Field4>("temp_rate_NC")) : ConstField4();
                           for (int s = 0; s < ns; ++s) {
                             const SolidModel& model = m_pb.solids[s];
                             const bool rigid = model.type == SolidModelType::rigid;
                             // Mid-step velocity: the stroke integrates the ramp to second order.
                             const Kokkos::Array<double, 3> v = model.rigid_velocity(m_time + 0.5 * dt);
                             const ParticleSet& ps = m_pb.particles[s];
                             TransferHeat transfer;
                             if (heat) transfer = {ctx.read<Field4>("transfer_energy_NC"), m_pb.materials.eos[m_pb.mpm[s]].cv};
                             with_shape(gimp, [&](auto shape) {
                               g2p<decltype(shape)>(grid, long(ps.size()), ps.data(), s, dt, pic, rigid, v, vel_star,
                                                    acc, rate, transfer);
                             });
                           }
                         }});
  m_steps.push_back(Step{"stress_update", {}, {}, [=, &dt](const StepContext&) {
                           double limit = 1e300;
                           for (int s = 0; s < ns; ++s)
                             limit = std::min(limit, stress_update(grid, long(m_pb.particles[s].size()),
                                                                   m_pb.particles[s].data(), m_pb.solids[s], dt));
                           m_mpm_dt_limit = limit;
                           stop_if_bad_particles(m_pb.decomposition->comm(), m_pb, "stress_update");
                         }});
  m_steps.push_back(Step{"migrate_particles", {}, {}, [this, ns, gimp](const StepContext&) {
                           long lost = 0;
                           const long interval = m_pb.input.mpm.sort_interval;
                           for (int s = 0; s < ns; ++s) {
                             lost += migrate(*m_pb.decomposition, m_pb.particles[s]).left_domain;
                             if (interval > 0 && (m_pb.step + 1) % interval == 0)
                               with_shape(gimp, [&](auto shape) {
                                 sort_particles_by_window<decltype(shape)>(m_pb.patch(), m_pb.particles[s]);
                               });
                           }
                           m_pb.particles_left_domain += global_sum(m_pb.decomposition->comm(), lost);
                         }});
}

}  // namespace mpmice
