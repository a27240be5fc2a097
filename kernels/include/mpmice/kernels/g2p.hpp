#pragma once
/// \file g2p.hpp
/// \brief Steps 21-22: grid-to-particle update of velocity (FLIP with an optional PIC
///        fraction) and position (E35), and the particle kinematics: velocity
///        gradient, deformation gradient and volume (E36). Weights use the old
///        positions.
#include <stdexcept>

#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>
#include <mpmice/kernels/node_reads.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/shape.hpp>
#include <mpmice/kernels/solid_models.hpp>
#include <mpmice/kernels/trilinear.hpp>

namespace mpmice {

/// The number of sub-steps of (E36): n = min(max(1, 2 floor(|L| dt)), 10000); 1 when
/// |L| dt is not a number. Clamped as a double, so that a huge or infinite |L| dt gets
/// 10000 (converted to int first, it would overflow).
KOKKOS_INLINE_FUNCTION int deformation_substeps(const Mat3& L, double dt) {
  const double nsub = 2.0 * math::floor(L.norm() * dt);
  return !(nsub >= 1.0) ? 1 : (nsub > 10000.0 ? 10000 : int(nsub));
}

/// Whether (E36) takes one sub-step, deformation_substeps(L, dt) == 1, that is |L| dt < 1
/// or not a number, tested without an int: an int in a particle loop makes GCC size its
/// vectors for 16 ints and split every double into two registers (design.md).
KOKKOS_INLINE_FUNCTION bool one_deformation_step(const Mat3& L, double dt) { return !(L.norm() * dt >= 1.0); }

/// The deformation over one step, (I + L dt/n)^n with n sub-steps (E36):
/// F_new = increment F_old.
KOKKOS_INLINE_FUNCTION Mat3 deformation_increment(const Mat3& L, double dt) {
  const int nsub = deformation_substeps(L, dt);
  const Mat3 step = Mat3::identity() + (dt / nsub) * L;
  Mat3 increment = step;
  for (int s = 1; s < nsub; ++s) increment = step * increment;
  return increment;
}

/// What MPMICE's g2p adds to a particle's heat besides the nodes' rate (E35): the
/// transfer's energy from `node_energy` (cell_rates_to_nodes) and the gas pressure's work
/// on the particle's volume; `cv` the material's c_v, J/kg/K. Empty for MPM alone.
struct TransferHeat {
  ConstField4 node_energy;
  double cv = 0;
};

namespace detail {
/// (E35, E36) for particle p of a material that deforms: with GIMP its node values read
/// through `read` (node_reads.hpp, `operator()`), with the linear shape from the
/// interpolants over its cell (trilinear.hpp, `in_cell`); `Heat` (MPMICE): the heat
/// rate temp_rate and the heat of `TransferHeat` given, else neither (MPM alone: g2p
/// takes both or neither). Returns 1 if the particle's deformation needs more than one
/// sub-step (its F and V are then left for `g2p_substeps`), else 0.
template <class Shape, bool Heat>
struct G2pParticle {
  NodeGrid grid;
  ParticleData data;
  NodeStencil<Shape::nodes> nodes;
  Kokkos::Array<long, 3> node_extent;  ///< of the node arrays along i, j, k
  Kokkos::Array<ConstNodeArray, 3> v_node, a_node;
  ConstNodeArray t_node, q_node;
  double dt, pic_fraction, inverse_cv;

  /// g2p's arguments for material slot m (see there).
  G2pParticle(const NodeGrid& grid_, const ParticleData& data_, int m, double dt_, double pic_fraction_,
              const ConstVectorField4& vel_star, const ConstVectorField4& acc, const ConstField4& temp_rate,
              const TransferHeat& transfer)
      : grid(grid_),
        data(data_),
        nodes(vel_star[0], m),
        node_extent{long(vel_star[0].extent(1)), long(vel_star[0].extent(2)), long(vel_star[0].extent(3))},
        v_node{node_array(vel_star[0]), node_array(vel_star[1]), node_array(vel_star[2])},
        a_node{node_array(acc[0]), node_array(acc[1]), node_array(acc[2])},
        t_node(node_array(temp_rate)),
        q_node(node_array(transfer.node_energy)),
        dt(dt_),
        pic_fraction(pic_fraction_),
        inverse_cv(Heat ? 1.0 / transfer.cv : 0.0) {}

  /// The place of particle p's first node as the body below finds it, or -1 if its
  /// window leaves the node arrays (window_place, reduce_over_particle_groups).
  KOKKOS_FORCEINLINE_FUNCTION long first(long p) const {
    return window_place(nodes, particle_weights<Shape>(grid, data, p).first, node_extent);
  }

  /// A particle's weighted sums of node values: sum S v*_i, sum S a_i, sum S aT_i,
  /// sum S q_i, sum S |a_i|^2 and L = sum v*_i (x) grad S_ip (E35, E36).
  struct GatheredSums {
    double v[3] = {0, 0, 0}, a[3] = {0, 0, 0}, t = 0, q = 0, a2 = 0;
    Mat3 L = Mat3::zero();
  };

  /// The sums node by node (GIMP, as MPMICE calls it): each node's weight and gradient,
  /// then its values. A node of zero weight has a zero gradient too (its w and dw are 0
  /// along some direction) and is read where the particle's middle node is
  /// (ReadOwnNodes), so its gradient is set to 0 here whatever the value read.
  template <class Read>
  KOKKOS_FORCEINLINE_FUNCTION void sum_node_by_node(const ParticleWeights<Shape>& wt, long first, long middle,
                                                    const Read& read, GatheredSums& s) const {
    constexpr int n = Shape::nodes;
    unrolled_for<n>([&](int a) {
      unrolled_for<n>([&](int b) {
        unrolled_for<n>([&](int c) {
          const double S = wt.weight(a, b, c);
          const auto node = read.node(first, middle, nodes.step(a, b, c), S);
          double g[3];
          wt.gradient(a, b, c, g);
          for (int e = 0; e < 3; ++e) g[e] = S != 0.0 ? g[e] : 0.0;
          if (Heat) {
            s.t += S * node(t_node);
            s.q += S * node(q_node);
          }
          for (int d = 0; d < 3; ++d) {
            const double v = node(v_node[d]);
            s.v[d] += S * v;
            const double an = node(a_node[d]);
            s.a[d] += S * an;
            if (Heat) s.a2 += S * an * an;
            for (int e = 0; e < 3; ++e) s.L(d, e) += v * g[e];
          }
        });
      });
    });
  }

  /// The same sums direction by direction: the weights are products w_i w_j w_k and
  /// the gradients' factors dw_i w_j w_k, w_i dw_j w_k, w_i w_j dw_k, so the sums over k
  /// (with w_k and dw_k), then over j, then over i take each node value into two
  /// products instead of four, and no 3D weight is formed. A node of zero weight (GIMP)
  /// has a zero w and dw along some direction, so its value (finite; ReadOwnNodes reads
  /// the middle node's there) adds nothing. With GIMP's 27 nodes, 1.1-1.2x on 1 thread
  /// (docs/performance.md, session 26). Not with the heat (MPMICE): with the sums of
  /// the transfers' terms too, the coarse container's g2p ran 0.92x, so this takes no
  /// heat sums at all.
  template <class Read>
  KOKKOS_FORCEINLINE_FUNCTION void sum_by_direction(const ParticleWeights<Shape>& wt, long first, long middle,
                                                    const Read& read, GatheredSums& s) const {
    static_assert(!Heat, "the heat's sums are taken node by node");
    constexpr int n = Shape::nodes;
    unrolled_for<n>([&](int a) {
      // Over j and k, for this i: w_j w_k, dw_j w_k and w_j dw_k of the velocity.
      double v_ww[3] = {0, 0, 0}, v_dw[3] = {0, 0, 0}, v_wd[3] = {0, 0, 0}, a_ww[3] = {0, 0, 0};
      unrolled_for<n>([&](int b) {
        double v_w[3] = {0, 0, 0}, v_d[3] = {0, 0, 0}, a_w[3] = {0, 0, 0};
        unrolled_for<n>([&](int c) {
          const auto node = read.node(first, middle, nodes.step(a, b, c), wt.weight(a, b, c));
          const double w = wt.w[2][c], dw = wt.dw[2][c];
          for (int d = 0; d < 3; ++d) {
            const double v = node(v_node[d]);
            v_w[d] += w * v;
            v_d[d] += dw * v;
            a_w[d] += w * node(a_node[d]);
          }
        });
        const double w = wt.w[1][b], dw = wt.dw[1][b];
        for (int d = 0; d < 3; ++d) {
          v_ww[d] += w * v_w[d];
          v_dw[d] += dw * v_w[d];
          v_wd[d] += w * v_d[d];
          a_ww[d] += w * a_w[d];
        }
      });
      const double w = wt.w[0][a], dw = wt.dw[0][a];
      for (int d = 0; d < 3; ++d) {
        s.v[d] += w * v_ww[d];
        s.a[d] += w * a_ww[d];
        s.L(d, 0) += dw * v_ww[d];
        s.L(d, 1) += w * v_dw[d];
        s.L(d, 2) += w * v_wd[d];
      }
    });
  }

  /// The linear shape's node fields over W cells, as the coefficients of their
  /// interpolants (trilinear.hpp): field f's coefficient j of cell w at c[f][j][w]. The
  /// fields: v* (0-2), a (3-5), and with `Heat` the heat rate (6), the transfers'
  /// energy and |a_i|^2 (7, 8).
  template <int W>
  struct CellFields {
    double c[9][8][W];
  };

  /// CellFields of the W cells whose first nodes are at `place`, place + 1, ...,
  /// place + W - 1 (along k in the host's layout), from their 8 nodes each, in one
  /// vector loop over the cells; returns `place`, or a lower one where the last of the W
  /// would read past the node arrays (W > 1: the cells from there, `place` among them).
  /// Every node of a cell is read: a node of zero weight (a particle on a node plane)
  /// has a gradient, and L needs it.
  template <int W>
  KOKKOS_FORCEINLINE_FUNCTION long cell_fields(long place, CellFields<W>& f) const {
    static_assert(Shape::nodes == 2, "the linear shape");
    const long last = long(v_node[0].extent(0)) - 1 - nodes.steps[7] - (W - 1);
    const long start = place < last ? place : last;
    MPMICE_PRAGMA_SIMD
    for (long w = 0; w < W; ++w) {
      const auto load = [&](const ConstNodeArray& values, double* node) {
        for (int i = 0; i < 8; ++i) node[i] = values(start + w + nodes.steps[i]);
      };
      double node[8], acc[3][8];  // acc: the accelerations, also for |a_i|^2
      for (int d = 0; d < 3; ++d) {
        load(v_node[d], node);
        trilinear::coefficients<W>(node, &f.c[d][0][w]);
        load(a_node[d], acc[d]);
        trilinear::coefficients<W>(acc[d], &f.c[3 + d][0][w]);
      }
      if (Heat) {
        load(t_node, node);
        trilinear::coefficients<W>(node, &f.c[6][0][w]);
        load(q_node, node);
        trilinear::coefficients<W>(node, &f.c[7][0][w]);
        for (int i = 0; i < 8; ++i) node[i] = acc[0][i] * acc[0][i] + acc[1][i] * acc[1][i] + acc[2][i] * acc[2][i];
        trilinear::coefficients<W>(node, &f.c[8][0][w]);
      }
    }
    return start;
  }

  /// Particle p of the linear shape in cell w of `f`, its own (particles sorted by cell
  /// share them: reduce_over_cell_runs). Its sums are the interpolants' values and L
  /// v*'s slopes; returns as operator().
  template <int W>
  KOKKOS_FORCEINLINE_FUNCTION double in_cell(long p, const CellFields<W>& f, long w) const {
    double x[3], half[3];
    particle_position(data, p, x, half);
    const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    const double r[3] = {wt.w[0][1], wt.w[1][1], wt.w[2][1]};  // w = (1 - r, r): LinearShape
    const auto at = [&](const double* c) { return trilinear::value<W>(c, r[0], r[1], r[2]); };
    GatheredSums s;
    for (int d = 0; d < 3; ++d) {
      double slope[3];
      s.v[d] = trilinear::value<W>(&f.c[d][0][w], r[0], r[1], r[2], slope);
      for (int e = 0; e < 3; ++e) s.L(d, e) = slope[e] * grid.inv_h[e];
      s.a[d] = at(&f.c[3 + d][0][w]);
    }
    if (Heat) {
      s.t = at(&f.c[6][0][w]);
      s.q = at(&f.c[7][0][w]);
      s.a2 = at(&f.c[8][0][w]);
    }
    return update(p, x, s);
  }

  /// Particle p of the linear shape with the fields of its own cell.
  KOKKOS_FORCEINLINE_FUNCTION double own_cell(long p) const {
    CellFields<1> f;
    cell_fields(first(p), f);
    return in_cell(p, f, 0);
  }

  template <class Read>
  KOKKOS_FORCEINLINE_FUNCTION double operator()(long p, const Read& read) const {
    static_assert(Shape::nodes == 3, "GIMP: the linear shape's particles take in_cell");
    double x[3], half[3];
    particle_position(data, p, x, half);
    const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
    const long first = nodes.at(wt.first), middle = nodes.middle(first);
    GatheredSums s;
    if constexpr (!Heat) {  // where it is faster (sum_by_direction)
      sum_by_direction(wt, first, middle, read, s);
    } else {
      sum_node_by_node(wt, first, middle, read, s);
    }
    return update(p, x, s);
  }

  /// (E35, E36) from particle p's sums, its position before the step `x`.
  KOKKOS_FORCEINLINE_FUNCTION double update(long p, const double* x, const GatheredSums& s) const {
    for (int d = 0; d < 3; ++d) {
      double& v = data(p, column(ParticleField::vx) + d);
      v = (1.0 - pic_fraction) * (v + dt * s.a[d]) + pic_fraction * s.v[d];
      data(p, column(ParticleField::x) + d) = x[d] + dt * s.v[d];
    }
    double& T = data(p, column(ParticleField::temperature));
    if (Heat) {
      // The transfers' heat (cell_rates_to_nodes: q_i; |D_i|^2 from the accelerations
      // here) and the work of (E24)'s isotropic part pp - q on the particle's volume,
      // V (pp - q) tr(L) dt, which is neither strain energy nor received by a fluid (the
      // equilibration hands the volume over at fixed temperature). With the nodes' rate,
      // at most half of c_v T leaves in one step: a trace particle on nodes where the
      // internal force and the exchange nearly cancel can owe more than it holds.
      const double increment2 = dt * dt * (s.a[0] * s.a[0] + s.a[1] * s.a[1] + s.a[2] * s.a[2]);
      const double owed = s.q + dt * dt * s.a2 - 0.5 * increment2;
      const double iso = data(p, column(ParticleField::gas_pressure)) - data(p, column(ParticleField::bulk_viscosity));
      const double gauge_work = data(p, column(ParticleField::volume)) * iso * s.L.trace() * dt;
      double dT = dt * s.t + (owed + gauge_work / data(p, column(ParticleField::mass))) * inverse_cv;
      T += dT < -0.5 * T ? -0.5 * T : dT;
    }  // MPM alone: T_p unchanged
    store_tensor(data, p, ParticleField::L00, s.L);
    // One sub-step, F_new = (I + dt L) F, here; more are left to g2p_substeps.
    const bool one_step = one_deformation_step(s.L, dt);
    const Mat3 F = load_tensor(data, p, ParticleField::F00);
    const Mat3 F_new = (Mat3::identity() + dt * s.L) * F;
    double& volume = data(p, column(ParticleField::volume));
    volume = one_step ? volume * (F_new.det() / F.det()) : volume;
    store_tensor(data, p, ParticleField::F00, one_step ? F_new : F);
    return one_step ? 0.0 : 1.0;
  }
};

/// Whether g2p reads GIMP's node values in groups. Groups of 8 particles in at most
/// three windows of nodes read the values once for the group instead of gathering them
/// particle by particle (reduce_over_particle_groups): 1.5-2.2x with linear weights on
/// an AVX-512 machine (docs/performance.md, sessions 19, 20 and 26; the linear shape
/// now reads by cell, session 37). Where the loops' vectors are wider than the
/// compiler's own choice (loops.hpp, MPMICE_WIDE_VECTORS: GCC tuning for AMD Zen 1),
/// every particle gathers its own instead: on AMD Zen 1 that was 1.3-1.6x the groups in
/// the narrower vectors, and 0.96x the groups in wide ones, which GCC 12 compiled 4x
/// (linear weights) to 10x (GIMP) more slowly (session 32).
constexpr bool g2p_reads_in_groups = !wide_vectors_are_wider;

/// (E35, E36) for the particles of a material that deforms (G2pParticle), their node
/// values read for many particles at once (`in_groups`: the linear shape's cells,
/// reduce_over_cell_runs; GIMP's groups, reduce_over_particle_groups) or particle by
/// particle (the tests compare the two: the same values, bit for bit). Returns 1 if a
/// particle's deformation needs more than one sub-step, else 0.
template <class Shape, bool Heat>
double g2p_deforming(const NodeGrid& grid, long count, const ParticleData& data, int m, double dt,
                     double pic_fraction, const ConstVectorField4& vel_star, const ConstVectorField4& acc,
                     const ConstField4& temp_rate, const TransferHeat& transfer,
                     bool in_groups = Shape::nodes == 2 || g2p_reads_in_groups) {
  const G2pParticle<Shape, Heat> body(grid, data, m, dt, pic_fraction, vel_star, acc, temp_rate, transfer);
  if constexpr (Shape::nodes == 2) {
    if (in_groups) return reduce_over_cell_runs<Reduction::max>("mpmice::g2p", count, body);
    return reduce_over_particles<Reduction::max>("mpmice::g2p", count,
                                                 KOKKOS_LAMBDA(long p) { return body.own_cell(p); });
  } else {
    if (in_groups) return reduce_over_particle_groups<Reduction::max>("mpmice::g2p", count, body);
    return reduce_over_particles<Reduction::max>("mpmice::g2p", count,
                                                 KOKKOS_LAMBDA(long p) { return body(p, ReadOwnNodes{}); });
  }
}

/// F and V of the particles whose deformation needs more than one sub-step (E36).
inline void g2p_substeps(long count, const ParticleData& data, double dt) {
  Kokkos::parallel_for(
      "mpmice::g2p_substeps", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        const Mat3 L = load_tensor(data, p, ParticleField::L00);
        if (one_deformation_step(L, dt)) return;
        const Mat3 F = load_tensor(data, p, ParticleField::F00);
        const Mat3 F_new = deformation_increment(L, dt) * F;
        data(p, column(ParticleField::volume)) *= F_new.det() / F.det();
        store_tensor(data, p, ParticleField::F00, F_new);
      });
}
}  // namespace detail

/// For the particles of material slot m: v_p <- (1-a)(v_p + dt sum S a_i) + a sum S v*_i,
/// x_p += dt sum S v*_i, T_p += dt sum S aT_i (E35) plus, with `transfer` (MPMICE), the
/// heat it describes (for FLIP, a = 0: the kinetic energy a PIC fraction removes is not
/// returned); `temp_rate` and `transfer.node_energy` are both given (MPMICE) or both
/// empty (MPM alone: T_p unchanged), else std::invalid_argument,
/// L_p = sum v*_i (x) grad S_ip, F <- (I + L dt/n)^n F, V_p <- V_p J_new/J_old (E36).
/// A rigid material moves with `rigid_velocity`.
///
/// The loop over particles vectorises (loops.hpp) and a particle whose deformation needs
/// more than one sub-step (|L| dt >= 1, rare) is finished by a second, scalar pass. With
/// the linear shape, the particles of a cell (sorted by cell, particle_sort.hpp) share the
/// interpolants of its node fields (trilinear.hpp), formed once per cell
/// (reduce_over_cell_runs; 1.15-1.5x the weights' sums node by node, docs/performance.md,
/// session 37). With GIMP the nodes are written out, a node of zero weight adds nothing
/// (ReadOwnNodes, node_reads.hpp), and groups of particles in at most three windows of
/// nodes (particles sorted by window) read their node values once per group
/// (reduce_over_particle_groups), except where wide vectors pay more
/// (detail::g2p_reads_in_groups).
template <class Shape>
void g2p(const NodeGrid& grid, long count, const ParticleData& data, int m, double dt,
         double pic_fraction, bool rigid, Kokkos::Array<double, 3> rigid_velocity,
         const ConstVectorField4& vel_star, const ConstVectorField4& acc,
         const ConstField4& temp_rate = ConstField4(), const TransferHeat& transfer = TransferHeat()) {
  if (rigid) {
    for_each_particle("mpmice::g2p_rigid", count, KOKKOS_LAMBDA(long p) {
      for (int d = 0; d < 3; ++d) {
        data(p, column(ParticleField::vx) + d) = rigid_velocity[d];
        data(p, column(ParticleField::x) + d) += dt * rigid_velocity[d];
      }
    });
    return;
  }
  // Both or neither, as MPM alone and MPMICE call it: with GIMP each combination takes
  // minutes to compile (3.0 without heat and 5.4 with both, GCC 12 on a 2.45 GHz Zen 3
  // core), in every file that calls g2p (the project's own programs: once, below;
  // docs/design.md, "Build time").
  const bool mpmice = transfer.node_energy.data() != nullptr;
  if (mpmice != (temp_rate.data() != nullptr))
    throw std::invalid_argument("g2p: temp_rate and transfer.node_energy are given together (MPMICE) or not at all");
  double substepped = 0;
  with_flag(mpmice, [&](auto heat) {
    substepped = detail::g2p_deforming<Shape, decltype(heat)::value>(
        grid, count, data, m, dt, pic_fraction, vel_star, acc, temp_rate, transfer);
  });
  if (substepped > 0) detail::g2p_substeps(count, data, dt);
}

#ifdef MPMICE_KERNEL_INSTANCES
// The project's own programs (tests, benchmarks, mini-app) compile the GIMP bodies once,
// in kernels/instances/, instead of in every file that calls g2p: minutes each
// (docs/design.md, "Build time"). A consumer of the installed package compiles them
// where it calls g2p, as with every other kernel.
namespace detail {
#define MPMICE_G2P_DEFORMING(Shape, Heat)                                                                    \
  double g2p_deforming<Shape, Heat>(const NodeGrid&, long, const ParticleData&, int, double, double,      \
                                    const ConstVectorField4&, const ConstVectorField4&, const ConstField4&, \
                                    const TransferHeat&, bool)
extern template MPMICE_G2P_DEFORMING(GimpShape, false);
extern template MPMICE_G2P_DEFORMING(GimpShape, true);
}  // namespace detail
#endif

}  // namespace mpmice
