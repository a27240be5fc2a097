#pragma once
/// \file boundary_conditions.hpp
/// \brief Boundary conditions on the faces of the domain (mpmice-algorithm.md 10):
///        fill the extra cells (the ghost layers beyond a non-periodic domain
///        boundary) of a cell field, and set normal velocities on boundary faces.
///        Periodic directions are not boundaries: the halo fills their ghosts.
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>

namespace mpmice {

enum class BcKind : int {
  neumann = 0,    ///< outward normal derivative `value` (0: zero gradient)
  dirichlet = 1,  ///< extra cells hold `value`
  symmetry = 2    ///< mirror image; the normal component of a vector changes sign
};

/// One variable's condition on one face of the domain.
struct Bc {
  BcKind kind = BcKind::neumann;
  double value[3] = {0.0, 0.0, 0.0};  ///< scalar in [0]; vector components in [0..2]
};

/// The six faces in the order x-, x+, y-, y+, z-, z+ (face = 2 d + side).
using FaceBcs = Kokkos::Array<Bc, 6>;

/// Fill every extra-cell layer of materials [m_begin, m_end) of `q` on the domain
/// faces this patch touches. `component` is -1 for a scalar, else the vector component
/// q holds (0, 1, 2). Directions are swept x, y, z, each over the extra cells already
/// filled, so edges and corners get values too. One launch per face for all the
/// materials.
inline void fill_extra_cells(const Kokkos::View<double****, MemSpace, Kokkos::MemoryUnmanaged>& q,
                             int m_begin, int m_end, const Patch& patch, const FaceBcs& bcs,
                             int component) {
  const int G = patch.ghosts;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!patch.on_domain_boundary(d, side)) continue;
      const Bc bc = bcs[2 * d + side];
      const int n = patch.owned_cells(d);
      IndexBox box = patch.owned_cells();
      for (int e = 0; e < d; ++e) {  // directions already swept carry their extra cells
        const IndexBox with_extra = patch.cells_with_extra();
        box.lo[e] = with_extra.lo[e];
        box.hi[e] = with_extra.hi[e];
      }
      box.lo[d] = side == 0 ? 0 : G + n;
      box.hi[d] = side == 0 ? G : 2 * G + n;
      const double h = patch.grid.spacing[d];
      const double value = bc.value[component < 0 ? 0 : component];
      const double mirror_sign = (bc.kind == BcKind::symmetry && component == d) ? -1.0 : 1.0;
      // Rows (i, j) of the slab, k innermost (for_each_index): no index division per
      // cell, which the flat loop over the slab spent most of its time on.
      for_each_index("mpmice::fill_extra_cells", box, KOKKOS_LAMBDA(long i, long j, long k) {
        const long idx[3] = {i, j, k};
        const long at = idx[d];
        // Layer l = 1, 2, ... away from the boundary; its mirror is interior layer l.
        const long l = side == 0 ? G - at : at - (G + n) + 1;
        long adjacent[3] = {i, j, k}, mirror[3] = {i, j, k};
        adjacent[d] = side == 0 ? G : G + n - 1;
        long mm = side == 0 ? G - 1 + l : G + n - l;
        if (mm < G) mm = G;
        if (mm > G + n - 1) mm = G + n - 1;
        mirror[d] = mm;
        for (int m = m_begin; m < m_end; ++m) {
          double out;
          if (bc.kind == BcKind::dirichlet)
            out = value;
          else if (bc.kind == BcKind::symmetry)
            out = mirror_sign * q(m, mirror[0], mirror[1], mirror[2]);
          else
            out = q(m, adjacent[0], adjacent[1], adjacent[2]) + value * h * l;
          q(m, i, j, k) = out;
        }
      });
    }
}

/// Fill the extra cells of material m of a per-material field.
inline void fill_extra_cells(const Field4& q, int m, const Patch& patch, const FaceBcs& bcs, int component) {
  fill_extra_cells(q, m, m + 1, patch, bcs, component);
}

/// Fill the extra cells of every material of a per-material field.
inline void fill_extra_cells(const Field4& q, const Patch& patch, const FaceBcs& bcs, int component) {
  fill_extra_cells(q, 0, int(q.extent(0)), patch, bcs, component);
}

/// Fill the extra cells of a material-independent field.
inline void fill_extra_cells(const Field3& q, const Patch& patch, const FaceBcs& bcs, int component) {
  const Kokkos::View<double****, MemSpace, Kokkos::MemoryUnmanaged> q4(q.data(), 1, q.extent(0), q.extent(1),
                                                                         q.extent(2));
  fill_extra_cells(q4, 0, 1, patch, bcs, component);
}

/// Normal velocity on the domain-boundary faces of direction d (E19's face BCs):
/// Dirichlet faces get the normal component of the boundary velocity, symmetry faces
/// 0, Neumann faces keep the computed value. `faces` bounds the tangential extent.
inline void set_boundary_face_velocity(const Field4& face_vel, int m, int d, const Patch& patch,
                                       const FaceBcs& velocity_bcs, const IndexBox& faces) {
  const int G = patch.ghosts;
  for (int side = 0; side < 2; ++side) {
    if (!patch.on_domain_boundary(d, side)) continue;
    const Bc bc = velocity_bcs[2 * d + side];
    if (bc.kind == BcKind::neumann) continue;
    const double value = bc.kind == BcKind::dirichlet ? bc.value[d] : 0.0;
    IndexBox box = faces;
    box.lo[d] = side == 0 ? G : G + patch.owned_cells(d);
    box.hi[d] = box.lo[d] + 1;
    Kokkos::parallel_for(
        "mpmice::boundary_face_velocity", box.policy(),
        KOKKOS_LAMBDA(int i, int j, int k) { face_vel(m, i, j, k) = value; });
  }
}

}  // namespace mpmice
