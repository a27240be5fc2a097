#pragma once
/// \file types.hpp
/// \brief View aliases and index boxes shared by every kernel. Layouts are decided
///        here once; kernels never spell a layout.
#include <Kokkos_Core.hpp>

/// Defined where the default execution space is a GPU's: the loop helpers (loops.hpp)
/// and the scatter (node_scatter.hpp) then take their device forms.
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
#define MPMICE_DEVICE_BACKEND 1
#endif

namespace mpmice {

using ExecSpace = Kokkos::DefaultExecutionSpace;

/// Most materials (ICE + MPM) one run may have: per-cell solves keep their
/// N x N systems in registers.
constexpr int max_materials = 8;
using MemSpace = ExecSpace::memory_space;

/// Per-material cell, node or face quantity, indexed (material, i, j, k).
using Field4 = Kokkos::View<double****, MemSpace>;
/// Material-independent cell, node or face quantity, indexed (i, j, k).
using Field3 = Kokkos::View<double***, MemSpace>;
/// One particle component (structure of arrays), indexed by particle.
using ParticleComponent = Kokkos::View<double*, Kokkos::LayoutLeft, MemSpace>;

/// Where a grid quantity lives. A field's location decides its extents and which
/// of its entries the halo exchanges.
enum class Location { cell, node, x_face, y_face, z_face };

/// True if `loc` has a point on the boundary plane normal to direction `d`
/// (nodes in every direction, x-faces in x, ...): such quantities have one more
/// entry than cells in that direction.
KOKKOS_INLINE_FUNCTION constexpr bool on_cell_boundary(Location loc, int d) {
  return loc == Location::node || (loc == Location::x_face && d == 0) ||
         (loc == Location::y_face && d == 1) || (loc == Location::z_face && d == 2);
}

/// Three components of a vector cell/face quantity, one view each.
using VectorField4 = Kokkos::Array<Field4, 3>;
using ConstField4 = Field4::const_type;
using ConstField3 = Field3::const_type;
using ConstVectorField4 = Kokkos::Array<ConstField4, 3>;

/// The integer type of a particle's first node. GCC sizes a particle loop's vectors by
/// the narrowest type in it, so an int takes 16 particles per 512-bit iteration, every
/// double in two registers (spilling: g2p 1.1-1.5x slower, docs/design.md). A long
/// avoids that, but a vector of doubles converts to 64-bit integers only with
/// AVX-512DQ: on AVX2 a long keeps the loop scalar, and the int is the one that vectorises.
#if defined(__AVX512DQ__)
using NodeOffset = long;
#else
using NodeOffset = int;
#endif

/// A half-open box of local indices [lo, hi) in three directions.
struct IndexBox {
  int lo[3] = {0, 0, 0};
  int hi[3] = {0, 0, 0};

  KOKKOS_INLINE_FUNCTION int extent(int d) const { return hi[d] > lo[d] ? hi[d] - lo[d] : 0; }
  KOKKOS_INLINE_FUNCTION long size() const {
    return long(extent(0)) * extent(1) * extent(2);
  }
  KOKKOS_INLINE_FUNCTION bool contains(int i, int j, int k) const {
    return i >= lo[0] && i < hi[0] && j >= lo[1] && j < hi[1] && k >= lo[2] && k < hi[2];
  }
  /// MDRange policy over the box, (i, j, k) with k fastest.
  Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<3>> policy() const {
    return Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<3>>({lo[0], lo[1], lo[2]},
                                                              {hi[0], hi[1], hi[2]});
  }
};

/// The faces of `cells` with normal d: one more than the cells along d.
inline IndexBox faces_of(const IndexBox& cells, int d) {
  IndexBox faces = cells;
  faces.hi[d] += 1;
  return faces;
}

}  // namespace mpmice
