// The solids' steps before the exchange: burn, particle-to-grid, node-to-cell, forces.
#include "cycle.hpp"

#include <cmath>
#include <string>

#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/cell_to_node.hpp>
#include <mpmice/kernels/grid_update.hpp>
#include <mpmice/kernels/internal_force.hpp>
#include <mpmice/kernels/node_to_cell.hpp>
#include <mpmice/kernels/p2g.hpp>
#include <mpmice/kernels/particle_burn.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/particle_pressure.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/simple_burn.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

// Step 4's transfer (E46), one step after Step 4 decided it: the reactant's particles lose
// the mass burn_dm_CC holds, the products gain it (reaction_*_CC), burned-out particles
// go. Done before P2G so that the solid's nodes and cells never see the burned mass
// (particle_burn.hpp; docs/design.md, "Reactions").
void Cycle::add_burn_step() {
  const Patch& p = m_pb.patch();
  const NodeGrid grid = node_grid(p);
  m_burn_cell_mass = make_field("burn_cell_mass", p, Location::cell);
  m_steps.push_back(Step{
      "burn_particles", {{"burn_dm_CC", 0}},
      cat<FieldWrite>({{{"reaction_mass_CC"}, {"reaction_eng_CC"}}, vec_out("reaction_mom_CC")}),
      [this, grid](const StepContext& ctx) {
        const ProductSources src{ctx.write<Field4>("reaction_mass_CC"), write_vec(ctx, "reaction_mom_CC"),
                                 ctx.write<Field4>("reaction_eng_CC")};
        Kokkos::deep_copy(src.mass, 0.0);
        Kokkos::deep_copy(src.energy, 0.0);
        for (int d = 0; d < 3; ++d) Kokkos::deep_copy(src.momentum[d], 0.0);
        double chemical = 0;
        long burned_out = 0;
        for (const SimpleBurn& b : m_pb.reactions) {
          ParticleSet& ps = m_pb.particles[b.reactant_slot];
          const double cv = m_pb.materials.eos[b.reactant].cv;
          SumQuanta q = scatter_quanta(b.reactant_slot);
          q.energy = quantum_for(cv * std::ldexp(q.heat, 41) + b.enthalpy * std::ldexp(q.mass, 41));
          chemical += b.enthalpy * burn_particles(grid, long(ps.size()), ps.data(), cv, m_pb.solids[b.reactant_slot], b,
                                                  ctx.read<Field4>("burn_dm_CC"), m_burn_cell_mass, src, q);
          burned_out += remove_massless_particles(ps);
        }
        MPI_Comm comm = m_pb.decomposition->comm();
        m_pb.chemical_energy_released += global_sum(comm, chemical);
        m_pb.particles_burned_out += global_sum(comm, burned_out);
      }});
}

// Step 1 (E12) and the node velocity and temperature; Steps 12 and 14 come later.
void Cycle::add_particle_to_grid_steps() {
  const Patch& p = m_pb.patch();
  const NodeGrid grid = node_grid(p);
  const int ns = m_pb.solid_count();
  const bool gimp = m_pb.input.mpm.gimp;
  const IndexBox nodes = p.with_extra(Location::node, p.ghosts);
  const FaceBcs velocity_bcs = m_pb.input.boundary.velocity;
  m_steps.push_back(Step{
      "p2g", {},
      cat<FieldWrite>({{{"mass_NC", 0, 1}, {"heat_NC", 0, 1}, {"volume_NC", 0, 1}}, vec_summed("mom_NC"),
                       vec_summed("fext_NC")}),
      [this, grid, gimp, ns](const StepContext& ctx) {
        const NodeSums sums{ctx.write<Field4>("mass_NC"), write_vec(ctx, "mom_NC"), ctx.write<Field4>("heat_NC"),
                            ctx.write<Field4>("volume_NC"), write_vec(ctx, "fext_NC")};
        for (int s = 0; s < ns; ++s) {
          const ParticleSet& ps = m_pb.particles[s];
          const SumQuanta q = scatter_quanta(s);
          with_shape(gimp, [&](auto shape) {
            p2g<decltype(shape)>(grid, long(ps.size()), ps.data(), s, sums, q, m_p2g_scatter);
          });
        }
      }});
  m_steps.push_back(Step{
      "node_velocity", cat<FieldRead>({{{"mass_NC", 0}, {"heat_NC", 0}}, vec("mom_NC", 0)}),
      cat<FieldWrite>({vec_out("vel_NC"), {{"temp_NC"}}}), [=](const StepContext& ctx) {
        const auto vel = write_vec(ctx, "vel_NC");
        for (int s = 0; s < ns; ++s)
          node_velocity_temperature(nodes, s, ctx.read<Field4>("mass_NC"), read_vec(ctx, "mom_NC"),
                                    ctx.read<Field4>("heat_NC"), vel, ctx.write<Field4>("temp_NC"));
        // Symmetry planes: no normal velocity (Step 1's node conditions).
        node_symmetry(p, nodes, ns, velocity_bcs, vel);
      }});
}

// Step 2 (E13): the solids' cell state from their nodes.
void Cycle::add_node_to_cell_step() {
  const Patch& p = m_pb.patch();
  const double V = p.grid.cell_volume();
  const IndexBox owned = p.owned_cells();
  const BoundaryInput bc = m_pb.input.boundary;
  m_steps.push_back(Step{
      "node_to_cell",
      cat<FieldRead>({{{"mass_NC", 1}, {"temp_NC", 1}, {"NC_CCweight", 1}, {"press_CC", 0}}, vec("vel_NC", 1)}),
      cat<FieldWrite>({{{"rho_CC"}, {"temp_CC"}, {"sp_vol_CC"}}, vec_out("vel_CC")}), [=](const StepContext& ctx) {
        const auto rho = ctx.write<Field4>("rho_CC");
        const auto vel = write_vec(ctx, "vel_CC");
        const auto temp = ctx.write<Field4>("temp_CC");
        const auto sp_vol = ctx.write<Field4>("sp_vol_CC");
        for (int s = 0; s < m_pb.solid_count(); ++s) {
          const int m = m_pb.mpm[s];
          if (m_pb.materials.is_rigid(m)) {
            const NodeGrid grid = node_grid(p);  // node 0 is also cell 0's low corner
            rigid_particle_to_cell(owned, V, m, m_pb.materials.eos[m], grid.lower, grid.inv_h,
                                   m_rigid_mass_quantum[s], m_pb.solids[s].rigid_velocity(m_time),
                                   long(m_pb.particles[s].size()),
                                   m_pb.particles[s].data(), ctx.read<Field3>("press_CC"), rho, vel, temp, sp_vol);
          } else {
            node_to_cell(owned, V, s, m, m_pb.materials.eos[m], ctx.read<Field3>("NC_CCweight"),
                         ctx.read<Field4>("mass_NC"), read_vec(ctx, "vel_NC"), ctx.read<Field4>("temp_NC"),
                         ctx.read<Field3>("press_CC"), rho, vel, temp, sp_vol);
          }
          // A solid does not flow in: its extra cells mirror the inside (zero gradient);
          // the faces' density and temperature conditions are the fluids'. (A Dirichlet
          // density there would advect solid volume fraction in through an inflow.)
          const FaceBcs inside = mirror_or_zero_gradient(bc.velocity);
          fill_extra_cells(Kokkos::Array<ExtraCellFill, 6>{ExtraCellFill(rho, m, inside, -1), ExtraCellFill(temp, m, inside, -1),
                                                        ExtraCellFill(sp_vol, m, inside, -1),
                                                        ExtraCellFill(vel[0], m, bc.velocity, 0),
                                                        ExtraCellFill(vel[1], m, bc.velocity, 1),
                                                        ExtraCellFill(vel[2], m, bc.velocity, 2)},
                           p);
        }
      }});
}

// Steps 11, 12, 14 (E11, E24, E26): the gas pressure on the particles, the internal
// force, and the node velocity after the forces.
void Cycle::add_force_steps() {
  const Patch& p = m_pb.patch();
  const NodeGrid grid = node_grid(p);
  const int ns = m_pb.solid_count();
  const bool gimp = m_pb.input.mpm.gimp;
  const IndexBox nodes = p.with_extra(Location::node, p.ghosts);
  const auto g = m_pb.input.mpm.gravity;
  const Kokkos::Array<double, 3> gravity{g[0], g[1], g[2]};
  const double damping = m_pb.input.mpm.damping;
  const double p_ref = m_pb.input.mpm.reference_pressure;
  const double& dt = m_dt;
  if (m_pb.has_cells()) {
    const IndexBox inside = nodes_inside_cells(p);
    m_steps.push_back(Step{"pressure_to_nodes", {{"press_CC_new", 1}}, {{"press_NC"}}, [=](const StepContext& ctx) {
                             pressure_to_nodes(inside, ctx.read<Field3>("press_CC_new"), ctx.write<Field3>("press_NC"));
                           }});
    m_steps.push_back(Step{"pressure_to_particles", {{"press_NC", 1}}, {}, [=](const StepContext& ctx) {
                             for (int s = 0; s < ns; ++s) {
                               if (m_pb.solids[s].type == SolidModelType::rigid) continue;
                               const ParticleSet& ps = m_pb.particles[s];
                               with_shape(gimp, [&](auto shape) {
                                 particle_pressure<decltype(shape)>(grid, long(ps.size()), ps.data(), p_ref,
                                                                    ctx.read<Field3>("press_NC"));
                               });
                             }
                           }});
  }
  m_steps.push_back(Step{"internal_force", {}, vec_summed("fint_NC"), [=](const StepContext& ctx) {
                           const VectorField4 fint = write_vec(ctx, "fint_NC");
                           for (int s = 0; s < ns; ++s) {
                             const ParticleSet& ps = m_pb.particles[s];
                             SumQuanta q;
                             q.mass = m_mass_quantum[s];
                             q.internal_force = quantum_for(global_max(
                                 m_pb.decomposition->comm(), internal_force_bound(grid, long(ps.size()), ps.data())));
                             with_shape(gimp, [&](auto shape) {
                               internal_force<decltype(shape)>(grid, long(ps.size()), ps.data(), s, fint, q,
                                                             m_force_scatter);
                             });
                           }
                         }});
  m_steps.push_back(Step{
      "grid_acceleration", cat<FieldRead>({{{"mass_NC", 0}}, vec("vel_NC", 0), vec("fint_NC", 0), vec("fext_NC", 0)}),
      cat<FieldWrite>({vec_out("vel_star_NC"), vec_out("acc_NC")}), [=, &dt](const StepContext& ctx) {
        for (int s = 0; s < ns; ++s)
          grid_acceleration(nodes, s, dt, gravity, damping, m_pb.solids[s].type == SolidModelType::rigid,
                            ctx.read<Field4>("mass_NC"), read_vec(ctx, "vel_NC"), read_vec(ctx, "fint_NC"),
                            read_vec(ctx, "fext_NC"), write_vec(ctx, "vel_star_NC"), write_vec(ctx, "acc_NC"));
      }});
}

}  // namespace mpmice
