// The Lagrangian steps: Lagrangian values, the exchange, the Lagrangian specific volume,
// and the solids' rates carried back to their nodes.
#include "cycle.hpp"

#include <string>

#include <mpmice/kernels/cell_to_node.hpp>
#include <mpmice/kernels/exchange.hpp>
#include <mpmice/kernels/lagrangian_values.hpp>
#include <mpmice/kernels/mpm_lagrangian_values.hpp>
#include <mpmice/kernels/pressure_work_heat.hpp>
#include <mpmice/kernels/specific_volume.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

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
}

}  // namespace mpmice
