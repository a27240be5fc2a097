#pragma once
// The run's input, read once from YAML into plain structs (units SI). Every key is
// declared with its type, range and default in input.cpp; unknown keys are errors.
#include <array>
#include <string>
#include <vector>

#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/eos.hpp>
#include <mpmice/kernels/simple_burn.hpp>
#include <mpmice/kernels/solid_models.hpp>

namespace mpmice {

struct GridInput {
  std::array<double, 3> lower{0, 0, 0}, upper{1, 1, 1};  // m
  std::array<int, 3> cells{1, 1, 1};
  std::array<bool, 3> periodic{false, false, false};
  std::array<int, 3> ranks{0, 0, 0};  // 0: chosen by the decomposition
};

struct TimeInput {
  double end = 0;                // s
  long max_steps = 1000000000L;
  double cfl = 0.25;
  double dt_initial = 1e-9;      // s
  double dt_min = 1e-20;         // s
  double dt_max = 1.0;           // s
  double max_increase = 1.0;     // dt may grow by at most this fraction per step
};

struct IceInput {
  bool second_order = true;
  bool kinetic_energy_fix = true;  // advection's lost kinetic energy becomes heat
  bool clamp_specific_volume = false;  // (E32) VL >= TINY_RHO V v instead of a redo
  std::array<double, 3> gravity{0, 0, 0};  // m/s^2
};

struct MpmInput {
  bool gimp = true;          // GIMP (E8) or linear (E6) shape functions
  double pic_fraction = 0;   // 0: FLIP, 1: PIC
  std::array<double, 3> gravity{0, 0, 0};  // m/s^2
  double damping = 0;        // 1/s: artificial damping of the solids' node accelerations (E26)
  long sort_interval = 20;   // steps between sorts of particles by window (particle_sort.hpp)
  double reference_pressure = 101325;  // Pa: the unstressed solid's pressure (p_ref)
};

/// A fluid (ICE, `eos`) or a solid (MPM, `solid`).
struct MaterialInput {
  std::string name;
  bool is_solid = false;
  Eos eos;          // a fluid's EOS; for a solid, its bulk law in the equilibration (E51, E52)
  SolidModel solid;
};

struct ExchangeInput {
  std::vector<double> momentum;  // N x N, K_rs
  std::vector<double> heat;      // N x N, H_rs
};

enum class Shape { box, cylinder, sphere };

struct GeometryPiece {
  int material = 0;
  Shape shape = Shape::box;
  std::array<double, 3> lower{0, 0, 0}, upper{0, 0, 0};  // box
  std::array<double, 3> bottom{0, 0, 0}, top{0, 0, 0};   // cylinder axis ends
  std::array<double, 3> center{0, 0, 0};                 // sphere
  double radius = 0;                                     // cylinder, sphere
  double density = 0;                                    // kg/m^3 (micro density)
  double temperature = 0;                                // K
  std::array<double, 3> velocity{0, 0, 0};               // m/s
  std::array<int, 3> particles_per_cell{2, 2, 2};        // solids
  // Solids: velocity + amplitude * sin(wavenumber . x), e.g. a vibration mode.
  std::array<double, 3> sine_amplitude{0, 0, 0}, sine_wavenumber{0, 0, 0};
  bool contains(const std::array<double, 3>& x) const;
};

/// Boundary conditions per face (x-, x+, y-, y+, z-, z+) and variable.
struct BoundaryInput {
  FaceBcs pressure, density, temperature, velocity;
};

struct ProbeInput {
  std::string name;
  std::array<double, 3> position{0, 0, 0};
  std::vector<std::string> quantities;
};

struct OutputInput {
  long history_interval = 1;  // steps
  long probe_interval = 1;    // steps
  bool final_fields = false;  // fields.csv with every cell's state at the end
  long field_interval = 0;    // steps between HDF5 + XDMF field outputs (0: none)
  std::vector<std::string> fields;  // what the field output holds (field_output_names())
};

struct CheckpointInput {
  long interval = 0;         // steps between checkpoints (0: none)
  double wall_interval = 0;  // wall-clock seconds between checkpoints (0: none)
  int keep = 2;              // newest checkpoints kept
};

struct Input {
  std::string file;
  GridInput grid;
  TimeInput time;
  IceInput ice;
  MpmInput mpm;
  std::vector<MaterialInput> materials;
  ExchangeInput exchange;
  std::vector<GeometryPiece> geometry;
  /// Solid -> gas reactions (Simple Burn); `reactant` and `product` are material
  /// indices (the node slot is filled in by the set-up).
  std::vector<SimpleBurn> reactions;
  int sample_points = 2;  // per cell and direction, for volume fractions
  BoundaryInput boundary;
  std::vector<ProbeInput> probes;
  OutputInput output;
  CheckpointInput checkpoint;
};

/// Quantities the field output may hold: cell fields (per fluid, pressure shared) and
/// particle fields (per solid; positions are always written).
const std::vector<std::string>& field_output_names();

/// Quantities a probe may record.
const std::vector<std::string>& probe_quantities();

/// Read and validate `file`, after applying `--set key.path=value` overrides.
/// Throws mpmice::InputError naming the key (and line) on any problem.
Input load_input(const std::string& file, const std::vector<std::string>& overrides);

}  // namespace mpmice
