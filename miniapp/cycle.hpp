#pragma once
// The timestep as an ordered list of declared steps (mpmice-algorithm.md section 5,
// the ICE materials' part). Each step names what it reads, with ghost depth, and what
// it writes; the StepRunner refreshes ghosts and times each step.
#include <stdexcept>
#include <vector>

#include <mpmice/halo/steps.hpp>
#include <mpmice/kernels/advection.hpp>
#include <mpmice/kernels/node_scatter.hpp>
#include <mpmice/kernels/quanta.hpp>

#include "problem.hpp"

namespace mpmice {

/// The step cannot be completed with this dt (an outflux slab larger than its cell,
/// or a non-positive Lagrangian volume, E39/E32); the state at t^n is untouched, so
/// the caller redoes it with a smaller dt.
struct RedoStep : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The steps as a markdown table: step, reads (field:ghost layers), writes (+: ghost
/// contributions summed into their owners).
std::string steps_table(const std::vector<Step>& steps);

class Cycle {
 public:
  explicit Cycle(Problem& problem);

  /// Advance the state from t^n = `time` to t^n + dt. Throws RedoStep or
  /// InvariantError.
  void advance(double time, double dt);
  /// The stable timestep of the current state, over all ranks: acoustic (E57) for
  /// fluids, dilatational wave speed (E58) for solids, times time.cfl.
  double stable_timestep() const;

  const std::vector<Step>& steps() const { return m_steps; }
  const StepRunner& runner() const { return m_runner; }

 private:
  // The cycle in the order of mpmice-algorithm.md section 5; each adds the steps of
  // its part that the problem's materials need.
  void add_burn_step();
  void add_particle_to_grid_steps();
  void add_node_to_cell_step();
  void add_pressure_steps();
  void add_force_steps();
  void add_lagrangian_steps();
  void add_particle_update_steps();
  void add_advection_steps();
  Problem& m_pb;
  StepRunner m_runner;
  std::vector<Step> m_steps;
  double m_dt = 0, m_time = 0;
  std::vector<double> m_rigid_mass_quantum;  // per solid: rigid_particle_to_cell's mass unit, kg
  std::vector<double> m_mass_quantum;  // per solid: the particle masses' grid (quanta.hpp), kg
  // This step's quanta of solid s's scatters, the same on every rank (quanta.hpp).
  SumQuanta scatter_quanta(int s) const;
  double m_mpm_dt_limit = 1e300;  // from the last stress update (E58)
  // Scratch of the advection operator (not fields of the cycle: no step shares them).
  GradientField m_grad, m_mass_grad;
  Field4 m_adv_mass, m_adv_q, m_ke;
  FaceFluxes m_face_flux;  // the fluxes of one material and quantity (face_fluxes, advection_change)
  Field3 m_burn_cell_mass;  // burn_particles' scratch: the reactant's particle mass per cell
  ScatterScratch m_p2g_scatter, m_force_scatter;  // the copies p2g and internal_force add into
};

}  // namespace mpmice
