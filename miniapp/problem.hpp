#pragma once
// A problem set up and ready to run: the decomposition, the halo, the material table,
// the boundary conditions and every field of the cycle, registered by name.
#include <mpi.h>

#include <memory>

#include <mpmice/halo/decomposition.hpp>
#include <mpmice/halo/halo.hpp>
#include <mpmice/halo/steps.hpp>
#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/particles.hpp>
#include <mpmice/kernels/simple_burn.hpp>
#include <mpmice/kernels/solid_models.hpp>

#include "input.hpp"

namespace mpmice {

/// Ghost layers every patch stores: second-order advection reads two.
constexpr int ghost_layers = 2;

struct Problem {
  Input input;
  std::unique_ptr<Decomposition> decomposition;
  std::unique_ptr<Halo> halo;
  FieldRegistry fields;
  /// Every material in input order (cell slot = input index).
  MaterialTable materials;
  /// The fluids' input indices.
  std::vector<int> ice;
  /// The MPM materials (solids) in input order: `mpm[s]` is the input index of node
  /// material slot s, with its model and particles.
  std::vector<int> mpm;
  std::vector<SolidModel> solids;
  std::vector<ParticleSet> particles;
  long particles_left_domain = 0;  // removed at non-periodic boundaries, all ranks
  /// The input's reactions with the reactant's node slot filled in.
  std::vector<SimpleBurn> reactions;
  double chemical_energy_released = 0;  // J, sum of dm dh since the start, all ranks
  long particles_burned_out = 0;        // removed when their whole mass burned, all ranks
  double time = 0;  // s
  long step = 0;

  const Patch& patch() const { return decomposition->patch(); }
  /// Number of materials, fluids and solids: the cell fields' material slots (a
  /// material's slot is its index in the input).
  int material_count() const { return materials.count; }
  /// Cell fields exist when there is a fluid (ICE or MPMICE); solids alone need nodes.
  bool has_cells() const { return !ice.empty(); }
  int solid_count() const { return int(mpm.size()); }
};

/// Decompose the grid over `comm`, allocate the fields and set the initial state
/// (mpmice-algorithm.md section 4). Throws InputError for inputs that only the set-up
/// can judge (too many ranks, cells no geometry piece covers).
std::unique_ptr<Problem> make_problem(const Input& input, MPI_Comm comm);

/// The names of the three components of a vector field: name_x, name_y, name_z.
std::array<std::string, 3> components(const std::string& name);

/// The three component views of a registered vector field.
VectorField4 vector_field(const FieldRegistry& fields, const std::string& name);

/// Host copies of the fluid state (cell fields of every material), for output.
struct HostState {
  Field4::HostMirror rho, temp, sp_vol;
  Field4::HostMirror vel[3];
  Field3::HostMirror press;
};
HostState host_state(const Problem& problem);

/// Fill the extra cells of every persistent state field (density, velocity,
/// temperature, specific volume, pressure), with the given suffix ("" or "_new").
void fill_state_extra_cells(Problem& problem, const std::string& suffix);

}  // namespace mpmice
