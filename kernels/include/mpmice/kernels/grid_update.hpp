#pragma once
/// \file grid_update.hpp
/// \brief Step 14: node acceleration and the updated node velocity (E26), and the
///        node velocity boundary conditions of Step 20 (symmetry, fixed, prescribed).
#include <mpmice/kernels/boundary_conditions.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

namespace detail {
template <bool Rigid>
void grid_acceleration_n(const IndexBox& nodes, int m, double dt, Kokkos::Array<double, 3> gravity,
                         double damping, const ConstField4& mass, const ConstVectorField4& vel,
                         const ConstVectorField4& fint, const ConstVectorField4& fext, const VectorField4& vel_star,
                         const VectorField4& acc) {
  for_each_index("mpmice::grid_acceleration", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const double inv = 1.0 / mass(m, i, j, k);
    for (int d = 0; d < 3; ++d) {
      double a = 0.0;
      if (!Rigid)
        a = (fint[d](m, i, j, k) + fext[d](m, i, j, k)) * inv + gravity[d] - damping * vel[d](m, i, j, k);
      acc[d](m, i, j, k) = a;
      vel_star[d](m, i, j, k) = vel[d](m, i, j, k) + dt * a;
    }
  });
}
}  // namespace detail

/// a = (f_int + f_ext)/m + g - alpha v, v* = v + dt a on `nodes` (E26). A rigid
/// material (`rigid`) keeps v* = v, a = 0. `damping` alpha (1/s, usually 0) is an
/// artificial damping of the solid's motion for problems that seek a static state
/// (as Uintah's artificial damping); it removes momentum and energy on purpose.
inline void grid_acceleration(const IndexBox& nodes, int m, double dt, Kokkos::Array<double, 3> gravity,
                              double damping, bool rigid, const ConstField4& mass, const ConstVectorField4& vel,
                              const ConstVectorField4& fint, const ConstVectorField4& fext,
                              const VectorField4& vel_star, const VectorField4& acc) {
  with_flag(rigid, [&](auto is_rigid) {
    detail::grid_acceleration_n<decltype(is_rigid)::value>(nodes, m, dt, gravity, damping, mass, vel, fint, fext,
                                                           vel_star, acc);
  });
}

/// Zero normal velocity on the node layers at and beyond each symmetry face (the
/// Step 1 node condition on v_i), for node slots [0, slots) in one launch per face.
inline void node_symmetry(const Patch& patch, const IndexBox& nodes, int slots, const FaceBcs& bcs,
                          const VectorField4& vel) {
  const int G = patch.ghosts;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!patch.on_domain_boundary(d, side) || bcs[2 * d + side].kind != BcKind::symmetry) continue;
      IndexBox box = nodes;
      const int n = patch.owned_cells(d);
      box.lo[d] = side == 0 ? 0 : G + n;
      box.hi[d] = side == 0 ? G + 1 : 2 * G + n + 1;
      const Field4 v = vel[d];
      for_each_index("mpmice::node_symmetry", box, KOKKOS_LAMBDA(long i, long j, long k) {
        for (int m = 0; m < slots; ++m) v(m, i, j, k) = 0.0;
      });
    }
}

/// Velocity conditions on the node layers at and beyond each domain face: symmetry
/// zeroes the normal component, Dirichlet sets the value (fixed: 0), Neumann leaves
/// the node free. Where a condition acts the acceleration becomes (v* - v)/dt, with
/// v the node velocity of Step 1 (Step 20). `nodes` bounds the tangential extent. For
/// the node slots m < `slots` with `applies[m]` set (not the rigid bodies), in one
/// launch per face.
inline void node_velocity_bcs(const Patch& patch, const IndexBox& nodes, int slots,
                              const Kokkos::Array<int, max_materials>& applies, double dt, const FaceBcs& bcs,
                              const VectorField4& vel, const VectorField4& vel_star, const VectorField4& acc) {
  const int G = patch.ghosts;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!patch.on_domain_boundary(d, side)) continue;
      const Bc bc = bcs[2 * d + side];
      if (bc.kind == BcKind::neumann) continue;
      IndexBox box = nodes;
      const int n = patch.owned_cells(d);
      box.lo[d] = side == 0 ? 0 : G + n;           // the boundary node layer and beyond
      box.hi[d] = side == 0 ? G + 1 : 2 * G + n + 1;
      for_each_index("mpmice::node_velocity_bcs", box, KOKKOS_LAMBDA(long i, long j, long k) {
        for (int m = 0; m < slots; ++m) {
          if (!applies[m]) continue;
          if (bc.kind == BcKind::symmetry) {
            vel[d](m, i, j, k) = 0.0;
            vel_star[d](m, i, j, k) = 0.0;
            acc[d](m, i, j, k) = 0.0;
          } else {
            for (int c = 0; c < 3; ++c) {
              vel_star[c](m, i, j, k) = bc.value[c];
              acc[c](m, i, j, k) = (bc.value[c] - vel[c](m, i, j, k)) / dt;
            }
          }
        }
      });
    }
}

}  // namespace mpmice
