#pragma once
/// \file advection.hpp
/// \brief The ICE advection operator Adv[Q] (mpmice-algorithm.md section 6): the net
///        change of a cell total Q over one step from the slabs of volume that cross
///        the cell's faces. First order (donor cell, E40) or second order with a
///        limited gradient (E41-E42) and compatible fluxes for mass-specific
///        quantities (E43).
///
/// Uintah's second-order advector is the reference for the slab centroids and the
/// compatible slab value m_slab q_c + m_c (G . r).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

using GradientField = Kokkos::Array<Field3, 3>;

/// Outflux distances of material m's cell (i,j,k) (E39): d[2*dir] through the low
/// face, d[2*dir+1] through the high face, m.
KOKKOS_INLINE_FUNCTION void outflux_distances(const ConstVectorField4& U, int m, int i, int j,
                                              int k, double dt, double* d) {
  const double ux_lo = U[0](m, i, j, k), ux_hi = U[0](m, i + 1, j, k);
  const double uy_lo = U[1](m, i, j, k), uy_hi = U[1](m, i, j + 1, k);
  const double uz_lo = U[2](m, i, j, k), uz_hi = U[2](m, i, j, k + 1);
  d[0] = ux_lo < 0 ? -ux_lo * dt : 0.0;
  d[1] = ux_hi > 0 ? ux_hi * dt : 0.0;
  d[2] = uy_lo < 0 ? -uy_lo * dt : 0.0;
  d[3] = uy_hi > 0 ? uy_hi * dt : 0.0;
  d[4] = uz_lo < 0 ? -uz_lo * dt : 0.0;
  d[5] = uz_hi > 0 ? uz_hi * dt : 0.0;
}

/// Largest sum of outflux volumes over cell volume, over the cells and materials: a
/// value above 1 makes the step invalid (E39).
inline double max_outflux_fraction(const IndexBox& cells, const Kokkos::Array<double, 3> h,
                                   double dt, int materials, const ConstVectorField4& U) {
  double worst = 0;
  Kokkos::parallel_reduce(
      "mpmice::max_outflux_fraction", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, double& w) {
        for (int m = 0; m < materials; ++m) {
          double d[6];
          outflux_distances(U, m, i, j, k, dt, d);
          const double frac = (d[0] + d[1]) / h[0] + (d[2] + d[3]) / h[1] + (d[4] + d[5]) / h[2];
          if (frac > w) w = frac;
        }
      },
      Kokkos::Max<double>(worst));
  return worst;
}

/// The limited gradient of q (material m) on `cells` (E41); q must be valid one cell
/// beyond. With `mass` (compatible fluxes, E43) the limiter sees the vertex values
/// q_c + (G . dv) m_c / m_vertex, m_vertex from the mass and its limited gradient.
inline void limited_gradient(const IndexBox& cells, const Kokkos::Array<double, 3> h,
                             const ConstField4& q, int m, const ConstField4& mass,
                             const GradientField& mass_grad, const GradientField& grad) {
  const bool compatible = mass.data() != nullptr;
  Kokkos::parallel_for(
      "mpmice::limited_gradient", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double qc = q(m, i, j, k);
        const double nb[6] = {q(m, i - 1, j, k), q(m, i + 1, j, k), q(m, i, j - 1, k),
                              q(m, i, j + 1, k), q(m, i, j, k - 1), q(m, i, j, k + 1)};
        double g[3], qmax = qc, qmin = qc;
        for (int d = 0; d < 3; ++d) g[d] = (nb[2 * d + 1] - nb[2 * d]) / (2.0 * h[d]);
        for (int f = 0; f < 6; ++f) {
          qmax = nb[f] > qmax ? nb[f] : qmax;
          qmin = nb[f] < qmin ? nb[f] : qmin;
        }
        double mc = 0, gm[3] = {0, 0, 0};
        if (compatible) {
          mc = mass(m, i, j, k);
          for (int d = 0; d < 3; ++d) gm[d] = mass_grad[d](i, j, k);
        }
        double vmax = qc, vmin = qc;
        for (int v = 0; v < 8; ++v) {
          double dq = 0, dm = 0;
          for (int d = 0; d < 3; ++d) {
            const double half = ((v >> d) & 1 ? 0.5 : -0.5) * h[d];
            dq += g[d] * half;
            dm += gm[d] * half;
          }
          if (compatible) dq *= mc / (mc + dm);
          const double qv = qc + dq;
          vmax = qv > vmax ? qv : vmax;
          vmin = qv < vmin ? qv : vmin;
        }
        constexpr double eps = 1.0e-100;
        double phi = 1.0;
        const double up = (qmax - qc + eps) / (vmax - qc + eps);
        const double down = (qmin - qc - eps) / (vmin - qc - eps);
        phi = up < phi ? up : phi;
        phi = down < phi ? down : phi;
        phi = phi > 0.0 ? phi : 0.0;
        for (int d = 0; d < 3; ++d) grad[d](i, j, k) = phi * g[d];
      });
}

namespace detail {

// The value carried by slab f of cell c (E42/E43); first order when there is no
// gradient.
struct SlabValue {
  ConstField4 q, mass;
  GradientField grad, mass_grad;
  bool second_order, compatible;
  int m;
  double h[3];

  KOKKOS_INLINE_FUNCTION double operator()(int i, int j, int k, int f, const double* d) const {
    const double qc = q(m, i, j, k);
    const double mc = compatible ? mass(m, i, j, k) : 1.0;
    if (!second_order) return mc * qc;
    // Centroid of slab f relative to the cell centre.
    const int dir = f / 2;
    double r[3];
    for (int c = 0; c < 3; ++c) r[c] = 0.5 * (d[2 * c] - d[2 * c + 1]);
    r[dir] = (f & 1) ? 0.5 * (h[dir] - d[f]) : 0.5 * (d[f] - h[dir]);
    double gq = 0;
    for (int c = 0; c < 3; ++c) gq += grad[c](i, j, k) * r[c];
    if (!compatible) return qc + gq;
    double gm = 0;
    for (int c = 0; c < 3; ++c) gm += mass_grad[c](i, j, k) * r[c];
    return (mc + gm) * qc + mc * gq;
  }
};

}  // namespace detail

/// Adv[Q] on `cells`, written to `change(m, ...)` (E40, E42, E43). Non-compatible: q
/// holds cell totals (mass, volume fraction). Compatible (`mass` given): q holds the
/// specific value and Q = mass q. `grad`, `mass_grad` are limited gradients (ignored
/// for first order); face velocities U must be valid on the faces of the cells and
/// of their neighbours.
inline void advection_change(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                             const ConstVectorField4& U, int m, const ConstField4& q,
                             const ConstField4& mass, bool second_order,
                             const GradientField& grad, const GradientField& mass_grad,
                             const Field4& change) {
  detail::SlabValue slab{q,  mass, grad, mass_grad, second_order, mass.data() != nullptr,
                         m,  {h[0], h[1], h[2]}};
  const double area[3] = {h[1] * h[2], h[0] * h[2], h[0] * h[1]};
  const double inv_volume = 1.0 / (h[0] * h[1] * h[2]);
  const double ax = area[0], ay = area[1], az = area[2];
  Kokkos::parallel_for(
      "mpmice::advection_change", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double a[3] = {ax, ay, az};
        double d[6];
        outflux_distances(U, m, i, j, k, dt, d);
        double sum = 0;
        for (int f = 0; f < 6; ++f) {
          const int dir = f / 2, side = f & 1;
          if (d[f] > 0) sum -= slab(i, j, k, f, d) * d[f] * a[dir];
          // The neighbour across face f and its slab through the same face.
          const int ni = i + (dir == 0 ? (side ? 1 : -1) : 0);
          const int nj = j + (dir == 1 ? (side ? 1 : -1) : 0);
          const int nk = k + (dir == 2 ? (side ? 1 : -1) : 0);
          const int nf = 2 * dir + (1 - side);
          const double u_face = U[dir](m, side ? (dir == 0 ? i + 1 : i) : i,
                                       side ? (dir == 1 ? j + 1 : j) : j,
                                       side ? (dir == 2 ? k + 1 : k) : k);
          const double inflow = side ? (u_face < 0 ? -u_face * dt : 0.0) : (u_face > 0 ? u_face * dt : 0.0);
          if (inflow > 0) {
            double dn[6];
            outflux_distances(U, m, ni, nj, nk, dt, dn);
            sum += slab(ni, nj, nk, nf, dn) * dn[nf] * a[dir];
          }
        }
        change(m, i, j, k) = sum * inv_volume;
      });
}

/// Adds to `flux(i, j, k)` the volume of the non-compatible quantity q (material m)
/// that crosses face (i, j, k) with normal `dir` over the step, positive along +dir
/// (m^3 for q a volume fraction): the donor cell's slab (E40, E42), the same value
/// `advection_change` moves, so minus the sum over a cell's faces of these fluxes is
/// V Adv[q] of that cell to round-off.
inline void add_face_flux(const IndexBox& faces, int dir, const Kokkos::Array<double, 3> h, double dt,
                          const ConstVectorField4& U, int m, const ConstField4& q, bool second_order,
                          const GradientField& grad, const Field3& flux) {
  detail::SlabValue slab{q, ConstField4(), grad, GradientField(), second_order, false, m, {h[0], h[1], h[2]}};
  const double area = dir == 0 ? h[1] * h[2] : dir == 1 ? h[0] * h[2] : h[0] * h[1];
  const int di = dir == 0, dj = dir == 1, dk = dir == 2;
  Kokkos::parallel_for(
      "mpmice::add_face_flux", faces.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double u = U[dir](m, i, j, k);
        double d[6];
        if (u > 0) {  // donor: the cell below the face, through its high face
          outflux_distances(U, m, i - di, j - dj, k - dk, dt, d);
          flux(i, j, k) += slab(i - di, j - dj, k - dk, 2 * dir + 1, d) * d[2 * dir + 1] * area;
        } else if (u < 0) {  // donor: the cell above, through its low face
          outflux_distances(U, m, i, j, k, dt, d);
          flux(i, j, k) -= slab(i, j, k, 2 * dir, d) * d[2 * dir] * area;
        }
      });
}

}  // namespace mpmice
