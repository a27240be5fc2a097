#include "input.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "yaml_reader.hpp"

namespace mpmice {
namespace {

constexpr double big = std::numeric_limits<double>::max();
const char* face_names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

// --set a.b.0.c=value: replace (or add) one entry of the tree.
void apply_override(YAML::Node& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", "--set takes key.path=value, got '" + assignment + "'");
  const std::string path = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw InputError(path, "--set " + path + ": the value '" + value + "' is not valid YAML");
  }
  YAML::Node node = root;
  std::stringstream ss(path);
  std::string part;
  std::vector<std::string> parts;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const std::string& key = parts[p];
    YAML::Node child;
    if (node.IsSequence()) {
      char* end = nullptr;
      const long idx = std::strtol(key.c_str(), &end, 10);
      if (*end != '\0' || idx < 0 || idx >= long(node.size()))
        throw InputError(path, "--set " + path + ": '" + key + "' is not an index of the list");
      child = node[std::size_t(idx)];
    } else {
      child = node[key];
    }
    node.reset(child);
  }
  node = parsed;
}

Bc read_bc(Reader& face, const std::string& var, bool vector, const Bc& fallback) {
  if (!face.has(var)) return fallback;
  YAML::Node n = face.node(var);
  Bc bc;
  if (n.IsScalar() && n.as<std::string>() == "symmetry") {
    bc.kind = BcKind::symmetry;
    return bc;
  }
  Reader r(n, face.key_path(var));
  const bool neu = r.has("neumann"), dir = r.has("dirichlet"), sym = r.has("symmetry");
  if (int(neu) + int(dir) + int(sym) != 1)
    r.fail("", "needs exactly one of neumann, dirichlet, symmetry");
  const std::string kind = neu ? "neumann" : (dir ? "dirichlet" : "symmetry");
  bc.kind = neu ? BcKind::neumann : (dir ? BcKind::dirichlet : BcKind::symmetry);
  if (!sym) {
    if (vector) {
      const auto v = r.vector3(kind);
      for (int d = 0; d < 3; ++d) bc.value[d] = v[d];
    } else {
      bc.value[0] = r.get<double>(kind);
      if (!std::isfinite(bc.value[0])) r.fail(kind, "must be finite");
      if (bc.kind == BcKind::dirichlet && bc.value[0] <= 0)
        r.fail(kind, "must be > 0 (a " + var + ")");
    }
  }
  r.finish();
  return bc;
}

void read_boundary(Reader& root, Input& in) {
  Bc symmetry;
  symmetry.kind = BcKind::symmetry;
  for (int f = 0; f < 6; ++f) {
    in.boundary.pressure[f] = in.boundary.density[f] = in.boundary.temperature[f] =
        in.boundary.velocity[f] = symmetry;
  }
  if (!root.has("boundary")) return;
  Reader b = root.map("boundary");
  for (int f = 0; f < 6; ++f) {
    const std::string name = face_names[f];
    if (!b.has(name)) continue;
    if (in.grid.periodic[f / 2])
      b.fail(name, "is given, but the direction is periodic (grid.periodic)");
    YAML::Node n = b.node(name);
    Bc zero;  // neumann 0
    if (n.IsScalar()) {
      const std::string s = n.as<std::string>();
      Bc all;
      if (s == "symmetry" || s == "wall")
        all.kind = BcKind::symmetry;
      else if (s == "outflow" || s == "zero_gradient")
        all.kind = BcKind::neumann;
      else
        b.fail(name, "is '" + s + "' (allowed: symmetry, wall, outflow, zero_gradient, or a map of "
                                  "pressure/density/temperature/velocity conditions)");
      in.boundary.pressure[f] = in.boundary.density[f] = in.boundary.temperature[f] =
          in.boundary.velocity[f] = all;
      continue;
    }
    Reader face(n, b.key_path(name));
    in.boundary.pressure[f] = read_bc(face, "pressure", false, zero);
    in.boundary.density[f] = read_bc(face, "density", false, zero);
    in.boundary.temperature[f] = read_bc(face, "temperature", false, zero);
    in.boundary.velocity[f] = read_bc(face, "velocity", true, zero);
    face.finish();
  }
  b.finish();
}

int material_index(const Input& in, Reader& r, const std::string& key) {
  const std::string name = r.get<std::string>(key);
  for (std::size_t m = 0; m < in.materials.size(); ++m)
    if (in.materials[m].name == name) return int(m);
  r.fail(key, "names '" + name + "', which is not a material");
}

void read_exchange_list(Reader& ex, const std::string& key, Input& in, std::vector<double>& k) {
  const std::size_t n = in.materials.size();
  k.assign(n * n, 0.0);
  if (!ex.has(key)) return;
  YAML::Node list = ex.node(key);
  if (!list.IsSequence()) ex.fail(key, "must be a list of {materials: [a, b], coefficient: c}");
  for (std::size_t e = 0; e < list.size(); ++e) {
    Reader r(list[e], ex.key_path(key) + "." + std::to_string(e));
    const auto names = r.get<std::vector<std::string>>("materials");
    if (names.size() != 2) r.fail("materials", "must name two materials");
    int idx[2];
    for (int s = 0; s < 2; ++s) {
      idx[s] = -1;
      for (std::size_t m = 0; m < n; ++m)
        if (in.materials[m].name == names[s]) idx[s] = int(m);
      if (idx[s] < 0) r.fail("materials", "names '" + names[s] + "', which is not a material");
    }
    if (idx[0] == idx[1]) r.fail("materials", "must name two different materials");
    const double c = r.number("coefficient", 0.0, big);
    k[idx[0] * n + idx[1]] = k[idx[1] * n + idx[0]] = c;
    r.finish();
  }
}

}  // namespace

const std::vector<std::string>& field_output_names() {
  static const std::vector<std::string> q{"pressure", "density", "temperature", "volume_fraction", "velocity",
                                          "particle_velocity", "particle_mass", "particle_temperature",
                                          "von_mises_stress", "plastic_strain", "particle_stress"};
  return q;
}

const std::vector<std::string>& probe_quantities() {
  static const std::vector<std::string> q{"pressure",   "density",     "velocity_x",
                                          "velocity_y", "velocity_z",  "temperature",
                                          "volume_fraction", "specific_volume"};
  return q;
}

bool GeometryPiece::contains(const std::array<double, 3>& x) const {
  switch (shape) {
    case Shape::box:
      for (int d = 0; d < 3; ++d)
        if (x[d] < lower[d] || x[d] > upper[d]) return false;
      return true;
    case Shape::sphere: {
      double r2 = 0;
      for (int d = 0; d < 3; ++d) r2 += (x[d] - center[d]) * (x[d] - center[d]);
      return r2 <= radius * radius;
    }
    case Shape::cylinder: {
      double axis[3], rel[3], len2 = 0, t = 0;
      for (int d = 0; d < 3; ++d) {
        axis[d] = top[d] - bottom[d];
        rel[d] = x[d] - bottom[d];
        len2 += axis[d] * axis[d];
        t += rel[d] * axis[d];
      }
      t /= len2;
      if (t < 0 || t > 1) return false;
      double dist2 = 0;
      for (int d = 0; d < 3; ++d) dist2 += (rel[d] - t * axis[d]) * (rel[d] - t * axis[d]);
      return dist2 <= radius * radius;
    }
  }
  return false;
}

Input load_input(const std::string& file, const std::vector<std::string>& overrides) {
  Input in;
  in.file = file;
  YAML::Node root;
  {
    std::ifstream probe(file);
    if (!probe) throw InputError("input", "cannot open input file '" + file + "'");
  }
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::ParserException& e) {
    throw InputError("input", "not valid YAML: " + e.msg, e.mark.line + 1);
  }
  if (!root.IsMap()) throw InputError("input", "the input must be a map of sections (grid, time, ...)");
  for (const auto& o : overrides) apply_override(root, o);

  Reader top(root, "");
  top.query<std::string>("description", "");

  // grid
  {
    Reader g = top.map("grid");
    in.grid.lower = g.vector3("lower");
    in.grid.upper = g.vector3("upper");
    const auto cells = g.get<std::vector<int>>("cells");
    if (cells.size() != 3) g.fail("cells", "must have 3 entries [nx, ny, nz]");
    for (int d = 0; d < 3; ++d) {
      if (cells[d] < 1) g.fail("cells", "must be >= 1 in every direction");
      if (!(in.grid.upper[d] > in.grid.lower[d])) g.fail("upper", "must exceed grid.lower in every direction");
      in.grid.cells[d] = cells[d];
    }
    if (g.has("periodic")) {
      const auto p = g.get<std::vector<bool>>("periodic");
      if (p.size() != 3) g.fail("periodic", "must have 3 entries");
      for (int d = 0; d < 3; ++d) in.grid.periodic[d] = p[d];
    }
    if (g.has("ranks")) {
      const auto r = g.get<std::vector<int>>("ranks");
      if (r.size() != 3) g.fail("ranks", "must have 3 entries (0: choose)");
      for (int d = 0; d < 3; ++d) {
        if (r[d] < 0) g.fail("ranks", "must be >= 0 in every direction");
        in.grid.ranks[d] = r[d];
      }
    }
    in.sample_points = int(g.number_or("sample_points", 2, 1, 16));
    g.finish();
  }
  // time
  {
    Reader t = top.map("time");
    in.time.end = t.number("end", 0.0, big, true);
    in.time.max_steps = long(t.number_or("max_steps", 1e9, 1, 1e15));
    in.time.cfl = t.number_or("cfl", 0.25, 0.0, 1.0, true);
    in.time.dt_initial = t.number_or("dt_initial", 1e-9, 0.0, big, true);
    in.time.dt_min = t.number_or("dt_min", 1e-20, 0.0, big, true);
    in.time.dt_max = t.number_or("dt_max", 1.0, in.time.dt_min, big, true);
    in.time.max_increase = t.number_or("max_increase", 1.0, 0.0, big, true);
    t.finish();
  }
  // ice options
  if (top.has("ice")) {
    Reader ice = top.map("ice");
    in.ice.second_order = ice.choice("advection", {"first_order", "second_order"}, "second_order") ==
                          "second_order";
    in.ice.gravity = ice.vector3_or("gravity", {0, 0, 0});
    in.ice.kinetic_energy_fix = ice.query<bool>("kinetic_energy_fix", true);
    in.ice.clamp_specific_volume = ice.query<bool>("clamp_specific_volume", false);
    ice.finish();
  }
  // mpm options
  if (top.has("mpm")) {
    Reader mpm = top.map("mpm");
    in.mpm.gimp = mpm.choice("shape", {"gimp", "linear"}, "gimp") == "gimp";
    in.mpm.pic_fraction = mpm.number_or("pic_fraction", 0.0, 0.0, 1.0);
    in.mpm.gravity = mpm.vector3_or("gravity", {0, 0, 0});
    in.mpm.damping = mpm.number_or("damping", 0.0, 0.0, big);
    in.mpm.sort_interval = long(mpm.number_or("sort_interval", 20, 0, 1e9));
    in.mpm.reference_pressure = mpm.number_or("reference_pressure", 101325.0, 0.0, big, true);
    mpm.finish();
  }
  // materials
  {
    YAML::Node list = top.node("materials");
    if (!list || !list.IsSequence() || list.size() == 0)
      top.fail("materials", "must be a non-empty list of materials");
    if (list.size() > std::size_t(max_materials))
      top.fail("materials", "has " + std::to_string(list.size()) + " entries; at most " +
                                std::to_string(max_materials) + " materials are supported");
    for (std::size_t m = 0; m < list.size(); ++m) {
      Reader r(list[m], "materials." + std::to_string(m));
      MaterialInput mat;
      mat.name = r.get<std::string>("name");
      for (const auto& other : in.materials)
        if (other.name == mat.name) r.fail("name", "'" + mat.name + "' is used by two materials");
      const std::string model =
          r.choice("model", {"ideal_gas", "neo_hookean", "neo_hookean_plastic", "rigid"});
      if (model == "ideal_gas") {
        mat.eos.type = EosType::ideal_gas;
        mat.eos.gamma = r.number("gamma", 1.0, 10.0, true);
        mat.eos.cv = r.number("cv", 0.0, big, true);
      } else {
        mat.is_solid = true;
        SolidModel& sm = mat.solid;
        sm.type = model == "rigid" ? SolidModelType::rigid
                  : model == "neo_hookean" ? SolidModelType::neo_hookean
                                           : SolidModelType::neo_hookean_plastic;
        sm.density = r.number("density", 0.0, big, true);
        sm.cv = r.number_or("cv", 1000.0, 0.0, big, true);
        // Every solid has a bulk modulus: its bulk law enters the equilibration (E51).
        sm.bulk_modulus = r.number("bulk_modulus", 0.0, big, true);
        mat.eos.modified = r.query<bool>("modified_eos", false);
        if (sm.type == SolidModelType::rigid) {
          const auto v = r.vector3("prescribed_velocity");
          for (int d = 0; d < 3; ++d) sm.prescribed_velocity[d] = v[d];
          sm.stop_time = r.number_or("stop_time", 1e300, 0.0, big);
          sm.ramp_time = r.number_or("ramp_time", 0.0, 0.0, big);
          if (2 * sm.ramp_time > sm.stop_time)
            r.fail("ramp_time", "is more than half of stop_time (the rise and the fall would overlap)");
        } else {
          sm.shear_modulus = r.number("shear_modulus", 0.0, big);
          if (sm.type == SolidModelType::neo_hookean_plastic) {
            sm.yield_stress = r.number("yield_stress", 0.0, big, true);
            sm.hardening_modulus = r.number_or("hardening_modulus", 0.0, 0.0, big);
            sm.failure_strain = r.number_or("failure_strain", 1e300, 0.0, big, true);
          }
        }
      }
      if (mat.is_solid) {
        mat.eos.type = EosType::solid;
        mat.eos.rho0 = mat.solid.density;
        mat.eos.bulk = mat.solid.bulk_modulus;
        mat.eos.cv = mat.solid.cv;
        mat.eos.p_ref = in.mpm.reference_pressure;
      }
      r.finish();
      in.materials.push_back(mat);
    }
  }
  // exchange
  {
    Reader ex = top.has("exchange") ? top.map("exchange") : Reader(YAML::Node(), "exchange");
    read_exchange_list(ex, "momentum", in, in.exchange.momentum);
    read_exchange_list(ex, "heat", in, in.exchange.heat);
    ex.finish();
  }
  // reactions
  if (top.has("reactions")) {
    YAML::Node list = top.node("reactions");
    if (!list.IsSequence()) top.fail("reactions", "must be a list of {model: simple_burn, reactant, product, ...}");
    for (std::size_t q = 0; q < list.size(); ++q) {
      Reader r(list[q], "reactions." + std::to_string(q));
      r.choice("model", {"simple_burn"});
      SimpleBurn b;
      b.reactant = material_index(in, r, "reactant");
      b.product = material_index(in, r, "product");
      const MaterialInput &reactant = in.materials[b.reactant], &product = in.materials[b.product];
      if (!reactant.is_solid || reactant.solid.type == SolidModelType::rigid)
        r.fail("reactant", "names '" + reactant.name + "', which is not a deformable solid (Simple Burn's reactant is an MPM material)");
      if (product.is_solid) r.fail("product", "names '" + product.name + "', which is not a fluid");
      for (const auto& other : in.reactions)
        if (other.reactant == b.reactant) r.fail("reactant", "'" + reactant.name + "' already reacts in another reaction");
      b.threshold_temperature = r.number_or("threshold_temperature", b.threshold_temperature, 0.0, big);
      b.threshold_pressure = r.number_or("threshold_pressure", b.threshold_pressure, 0.0, big);
      b.enthalpy = r.number_or("enthalpy", b.enthalpy, 0.0, big);
      b.coefficient = r.number_or("coefficient", b.coefficient, 0.0, big);
      b.reference_pressure = r.number_or("reference_pressure", b.reference_pressure, 0.0, big, true);
      b.exponent = r.number_or("exponent", b.exponent, 0.0, 10.0);
      r.finish();
      in.reactions.push_back(b);
    }
  }
  // geometry
  {
    YAML::Node list = top.node("geometry");
    if (!list || !list.IsSequence() || list.size() == 0)
      top.fail("geometry", "must be a non-empty list of pieces (later pieces override earlier ones)");
    for (std::size_t p = 0; p < list.size(); ++p) {
      Reader r(list[p], "geometry." + std::to_string(p));
      GeometryPiece g;
      g.material = material_index(in, r, "material");
      const int shapes = int(r.has("box")) + int(r.has("cylinder")) + int(r.has("sphere"));
      if (shapes != 1) r.fail("", "needs exactly one shape: box, cylinder or sphere");
      if (r.has("box")) {
        Reader s = r.map("box");
        g.shape = Shape::box;
        g.lower = s.vector3("lower");
        g.upper = s.vector3("upper");
        for (int d = 0; d < 3; ++d)
          if (!(g.upper[d] >= g.lower[d])) s.fail("upper", "must not be below box.lower");
        s.finish();
      } else if (r.has("cylinder")) {
        Reader s = r.map("cylinder");
        g.shape = Shape::cylinder;
        g.bottom = s.vector3("bottom");
        g.top = s.vector3("top");
        g.radius = s.number("radius", 0.0, big, true);
        double len = 0;
        for (int d = 0; d < 3; ++d) len += (g.top[d] - g.bottom[d]) * (g.top[d] - g.bottom[d]);
        if (len == 0) s.fail("top", "must differ from cylinder.bottom");
        s.finish();
      } else {
        Reader s = r.map("sphere");
        g.shape = Shape::sphere;
        g.center = s.vector3("center");
        g.radius = s.number("radius", 0.0, big, true);
        s.finish();
      }
      const MaterialInput& mat = in.materials[g.material];
      if (mat.is_solid) {
        if (r.has("density")) r.fail("density", "is the material's (materials." + mat.name + ".density) for a solid");
        if (r.has("pressure")) r.fail("pressure", "cannot be given for a solid; give its temperature");
        g.density = mat.solid.density;
        g.temperature = r.number_or("temperature", 300.0, 0.0, big, true);
        if (r.has("particles_per_cell")) {
          const auto ppc = r.get<std::vector<int>>("particles_per_cell");
          if (ppc.size() != 3) r.fail("particles_per_cell", "must have 3 entries");
          for (int d = 0; d < 3; ++d) {
            if (ppc[d] < 1 || ppc[d] > 8) r.fail("particles_per_cell", "must be 1 to 8 in every direction");
            g.particles_per_cell[d] = ppc[d];
          }
        }
        if (r.has("velocity_sine")) {
          Reader vs = r.map("velocity_sine");
          g.sine_amplitude = vs.vector3("amplitude");
          g.sine_wavenumber = vs.vector3("wavenumber");
          vs.finish();
        }
      } else {
        if (r.has("particles_per_cell")) r.fail("particles_per_cell", "is for solids; '" + mat.name + "' is a fluid");
        if (r.has("velocity_sine")) r.fail("velocity_sine", "is for solids; '" + mat.name + "' is a fluid");
        g.density = r.number("density", 0.0, big, true);
        const bool has_t = r.has("temperature"), has_p = r.has("pressure");
        if (has_t == has_p) r.fail("", "needs exactly one of temperature and pressure");
        const Eos& eos = mat.eos;
        if (has_t)
          g.temperature = r.number("temperature", 0.0, big, true);
        else
          g.temperature = r.number("pressure", 0.0, big, true) / ((eos.gamma - 1.0) * g.density * eos.cv);
      }
      g.velocity = r.vector3_or("velocity", {0, 0, 0});
      r.finish();
      in.geometry.push_back(g);
    }
    for (std::size_t m = 0; m < in.materials.size(); ++m) {
      bool found = false;
      for (const auto& g : in.geometry) found |= g.material == int(m);
      if (!found)
        top.fail("geometry", "has no piece of material '" + in.materials[m].name +
                                 "' (every material needs its state somewhere)");
    }
  }
  read_boundary(top, in);
  // probes
  if (top.has("probes")) {
    YAML::Node list = top.node("probes");
    if (!list.IsSequence()) top.fail("probes", "must be a list");
    for (std::size_t p = 0; p < list.size(); ++p) {
      Reader r(list[p], "probes." + std::to_string(p));
      ProbeInput probe;
      probe.name = r.get<std::string>("name");
      probe.position = r.vector3("position");
      for (int d = 0; d < 3; ++d)
        if (probe.position[d] < in.grid.lower[d] || probe.position[d] > in.grid.upper[d])
          r.fail("position", "lies outside the grid");
      probe.quantities = r.names("quantities", probe_quantities());
      if (probe.quantities.empty()) r.fail("quantities", "must name at least one quantity");
      r.finish();
      in.probes.push_back(probe);
    }
  }
  if (top.has("output")) {
    Reader o = top.map("output");
    in.output.history_interval = long(o.number_or("history_interval", 1, 1, 1e15));
    in.output.probe_interval = long(o.number_or("probe_interval", 1, 1, 1e15));
    in.output.final_fields = o.query<bool>("final_fields", false);
    in.output.field_interval = long(o.number_or("field_interval", 0, 0, 1e15));
    if (o.has("fields")) in.output.fields = o.names("fields", field_output_names());
    o.finish();
  }
  if (in.output.fields.empty()) in.output.fields = field_output_names();
  if (top.has("checkpoint")) {
    Reader c = top.map("checkpoint");
    in.checkpoint.interval = long(c.number_or("interval", 0, 0, 1e15));
    in.checkpoint.wall_interval = c.number_or("wall_interval", 0.0, 0.0, 1e15);
    in.checkpoint.keep = int(c.number_or("keep", 2, 1, 1e6));
    c.finish();
  }
  top.finish();
  return in;
}

}  // namespace mpmice
