#pragma once
/// \file grid_state.hpp
/// \brief Allocation of cell, node and face fields with the extents a patch needs.
#include <string>
#include <mpmice/kernels/grid.hpp>

namespace mpmice {

/// A per-material field at `loc`, zero-initialised, indexed (m, i, j, k).
inline Field4 make_field(const std::string& label, const Patch& patch, Location loc,
                         int materials) {
  return Field4(label, materials, patch.extent(loc, 0), patch.extent(loc, 1),
                patch.extent(loc, 2));
}

/// A material-independent field at `loc`, zero-initialised, indexed (i, j, k).
inline Field3 make_field(const std::string& label, const Patch& patch, Location loc) {
  return Field3(label, patch.extent(loc, 0), patch.extent(loc, 1), patch.extent(loc, 2));
}

/// Face-normal quantities in the three directions (uvel_FC, vvel_FC, wvel_FC).
struct FaceFields {
  Field4 x, y, z;
  const Field4& operator[](int d) const { return d == 0 ? x : (d == 1 ? y : z); }
};

inline FaceFields make_face_fields(const std::string& label, const Patch& patch,
                                   int materials) {
  return {make_field(label + "_x", patch, Location::x_face, materials),
          make_field(label + "_y", patch, Location::y_face, materials),
          make_field(label + "_z", patch, Location::z_face, materials)};
}

}  // namespace mpmice
