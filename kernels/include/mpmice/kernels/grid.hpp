#pragma once
/// \file grid.hpp
/// \brief The global grid and one patch of it, with the index conventions of
///        mpmice-algorithm.md section 1.2.
///
/// Conventions (all directions alike; a direction with one cell makes 2D/1D problems):
///  - Cell (i,j,k) has its low corner at node (i,j,k); its 8 nodes are i..i+1 etc.
///  - x-face (i,j,k) lies between cells i-1 and i (same for y, z faces).
///  - A patch owns the global cells [lo, hi) and stores G ghost layers on each side.
///    Local index = global index - (lo - G), so owned cells are local [G, G+n).
///  - Node-like directions (nodes; faces along their normal) have n+2G+1 entries.
///    A node shared by two patches belongs to the upper one; the patch on a
///    non-periodic high domain boundary also owns the last node.
#include <array>
#include <cmath>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

/// The global, uniform Cartesian grid. Units: m.
struct Grid {
  std::array<double, 3> lower{0, 0, 0};    ///< low corner of the domain
  std::array<double, 3> spacing{1, 1, 1};  ///< cell size h_d
  std::array<int, 3> cells{1, 1, 1};       ///< cell count per direction

  double upper(int d) const { return lower[d] + spacing[d] * cells[d]; }
  double cell_volume() const { return spacing[0] * spacing[1] * spacing[2]; }
  double face_area(int d) const { return cell_volume() / spacing[d]; }
  /// The spacing as the kernels take it.
  Kokkos::Array<double, 3> spacing_array() const { return {spacing[0], spacing[1], spacing[2]}; }
  long cell_count() const { return long(cells[0]) * cells[1] * cells[2]; }
};

/// One rank's box of the grid: owned cells [lo, hi) in global indices, G ghost
/// layers. Everything a kernel needs to place a local index in space.
struct Patch {
  Grid grid;
  std::array<int, 3> lo{0, 0, 0};  ///< first owned cell, global index
  std::array<int, 3> hi{1, 1, 1};  ///< one past the last owned cell, global index
  int ghosts = 2;                  ///< G, ghost layers stored on each side
  /// True where the patch's high side is a non-periodic domain boundary: the last
  /// node-like layer there is owned by this patch.
  std::array<bool, 3> owns_high_boundary{true, true, true};
  /// Periodic directions of the domain.
  std::array<bool, 3> periodic{false, false, false};

  int owned_cells(int d) const { return hi[d] - lo[d]; }
  /// Local extent of a field at `loc` in direction d (ghosts included).
  int extent(Location loc, int d) const {
    return owned_cells(d) + 2 * ghosts + (on_cell_boundary(loc, d) ? 1 : 0);
  }
  /// Global index of local index `l` in direction d.
  int global_index(int l, int d) const { return l + lo[d] - ghosts; }
  int local_index(int g, int d) const { return g - lo[d] + ghosts; }

  /// Owned entries of a field at `loc`, local indices.
  IndexBox owned(Location loc) const {
    IndexBox b;
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = ghosts;
      b.hi[d] = ghosts + owned_cells(d) +
                (on_cell_boundary(loc, d) && owns_high_boundary[d] ? 1 : 0);
    }
    return b;
  }
  /// Owned entries plus `g` ghost layers on every side (for node-like directions the
  /// shared high layer counts as part of the patch, so g layers lie beyond it).
  IndexBox ghosted(Location loc, int g) const {
    IndexBox b;
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = ghosts - g;
      b.hi[d] = ghosts + owned_cells(d) + g + (on_cell_boundary(loc, d) ? 1 : 0);
    }
    return b;
  }
  IndexBox owned_cells() const { return owned(Location::cell); }
  IndexBox ghosted_cells(int g) const { return ghosted(Location::cell, g); }
  IndexBox owned_nodes() const { return owned(Location::node); }
  IndexBox ghosted_nodes(int g) const { return ghosted(Location::node, g); }

  /// True if side `side` (0 low, 1 high) of direction d is a non-periodic domain
  /// boundary: its ghost layers are extra cells filled by boundary conditions.
  bool on_domain_boundary(int d, int side) const {
    return side == 0 ? (lo[d] == 0 && !periodic[d]) : (hi[d] == grid.cells[d] && !periodic[d]);
  }
  /// Owned entries plus `g` extra layers across non-periodic domain boundaries (the
  /// ghost layers there, which the boundary conditions fill): what this patch
  /// computes itself, Uintah's extra-cell iterator.
  IndexBox with_extra(Location loc, int g) const {
    IndexBox b = owned(loc);
    for (int d = 0; d < 3; ++d) {
      if (on_domain_boundary(d, 0)) b.lo[d] -= g;
      if (on_domain_boundary(d, 1)) b.hi[d] += g;
    }
    return b;
  }
  /// Owned cells and all G extra-cell layers: where cell-local steps compute.
  IndexBox cells_with_extra() const { return with_extra(Location::cell, ghosts); }

  /// Position of the centre of local cell (i,j,k) in direction d.
  double cell_center(int l, int d) const {
    return grid.lower[d] + (global_index(l, d) + 0.5) * grid.spacing[d];
  }
  /// Position of local node l in direction d.
  double node_position(int l, int d) const {
    return grid.lower[d] + global_index(l, d) * grid.spacing[d];
  }
  /// Low corner of the owned region, m.
  double owned_lower(int d) const { return grid.lower[d] + lo[d] * grid.spacing[d]; }
  /// High corner of the owned region, m.
  double owned_upper(int d) const { return grid.lower[d] + hi[d] * grid.spacing[d]; }
};

/// A patch covering the whole grid (single rank, no decomposition).
inline Patch whole_grid_patch(const Grid& grid, int ghosts) {
  Patch p;
  p.grid = grid;
  p.lo = {0, 0, 0};
  p.hi = grid.cells;
  p.ghosts = ghosts;
  p.owns_high_boundary = {true, true, true};
  return p;
}

/// Offset (0 or 1) along direction d of corner n = 4a + 2b + c of the 2 x 2 x 2 nodes
/// of a cell, or cells around a node: a (x) outermost, c (z) innermost.
KOKKOS_FORCEINLINE_FUNCTION constexpr long corner(int n, int d) { return (n >> (2 - d)) & 1; }

}  // namespace mpmice
