// The fluids' pressure steps: equilibration to the momentum and energy sources.
#include "cycle.hpp"

#include <string>

#include <mpmice/kernels/advection.hpp>
#include <mpmice/kernels/equilibrate_pressure.hpp>
#include <mpmice/kernels/face_exchange.hpp>
#include <mpmice/kernels/face_pressure.hpp>
#include <mpmice/kernels/face_velocity.hpp>
#include <mpmice/kernels/particle_burn.hpp>
#include <mpmice/kernels/pressure_update.hpp>
#include <mpmice/kernels/simple_burn.hpp>
#include <mpmice/kernels/sources.hpp>
#include <mpmice/kernels/specific_volume.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

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

}  // namespace mpmice
