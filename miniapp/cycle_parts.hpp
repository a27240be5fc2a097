#pragma once
// What the files of the cycle (cycle*.cpp, one per part of mpmice-algorithm.md section
// 5) share: how a step declares and takes its vector fields, how it stops the run, and
// the choice of shape. The parts are separate translation units so that a build on
// two cores compiles them side by side (docs/design.md, "Build time").
#include <initializer_list>
#include <string>
#include <vector>

#include <mpmice/halo/reduce.hpp>
#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/shape.hpp>

#include "cycle.hpp"

namespace mpmice::cycle_parts {

using Reads = std::vector<FieldRead>;
using Writes = std::vector<FieldWrite>;

// Reads of the three components of a vector field.
inline Reads vec(const std::string& name, int ghosts) {
  Reads r;
  for (const auto& c : components(name)) r.push_back({c, ghosts});
  return r;
}
inline Writes vec_out(const std::string& name, int valid_ghosts = 0) {
  Writes w;
  for (const auto& c : components(name)) w.push_back({c, valid_ghosts});
  return w;
}
// Writes of a vector field a scatter adds into: one ghost layer summed into owners.
inline Writes vec_summed(const std::string& name) {
  Writes w;
  for (const auto& c : components(name)) w.push_back({c, 0, 1});
  return w;
}
template <class T>
std::vector<T> cat(std::initializer_list<std::vector<T>> parts) {
  std::vector<T> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}
inline ConstVectorField4 read_vec(const StepContext& ctx, const std::string& name) {
  const auto c = components(name);
  return {ctx.read<Field4>(c[0]), ctx.read<Field4>(c[1]), ctx.read<Field4>(c[2])};
}
inline VectorField4 write_vec(const StepContext& ctx, const std::string& name) {
  const auto c = components(name);
  return {ctx.write<Field4>(c[0]), ctx.write<Field4>(c[1]), ctx.write<Field4>(c[2])};
}

// Every rank learns whether any rank failed; the failing ranks' messages go with the
// exception (main prints them).
inline void stop_if_any(MPI_Comm comm, bool local_bad, const std::string& message) {
  if (global_max(comm, local_bad ? 1.0 : 0.0) > 0)
    throw InvariantError(local_bad ? message : std::string());
}

inline std::string cell_name(const Patch& p, const int* c) {
  return "(" + std::to_string(p.global_index(c[0], 0)) + ", " + std::to_string(p.global_index(c[1], 1)) +
         ", " + std::to_string(p.global_index(c[2], 2)) + ")";
}

// Call f with the shape function type the input chose.
template <class F>
void with_shape(bool gimp, F&& f) {
  if (gimp)
    f(GimpShape{});
  else
    f(LinearShape{});
}

// Boundary conditions for the MPM cell rates in extra cells: mirrored across symmetry
// planes (normal component negated), zero gradient elsewhere (E33).
inline FaceBcs mirror_or_zero_gradient(const FaceBcs& velocity) {
  FaceBcs out;
  for (int f = 0; f < 6; ++f) out[f].kind = velocity[f].kind == BcKind::symmetry ? BcKind::symmetry : BcKind::neumann;
  return out;
}

// Nodes whose 8 surrounding cells all lie in the patch's arrays (the cell-to-node
// averages of (E11), (E34)), within the owned and extra nodes.
inline IndexBox nodes_inside_cells(const Patch& p) {
  IndexBox b = p.with_extra(Location::node, p.ghosts);
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::max(b.lo[d], 1);
    b.hi[d] = std::min(b.hi[d], p.extent(Location::cell, d));
  }
  return b;
}

}  // namespace mpmice::cycle_parts
