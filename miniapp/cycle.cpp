#include "cycle.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include <mpmice/halo/migrate.hpp>
#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/bad_particles.hpp>
#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/cell_to_node.hpp>
#include <mpmice/kernels/mpm_lagrangian_values.hpp>
#include <mpmice/kernels/node_to_cell.hpp>
#include <mpmice/kernels/particle_burn.hpp>
#include <mpmice/kernels/particle_pressure.hpp>
#include <mpmice/kernels/conserved_to_primitive.hpp>
#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/equilibrate_pressure.hpp>
#include <mpmice/kernels/exchange.hpp>
#include <mpmice/kernels/face_exchange.hpp>
#include <mpmice/kernels/face_pressure.hpp>
#include <mpmice/kernels/face_velocity.hpp>
#include <mpmice/kernels/g2p.hpp>
#include <mpmice/kernels/grid_update.hpp>
#include <mpmice/kernels/internal_force.hpp>
#include <mpmice/kernels/p2g.hpp>
#include <mpmice/kernels/particle_sort.hpp>
#include <mpmice/kernels/particle_totals.hpp>
#include <mpmice/kernels/stress_update.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/kinetic_energy_fix.hpp>
#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/pressure_update.hpp>
#include <mpmice/kernels/pressure_work_heat.hpp>
#include <mpmice/kernels/simple_burn.hpp>
#include <mpmice/kernels/sources.hpp>
#include <mpmice/kernels/specific_volume.hpp>
#include <mpmice/kernels/timestep.hpp>

namespace mpmice {
namespace {

using Reads = std::vector<FieldRead>;
using Writes = std::vector<FieldWrite>;

// Reads of the three components of a vector field.
Reads vec(const std::string& name, int ghosts) {
  Reads r;
  for (const auto& c : components(name)) r.push_back({c, ghosts});
  return r;
}
Writes vec_out(const std::string& name, int valid_ghosts = 0) {
  Writes w;
  for (const auto& c : components(name)) w.push_back({c, valid_ghosts});
  return w;
}
// Writes of a vector field a scatter adds into: one ghost layer summed into owners.
Writes vec_summed(const std::string& name) {
  Writes w;
  for (const auto& c : components(name)) w.push_back({c, 0, 1});
  return w;
}
template <class T>
std::vector<T> cat(std::initializer_list<std::vector<T>> parts) {
  std::vector<T> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}
ConstVectorField4 read_vec(const StepContext& ctx, const std::string& name) {
  const auto c = components(name);
  return {ctx.read<Field4>(c[0]), ctx.read<Field4>(c[1]), ctx.read<Field4>(c[2])};
}
VectorField4 write_vec(const StepContext& ctx, const std::string& name) {
  const auto c = components(name);
  return {ctx.write<Field4>(c[0]), ctx.write<Field4>(c[1]), ctx.write<Field4>(c[2])};
}

// Every rank learns whether any rank failed; the failing ranks' messages go with the
// exception (main prints them).
void stop_if_any(MPI_Comm comm, bool local_bad, const std::string& message) {
  if (global_max(comm, local_bad ? 1.0 : 0.0) > 0)
    throw InvariantError(local_bad ? message : std::string());
}

std::string cell_name(const Patch& p, const int* c) {
  return "(" + std::to_string(p.global_index(c[0], 0)) + ", " + std::to_string(p.global_index(c[1], 1)) +
         ", " + std::to_string(p.global_index(c[2], 2)) + ")";
}

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

namespace {

// Call f with the shape function type the input chose.
template <class F>
void with_shape(bool gimp, F&& f) {
  if (gimp)
    f(GimpShape{});
  else
    f(LinearShape{});
}

// Boundary conditions for the MPM cell rates in extra cells: mirrored across symmetry
// planes (normal component negated), zero gradient elsewhere (E33).
FaceBcs mirror_or_zero_gradient(const FaceBcs& velocity) {
  FaceBcs out;
  for (int f = 0; f < 6; ++f) out[f].kind = velocity[f].kind == BcKind::symmetry ? BcKind::symmetry : BcKind::neumann;
  return out;
}

// Nodes whose 8 surrounding cells all lie in the patch's arrays (the cell-to-node
// averages of (E11), (E34)), within the owned and extra nodes.
IndexBox nodes_inside_cells(const Patch& p) {
  IndexBox b = p.with_extra(Location::node, p.ghosts);
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::max(b.lo[d], 1);
    b.hi[d] = std::min(b.hi[d], p.extent(Location::cell, d));
  }
  return b;
}

}  // namespace

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

// Steps 3-10 (E14-E23): equilibration, face velocities and their exchange, the
// pressure update, face pressures, momentum and energy sources.
void Cycle::add_pressure_steps() {
  Problem& pb = m_pb;
  const Patch& p = pb.patch();
  const MaterialTable mats = pb.materials;
  const int n = mats.count;
  const BoundaryInput bc = pb.input.boundary;
  const double V = p.grid.cell_volume();
  const Kokkos::Array<double, 3> h = p.grid.spacing_array();
  const bool second_order = pb.input.ice.second_order;
  const auto gravity = pb.input.ice.gravity;
  const IndexBox owned = p.owned_cells(), with_extra = p.cells_with_extra();
  MPI_Comm comm = pb.decomposition->comm();
  const double& dt = m_dt;
  // Step 3 (E14-E16)
  m_steps.push_back(Step{
      "equilibrate_pressure",
      {{"rho_CC", 0}, {"temp_CC", 0}, {"sp_vol_CC", 0}, {"press_CC", 0}},
      {{"press_equil_CC"}, {"vol_frac_CC"}, {"sp_vol_equil_CC"}, {"speedSound_CC"}, {"kappa_CC"},
       {"sumKappa_CC"}, {"TMV_CC"}},
      [=](const StepContext& ctx) {
        EquilibrationIn in{ctx.read<Field4>("rho_CC"), ctx.read<Field4>("temp_CC"),
                           ctx.read<Field4>("sp_vol_CC"), ctx.read<Field3>("press_CC")};
        EquilibrationOut out{ctx.write<Field3>("press_equil_CC"), ctx.write<Field4>("vol_frac_CC"),
                             ctx.write<Field4>("sp_vol_equil_CC"), ctx.write<Field4>("speedSound_CC"),
                             ctx.write<Field4>("kappa_CC"), ctx.write<Field3>("sumKappa_CC"),
                             ctx.write<Field3>("TMV_CC")};
        const EquilibrationFailure f = equilibrate_pressure(with_extra, V, mats, in, out);
        stop_if_any(comm, f.failed,
                    "equilibrate_pressure: no pressure makes the volume fractions sum to 1 in cell " +
                        cell_name(p, f.cell));
        fill_extra_cells(out.press_eq, p, bc.pressure, -1);
        specific_volume_from_density(with_extra, owned, n, out.vol_frac, in.rho, out.sp_vol);
      }});

  // Step 4 (E44-E45): what each reactant burns; the particles lose it at the start of
  // the next step (add_burn_step). (E17) is not needed: the reactant's volume leaves
  // with its particles' mass, so the volume fractions stay those of Step 3.
  if (!pb.reactions.empty()) {
    const std::vector<SimpleBurn> reactions = pb.reactions;
    m_steps.push_back(Step{
        "burn_rate",
        {{"mass_NC", 1}, {"NC_CCweight", 1}, {"rho_CC", 0}, {"temp_CC", 0}, {"vol_frac_CC", 0}, {"press_equil_CC", 0}},
        {{"burn_dm_CC"}},
        [=, &dt](const StepContext& ctx) {
          const double hh[3] = {h[0], h[1], h[2]};
          for (const SimpleBurn& b : reactions)
            burn_rate(owned, hh, dt, n, b, ctx.read<Field3>("NC_CCweight"), ctx.read<Field4>("mass_NC"),
                      ctx.read<Field4>("rho_CC"), ctx.read<Field4>("temp_CC"), ctx.read<Field4>("vol_frac_CC"),
                      ctx.read<Field3>("press_equil_CC"), ctx.write<Field4>("burn_dm_CC"));
        }});
  }

  // Step 5 (E18)
  m_steps.push_back(Step{
      "face_velocity",
      cat<FieldRead>({{{"press_equil_CC", 2}, {"rho_CC", 2}, {"sp_vol_equil_CC", 2}}, vec("vel_CC", 2)}),
      vec_out("vel_FC", 1), [=, &dt](const StepContext& ctx) {
        const auto vel = read_vec(ctx, "vel_CC");
        const auto out = write_vec(ctx, "vel_FC");
        for (int d = 0; d < 3; ++d) {
          const IndexBox faces = faces_around_cells(p, d);
          face_velocity(faces, d, h[d], dt, gravity[d], mats, ctx.read<Field3>("press_equil_CC"),
                        ctx.read<Field4>("rho_CC"), ctx.read<Field4>("sp_vol_equil_CC"), vel[d], out[d]);
          set_boundary_face_velocity(out[d], d, p, bc.velocity, faces);
        }
      }});

  // Step 6 (E19)
  m_steps.push_back(Step{
      "face_exchange", cat<FieldRead>({{{"vol_frac_CC", 2}, {"sp_vol_equil_CC", 2}}, vec("vel_FC", 1)}),
      vec_out("vel_FCME", 1), [=, &dt](const StepContext& ctx) {
        const auto in = read_vec(ctx, "vel_FC");
        const auto out = write_vec(ctx, "vel_FCME");
        for (int d = 0; d < 3; ++d) {
          const IndexBox faces = faces_around_cells(p, d);
          face_exchange(faces, d, dt, mats, ctx.read<Field4>("vol_frac_CC"),
                        ctx.read<Field4>("sp_vol_equil_CC"), in[d], out[d]);
          set_boundary_face_velocity(out[d], d, p, bc.velocity, faces);
        }
      }});

  // Step 7 (E20, with Adv[theta] of section 6)
  const bool reacting = !pb.reactions.empty();
  Reads mass_source_read;
  Writes new_gas_write;
  if (reacting) {
    mass_source_read = {{"reaction_mass_CC", 0}, {"reaction_eng_CC", 0}};
    new_gas_write.push_back({"reaction_sp_vol_CC"});
  }
  m_steps.push_back(Step{
      "pressure_update",
      cat<FieldRead>({mass_source_read,
                      {{"vol_frac_CC", 2},
                       {"sp_vol_equil_CC", 0},
                       {"sumKappa_CC", 0},
                       {"press_equil_CC", 0},
                       {"rho_CC", 0}},
                      vec("vel_FCME", 1)}),
      cat<FieldWrite>({{{"adv_vol_frac_CC"}, {"delP_Dilatate"}, {"delP_MassX"}, {"press_CC_new"}, {"sum_rho_CC"}},
                       vec_out("vol_flux_FC"), vec_out("solid_vol_flux_FC"), new_gas_write}),
      [=, &dt](const StepContext& ctx) {
        const auto U = read_vec(ctx, "vel_FCME");
        const double outflux = max_outflux_fraction(owned, h, dt, n, U);
        if (global_max(comm, outflux) > 1.0)
          throw RedoStep("an outflux slab exceeds its cell (E39)");
        const auto theta = ctx.read<Field4>("vol_frac_CC");
        const auto adv = ctx.write<Field4>("adv_vol_frac_CC");
        const auto flux_names = components("vol_flux_FC");
        const Field3 flux[3] = {ctx.write<Field3>(flux_names[0]), ctx.write<Field3>(flux_names[1]),
                                ctx.write<Field3>(flux_names[2])};
        const auto solid_flux_names = components("solid_vol_flux_FC");
        const Field3 solid_flux[3] = {ctx.write<Field3>(solid_flux_names[0]), ctx.write<Field3>(solid_flux_names[1]),
                                      ctx.write<Field3>(solid_flux_names[2])};
        for (int d = 0; d < 3; ++d) {
          Kokkos::deep_copy(flux[d], 0.0);
          Kokkos::deep_copy(solid_flux[d], 0.0);
        }
        for (int m = 0; m < n; ++m) {
          if (second_order) limited_gradient(p.ghosted_cells(1), h, theta, m, ConstField4(), GradientField(), m_grad);
          face_fluxes(owned, h, dt, U, m, theta, ConstField4(), second_order, m_grad, GradientField(), m_face_flux);
          flux_difference(owned, 1.0 / V, m_face_flux, m, adv);
          // The fluids' and the deforming solids' volume fluxes, for the pressure work's
          // heat (pressure_work_heat.hpp).
          if (mats.is_ice(m)) add_face_fluxes(owned, m_face_flux, FaceFluxes{flux[0], flux[1], flux[2]});
          else if (!mats.is_rigid(m))
            add_face_fluxes(owned, m_face_flux, FaceFluxes{solid_flux[0], solid_flux[1], solid_flux[2]});
        }
        const auto press = ctx.write<Field3>("press_CC_new");
        // dP_mx (E20) with the new gas's own specific volume (new_gas_specific_volume).
        ConstField4 mass_source, source_sp_vol = ctx.read<Field4>("sp_vol_equil_CC");
        if (reacting) {
          mass_source = ctx.read<Field4>("reaction_mass_CC");
          const Field4 v_new = ctx.write<Field4>("reaction_sp_vol_CC");
          new_gas_specific_volume(owned, mats, mass_source, ctx.read<Field4>("reaction_eng_CC"),
                                  ctx.read<Field3>("press_equil_CC"), v_new);
          source_sp_vol = v_new;
        }
        pressure_update(owned, V, n, adv, mass_source, source_sp_vol,
                        ctx.read<Field3>("sumKappa_CC"), ctx.read<Field3>("press_equil_CC"),
                        ctx.write<Field3>("delP_Dilatate"), ctx.write<Field3>("delP_MassX"), press);
        fill_extra_cells(press, p, bc.pressure, -1);
        sum_density(with_extra, n, ctx.read<Field4>("rho_CC"), ctx.write<Field3>("sum_rho_CC"));
      }});

  // Step 8 (E21)
  m_steps.push_back(Step{"face_pressure", {{"press_CC_new", 1}, {"sum_rho_CC", 1}}, vec_out("press_FC"),
                         [=](const StepContext& ctx) {
                           const auto c = components("press_FC");
                           for (int d = 0; d < 3; ++d)
                             face_pressure(faces_of_owned_cells(p, d), d, ctx.read<Field3>("press_CC_new"),
                                           ctx.read<Field3>("sum_rho_CC"), ctx.write<Field3>(c[d]));
                         }});

  // Steps 9-10 (E22, E23)
  Kokkos::Array<int, max_materials> ice_on;
  for (int m = 0; m < max_materials; ++m) ice_on[m] = m < n && mats.is_ice(m);
  m_steps.push_back(Step{
      "momentum_energy_sources",
      cat<FieldRead>({vec("press_FC", 0),
                      {{"vol_frac_CC", 0},
                       {"rho_CC", 0},
                       {"TMV_CC", 0},
                       {"kappa_CC", 0},
                       {"press_CC_new", 0},
                       {"delP_Dilatate", 0}},
                      reacting ? Reads{{"reaction_mass_CC", 0}, {"delP_MassX", 0}} : Reads{}}),
      cat<FieldWrite>({vec_out("mom_source_CC"), {{"int_eng_source_CC"}}}),
      [=, &dt](const StepContext& ctx) {
        const auto c = components("press_FC");
        Kokkos::Array<ConstField3, 3> pf{ctx.read<Field3>(c[0]), ctx.read<Field3>(c[1]), ctx.read<Field3>(c[2])};
        momentum_source(owned, p, dt, n, {gravity[0], gravity[1], gravity[2]}, ice_on,
                        ctx.read<Field4>("vol_frac_CC"), ctx.read<Field4>("rho_CC"), pf,
                        write_vec(ctx, "mom_source_CC"));
        energy_source(owned, n, ice_on, ctx.read<Field3>("TMV_CC"), ctx.read<Field4>("vol_frac_CC"),
                      ctx.read<Field4>("kappa_CC"), ctx.read<Field3>("press_CC_new"),
                      ctx.read<Field3>("delP_Dilatate"), ctx.write<Field4>("int_eng_source_CC"));
        if (reacting)
          mass_exchange_work(owned, n, ice_on, ctx.read<Field3>("TMV_CC"), ctx.read<Field4>("vol_frac_CC"),
                             ctx.read<Field4>("kappa_CC"), ctx.read<Field3>("press_CC_new"),
                             ctx.read<Field3>("delP_MassX"), ctx.read<Field4>("reaction_mass_CC"),
                             ctx.write<Field4>("int_eng_source_CC"));
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

// Steps 15-20 (E27-E34): Lagrangian values of fluids and solids, the exchange, the
// Lagrangian specific volume, and what the exchange did to the solids carried back
// to their nodes.
void Cycle::add_lagrangian_steps() {
  Problem& pb = m_pb;
  const Patch& p = pb.patch();
  const MaterialTable mats = pb.materials;
  const int n = mats.count;
  const BoundaryInput bc = pb.input.boundary;
  const double V = p.grid.cell_volume();
  const IndexBox owned = p.owned_cells(), with_extra = p.cells_with_extra();
  const IndexBox nodes = p.with_extra(Location::node, p.ghosts);
  MPI_Comm comm = pb.decomposition->comm();
  const bool solids = pb.solid_count() > 0;
  const bool clamp = pb.input.ice.clamp_specific_volume;
  const double& dt = m_dt;
  Reads solid_reads;
  if (solids)
    solid_reads = cat<FieldRead>({{{"mass_NC", 1}, {"temp_NC", 1}, {"NC_CCweight", 1}}, vec("vel_star_NC", 1)});
  const bool reacting = !pb.reactions.empty();
  // With reactions the exchange's and (E32)'s temperature before the step is the mixed one.
  const std::string temp_before = reacting ? "temp_mixed_CC" : "temp_CC";
  Reads source_reads;
  if (reacting)
    source_reads = cat<FieldRead>({{{"reaction_mass_CC", 0}, {"reaction_eng_CC", 0}}, vec("reaction_mom_CC", 0)});
  // Step 16 (E29)
  m_steps.push_back(Step{
      "lagrangian_values",
      cat<FieldRead>({{{"rho_CC", 0}, {"temp_CC", 0}, {"int_eng_source_CC", 0}}, vec("vel_CC", 0),
                      vec("mom_source_CC", 0), solid_reads, source_reads}),
      cat<FieldWrite>({{{"mass_L_CC"}, {"int_eng_L_CC"}}, vec_out("mom_L_CC"),
                       reacting ? Writes{{"temp_mixed_CC"}} : Writes{}}),
      [=](const StepContext& ctx) {
        const auto mass = ctx.write<Field4>("mass_L_CC");
        lagrangian_mass(with_extra, V, n, ctx.read<Field4>("rho_CC"), mass);
        lagrangian_momentum_energy(owned, mats, mass, read_vec(ctx, "vel_CC"), ctx.read<Field4>("temp_CC"),
                                   read_vec(ctx, "mom_source_CC"), ctx.read<Field4>("int_eng_source_CC"),
                                   write_vec(ctx, "mom_L_CC"), ctx.write<Field4>("int_eng_L_CC"));
        // (E27): the solids' slots from their nodes.
        for (int s = 0; s < m_pb.solid_count(); ++s) {
          const int m = m_pb.mpm[s];
          mpm_lagrangian_values(owned, V, s, m, mats.eos[m].cv, mats.is_rigid(m), ctx.read<Field3>("NC_CCweight"),
                                ctx.read<Field4>("mass_NC"), read_vec(ctx, "vel_star_NC"), ctx.read<Field4>("temp_NC"),
                                ctx.read<Field4>("rho_CC"), read_vec(ctx, "vel_CC"), ctx.read<Field4>("temp_CC"),
                                read_vec(ctx, "mom_source_CC"), write_vec(ctx, "mom_L_CC"),
                                ctx.write<Field4>("int_eng_L_CC"));
        }
        // (E30): what the products gained from the particles this step.
        if (reacting)
          add_product_sources(owned, mats, ctx.read<Field4>("reaction_mass_CC"), read_vec(ctx, "reaction_mom_CC"),
                              ctx.read<Field4>("reaction_eng_CC"), read_vec(ctx, "vel_CC"), ctx.read<Field4>("temp_CC"),
                              mass,
                              write_vec(ctx, "mom_L_CC"), ctx.write<Field4>("int_eng_L_CC"),
                              ctx.write<Field4>("temp_mixed_CC"));
      }});

  // Step 17 (E31)
  m_steps.push_back(Step{
      "exchange",
      cat<FieldRead>({{{"mass_L_CC", 0},
                       {"int_eng_L_CC", 0},
                       {"sp_vol_equil_CC", 0},
                       {"vol_frac_CC", 0},
                       {temp_before, 0}},
                      vec("mom_L_CC", 0)}),
      cat<FieldWrite>({vec_out("vel_ME_CC"), {{"temp_ME_CC"}, {"Tdot_CC"}}}),
      [=, &dt](const StepContext& ctx) {
        const auto vel = write_vec(ctx, "vel_ME_CC");
        const auto temp = ctx.write<Field4>("temp_ME_CC");
        exchange(owned, dt, mats, ctx.read<Field4>("mass_L_CC"), read_vec(ctx, "mom_L_CC"),
                 ctx.read<Field4>("int_eng_L_CC"), ctx.read<Field4>("sp_vol_equil_CC"),
                 ctx.read<Field4>("vol_frac_CC"), ctx.read<Field4>(temp_before), vel, temp,
                 ctx.write<Field4>("Tdot_CC"));
        fill_extra_cells(Kokkos::Array<ExtraCellFill, 4>{ExtraCellFill(vel[0], bc.velocity, 0),
                                                      ExtraCellFill(vel[1], bc.velocity, 1),
                                                      ExtraCellFill(vel[2], bc.velocity, 2),
                                                      ExtraCellFill(temp, bc.temperature, -1)},
                         p);
      }});

  // After Step 17: the pressure work's heat (pressure_work_heat.hpp; docs/design.md).
  const Kokkos::Array<double, 3> h = p.grid.spacing_array();
  const auto gravity = pb.input.ice.gravity;
  m_steps.push_back(Step{
      "pressure_work_heat",
      cat<FieldRead>({vec("press_FC", 0), vec("vol_flux_FC", 0), vec("solid_vol_flux_FC", 0),
                      {{"vol_frac_CC", 1},
                       {"int_eng_source_CC", 0},
                       {"kappa_CC", 1},
                       {"sumKappa_CC", 1},
                       {"rho_CC", 0},
                       {"mass_L_CC", 0}},
                      vec("mom_L_CC", 0), vec("mom_source_CC", 0), vec("vel_ME_CC", 0)}),
      {{"temp_ME_CC"}, {"Tdot_CC"}},
      [=, &dt](const StepContext& ctx) {
        const auto c = components("press_FC");
        PressureWorkInputs in;
        for (int d = 0; d < 3; ++d) in.press_face[d] = ctx.read<Field3>(c[d]);
        const auto flux_names = components("vol_flux_FC");
        for (int d = 0; d < 3; ++d) in.face_flux[d] = ctx.read<Field3>(flux_names[d]);
        const auto solid_flux_names = components("solid_vol_flux_FC");
        for (int d = 0; d < 3; ++d) in.solid_face_flux[d] = ctx.read<Field3>(solid_flux_names[d]);
        in.vol_frac = ctx.read<Field4>("vol_frac_CC");
        in.work = ctx.read<Field4>("int_eng_source_CC");
        in.kappa = ctx.read<Field4>("kappa_CC");
        in.sum_kappa = ctx.read<Field3>("sumKappa_CC");
        in.rho = ctx.read<Field4>("rho_CC");
        in.mass_L = ctx.read<Field4>("mass_L_CC");
        in.mom_L = read_vec(ctx, "mom_L_CC");
        in.mom_source = read_vec(ctx, "mom_source_CC");
        in.vel_me = read_vec(ctx, "vel_ME_CC");
        const auto temp = ctx.write<Field4>("temp_ME_CC");
        pressure_work_heat(owned, h, dt, {gravity[0], gravity[1], gravity[2]}, mats, in, temp,
                           ctx.write<Field4>("Tdot_CC"));
        fill_extra_cells(temp, p, bc.temperature, -1);
      }});

  // Step 18 (E32)
  m_steps.push_back(Step{
      "lagrangian_specific_volume",
      cat<FieldRead>({{{"rho_CC", 0},
                       {"mass_L_CC", 0},
                       {"sp_vol_equil_CC", 0},
                       {"vol_frac_CC", 0},
                       {"kappa_CC", 0},
                       {"sumKappa_CC", 0},
                       {"delP_Dilatate", 0},
                       {temp_before, 0},
                       {"Tdot_CC", 0},
                       {"delP_MassX", 0}},
                      reacting ? Reads{{"reaction_mass_CC", 0}, {"reaction_sp_vol_CC", 0}} : Reads{}}),
      {{"sp_vol_L_CC"}},
      [=, &dt](const StepContext& ctx) {
        const auto out = ctx.write<Field4>("sp_vol_L_CC");
        const ConstField4 mass_source = reacting ? ConstField4(ctx.read<Field4>("reaction_mass_CC")) : ConstField4();
        const ConstField4 source_sp_vol = reacting ? ConstField4(ctx.read<Field4>("reaction_sp_vol_CC")) : ConstField4();
        const SpecificVolumeInputs in{
            ctx.read<Field4>("rho_CC"), ctx.read<Field4>("mass_L_CC"), ctx.read<Field4>("sp_vol_equil_CC"),
            ctx.read<Field4>("vol_frac_CC"), ctx.read<Field4>("kappa_CC"), ctx.read<Field3>("sumKappa_CC"),
            ctx.read<Field3>("delP_Dilatate"), ctx.read<Field4>(temp_before), ctx.read<Field4>("Tdot_CC"),
            mass_source, source_sp_vol, ctx.read<Field3>("delP_MassX")};
        const long bad = lagrangian_specific_volume(owned, V, dt, clamp, mats, in, out);
        if (global_sum(comm, bad) > 0) {
          std::string where;
          if (bad > 0) {  // name the first such cell on this rank (a failure path: on the host)
            const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
            for (int i = owned.lo[0]; i < owned.hi[0] && where.empty(); ++i)
              for (int j = owned.lo[1]; j < owned.hi[1] && where.empty(); ++j)
                for (int k = owned.lo[2]; k < owned.hi[2] && where.empty(); ++k)
                  for (int m = 0; m < n && where.empty(); ++m)
                    if (!(h(m, i, j, k) > 0)) {
                      const int c[3] = {i, j, k};
                      where = " for material '" + m_pb.input.materials[m].name + "' in cell " + cell_name(p, c);
                    }
          }
          throw RedoStep("a Lagrangian specific volume is not positive (E32)" + where);
        }
        specific_volume_from_density(with_extra, owned, n, ctx.read<Field4>("vol_frac_CC"),
                                     ctx.read<Field4>("rho_CC"), out);
      }});

  if (!solids) return;
  // Steps 19-20 (E33, E34)
  const FaceBcs rate_bcs = mirror_or_zero_gradient(bc.velocity);
  const IndexBox inside = nodes_inside_cells(p);
  m_steps.push_back(Step{
      "solid_cell_rates",
      cat<FieldRead>({{{"mass_L_CC", 0}, {"int_eng_L_CC", 0}, {"temp_ME_CC", 0}}, vec("mom_L_CC", 0),
                      vec("mom_source_CC", 0), vec("vel_ME_CC", 0)}),
      cat<FieldWrite>({vec_out("dVdt_CC"), {{"dTdt_CC"}}}), [=, &dt](const StepContext& ctx) {
        const auto acc = write_vec(ctx, "dVdt_CC");
        const auto rate = ctx.write<Field4>("dTdt_CC");
        for (int s = 0; s < m_pb.solid_count(); ++s) {
          const int m = m_pb.mpm[s];
          mpm_cell_rates(owned, dt, s, m, mats.eos[m].cv, mats.is_rigid(m), ctx.read<Field4>("mass_L_CC"),
                         read_vec(ctx, "mom_L_CC"), ctx.read<Field4>("int_eng_L_CC"), read_vec(ctx, "mom_source_CC"),
                         read_vec(ctx, "vel_ME_CC"), ctx.read<Field4>("temp_ME_CC"), acc, rate);
          fill_extra_cells(Kokkos::Array<ExtraCellFill, 4>{ExtraCellFill(acc[0], s, rate_bcs, 0),
                                                        ExtraCellFill(acc[1], s, rate_bcs, 1),
                                                        ExtraCellFill(acc[2], s, rate_bcs, 2),
                                                        ExtraCellFill(rate, s, rate_bcs, -1)},
                           p);
        }
      }});
  m_steps.push_back(Step{
      "cell_to_node", cat<FieldRead>({vec("dVdt_CC", 1), {{"dTdt_CC", 1}}}),
      cat<FieldWrite>({vec_out("vel_star_NC"), vec_out("acc_NC"), {{"temp_rate_NC"}, {"transfer_energy_NC"}}}),
      [=, &dt](const StepContext& ctx) {
        for (int s = 0; s < m_pb.solid_count(); ++s)
          cell_rates_to_nodes(inside, s, dt, read_vec(ctx, "dVdt_CC"), ctx.read<Field4>("dTdt_CC"),
                              write_vec(ctx, "vel_star_NC"), write_vec(ctx, "acc_NC"), ctx.write<Field4>("temp_rate_NC"),
                              ctx.write<Field4>("transfer_energy_NC"));
      }});
  (void)comm;
  (void)with_extra;
  (void)n;
}

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

// Steps 25-27 (E37, E38): advection of the fluids, the new state's boundary values.
void Cycle::add_advection_steps() {
  Problem& pb = m_pb;
  const Patch& p = pb.patch();
  const MaterialTable mats = pb.materials;
  const int n = mats.count;
  const double V = p.grid.cell_volume();
  const Kokkos::Array<double, 3> h = p.grid.spacing_array();
  const bool second_order = pb.input.ice.second_order;
  const bool ke_fix = pb.input.ice.kinetic_energy_fix;
  const IndexBox owned = p.owned_cells();
  MPI_Comm comm = pb.decomposition->comm();
  const double& dt = m_dt;
  // Steps 25-26 (E37, E38)
  m_steps.push_back(Step{
      "advect_and_advance",
      cat<FieldRead>({vec("vel_FCME", 1),
                      {{"mass_L_CC", 2}, {"temp_ME_CC", 2}, {"sp_vol_L_CC", 2}, {"rho_CC", 0}, {"sp_vol_equil_CC", 0}},
                      vec("vel_ME_CC", 2)}),
      cat<FieldWrite>({{{"rho_CC_new"}, {"temp_CC_new"}, {"sp_vol_CC_new"}}, vec_out("vel_CC_new")}),
      [=, &dt](const StepContext& ctx) {
        const auto U = read_vec(ctx, "vel_FCME");
        const auto mass = ctx.read<Field4>("mass_L_CC");
        const auto rho_new = ctx.write<Field4>("rho_CC_new");
        const auto vel_me = read_vec(ctx, "vel_ME_CC");
        const auto vel_new = write_vec(ctx, "vel_CC_new");
        const ConstField4 q_in[5] = {vel_me[0], vel_me[1], vel_me[2], ctx.read<Field4>("temp_ME_CC"),
                                     ctx.read<Field4>("sp_vol_L_CC")};
        const Field4 q_out[5] = {vel_new[0], vel_new[1], vel_new[2], ctx.write<Field4>("temp_CC_new"),
                                 ctx.write<Field4>("sp_vol_CC_new")};
        const IndexBox around = p.ghosted_cells(1);
        if (ke_fix) specific_kinetic_energy(p.ghosted_cells(2), n, vel_me, m_ke);
        for (int m = 0; m < n; ++m) {
          if (!mats.is_ice(m)) {
            // A solid's cell state is rebuilt from its nodes; keep the exchanged values
            // (E13 blends with them where the solid has no mass).
            auto slot = [m](const auto& f) { return Kokkos::subview(f, m, Kokkos::ALL, Kokkos::ALL, Kokkos::ALL); };
            Kokkos::deep_copy(slot(rho_new), slot(ctx.read<Field4>("rho_CC")));
            for (int q = 0; q < 5; ++q) Kokkos::deep_copy(slot(q_out[q]), slot(q_in[q]));
            Kokkos::deep_copy(slot(q_out[4]), slot(ctx.read<Field4>("sp_vol_equil_CC")));
            continue;
          }
          if (second_order) limited_gradient(around, h, mass, m, ConstField4(), GradientField(), m_mass_grad);
          advection_change(owned, h, dt, U, m, mass, ConstField4(), second_order, m_mass_grad,
                           GradientField(), m_adv_mass, m_face_flux);
          advance_density(owned, V, m, mass, m_adv_mass, rho_new);
          // Adv[m q] of a mass-specific quantity q into m_adv_q (compatible fluxes, E43).
          const auto advect_specific = [&](const ConstField4& q) {
            if (second_order)
              limited_advection_change(owned, h, dt, U, m, q, mass, m_mass_grad, m_adv_q, m_face_flux, m_grad);
            else
              advection_change(owned, h, dt, U, m, q, mass, false, GradientField(), GradientField(), m_adv_q);
          };
          for (int q = 0; q < 5; ++q) {
            advect_specific(q_in[q]);
            advance_specific(owned, V, m, mass, q_in[q], m_adv_q, rho_new, q_out[q]);
          }
          if (ke_fix) {
            advect_specific(m_ke);
            kinetic_energy_to_heat(owned, V, m, mats.eos[m].cv, mass, m_ke, m_adv_q, rho_new,
                                   ConstVectorField4{vel_new[0], vel_new[1], vel_new[2]}, q_out[3]);
          }
        }
        const BadState bad = find_bad_states(owned, n, rho_new, q_out[3], q_out[4],
                                             ConstVectorField4{vel_new[0], vel_new[1], vel_new[2]});
        const char* quantity[4] = {"density", "temperature", "specific volume", "velocity"};
        stop_if_any(comm, bad.count > 0,
                    "advect_and_advance: " + std::string(quantity[bad.quantity]) + " of material '" +
                        m_pb.input.materials[bad.material].name + "' in cell " + cell_name(p, bad.cell) +
                        " is not positive or not finite (E38; " + std::to_string(bad.count) + " cells on this rank)");
      }});

  // End of step: boundary values of the new state (E38's BCs).
  m_steps.push_back(Step{"state_boundary_conditions",
                         {},
                         cat<FieldWrite>({{{"rho_CC_new"}, {"temp_CC_new"}, {"sp_vol_CC_new"}, {"press_CC_new"}},
                                          vec_out("vel_CC_new")}),
                         [this](const StepContext&) { fill_state_extra_cells(m_pb, "_new"); }});
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
