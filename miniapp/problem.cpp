#include "problem.hpp"

#include <cmath>
#include <string>

#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/node_to_cell.hpp>

namespace mpmice {

std::array<std::string, 3> components(const std::string& name) {
  return {name + "_x", name + "_y", name + "_z"};
}

VectorField4 vector_field(const FieldRegistry& fields, const std::string& name) {
  const auto c = components(name);
  return {fields.get<Field4>(c[0]), fields.get<Field4>(c[1]), fields.get<Field4>(c[2])};
}

namespace {

// The node fields of the MPM steps, one material slot per solid.
void register_node_fields(Problem& pb) {
  const Patch& p = pb.patch();
  const int n = pb.solid_count();
  for (const std::string name : {"mass_NC", "heat_NC", "volume_NC", "temp_NC", "temp_rate_NC"})
    pb.fields.add(name, make_field(name, p, Location::node, n), Location::node);
  for (const std::string name : {"mom_NC", "fext_NC", "fint_NC", "vel_NC", "vel_star_NC", "acc_NC"})
    for (const auto& c : components(name)) pb.fields.add(c, make_field(c, p, Location::node, n), Location::node);
  if (!pb.has_cells()) return;
  // The coupling: node weights (E10), node pressure (E11), the solids' cell rates (E33).
  Field3 weight = make_field("NC_CCweight", p, Location::node);
  node_cell_weights(p, pb.input.boundary.velocity, weight);
  pb.fields.add("NC_CCweight", weight, Location::node);
  pb.fields.set_valid_ghosts("NC_CCweight", p.ghosts);  // computed on every node, never changes
  pb.fields.add("press_NC", make_field("press_NC", p, Location::node), Location::node);
  pb.fields.add("dTdt_CC", make_field("dTdt_CC", p, Location::cell, n), Location::cell);
  pb.fields.add("transfer_energy_NC", make_field("transfer_energy_NC", p, Location::node, n), Location::node);
  for (const auto& c : components("dVdt_CC")) pb.fields.add(c, make_field(c, p, Location::cell, n), Location::cell);
}

// Particles on a res_d lattice in every owned cell where the last geometry piece
// containing the lattice point is of the solid (section 4, item 2).
void create_particles(Problem& pb) {
  const Input& in = pb.input;
  const Patch& p = pb.patch();
  const IndexBox own = p.owned_cells();
  const double cell_volume = p.grid.cell_volume();
  for (int s = 0; s < pb.solid_count(); ++s) {
    const int mat = pb.mpm[s];
    const SolidModel& model = pb.solids[s];
    std::vector<std::array<double, particle_field_count>> rows;
    std::vector<std::int64_t> ids;
    for (int i = own.lo[0]; i < own.hi[0]; ++i)
      for (int j = own.lo[1]; j < own.hi[1]; ++j)
        for (int k = own.lo[2]; k < own.hi[2]; ++k) {
          const int idx[3] = {i, j, k};
          const long cell_id = (long(p.global_index(i, 0)) * p.grid.cells[1] + p.global_index(j, 1)) *
                                   p.grid.cells[2] + p.global_index(k, 2);
          // A cell's lattice comes from the piece of this solid covering the cell centre,
          // or from the solid's first piece.
          std::array<double, 3> centre;
          for (int d = 0; d < 3; ++d) centre[d] = p.cell_center(idx[d], d);
          int lattice = -1;
          for (std::size_t g = 0; g < in.geometry.size(); ++g)
            if (in.geometry[g].material == mat && (lattice < 0 || in.geometry[g].contains(centre))) lattice = int(g);
          const auto res = in.geometry[lattice].particles_per_cell;
          const int ppc = res[0] * res[1] * res[2];
          for (int a = 0; a < res[0]; ++a)
            for (int b = 0; b < res[1]; ++b)
              for (int c = 0; c < res[2]; ++c) {
                const int sub[3] = {a, b, c};
                std::array<double, 3> x;
                for (int d = 0; d < 3; ++d)
                  x[d] = p.node_position(idx[d], d) + (sub[d] + 0.5) / res[d] * p.grid.spacing[d];
                int owner = -1;
                for (std::size_t g = 0; g < in.geometry.size(); ++g)
                  if (in.geometry[g].contains(x)) owner = int(g);
                if (owner < 0 || in.geometry[owner].material != mat) continue;
                const GeometryPiece& piece = in.geometry[owner];
                std::array<double, particle_field_count> row{};
                const double phase = piece.sine_wavenumber[0] * x[0] + piece.sine_wavenumber[1] * x[1] +
                                     piece.sine_wavenumber[2] * x[2];
                for (int d = 0; d < 3; ++d) {
                  row[column(ParticleField::x) + d] = x[d];
                  row[column(ParticleField::vx) + d] = piece.velocity[d] + piece.sine_amplitude[d] * std::sin(phase);
                  row[column(ParticleField::size_x) + d] = 1.0 / res[d];
                  row[tensor_column(ParticleField::F00, d, d)] = 1.0;
                  row[tensor_column(ParticleField::be00, d, d)] = 1.0;
                }
                if (model.type == SolidModelType::rigid)
                  for (int d = 0; d < 3; ++d) row[column(ParticleField::vx) + d] = model.rigid_velocity(0.0)[d];
                row[column(ParticleField::volume)] = cell_volume / ppc;
                row[column(ParticleField::mass)] = model.density * cell_volume / ppc;
                row[column(ParticleField::temperature)] = piece.temperature;
                rows.push_back(row);
                ids.push_back(cell_id * 512 + (a * 8 + b) * 8 + c);
              }
        }
    ParticleSet ps(in.materials[mat].name, rows.size());
    ps.resize(rows.size());
    auto data = Kokkos::create_mirror_view(ps.data());
    auto id = Kokkos::create_mirror_view(ps.id());
    for (std::size_t q = 0; q < rows.size(); ++q) {
      for (int c = 0; c < particle_field_count; ++c) data(q, c) = rows[q][c];
      id(q) = ids[q];
    }
    Kokkos::deep_copy(ps.data(), data);
    Kokkos::deep_copy(ps.id(), id);
    pb.particles.push_back(std::move(ps));
  }
}

// Every field the cycle uses (Uintah's names; _new: the state at t^{n+1}).
void register_fields(Problem& pb) {
  const Patch& p = pb.patch();
  const int n = pb.material_count();
  FieldRegistry& f = pb.fields;
  auto cell4 = [&](const std::string& name) { f.add(name, make_field(name, p, Location::cell, n), Location::cell); };
  auto cell3 = [&](const std::string& name) { f.add(name, make_field(name, p, Location::cell), Location::cell); };
  auto vec4 = [&](const std::string& name) {
    for (const auto& c : components(name)) cell4(c);
  };
  const Location face_loc[3] = {Location::x_face, Location::y_face, Location::z_face};
  auto face4 = [&](const std::string& name) {
    const auto c = components(name);
    for (int d = 0; d < 3; ++d) f.add(c[d], make_field(c[d], p, face_loc[d], n), face_loc[d]);
  };
  auto face3 = [&](const std::string& name) {
    const auto c = components(name);
    for (int d = 0; d < 3; ++d) f.add(c[d], make_field(c[d], p, face_loc[d]), face_loc[d]);
  };
  for (const std::string suffix : {"", "_new"}) {
    cell4("rho_CC" + suffix);
    vec4("vel_CC" + suffix);
    cell4("temp_CC" + suffix);
    cell4("sp_vol_CC" + suffix);
    cell3("press_CC" + suffix);
  }
  // Step 3
  cell3("press_equil_CC");
  cell4("vol_frac_CC");
  cell4("sp_vol_equil_CC");
  cell4("speedSound_CC");
  cell4("kappa_CC");
  cell3("sumKappa_CC");
  cell3("TMV_CC");
  // Steps 5-6
  face4("vel_FC");
  face4("vel_FCME");
  // Step 7
  cell4("adv_vol_frac_CC");
  face3("vol_flux_FC");  // the fluids' volume flux through each face (pressure_work_heat)
  face3("solid_vol_flux_FC");  // the deforming solids' volume flux through each face (the same)
  cell3("delP_Dilatate");
  cell3("delP_MassX");
  cell3("sum_rho_CC");
  // Step 8-10
  face3("press_FC");
  vec4("mom_source_CC");
  cell4("int_eng_source_CC");
  // Steps 16-18
  cell4("mass_L_CC");
  vec4("mom_L_CC");
  cell4("int_eng_L_CC");
  vec4("vel_ME_CC");
  cell4("temp_ME_CC");
  cell4("Tdot_CC");
  cell4("sp_vol_L_CC");
  if (!pb.reactions.empty()) {
    // Step 4: the mass each reactant is to burn next step (checkpointed: it carries
    // the reaction from one step to the next), and what the product gains this step.
    cell4("burn_dm_CC");
    cell4("reaction_sp_vol_CC");
    cell4("temp_mixed_CC");
    cell4("reaction_mass_CC");
    vec4("reaction_mom_CC");
    cell4("reaction_eng_CC");
  }
}

// Volume fractions and state by sampling each cell with res^3 points; the last piece
// containing a point owns it (section 4, item 1).
void initialize_state(Problem& pb) {
  const Input& in = pb.input;
  const Patch& p = pb.patch();
  const int n = pb.material_count();
  const int res = in.sample_points;
  auto rho = Kokkos::create_mirror_view(pb.fields.get<Field4>("rho_CC"));
  auto temp = Kokkos::create_mirror_view(pb.fields.get<Field4>("temp_CC"));
  auto spv = Kokkos::create_mirror_view(pb.fields.get<Field4>("sp_vol_CC"));
  auto press = Kokkos::create_mirror_view(pb.fields.get<Field3>("press_CC"));
  const VectorField4 vel_d = vector_field(pb.fields, "vel_CC");
  decltype(rho) vel[3] = {Kokkos::create_mirror_view(vel_d[0]), Kokkos::create_mirror_view(vel_d[1]),
                          Kokkos::create_mirror_view(vel_d[2])};
  std::vector<int> first_piece(n, -1);
  for (std::size_t g = 0; g < in.geometry.size(); ++g)
    if (first_piece[in.geometry[g].material] < 0) first_piece[in.geometry[g].material] = int(g);

  const IndexBox own = p.owned_cells();
  std::vector<int> count(in.geometry.size());
  for (int i = own.lo[0]; i < own.hi[0]; ++i)
    for (int j = own.lo[1]; j < own.hi[1]; ++j)
      for (int k = own.lo[2]; k < own.hi[2]; ++k) {
        std::fill(count.begin(), count.end(), 0);
        const int idx[3] = {i, j, k};
        for (int a = 0; a < res; ++a)
          for (int b = 0; b < res; ++b)
            for (int c = 0; c < res; ++c) {
              const int sub[3] = {a, b, c};
              std::array<double, 3> x;
              for (int d = 0; d < 3; ++d)
                x[d] = p.node_position(idx[d], d) + (sub[d] + 0.5) / res * p.grid.spacing[d];
              int owner = -1;
              for (std::size_t g = 0; g < in.geometry.size(); ++g)
                if (in.geometry[g].contains(x)) owner = int(g);
              if (owner < 0) {
                char where[160];
                std::snprintf(where, sizeof where, "cell (%d, %d, %d) at (%g, %g, %g) m",
                              p.global_index(i, 0), p.global_index(j, 1), p.global_index(k, 2),
                              x[0], x[1], x[2]);
                throw InputError("geometry", std::string("no geometry piece covers ") + where);
              }
              ++count[owner];
            }
        const double points = double(res) * res * res;
        double best_theta = -1, best_press = 0;
        for (int m = 0; m < n; ++m) {
          int points_m = 0, piece = first_piece[m], most = -1;
          for (std::size_t g = 0; g < in.geometry.size(); ++g)
            if (in.geometry[g].material == m) {
              points_m += count[g];
              if (count[g] > most && count[g] > 0) {
                most = count[g];
                piece = int(g);
              }
            }
          const GeometryPiece& src = in.geometry[piece];
          const double theta = points_m / points;
          rho(m, i, j, k) = src.density * theta + tiny_rho * src.density;
          spv(m, i, j, k) = 1.0 / src.density;
          temp(m, i, j, k) = src.temperature;
          for (int d = 0; d < 3; ++d) vel[d](m, i, j, k) = src.velocity[d];
          if (theta > best_theta) {
            best_theta = theta;
            best_press = eos_pressure(pb.materials.eos[m], src.density, src.temperature);
          }
        }
        press(i, j, k) = best_press;
      }
  Kokkos::deep_copy(pb.fields.get<Field4>("rho_CC"), rho);
  Kokkos::deep_copy(pb.fields.get<Field4>("temp_CC"), temp);
  Kokkos::deep_copy(pb.fields.get<Field4>("sp_vol_CC"), spv);
  Kokkos::deep_copy(pb.fields.get<Field3>("press_CC"), press);
  for (int d = 0; d < 3; ++d) Kokkos::deep_copy(vel_d[d], vel[d]);
}

}  // namespace

HostState host_state(const Problem& pb) {
  auto copy = [](const auto& view) { return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view); };
  const VectorField4 vel = vector_field(pb.fields, "vel_CC");
  return HostState{copy(pb.fields.get<Field4>("rho_CC")),
                   copy(pb.fields.get<Field4>("temp_CC")),
                   copy(pb.fields.get<Field4>("sp_vol_CC")),
                   {copy(vel[0]), copy(vel[1]), copy(vel[2])},
                   copy(pb.fields.get<Field3>("press_CC"))};
}

void fill_state_extra_cells(Problem& pb, const std::string& suffix) {
  const Patch& p = pb.patch();
  const BoundaryInput& bc = pb.input.boundary;
  const VectorField4 vel = vector_field(pb.fields, "vel_CC" + suffix);
  // The specific volume follows the density's condition; where the density is given,
  // the inflowing material fills the extra cell, so v = 1/rho there.
  FaceBcs sp_vol_bc = bc.density;
  for (int f = 0; f < 6; ++f)
    if (sp_vol_bc[f].kind == BcKind::dirichlet) sp_vol_bc[f].value[0] = 1.0 / bc.density[f].value[0];
  fill_extra_cells(
      Kokkos::Array<ExtraCellFill, 7>{
          ExtraCellFill(pb.fields.get<Field4>("rho_CC" + suffix), bc.density, -1),
          ExtraCellFill(pb.fields.get<Field4>("temp_CC" + suffix), bc.temperature, -1),
          ExtraCellFill(pb.fields.get<Field4>("sp_vol_CC" + suffix), sp_vol_bc, -1), ExtraCellFill(vel[0], bc.velocity, 0),
          ExtraCellFill(vel[1], bc.velocity, 1), ExtraCellFill(vel[2], bc.velocity, 2),
          ExtraCellFill(pb.fields.get<Field3>("press_CC" + suffix), bc.pressure, -1)},
      p);
}

std::unique_ptr<Problem> make_problem(const Input& input, MPI_Comm comm) {
  auto pb = std::make_unique<Problem>();
  pb->input = input;
  Grid grid;
  for (int d = 0; d < 3; ++d) {
    grid.lower[d] = input.grid.lower[d];
    grid.cells[d] = input.grid.cells[d];
    grid.spacing[d] = (input.grid.upper[d] - input.grid.lower[d]) / input.grid.cells[d];
  }
  DecompositionOptions opt;
  opt.ranks = input.grid.ranks;
  opt.periodic = input.grid.periodic;
  opt.ghosts = ghost_layers;
  pb->decomposition = std::make_unique<Decomposition>(comm, grid, opt);
  pb->halo = std::make_unique<Halo>(*pb->decomposition);

  for (int m = 0; m < int(input.materials.size()); ++m) {
    if (input.materials[m].is_solid) {
      pb->mpm.push_back(m);
      pb->solids.push_back(input.materials[m].solid);
    } else {
      pb->ice.push_back(m);
    }
  }
  const int n = int(input.materials.size());
  pb->materials.count = n;
  for (int m = 0; m < n; ++m) {
    const MaterialInput& mat = input.materials[m];
    pb->materials.eos[m] = mat.eos;
    pb->materials.kind[m] = !mat.is_solid ? ice_material
                            : mat.solid.type == SolidModelType::rigid ? rigid_material
                                                                       : mpm_material;
  }
  for (int r = 0; r < n; ++r)
    for (int s = 0; s < n; ++s) {
      pb->materials.momentum_exchange[r * max_materials + s] = input.exchange.momentum[r * n + s];
      pb->materials.heat_exchange[r * max_materials + s] = input.exchange.heat[r * n + s];
    }
  for (SimpleBurn b : input.reactions) {
    for (int s = 0; s < pb->solid_count(); ++s)
      if (pb->mpm[s] == b.reactant) b.reactant_slot = s;
    pb->reactions.push_back(b);
  }
  if (pb->has_cells()) {
    register_fields(*pb);
    initialize_state(*pb);
    fill_state_extra_cells(*pb, "");
  }
  if (!pb->mpm.empty()) {
    register_node_fields(*pb);
    create_particles(*pb);
  }
  return pb;
}

}  // namespace mpmice
