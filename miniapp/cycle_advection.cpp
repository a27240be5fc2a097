// The advection steps: the fluids advected and advanced, the new state's boundary values.
#include "cycle.hpp"

#include <string>

#include <mpmice/kernels/advection.hpp>
#include <mpmice/kernels/conserved_to_primitive.hpp>
#include <mpmice/kernels/kinetic_energy_fix.hpp>

#include "cycle_parts.hpp"

namespace mpmice {
using namespace cycle_parts;

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

}  // namespace mpmice
