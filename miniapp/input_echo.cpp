#include "input_echo.hpp"

#include <yaml-cpp/yaml.h>

namespace mpmice {
namespace {

const char* face_names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

template <class A>
YAML::Node seq(const A& a) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const auto& x : a) n.push_back(x);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node bc_node(const Bc& bc, bool vector) {
  YAML::Node n;
  if (bc.kind == BcKind::symmetry) return YAML::Node("symmetry");
  const char* kind = bc.kind == BcKind::dirichlet ? "dirichlet" : "neumann";
  if (vector)
    n[kind] = seq(std::vector<double>{bc.value[0], bc.value[1], bc.value[2]});
  else
    n[kind] = bc.value[0];
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

}  // namespace

std::string resolved_yaml(const Input& in) {
  YAML::Node root;
  YAML::Node grid;
  grid["lower"] = seq(in.grid.lower);
  grid["upper"] = seq(in.grid.upper);
  grid["cells"] = seq(in.grid.cells);
  grid["periodic"] = seq(in.grid.periodic);
  grid["ranks"] = seq(in.grid.ranks);
  grid["sample_points"] = in.sample_points;
  root["grid"] = grid;
  YAML::Node time;
  time["end"] = in.time.end;
  time["max_steps"] = in.time.max_steps;
  time["cfl"] = in.time.cfl;
  time["dt_initial"] = in.time.dt_initial;
  time["dt_min"] = in.time.dt_min;
  time["dt_max"] = in.time.dt_max;
  time["max_increase"] = in.time.max_increase;
  root["time"] = time;
  YAML::Node ice;
  ice["advection"] = in.ice.second_order ? "second_order" : "first_order";
  ice["gravity"] = seq(in.ice.gravity);
  ice["kinetic_energy_fix"] = in.ice.kinetic_energy_fix;
  ice["clamp_specific_volume"] = in.ice.clamp_specific_volume;
  root["ice"] = ice;
  YAML::Node mpm;
  mpm["shape"] = in.mpm.gimp ? "gimp" : "linear";
  mpm["pic_fraction"] = in.mpm.pic_fraction;
  mpm["gravity"] = seq(in.mpm.gravity);
  mpm["damping"] = in.mpm.damping;
  mpm["sort_interval"] = in.mpm.sort_interval;
  mpm["reference_pressure"] = in.mpm.reference_pressure;
  root["mpm"] = mpm;
  const std::size_t n = in.materials.size();
  for (const auto& m : in.materials) {
    YAML::Node mat;
    mat["name"] = m.name;
    if (!m.is_solid) {
      mat["model"] = "ideal_gas";
      mat["gamma"] = m.eos.gamma;
      mat["cv"] = m.eos.cv;
    } else {
      const SolidModel& s = m.solid;
      mat["model"] = s.type == SolidModelType::rigid ? "rigid"
                     : s.type == SolidModelType::neo_hookean ? "neo_hookean"
                                                             : "neo_hookean_plastic";
      mat["density"] = s.density;
      mat["bulk_modulus"] = s.bulk_modulus;
      mat["cv"] = s.cv;
      mat["modified_eos"] = m.eos.modified;
      if (s.type == SolidModelType::rigid) {
        mat["prescribed_velocity"] = seq(std::vector<double>{s.prescribed_velocity[0], s.prescribed_velocity[1],
                                                             s.prescribed_velocity[2]});
        mat["stop_time"] = s.stop_time;
        mat["ramp_time"] = s.ramp_time;
      } else {
        mat["shear_modulus"] = s.shear_modulus;
        if (s.type == SolidModelType::neo_hookean_plastic) {
          mat["yield_stress"] = s.yield_stress;
          mat["hardening_modulus"] = s.hardening_modulus;
          if (s.failure_strain < 1e300) mat["failure_strain"] = s.failure_strain;
        }
      }
    }
    root["materials"].push_back(mat);
  }
  YAML::Node exchange;
  exchange["momentum"] = YAML::Node(YAML::NodeType::Sequence);
  exchange["heat"] = YAML::Node(YAML::NodeType::Sequence);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t s = r + 1; s < n; ++s) {
      for (const char* kind : {"momentum", "heat"}) {
        const auto& k = std::string(kind) == "momentum" ? in.exchange.momentum : in.exchange.heat;
        if (k[r * n + s] == 0) continue;
        YAML::Node e;
        e["materials"] = seq(std::vector<std::string>{in.materials[r].name, in.materials[s].name});
        e["coefficient"] = k[r * n + s];
        e.SetStyle(YAML::EmitterStyle::Flow);
        exchange[kind].push_back(e);
      }
    }
  root["exchange"] = exchange;
  for (const auto& b : in.reactions) {
    YAML::Node r;
    r["model"] = "simple_burn";
    r["reactant"] = in.materials[b.reactant].name;
    r["product"] = in.materials[b.product].name;
    r["threshold_temperature"] = b.threshold_temperature;
    r["threshold_pressure"] = b.threshold_pressure;
    r["enthalpy"] = b.enthalpy;
    r["coefficient"] = b.coefficient;
    r["reference_pressure"] = b.reference_pressure;
    r["exponent"] = b.exponent;
    root["reactions"].push_back(r);
  }
  for (const auto& g : in.geometry) {
    YAML::Node piece;
    piece["material"] = in.materials[g.material].name;
    YAML::Node shape;
    if (g.shape == Shape::box) {
      shape["lower"] = seq(g.lower);
      shape["upper"] = seq(g.upper);
      piece["box"] = shape;
    } else if (g.shape == Shape::cylinder) {
      shape["bottom"] = seq(g.bottom);
      shape["top"] = seq(g.top);
      shape["radius"] = g.radius;
      piece["cylinder"] = shape;
    } else {
      shape["center"] = seq(g.center);
      shape["radius"] = g.radius;
      piece["sphere"] = shape;
    }
    shape.SetStyle(YAML::EmitterStyle::Flow);
    if (!in.materials[g.material].is_solid) piece["density"] = g.density;
    piece["temperature"] = g.temperature;
    piece["velocity"] = seq(g.velocity);
    if (in.materials[g.material].is_solid) piece["particles_per_cell"] = seq(g.particles_per_cell);
    root["geometry"].push_back(piece);
  }
  YAML::Node boundary;
  for (int f = 0; f < 6; ++f) {
    if (in.grid.periodic[f / 2]) continue;
    YAML::Node face;
    face["pressure"] = bc_node(in.boundary.pressure[f], false);
    face["density"] = bc_node(in.boundary.density[f], false);
    face["temperature"] = bc_node(in.boundary.temperature[f], false);
    face["velocity"] = bc_node(in.boundary.velocity[f], true);
    boundary[face_names[f]] = face;
  }
  root["boundary"] = boundary;
  for (const auto& p : in.probes) {
    YAML::Node probe;
    probe["name"] = p.name;
    probe["position"] = seq(p.position);
    probe["quantities"] = seq(p.quantities);
    probe.SetStyle(YAML::EmitterStyle::Flow);
    root["probes"].push_back(probe);
  }
  YAML::Node output;
  output["history_interval"] = in.output.history_interval;
  output["probe_interval"] = in.output.probe_interval;
  output["final_fields"] = in.output.final_fields;
  output["field_interval"] = in.output.field_interval;
  output["fields"] = seq(in.output.fields);
  root["output"] = output;
  YAML::Node checkpoint;
  checkpoint["interval"] = in.checkpoint.interval;
  checkpoint["wall_interval"] = in.checkpoint.wall_interval;
  checkpoint["keep"] = in.checkpoint.keep;
  root["checkpoint"] = checkpoint;
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace mpmice
