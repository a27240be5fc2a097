#include "cycle.hpp"

#include <string>

#include <mpmice/halo/migrate.hpp>
#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/boundary_conditions.hpp>
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
#include <mpmice/kernels/stress_update.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/kinetic_energy_fix.hpp>
#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/pressure_update.hpp>
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

}  // namespace

Cycle::Cycle(Problem& pb) : m_pb(pb), m_runner(*pb.halo, pb.fields) {
  const Patch& p = pb.patch();
  if (pb.material_count() > 0) {
    for (int d = 0; d < 3; ++d) {
      m_grad[d] = make_field("advection_gradient", p, Location::cell);
      m_mass_grad[d] = make_field("advection_mass_gradient", p, Location::cell);
    }
    m_adv_mass = make_field("advected_mass", p, Location::cell, pb.material_count());
    m_adv_q = make_field("advected_quantity", p, Location::cell, pb.material_count());
    m_ke = make_field("specific_kinetic_energy", p, Location::cell, pb.material_count());
    build_ice_steps();
  } else {
    build_mpm_steps();
    // The first step's limit from the initial particles (stress from F = I: zero).
    const NodeGrid grid = node_grid(p);
    for (int s = 0; s < pb.solid_count(); ++s)
      m_mpm_dt_limit = std::min(m_mpm_dt_limit, stress_update(grid, long(pb.particles[s].size()),
                                                              pb.particles[s].data(), pb.solids[s], 0.0));
  }
  for (const auto& s : m_steps) m_runner.validate(s);
}

void Cycle::build_mpm_steps() {
  Problem& pb = m_pb;
  const Patch& p = pb.patch();
  const NodeGrid grid = node_grid(p);
  const int ns = pb.solid_count();
  const bool gimp = pb.input.mpm.gimp;
  const double pic = pb.input.mpm.pic_fraction;
  const auto g = pb.input.mpm.gravity;
  const Kokkos::Array<double, 3> gravity{g[0], g[1], g[2]};
  const FaceBcs velocity_bcs = pb.input.boundary.velocity;
  const IndexBox nodes = p.with_extra(Location::node, p.ghosts);
  const double& dt = m_dt;

  auto sums_out = [](const std::string& name) {
    Writes w;
    for (const auto& c : components(name)) w.push_back({c, 0, 1});
    return w;
  };
  // Step 1 (E12)
  m_steps.push_back(Step{
      "p2g", {},
      cat<FieldWrite>({{{"mass_NC", 0, 1}, {"heat_NC", 0, 1}, {"volume_NC", 0, 1}}, sums_out("mom_NC"),
                       sums_out("fext_NC")}),
      [this, grid, gimp, ns](const StepContext& ctx) {
        const NodeSums sums{ctx.write<Field4>("mass_NC"), write_vec(ctx, "mom_NC"), ctx.write<Field4>("heat_NC"),
                            ctx.write<Field4>("volume_NC"), write_vec(ctx, "fext_NC")};
        for (int s = 0; s < ns; ++s) {
          const ParticleSet& ps = m_pb.particles[s];
          if (gimp) p2g<GimpShape>(grid, long(ps.size()), ps.data(), s, sums);
          else p2g<LinearShape>(grid, long(ps.size()), ps.data(), s, sums);
        }
      }});
  // Step 12 (E24)
  m_steps.push_back(Step{"internal_force", {}, sums_out("fint_NC"), [this, grid, gimp, ns](const StepContext& ctx) {
                           const VectorField4 fint = write_vec(ctx, "fint_NC");
                           for (int s = 0; s < ns; ++s) {
                             const ParticleSet& ps = m_pb.particles[s];
                             if (gimp) internal_force<GimpShape>(grid, long(ps.size()), ps.data(), s, fint);
                             else internal_force<LinearShape>(grid, long(ps.size()), ps.data(), s, fint);
                           }
                         }});
  // Steps 14 and 20's node conditions (E26)
  m_steps.push_back(Step{
      "grid_update",
      cat<FieldRead>({{{"mass_NC", 0}, {"heat_NC", 0}}, vec("mom_NC", 0), vec("fint_NC", 0), vec("fext_NC", 0)}),
      cat<FieldWrite>({vec_out("vel_NC"), {{"temp_NC"}}, vec_out("vel_star_NC"), vec_out("acc_NC")}),
      [this, p, nodes, gravity, velocity_bcs, ns, &dt](const StepContext& ctx) {
        const auto mass = ctx.read<Field4>("mass_NC");
        const auto vel = write_vec(ctx, "vel_NC");
        const auto vel_star = write_vec(ctx, "vel_star_NC");
        const auto acc = write_vec(ctx, "acc_NC");
        for (int s = 0; s < ns; ++s) {
          node_velocity_temperature(nodes, s, mass, read_vec(ctx, "mom_NC"), ctx.read<Field4>("heat_NC"), vel,
                                    ctx.write<Field4>("temp_NC"));
          const bool rigid = m_pb.solids[s].type == SolidModelType::rigid;
          grid_acceleration(nodes, s, dt, gravity, rigid, mass, ConstVectorField4{vel[0], vel[1], vel[2]},
                            read_vec(ctx, "fint_NC"), read_vec(ctx, "fext_NC"), vel_star, acc);
          if (!rigid) node_velocity_bcs(p, nodes, s, dt, velocity_bcs, vel, vel_star, acc);
        }
      }});
  // Steps 21-22 (E35, E36)
  m_steps.push_back(Step{
      "g2p", cat<FieldRead>({vec("vel_star_NC", 1), vec("acc_NC", 1)}), {},
      [this, grid, gimp, pic, ns, &dt](const StepContext& ctx) {
        const auto vel_star = read_vec(ctx, "vel_star_NC");
        const auto acc = read_vec(ctx, "acc_NC");
        for (int s = 0; s < ns; ++s) {
          const SolidModel& model = m_pb.solids[s];
          const bool rigid = model.type == SolidModelType::rigid;
          const bool moving = m_time < model.stop_time;
          Kokkos::Array<double, 3> v{0, 0, 0};
          for (int d = 0; d < 3; ++d) v[d] = moving ? model.prescribed_velocity[d] : 0.0;
          const ParticleSet& ps = m_pb.particles[s];
          if (gimp) g2p<GimpShape>(grid, long(ps.size()), ps.data(), s, dt, pic, rigid, v, vel_star, acc);
          else g2p<LinearShape>(grid, long(ps.size()), ps.data(), s, dt, pic, rigid, v, vel_star, acc);
        }
      }});
  // Step 23 (E53, E54, E58)
  m_steps.push_back(Step{"stress_update", {}, {}, [this, grid, ns, &dt](const StepContext&) {
                           double limit = 1e300;
                           for (int s = 0; s < ns; ++s)
                             limit = std::min(limit, stress_update(grid, long(m_pb.particles[s].size()),
                                                                   m_pb.particles[s].data(), m_pb.solids[s], dt));
                           m_mpm_dt_limit = limit;
                         }});
  // Step 27: particles to the patches that own them; lost ones counted.
  m_steps.push_back(Step{"migrate_particles", {}, {}, [this, ns](const StepContext&) {
                           long lost = 0;
                           const long interval = m_pb.input.mpm.sort_interval;
                           for (int s = 0; s < ns; ++s) {
                             lost += migrate(*m_pb.decomposition, m_pb.particles[s]).left_domain;
                             if (interval > 0 && (m_pb.step + 1) % interval == 0)
                               sort_particles_by_cell(m_pb.patch(), m_pb.particles[s]);
                           }
                           m_pb.particles_left_domain += global_sum(m_pb.decomposition->comm(), lost);
                         }});
}

void Cycle::build_ice_steps() {
  Problem& pb = m_pb;
  const Patch& p = pb.patch();
  const MaterialTable mats = pb.materials;
  const int n = mats.count;
  const BoundaryInput bc = pb.input.boundary;
  const double V = p.grid.cell_volume();
  const Kokkos::Array<double, 3> h{p.grid.spacing[0], p.grid.spacing[1], p.grid.spacing[2]};
  const bool second_order = pb.input.ice.second_order;
  const bool ke_fix = pb.input.ice.kinetic_energy_fix;
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

  // Step 5 (E18)
  m_steps.push_back(Step{
      "face_velocity",
      cat<FieldRead>({{{"press_equil_CC", 2}, {"rho_CC", 2}, {"sp_vol_equil_CC", 2}}, vec("vel_CC", 2)}),
      vec_out("vel_FC", 1), [=, &dt](const StepContext& ctx) {
        const auto vel = read_vec(ctx, "vel_CC");
        const auto out = write_vec(ctx, "vel_FC");
        for (int d = 0; d < 3; ++d) {
          const IndexBox faces = faces_around_cells(p, d);
          face_velocity(faces, d, h[d], dt, gravity[d], n, ctx.read<Field3>("press_equil_CC"),
                        ctx.read<Field4>("rho_CC"), ctx.read<Field4>("sp_vol_equil_CC"), vel[d], out[d]);
          for (int m = 0; m < n; ++m) set_boundary_face_velocity(out[d], m, d, p, bc.velocity, faces);
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
          for (int m = 0; m < n; ++m) set_boundary_face_velocity(out[d], m, d, p, bc.velocity, faces);
        }
      }});

  // Step 7 (E20, with Adv[theta] of section 6)
  m_steps.push_back(Step{
      "pressure_update",
      cat<FieldRead>({{{"vol_frac_CC", 2},
                       {"sp_vol_equil_CC", 0},
                       {"sumKappa_CC", 0},
                       {"press_equil_CC", 0},
                       {"rho_CC", 0}},
                      vec("vel_FCME", 1)}),
      {{"adv_vol_frac_CC"}, {"delP_Dilatate"}, {"delP_MassX"}, {"press_CC_new"}, {"sum_rho_CC"}},
      [=, &dt](const StepContext& ctx) {
        const auto U = read_vec(ctx, "vel_FCME");
        const double outflux = max_outflux_fraction(owned, h, dt, n, U);
        if (global_max(comm, outflux) > 1.0)
          throw RedoStep("an outflux slab exceeds its cell (E39)");
        const auto theta = ctx.read<Field4>("vol_frac_CC");
        const auto adv = ctx.write<Field4>("adv_vol_frac_CC");
        for (int m = 0; m < n; ++m) {
          if (second_order) limited_gradient(p.ghosted_cells(1), h, theta, m, ConstField4(), GradientField(), m_grad);
          advection_change(owned, h, dt, U, m, theta, ConstField4(), second_order, m_grad, GradientField(), adv);
        }
        const auto press = ctx.write<Field3>("press_CC_new");
        pressure_update(owned, V, n, adv, ConstField4(), ctx.read<Field4>("sp_vol_equil_CC"),
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
  for (int m = 0; m < max_materials; ++m) ice_on[m] = 1;
  m_steps.push_back(Step{
      "momentum_energy_sources",
      cat<FieldRead>({vec("press_FC", 0),
                      {{"vol_frac_CC", 0},
                       {"rho_CC", 0},
                       {"TMV_CC", 0},
                       {"kappa_CC", 0},
                       {"press_CC_new", 0},
                       {"delP_Dilatate", 0}}}),
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
      }});

  // Step 16 (E29)
  m_steps.push_back(Step{
      "lagrangian_values",
      cat<FieldRead>({{{"rho_CC", 0}, {"temp_CC", 0}, {"int_eng_source_CC", 0}}, vec("vel_CC", 0),
                      vec("mom_source_CC", 0)}),
      cat<FieldWrite>({{{"mass_L_CC"}, {"int_eng_L_CC"}}, vec_out("mom_L_CC")}),
      [=](const StepContext& ctx) {
        const auto mass = ctx.write<Field4>("mass_L_CC");
        lagrangian_mass(with_extra, V, n, ctx.read<Field4>("rho_CC"), mass);
        lagrangian_momentum_energy(owned, mats, mass, read_vec(ctx, "vel_CC"), ctx.read<Field4>("temp_CC"),
                                   read_vec(ctx, "mom_source_CC"), ctx.read<Field4>("int_eng_source_CC"),
                                   write_vec(ctx, "mom_L_CC"), ctx.write<Field4>("int_eng_L_CC"));
      }});

  // Step 17 (E31)
  m_steps.push_back(Step{
      "exchange",
      cat<FieldRead>({{{"mass_L_CC", 0},
                       {"int_eng_L_CC", 0},
                       {"sp_vol_equil_CC", 0},
                       {"vol_frac_CC", 0},
                       {"temp_CC", 0}},
                      vec("mom_L_CC", 0)}),
      cat<FieldWrite>({vec_out("vel_ME_CC"), {{"temp_ME_CC"}, {"Tdot_CC"}}}),
      [=, &dt](const StepContext& ctx) {
        const auto vel = write_vec(ctx, "vel_ME_CC");
        const auto temp = ctx.write<Field4>("temp_ME_CC");
        exchange(owned, dt, mats, ctx.read<Field4>("mass_L_CC"), read_vec(ctx, "mom_L_CC"),
                 ctx.read<Field4>("int_eng_L_CC"), ctx.read<Field4>("sp_vol_equil_CC"),
                 ctx.read<Field4>("vol_frac_CC"), ctx.read<Field4>("temp_CC"), vel, temp,
                 ctx.write<Field4>("Tdot_CC"));
        for (int m = 0; m < n; ++m) {
          for (int d = 0; d < 3; ++d) fill_extra_cells(vel[d], m, p, bc.velocity, d);
          fill_extra_cells(temp, m, p, bc.temperature, -1);
        }
      }});

  // Step 18 (E32)
  m_steps.push_back(Step{
      "lagrangian_specific_volume",
      {{"rho_CC", 0},
       {"sp_vol_equil_CC", 0},
       {"vol_frac_CC", 0},
       {"kappa_CC", 0},
       {"sumKappa_CC", 0},
       {"delP_Dilatate", 0},
       {"temp_CC", 0},
       {"Tdot_CC", 0}},
      {{"sp_vol_L_CC"}},
      [=, &dt](const StepContext& ctx) {
        const auto out = ctx.write<Field4>("sp_vol_L_CC");
        const long bad = lagrangian_specific_volume(
            owned, V, dt, mats, ctx.read<Field4>("rho_CC"), ctx.read<Field4>("sp_vol_equil_CC"),
            ctx.read<Field4>("vol_frac_CC"), ctx.read<Field4>("kappa_CC"), ctx.read<Field3>("sumKappa_CC"),
            ctx.read<Field3>("delP_Dilatate"), ctx.read<Field4>("temp_CC"), ctx.read<Field4>("Tdot_CC"), out);
        if (global_sum(comm, bad) > 0) throw RedoStep("a Lagrangian specific volume is not positive (E32)");
        specific_volume_from_density(with_extra, owned, n, ctx.read<Field4>("vol_frac_CC"),
                                     ctx.read<Field4>("rho_CC"), out);
      }});

  // Steps 25-26 (E37, E38)
  m_steps.push_back(Step{
      "advect_and_advance",
      cat<FieldRead>({vec("vel_FCME", 1), {{"mass_L_CC", 2}, {"temp_ME_CC", 2}, {"sp_vol_L_CC", 2}},
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
        for (int m = 0; m < n; ++m) {
          if (second_order) limited_gradient(around, h, mass, m, ConstField4(), GradientField(), m_mass_grad);
          advection_change(owned, h, dt, U, m, mass, ConstField4(), second_order, m_mass_grad,
                           GradientField(), m_adv_mass);
          advance_density(owned, V, m, mass, m_adv_mass, rho_new);
          for (int q = 0; q < 5; ++q) {
            if (second_order) limited_gradient(around, h, q_in[q], m, mass, m_mass_grad, m_grad);
            advection_change(owned, h, dt, U, m, q_in[q], mass, second_order, m_grad, m_mass_grad, m_adv_q);
            advance_specific(owned, V, m, mass, q_in[q], m_adv_q, rho_new, q_out[q]);
          }
          if (ke_fix) {
            if (m == 0) specific_kinetic_energy(p.ghosted_cells(2), n, vel_me, m_ke);
            if (second_order) limited_gradient(around, h, m_ke, m, mass, m_mass_grad, m_grad);
            advection_change(owned, h, dt, U, m, m_ke, mass, second_order, m_grad, m_mass_grad, m_adv_q);
            kinetic_energy_to_heat(owned, V, m, mats.eos[m].cv, mass, m_ke, m_adv_q, rho_new,
                                   ConstVectorField4{vel_new[0], vel_new[1], vel_new[2]}, q_out[3]);
          }
        }
        const long bad = count_bad_states(owned, n, rho_new, q_out[3], q_out[4],
                                          ConstVectorField4{vel_new[0], vel_new[1], vel_new[2]});
        stop_if_any(comm, bad > 0,
                    "advect_and_advance: " + std::to_string(bad) +
                        " cells with a non-positive density, temperature or specific volume, or a "
                        "non-finite velocity (E38)");
      }});

  // End of step: boundary values of the new state (E38's BCs).
  m_steps.push_back(Step{"state_boundary_conditions",
                         {},
                         cat<FieldWrite>({{{"rho_CC_new"}, {"temp_CC_new"}, {"sp_vol_CC_new"}, {"press_CC_new"}},
                                          vec_out("vel_CC_new")}),
                         [this](const StepContext&) { fill_state_extra_cells(m_pb, "_new"); }});
}

void Cycle::advance(double time, double dt) {
  m_dt = dt;
  m_time = time;
  if (m_pb.material_count() == 0) {
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
  if (m_pb.material_count() == 0)
    return m_pb.input.time.cfl * global_min(m_pb.decomposition->comm(), m_mpm_dt_limit);
  const VectorField4 vel = vector_field(m_pb.fields, "vel_CC");
  const double dt = ice_timestep(p.owned_cells(), {p.grid.spacing[0], p.grid.spacing[1], p.grid.spacing[2]},
                                 m_pb.input.time.cfl, m_pb.materials, m_pb.fields.get<Field4>("sp_vol_CC"),
                                 m_pb.fields.get<Field4>("temp_CC"), ConstVectorField4{vel[0], vel[1], vel[2]});
  return global_min(m_pb.decomposition->comm(), dt);
}

}  // namespace mpmice
