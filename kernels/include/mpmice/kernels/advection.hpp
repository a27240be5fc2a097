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
#include <type_traits>

#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

using GradientField = Kokkos::Array<Field3, 3>;

/// Outflux distances of material m's cell (i,j,k) (E39): d[2*dir] through the low
/// face, d[2*dir+1] through the high face, m.
KOKKOS_FORCEINLINE_FUNCTION void outflux_distances(const ConstVectorField4& U, int m, int i, int j,
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

namespace detail {

// limited_gradient() with the compatible choice a template argument.
template <bool Compatible>
void limited_gradient(const IndexBox& cells, const Kokkos::Array<double, 3> h, const ConstField4& q, int m,
                      const ConstField4& mass, const GradientField& mass_grad, const GradientField& grad) {
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
        if (Compatible) {
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
          if (Compatible) dq *= mc / (mc + dm);
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

}  // namespace detail

/// The limited gradient of q (material m) on `cells` (E41); q must be valid one cell
/// beyond. With `mass` (compatible fluxes, E43) the limiter sees the vertex values
/// q_c + (G . dv) m_c / m_vertex, m_vertex from the mass and its limited gradient.
inline void limited_gradient(const IndexBox& cells, const Kokkos::Array<double, 3> h,
                             const ConstField4& q, int m, const ConstField4& mass,
                             const GradientField& mass_grad, const GradientField& grad) {
  if (mass.data() != nullptr)
    detail::limited_gradient<true>(cells, h, q, m, mass, mass_grad, grad);
  else
    detail::limited_gradient<false>(cells, h, q, m, mass, mass_grad, grad);
}

namespace detail {

// The value carried by slab f of cell c (E42/E43); first order when there is no
// gradient. The two choices are template arguments, so that each of the four kernels
// carries only its own arithmetic.
template <bool SecondOrder, bool Compatible>
struct SlabValue {
  static constexpr bool second_order = SecondOrder;  // uses the six outflux distances d
  ConstField4 q, mass;
  GradientField grad, mass_grad;
  int m;
  double h[3];

  KOKKOS_FORCEINLINE_FUNCTION double operator()(int i, int j, int k, int f, const double* d) const {
    const double qc = q(m, i, j, k);
    if (!SecondOrder) return Compatible ? mass(m, i, j, k) * qc : qc;
    const double mc = Compatible ? mass(m, i, j, k) : 1.0;
    // Centroid of slab f relative to the cell centre.
    const int dir = f / 2;
    double r[3];
    for (int c = 0; c < 3; ++c) r[c] = 0.5 * (d[2 * c] - d[2 * c + 1]);
    r[dir] = (f & 1) ? 0.5 * (h[dir] - d[f]) : 0.5 * (d[f] - h[dir]);
    double gq = 0;
    for (int c = 0; c < 3; ++c) gq += grad[c](i, j, k) * r[c];
    if (!Compatible) return qc + gq;
    double gm = 0;
    for (int c = 0; c < 3; ++c) gm += mass_grad[c](i, j, k) * r[c];
    return (mc + gm) * qc + mc * gq;
  }
};

// Calls f(std::integral_constant<bool, second_order>{}, std::integral_constant<bool, compatible>{}).
template <class F>
void with_slab_kind(bool second_order, bool compatible, F&& f) {
  using yes = std::integral_constant<bool, true>;
  using no = std::integral_constant<bool, false>;
  if (second_order) {
    if (compatible) f(yes{}, yes{}); else f(yes{}, no{});
  } else {
    if (compatible) f(no{}, yes{}); else f(no{}, no{});
  }
}

// First order: what one face of cell (i, j, k) (normal Dir, the high face if `high`)
// adds to the cell, the donor's value times |u| dt A with the donor chosen by the
// sign of u without a branch (face velocities of either sign would mispredict one
// branch per face); written per direction so that every index is known.
template <int Dir, class Slab>
KOKKOS_FORCEINLINE_FUNCTION double first_order_face_term(const ConstVectorField4& U, int m, const Slab& slab, int i,
                                                    int j, int k, double dt, double area, bool high) {
  constexpr int di = Dir == 0, dj = Dir == 1, dk = Dir == 2;
  const int step = high ? 1 : -1;
  const int ni = i + step * di, nj = j + step * dj, nk = k + step * dk;
  const double u = high ? U[Dir](m, ni, nj, nk) : U[Dir](m, i, j, k);
  const double outward = high ? u : -u;
  const double q_donor = outward > 0 ? slab(i, j, k, 0, nullptr) : slab(ni, nj, nk, 0, nullptr);
  const double moved = q_donor * (math::abs(u) * dt) * area;
  return outward > 0 ? -moved : (outward < 0 ? moved : 0.0);
}

// Second order: what one face adds to cell (i, j, k) whose outflux distances are d:
// its own slab out (E42/E43, centroid from d), or the neighbour's slab in, whichever
// way u points.
template <int Dir, class Slab>
KOKKOS_FORCEINLINE_FUNCTION double second_order_face_term(const ConstVectorField4& U, int m, const Slab& slab, int i,
                                                     int j, int k, const double* d, double dt, double area,
                                                     bool high) {
  constexpr int di = Dir == 0, dj = Dir == 1, dk = Dir == 2;
  const int f = 2 * Dir + (high ? 1 : 0);
  if (d[f] > 0) return -(slab(i, j, k, f, d) * d[f] * area);
  const int step = high ? 1 : -1;
  const int ni = i + step * di, nj = j + step * dj, nk = k + step * dk;
  const double u = high ? U[Dir](m, ni, nj, nk) : U[Dir](m, i, j, k);
  const double inflow = high ? (u < 0 ? -u * dt : 0.0) : (u > 0 ? u * dt : 0.0);
  if (!(inflow > 0)) return 0.0;
  // The neighbour across the face and its slab through the same face.
  double dn[6];
  outflux_distances(U, m, ni, nj, nk, dt, dn);
  return slab(ni, nj, nk, f ^ 1, dn) * dn[f ^ 1] * area;
}

template <class Slab>
void advection_change(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                      const ConstVectorField4& U, int m, const Slab& slab, const Field4& change) {
  const double inv_volume = 1.0 / (h[0] * h[1] * h[2]);
  const double ax = h[1] * h[2], ay = h[0] * h[2], az = h[0] * h[1];
  if constexpr (!Slab::second_order) {
    Kokkos::parallel_for(
        "mpmice::advection_change", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
          // Faces in the order x-low, x-high, y-low, ... as in the general case.
          double sum = 0;
          sum += first_order_face_term<0>(U, m, slab, i, j, k, dt, ax, false);
          sum += first_order_face_term<0>(U, m, slab, i, j, k, dt, ax, true);
          sum += first_order_face_term<1>(U, m, slab, i, j, k, dt, ay, false);
          sum += first_order_face_term<1>(U, m, slab, i, j, k, dt, ay, true);
          sum += first_order_face_term<2>(U, m, slab, i, j, k, dt, az, false);
          sum += first_order_face_term<2>(U, m, slab, i, j, k, dt, az, true);
          change(m, i, j, k) = sum * inv_volume;
        });
    return;
  }
  Kokkos::parallel_for(
      "mpmice::advection_change", cells.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        double d[6];
        outflux_distances(U, m, i, j, k, dt, d);
        double sum = 0;
        sum += second_order_face_term<0>(U, m, slab, i, j, k, d, dt, ax, false);
        sum += second_order_face_term<0>(U, m, slab, i, j, k, d, dt, ax, true);
        sum += second_order_face_term<1>(U, m, slab, i, j, k, d, dt, ay, false);
        sum += second_order_face_term<1>(U, m, slab, i, j, k, d, dt, ay, true);
        sum += second_order_face_term<2>(U, m, slab, i, j, k, d, dt, az, false);
        sum += second_order_face_term<2>(U, m, slab, i, j, k, d, dt, az, true);
        change(m, i, j, k) = sum * inv_volume;
      });
}

template <class Slab>
void add_face_flux(const IndexBox& faces, int dir, const Kokkos::Array<double, 3> h, double dt,
                   const ConstVectorField4& U, int m, const Slab& slab, const Field3& flux) {
  const double area = dir == 0 ? h[1] * h[2] : dir == 1 ? h[0] * h[2] : h[0] * h[1];
  const int di = dir == 0, dj = dir == 1, dk = dir == 2;
  Kokkos::parallel_for(
      "mpmice::add_face_flux", faces.policy(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double u = U[dir](m, i, j, k);
        double d[6];
        if (u > 0) {  // donor: the cell below the face, through its high face
          if (Slab::second_order)
            outflux_distances(U, m, i - di, j - dj, k - dk, dt, d);
          else
            d[2 * dir + 1] = u * dt;
          flux(i, j, k) += slab(i - di, j - dj, k - dk, 2 * dir + 1, d) * d[2 * dir + 1] * area;
        } else if (u < 0) {  // donor: the cell above, through its low face
          if (Slab::second_order)
            outflux_distances(U, m, i, j, k, dt, d);
          else
            d[2 * dir] = -u * dt;
          flux(i, j, k) -= slab(i, j, k, 2 * dir, d) * d[2 * dir] * area;
        }
      });
}

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
  detail::with_slab_kind(second_order, mass.data() != nullptr, [&](auto second, auto compatible) {
    const detail::SlabValue<decltype(second)::value, decltype(compatible)::value> slab{
        q, mass, grad, mass_grad, m, {h[0], h[1], h[2]}};
    detail::advection_change(cells, h, dt, U, m, slab, change);
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
  detail::with_slab_kind(second_order, false, [&](auto second, auto) {
    const detail::SlabValue<decltype(second)::value, false> slab{
        q, ConstField4(), grad, GradientField(), m, {h[0], h[1], h[2]}};
    detail::add_face_flux(faces, dir, h, dt, U, m, slab, flux);
  });
}

}  // namespace mpmice
