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

using UnmanagedField4 = Kokkos::View<double****, MemSpace, Kokkos::MemoryUnmanaged>;

/// One field whose extra cells `fill_extra_cells` fills: materials [m_begin, m_end) of
/// q, the conditions on its six faces, and the vector component q holds (-1 for a
/// scalar).
struct ExtraCellFill {
  UnmanagedField4 q;
  int m_begin = 0, m_end = 0;
  FaceBcs bcs;
  int component = -1;
  ExtraCellFill() = default;
  ExtraCellFill(const UnmanagedField4& field, int first, int end, const FaceBcs& conditions, int comp)
      : q(field), m_begin(first), m_end(end), bcs(conditions), component(comp) {}
  /// Material m of a per-material field.
  ExtraCellFill(const Field4& field, int m, const FaceBcs& conditions, int comp)
      : ExtraCellFill(field, m, m + 1, conditions, comp) {}
  /// Every material of a per-material field.
  ExtraCellFill(const Field4& field, const FaceBcs& conditions, int comp)
      : ExtraCellFill(field, 0, int(field.extent(0)), conditions, comp) {}
  /// A material-independent field.
  ExtraCellFill(const Field3& field, const FaceBcs& conditions, int comp)
      : ExtraCellFill(UnmanagedField4(field.data(), 1, field.extent(0), field.extent(1), field.extent(2)), 0, 1,
                   conditions, comp) {}
};

namespace detail {
/// What one face's launch of `fill_extra_cells` needs of a field.
struct FaceFill {
  UnmanagedField4 q;
  int m_begin, m_end;
  BcKind kind;
  double value;        ///< the Dirichlet value, or the Neumann gradient
  double mirror_sign;  ///< -1 for the normal component at a symmetry face
};
}  // namespace detail

/// Fill every extra-cell layer of the `fields` on the domain faces this patch touches.
/// Directions are swept x, y, z, each over the extra cells already filled, so edges
/// and corners get values too. One launch per face for all the fields and materials:
/// the fields are independent, and a launch costs more than a face's few cells in a
/// small or quasi-1D problem (the piston's 1 x 100 x 1 cells have 25 extra cells for
/// each inside one).
template <std::size_t N>
void fill_extra_cells(const Kokkos::Array<ExtraCellFill, N>& fields, const Patch& patch) {
  const int G = patch.ghosts;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!patch.on_domain_boundary(d, side)) continue;
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
      Kokkos::Array<detail::FaceFill, N> face;
      for (std::size_t f = 0; f < N; ++f) {
        const ExtraCellFill& e = fields[f];
        const Bc bc = e.bcs[2 * d + side];
        face[f] = {e.q, e.m_begin, e.m_end, bc.kind, bc.value[e.component < 0 ? 0 : e.component],
                   (bc.kind == BcKind::symmetry && e.component == d) ? -1.0 : 1.0};
      }
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
        unrolled_for<int(N)>([&](int f) {
          const detail::FaceFill& ff = face[f];
          for (int m = ff.m_begin; m < ff.m_end; ++m) {
            double out;
            if (ff.kind == BcKind::dirichlet)
              out = ff.value;
            else if (ff.kind == BcKind::symmetry)
              out = ff.mirror_sign * ff.q(m, mirror[0], mirror[1], mirror[2]);
            else
              out = ff.q(m, adjacent[0], adjacent[1], adjacent[2]) + ff.value * h * l;
            ff.q(m, i, j, k) = out;
          }
        });
      });
    }
}

/// Fill the extra cells of one field (`ExtraCellFill` says which materials, conditions
/// and component).
inline void fill_extra_cells(const ExtraCellFill& field, const Patch& patch) {
  fill_extra_cells(Kokkos::Array<ExtraCellFill, 1>{field}, patch);
}

/// Fill the extra cells of material m of a per-material field.
inline void fill_extra_cells(const Field4& q, int m, const Patch& patch, const FaceBcs& bcs, int component) {
  fill_extra_cells(ExtraCellFill(q, m, bcs, component), patch);
}

/// Fill the extra cells of every material of a per-material field.
inline void fill_extra_cells(const Field4& q, const Patch& patch, const FaceBcs& bcs, int component) {
  fill_extra_cells(ExtraCellFill(q, bcs, component), patch);
}

/// Fill the extra cells of a material-independent field.
inline void fill_extra_cells(const Field3& q, const Patch& patch, const FaceBcs& bcs, int component) {
  fill_extra_cells(ExtraCellFill(q, bcs, component), patch);
}

/// Normal velocity on the domain-boundary faces of direction d (E19's face BCs), for
/// every material of `face_vel` in one launch per face: Dirichlet faces get the normal
/// component of the boundary velocity, symmetry faces 0, Neumann faces keep the
/// computed value. `faces` bounds the tangential extent.
inline void set_boundary_face_velocity(const Field4& face_vel, int d, const Patch& patch,
                                       const FaceBcs& velocity_bcs, const IndexBox& faces) {
  const int G = patch.ghosts, materials = int(face_vel.extent(0));
  for (int side = 0; side < 2; ++side) {
    if (!patch.on_domain_boundary(d, side)) continue;
    const Bc bc = velocity_bcs[2 * d + side];
    if (bc.kind == BcKind::neumann) continue;
    const double value = bc.kind == BcKind::dirichlet ? bc.value[d] : 0.0;
    IndexBox box = faces;
    box.lo[d] = side == 0 ? G : G + patch.owned_cells(d);
    box.hi[d] = box.lo[d] + 1;
    for_each_index("mpmice::boundary_face_velocity", box, KOKKOS_LAMBDA(long i, long j, long k) {
      for (int m = 0; m < materials; ++m) face_vel(m, i, j, k) = value;
    });
  }
}

}  // namespace mpmice
