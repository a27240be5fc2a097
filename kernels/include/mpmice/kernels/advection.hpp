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
#include <string>
#include <type_traits>

#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

using GradientField = Kokkos::Array<Field3, 3>;

/// Outflux distances of material m's cell (i,j,k) (E39): d[2*dir] through the low
/// face, d[2*dir+1] through the high face, m.
KOKKOS_FORCEINLINE_FUNCTION void outflux_distances(const ConstVectorField4& U, int m, long i, long j,
                                                   long k, double dt, double* d) {
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

namespace detail {
// max_outflux_fraction() for N materials, written out so that the rows vectorise.
template <int N>
double max_outflux_fraction_n(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                              const ConstVectorField4& U) {
  return reduce_over_index<Reduction::max>(
      "mpmice::max_outflux_fraction", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double w = 0;
        unrolled_for<N>([&](int m) {
          double d[6];
          outflux_distances(U, m, i, j, k, dt, d);
          const double frac = (d[0] + d[1]) / h[0] + (d[2] + d[3]) / h[1] + (d[4] + d[5]) / h[2];
          w = frac > w ? frac : w;
        });
        return w;
      });
}
}  // namespace detail

/// Largest sum of outflux volumes over cell volume, over the cells and materials: a
/// value above 1 makes the step invalid (E39).
inline double max_outflux_fraction(const IndexBox& cells, const Kokkos::Array<double, 3> h,
                                   double dt, int materials, const ConstVectorField4& U) {
  double worst = 0;
  with_material_count(materials,
                      [&](auto n) { worst = detail::max_outflux_fraction_n<decltype(n)::value>(cells, h, dt, U); });
  return worst;
}

namespace detail {

// The limited gradient of q (material m) at cell (i, j, k), whose value is qc (E41):
// central differences, limited so that no vertex value leaves the range of the cell
// and its six neighbours. With Compatible (E43) the vertex values are
// q_c + (G . dv) m_c / m_vertex, from the cell's mass mc and the mass's limited
// gradient gm. Shared by limited_gradient, which stores it, and the outflux pass of
// limited_advection_change, which uses it where it is made.
template <bool Compatible>
KOKKOS_FORCEINLINE_FUNCTION void limited_gradient_at(const ConstField4& q, int m, long i, long j, long k,
                                                     const double* h, double qc, double mc, const double* gm,
                                                     double* grad) {
  const double nb[6] = {q(m, i - 1, j, k), q(m, i + 1, j, k), q(m, i, j - 1, k),
                        q(m, i, j + 1, k), q(m, i, j, k - 1), q(m, i, j, k + 1)};
  double g[3], qmax = qc, qmin = qc;
  unrolled_for<3>([&](int d) { g[d] = (nb[2 * d + 1] - nb[2 * d]) / (2.0 * h[d]); });
  unrolled_for<6>([&](int f) {
    qmax = nb[f] > qmax ? nb[f] : qmax;
    qmin = nb[f] < qmin ? nb[f] : qmin;
  });
  double vmax = qc, vmin = qc;
  unrolled_for<8>([&](int v) {
    double dq = 0, dm = 0;
    unrolled_for<3>([&](int d) {
      const double half = ((v >> d) & 1 ? 0.5 : -0.5) * h[d];
      dq += g[d] * half;
      if (Compatible) dm += gm[d] * half;
    });
    if (Compatible) dq *= mc / (mc + dm);
    const double qv = qc + dq;
    vmax = qv > vmax ? qv : vmax;
    vmin = qv < vmin ? qv : vmin;
  });
  constexpr double eps = 1.0e-100;
  double phi = 1.0;
  const double up = (qmax - qc + eps) / (vmax - qc + eps);
  const double down = (qmin - qc - eps) / (vmin - qc - eps);
  phi = up < phi ? up : phi;
  phi = down < phi ? down : phi;
  phi = phi > 0.0 ? phi : 0.0;
  unrolled_for<3>([&](int d) { grad[d] = phi * g[d]; });
}

// limited_gradient() with the compatible choice a template argument.
template <bool Compatible>
void limited_gradient(const IndexBox& cells, const Kokkos::Array<double, 3> h, const ConstField4& q, int m,
                      const ConstField4& mass, const GradientField& mass_grad, const GradientField& grad) {
  for_each_index<Rows::longest>(
      "mpmice::limited_gradient", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        const double hd[3] = {h[0], h[1], h[2]};
        double mc = 0, gm[3] = {0, 0, 0}, g[3];
        if (Compatible) {
          mc = mass(m, i, j, k);
          unrolled_for<3>([&](int d) { gm[d] = mass_grad[d](i, j, k); });
        }
        limited_gradient_at<Compatible>(q, m, i, j, k, hd, q(m, i, j, k), mc, gm, g);
        unrolled_for<3>([&](int d) { grad[d](i, j, k) = g[d]; });
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
// gradient. The choices are template arguments, so that each kernel carries only its
// own arithmetic. With InlineGradient (second order) q's limited gradient is made from
// q's neighbours when the cell is loaded (limited_gradient_at), not read from `grad`.
template <bool SecondOrder, bool Compatible, bool InlineGradient = false>
struct SlabValue {
  static constexpr bool second_order = SecondOrder;  // uses the six outflux distances d
  ConstField4 q, mass;
  GradientField grad, mass_grad;
  int m;
  double h[3];

  // What a cell's slabs are made of: q, the mass, and their gradients, as used.
  struct Cell {
    double qc, mc, gq[3], gm[3];
  };
  KOKKOS_FORCEINLINE_FUNCTION Cell load(long i, long j, long k) const {
    Cell c{q(m, i, j, k), Compatible ? mass(m, i, j, k) : 1.0, {0, 0, 0}, {0, 0, 0}};
    if (SecondOrder)
      unrolled_for<3>([&](int d) {
        if (!InlineGradient) c.gq[d] = grad[d](i, j, k);
        if (Compatible) c.gm[d] = mass_grad[d](i, j, k);
      });
    if (SecondOrder && InlineGradient) limited_gradient_at<Compatible>(q, m, i, j, k, h, c.qc, c.mc, c.gm, c.gq);
    return c;
  }
  // The value of slab f of a cell whose values are `c`.
  KOKKOS_FORCEINLINE_FUNCTION double value(const Cell& c, int f, const double* d) const {
    if (!SecondOrder) return Compatible ? c.mc * c.qc : c.qc;
    // Centroid of slab f relative to the cell centre.
    const int dir = f / 2;
    double r[3];
    unrolled_for<3>([&](int e) { r[e] = 0.5 * (d[2 * e] - d[2 * e + 1]); });
    r[dir] = (f & 1) ? 0.5 * (h[dir] - d[f]) : 0.5 * (d[f] - h[dir]);
    double gq = 0;
    unrolled_for<3>([&](int e) { gq += c.gq[e] * r[e]; });
    if (!Compatible) return c.qc + gq;
    double gm = 0;
    unrolled_for<3>([&](int e) { gm += c.gm[e] * r[e]; });
    return (c.mc + gm) * c.qc + c.mc * gq;
  }
  KOKKOS_FORCEINLINE_FUNCTION double operator()(long i, long j, long k, int f, const double* d) const {
    return value(load(i, j, k), f, d);
  }
};

// Calls f(slab) with the SlabValue of q that `second_order` and `mass` (compatible when
// given) choose, its gradient made inline with InlineGradient (second order).
template <bool InlineGradient = false, class F>
void with_slab(bool second_order, const ConstField4& q, const ConstField4& mass, const GradientField& grad,
               const GradientField& mass_grad, int m, const Kokkos::Array<double, 3> h, F&& f) {
  auto call = [&](auto second, auto compatible) {
    using Slab = SlabValue<decltype(second)::value, decltype(compatible)::value, InlineGradient>;
    f(Slab{q, mass, grad, mass_grad, m, {h[0], h[1], h[2]}});
  };
  using yes = std::integral_constant<bool, true>;
  using no = std::integral_constant<bool, false>;
  const bool compatible = mass.data() != nullptr;
  if (second_order) {
    if (compatible) call(yes{}, yes{}); else call(yes{}, no{});
  } else {
    if (compatible) call(no{}, yes{}); else call(no{}, no{});
  }
}

// What crosses the faces of `cells` to second order (E42, E43), written to flux[d] on
// the d-faces, positive along +d, by the face's donor: the cell the face velocity
// points out of sends its slab value times its outflux volume d A (the cell below
// through its high face, the cell above through its low face, negated); where the
// velocity does not point out of either, the cell above writes 0. Each face is thus
// written by one of its two cells only, whichever thread runs the other, and gets
// what the difference of the two cells' outfluxes would be, bit for bit (x - 0 = x,
// 0 - y = -y). One pass computes each cell's outflux distances once and writes 3
// arrays: 9 array passes per cell fewer than the six cell outfluxes written, and read
// back, until session 44 (docs/performance.md); the writes are masked vector stores.
// Any face of a cell in `cells` may be written, so `flux` must be face arrays over a
// box that holds them all (the patch's, for its cells and one layer around them).
template <class Slab>
void donor_face_fluxes(const IndexBox& cells, double dt, const Kokkos::Array<double, 3> area,
                       const ConstVectorField4& U, int m, const Slab& slab, const Kokkos::Array<Field3, 3>& flux) {
  // flux[2] again, for the high z-faces: the store at k + 1 after one at k into the same
  // view is a dependence of distance 1 that GCC 12 does not let `omp simd` waive (the
  // loop stayed scalar); through a second view it cannot tell that the array is the
  // same. No two lanes store to one face: their conditions exclude each other.
  const Field3 z_high = flux[2];
  for_each_index<Rows::longest>(
      "mpmice::donor_face_fluxes", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double d[6], o[6];
        outflux_distances(U, m, i, j, k, dt, d);
        // The cell's values are loaded once and the fluxes stored after all are
        // computed: a store between them made GCC load them again (it may alias them).
        const auto cell = slab.load(i, j, k);
        unrolled_for<6>([&](int f) {
          // Computed, then selected: a conditional call would be a branch, and the loop
          // would not vectorise.
          const double out_f = slab.value(cell, f, d) * d[f] * area[f / 2];
          o[f] = d[f] > 0 ? out_f : 0.0;
        });
        // Whether this cell writes its low and its high face of each direction.
        const bool low[3] = {!(U[0](m, i, j, k) > 0), !(U[1](m, i, j, k) > 0), !(U[2](m, i, j, k) > 0)};
        const bool high[3] = {U[0](m, i + 1, j, k) > 0, U[1](m, i, j + 1, k) > 0, U[2](m, i, j, k + 1) > 0};
        // The faces' addresses are taken before the conditions: inside them, the views'
        // data pointers were loaded under the mask too, which GCC 12 cannot vectorise.
        double* const at_low[3] = {&flux[0](i, j, k), &flux[1](i, j, k), &flux[2](i, j, k)};
        double* const at_high[3] = {&flux[0](i + 1, j, k), &flux[1](i, j + 1, k), &z_high(i, j, k + 1)};
        unrolled_for<3>([&](int e) {
          if (low[e]) *at_low[e] = 0.0 - o[2 * e];
          if (high[e]) *at_high[e] = o[2 * e + 1];
        });
      });
}

// Three ways to the flux through the low Dir-face of cell (i, j, k), positive along
// +Dir, each as `at<Dir>(i, j, k)`: change_from_fluxes and fill_face_fluxes take any.

// First order (E40): the donor's value q (u dt) A, the donor chosen by the sign of u
// without a branch (face velocities of either sign would mispredict one branch per
// face, and the loops vectorise). q (u dt) A is q (|u| dt) A with the flux's sign,
// rounding being symmetric.
template <class Slab>
struct FirstOrderFlux {
  ConstVectorField4 U;
  int m;
  Slab slab;
  double dt;
  Kokkos::Array<double, 3> area;

  template <int Dir>
  KOKKOS_FORCEINLINE_FUNCTION double at(long i, long j, long k) const {
    constexpr long di = Dir == 0, dj = Dir == 1, dk = Dir == 2;
    constexpr int low = 2 * Dir, high = 2 * Dir + 1;  // the donor's face: below the face, its high one
    const double u = U[Dir](m, i, j, k);
    const double q_below = slab(i - di, j - dj, k - dk, high, nullptr), q_above = slab(i, j, k, low, nullptr);
    return (u > 0 ? q_below : q_above) * (u * dt) * area[Dir];
  }
};

// Fluxes stored on face arrays (face_fluxes, donor_face_fluxes).
struct StoredFlux {
  Kokkos::Array<Field3, 3> flux;

  template <int Dir>
  KOKKOS_FORCEINLINE_FUNCTION double at(long i, long j, long k) const {
    return flux[Dir](i, j, k);
  }
};

// change(m, ...) on `cells`: what enters a cell through its six faces minus what leaves,
// over its volume (E40), the faces in the order x-low, x-high, y-low, ... With
// FirstOrderFlux each cell computes its faces' fluxes itself (every face twice): 40 B
// per cell against 88 for face_fluxes then flux_difference, 1.8-1.9x faster at 64^3 and
// 128^3, and equal to them to round-off only: the compiler may fuse a flux's last
// product into the sum (an FMA, GCC's default -ffp-contract=fast), so a face's two uses
// differ at round-off. With StoredFlux the values are bit for bit those of the stored
// fluxes.
template <class Flux>
void change_from_fluxes(const std::string& label, const IndexBox& cells, double inv_volume, const Flux& flux, int m,
                        const Field4& change) {
  for_each_index<Rows::longest>(
      label, cells, KOKKOS_LAMBDA(long i, long j, long k) {
        double sum = 0;
        sum += flux.template at<0>(i, j, k);
        sum += -flux.template at<0>(i + 1, j, k);
        sum += flux.template at<1>(i, j, k);
        sum += -flux.template at<1>(i, j + 1, k);
        sum += flux.template at<2>(i, j, k);
        sum += -flux.template at<2>(i, j, k + 1);
        change(m, i, j, k) = sum * inv_volume;
      });
}

// out(i, j, k) = flux.at<Dir>(i, j, k) on the Dir-faces in `faces`.
template <int Dir, class Flux>
void fill_face_fluxes(const IndexBox& faces, const Flux& flux, const Field3& out) {
  for_each_index(
      "mpmice::face_fluxes", faces,
      KOKKOS_LAMBDA(long i, long j, long k) { out(i, j, k) = flux.template at<Dir>(i, j, k); });
}

// out[d] on the d-faces of `cells`, for d = x, y, z.
template <class Flux>
void fill_face_fluxes(const IndexBox& cells, const Flux& flux, const Kokkos::Array<Field3, 3>& out) {
  fill_face_fluxes<0>(faces_of(cells, 0), flux, out[0]);
  fill_face_fluxes<1>(faces_of(cells, 1), flux, out[1]);
  fill_face_fluxes<2>(faces_of(cells, 2), flux, out[2]);
}

}  // namespace detail

/// What crosses the faces of the cells over the step, one Field3 per direction d on
/// d-face arrays: flux[d](i, j, k) through the low d-face of cell (i, j, k), positive
/// along +d (m^3 for q a volume fraction, kg m/s for momentum, ...).
using FaceFluxes = Kokkos::Array<Field3, 3>;

inline FaceFluxes make_face_fluxes(const std::string& label, const Patch& patch) {
  return {make_field(label + "_x", patch, Location::x_face), make_field(label + "_y", patch, Location::y_face),
          make_field(label + "_z", patch, Location::z_face)};
}

/// Adv[Q] = (what comes in - what goes out) / V from the fluxes through a cell's six
/// faces, written to `change(m, ...)` on `cells`.
inline void flux_difference(const IndexBox& cells, double inv_volume, const FaceFluxes& flux, int m,
                            const Field4& change) {
  detail::change_from_fluxes("mpmice::flux_difference", cells, inv_volume, detail::StoredFlux{flux}, m, change);
}

namespace detail {

inline Kokkos::Array<double, 3> face_areas(const Kokkos::Array<double, 3> h) {
  return {h[1] * h[2], h[0] * h[2], h[0] * h[1]};
}

// `cells` and the layer of cells around them: the donors of the cells' faces (whose
// slabs need their limited gradients).
inline IndexBox with_layer_around(IndexBox cells) {
  for (int d = 0; d < 3; ++d) {
    cells.lo[d] -= 1;
    cells.hi[d] += 1;
  }
  return cells;
}

// The second-order fluxes through the faces of `cells` (donor_face_fluxes over the
// cells and the layer around them: a face's donor may be either of its cells), into
// `flux`, allocated here as face arrays over q's cells if empty. The layer's edge and
// corner cells are computed too (one box, one pass) and write faces never read. With
// InlineGradient, q's limited gradient is made in the same pass (`grad` is not read).
template <bool InlineGradient = false>
FaceFluxes second_order_face_fluxes(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                                    const ConstVectorField4& U, int m, const ConstField4& q, const ConstField4& mass,
                                    const GradientField& grad, const GradientField& mass_grad, FaceFluxes flux) {
  if (flux[0].data() == nullptr)
    for (int d = 0; d < 3; ++d)
      flux[d] = Field3("advection_face_flux", q.extent(1) + (d == 0), q.extent(2) + (d == 1), q.extent(3) + (d == 2));
  with_slab<InlineGradient>(true, q, mass, grad, mass_grad, m, h, [&](const auto& slab) {
    if constexpr (std::decay_t<decltype(slab)>::second_order)
      donor_face_fluxes(with_layer_around(cells), dt, face_areas(h), U, m, slab, flux);
  });
  return flux;
}

// Adv[Q] to second order on `cells`, written to change(m, ...): the fluxes through the
// cells' faces (second_order_face_fluxes, into `scratch`), then each cell's change
// from its six.
template <bool InlineGradient = false>
void second_order_change(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                         const ConstVectorField4& U, int m, const ConstField4& q, const ConstField4& mass,
                         const GradientField& grad, const GradientField& mass_grad, const Field4& change,
                         const FaceFluxes& scratch) {
  const FaceFluxes flux = second_order_face_fluxes<InlineGradient>(cells, h, dt, U, m, q, mass, grad, mass_grad,
                                                                   scratch);
  flux_difference(cells, 1.0 / (h[0] * h[1] * h[2]), flux, m, change);
}

// Calls f(FirstOrderFlux<...>) for q: compatible when `mass` is given.
template <class F>
void with_first_order_flux(const Kokkos::Array<double, 3> h, double dt, const ConstVectorField4& U, int m,
                           const ConstField4& q, const ConstField4& mass, F&& f) {
  with_slab(false, q, mass, GradientField(), GradientField(), m, h, [&](const auto& slab) {
    using Slab = std::decay_t<decltype(slab)>;
    if constexpr (!Slab::second_order) f(FirstOrderFlux<Slab>{U, m, slab, dt, face_areas(h)});
  });
}

}  // namespace detail

/// The amount of Q (material m) through every face of `cells` (E40, E42, E43), each
/// face once: the donor cell's slab, positive along +d. Non-compatible: q holds cell
/// totals (mass, volume fraction). Compatible (`mass` given): q holds the specific value
/// and Q = mass q. `grad`, `mass_grad` are limited gradients (ignored for first order);
/// face velocities U must be valid on the faces of the cells and of their neighbours.
/// Second order writes each face from its donor cell (donor_face_fluxes), which may be
/// in the layer of cells around `cells`: those cells' other faces are written too.
inline void face_fluxes(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                        const ConstVectorField4& U, int m, const ConstField4& q, const ConstField4& mass,
                        bool second_order, const GradientField& grad, const GradientField& mass_grad,
                        const FaceFluxes& flux) {
  if (second_order) {
    detail::second_order_face_fluxes(cells, h, dt, U, m, q, mass, grad, mass_grad, flux);
  } else {
    detail::with_first_order_flux(h, dt, U, m, q, mass,
                                  [&](const auto& first_order) { detail::fill_face_fluxes(cells, first_order, flux); });
  }
}

/// Adv[Q] on `cells`, written to `change(m, ...)` (E40, E42, E43), the same values as
/// flux_difference of face_fluxes. First order: one pass (equal to round-off). Second
/// order: face_fluxes into `scratch` (make_face_fluxes; allocated here if empty), then
/// flux_difference (bit for bit).
inline void advection_change(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                             const ConstVectorField4& U, int m, const ConstField4& q,
                             const ConstField4& mass, bool second_order,
                             const GradientField& grad, const GradientField& mass_grad,
                             const Field4& change, const FaceFluxes& scratch = FaceFluxes()) {
  if (second_order) {
    detail::second_order_change(cells, h, dt, U, m, q, mass, grad, mass_grad, change, scratch);
  } else {
    const double inv_volume = 1.0 / (h[0] * h[1] * h[2]);
    detail::with_first_order_flux(h, dt, U, m, q, mass, [&](const auto& first_order) {
      detail::change_from_fluxes("mpmice::first_order_change", cells, inv_volume, first_order, m, change);
    });
  }
}

/// Boxes of at least this many cells take limited_advection_change's one flux pass
/// with the gradient limited in it; smaller boxes two passes, the gradient
/// stored and read back. One pass saves writing and reading 3 arrays, which pays once
/// they come from memory (1.02-1.21x at 64^3 and 128^3 cells); in cache its longer
/// loop body runs slower (0.84-1.01x at 16^3 and 32^3; docs/performance.md, session 43).
constexpr long advection_inline_gradient_cells = 1L << 17;

/// Adv[Q] to second order on `cells` (E41-E43) with q's limited gradient, written to
/// `change(m, ...)`: the same values as limited_gradient of q on the cells and the
/// layer around them, then advection_change with that gradient (bit for bit in a build
/// without fused multiply-adds, MPMICE_REPRODUCIBLE). Boxes of `inline_from` cells or
/// more take one flux pass that limits each donor cell's gradient itself
/// (limited_gradient_at) instead of storing it in `grad` (allocated here if empty and
/// needed). q must be valid two cells beyond `cells`; compatible when `mass` is given,
/// with `mass_grad` the mass's limited gradient on the cells and the layer around
/// them; `scratch` as advection_change.
inline void limited_advection_change(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                                     const ConstVectorField4& U, int m, const ConstField4& q,
                                     const ConstField4& mass, const GradientField& mass_grad, const Field4& change,
                                     const FaceFluxes& scratch = FaceFluxes(), GradientField grad = GradientField(),
                                     long inline_from = advection_inline_gradient_cells) {
  if (cells.size() < inline_from) {
    if (grad[0].data() == nullptr)
      for (int d = 0; d < 3; ++d) grad[d] = Field3("advection_gradient", q.extent(1), q.extent(2), q.extent(3));
    limited_gradient(detail::with_layer_around(cells), h, q, m, mass, mass_grad, grad);
    advection_change(cells, h, dt, U, m, q, mass, true, grad, mass_grad, change, scratch);
    return;
  }
  detail::second_order_change<true>(cells, h, dt, U, m, q, mass, GradientField(), mass_grad, change, scratch);
}

/// to[d] += from[d] on the faces of `cells` (the fluids' volume fluxes summed over them).
inline void add_face_fluxes(const IndexBox& cells, const FaceFluxes& from, const FaceFluxes& to) {
  for (int d = 0; d < 3; ++d) {
    const Field3 src = from[d], dst = to[d];
    for_each_index(
        "mpmice::add_face_fluxes", faces_of(cells, d),
        KOKKOS_LAMBDA(long i, long j, long k) { dst(i, j, k) += src(i, j, k); });
  }
}

}  // namespace mpmice
