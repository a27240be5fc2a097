#pragma once
/// \file quanta.hpp
/// \brief Sums that do not depend on their order: every particle's contribution to a
///        node or cell sum is rounded to a multiple of a power-of-two quantum q, 2^-40
///        of the largest contribution on any rank. Sums of such multiples stay exact in
///        double precision (below 2^53 q), so a node gets the same value whatever the
///        order of its particles, the threads, or the decomposition that adds a
///        neighbour's ghost nodes into it: the same run on 1 and N ranks gives the same
///        answer to round-off of the diagnostics only. The rounding changes each
///        contribution by at most 2^-41 of the largest one.
#include <cmath>

#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// The quanta of one step's particle scatters (0: no rounding).
struct SumQuanta {
  double mass = 0;            ///< kg: S m_p, burned mass
  double momentum = 0;        ///< kg m/s: S m_p v_p, burned momentum
  double heat = 0;            ///< kg K: S m_p T_p
  double volume = 0;          ///< m^3: S V_p
  double external_force = 0;  ///< N: S f_ext
  double internal_force = 0;  ///< N: V_p sigma_p . grad S
  double energy = 0;          ///< J: burned m (c_v T + dh)
};

/// A power-of-two quantum q (quantum_for, 0 for none) with its reciprocal, which is
/// exact: x (1/q) equals x/q bit for bit and the product back is exact.
struct Quantum {
  double q = 0, inverse = 0;
  double unrounded = 1;  ///< 1 if q = 0, else 0
  double unit = 1;       ///< what `in_units` counts in: q, or 1 if q = 0
  double scale = 1;      ///< 1/unit, exact
  double half = 0;       ///< 1/2 if q > 0, else 0
  Quantum() = default;
  KOKKOS_INLINE_FUNCTION Quantum(double quantum)
      : q(quantum), inverse(quantum > 0 ? 1.0 / quantum : 0.0), unrounded(quantum > 0 ? 0.0 : 1.0),
        unit(quantum > 0 ? quantum : 1.0), scale(quantum > 0 ? 1.0 / quantum : 1.0), half(quantum > 0 ? 0.5 : 0.0) {}
  /// x rounded to the nearest multiple of q (x itself if q = 0).
  KOKKOS_INLINE_FUNCTION double round(double x) const { return q > 0 ? math::floor(x * inverse + 0.5) * q : x; }
  /// `round(x)` counted in `unit`s, without a branch (straight code that GCC vectorises;
  /// it keeps `round`'s select as a branch there): a whole number below 2^53 with q > 0,
  /// x itself with q = 0. `unit` times it is round(x) bit for bit, and so is `unit`
  /// times a sum of them the sum of the rounded values: a loop adding many
  /// contributions adds their counts and multiplies once (p2g_cell_runs).
  KOKKOS_INLINE_FUNCTION double in_units(double x) const { return count_units(x, scale, half, unrounded); }

  /// in_units from a quantum's parts (also QuantumArray's).
  KOKKOS_FORCEINLINE_FUNCTION static double count_units(double x, double scale, double half, double unrounded) {
    const double t = x * scale + half;  // x scale is exact: a power of two
    return unrounded != 0.0 ? t : math::floor(t);
  }
};

/// F quanta part by part (a structure of arrays), so that a loop over them is a vector
/// loop: `round(f, x)` is q[f].round(x) bit for bit, as unit times in_units.
template <int F>
struct QuantumArray {
  Kokkos::Array<double, F> scale, half, unrounded, unit;
  explicit QuantumArray(const Kokkos::Array<Quantum, F>& q) {
    for (int f = 0; f < F; ++f) {
      scale[f] = q[f].scale;
      half[f] = q[f].half;
      unrounded[f] = q[f].unrounded;
      unit[f] = q[f].unit;
    }
  }
  KOKKOS_FORCEINLINE_FUNCTION double round(int f, double x) const {
    return unit[f] * Quantum::count_units(x, scale[f], half[f], unrounded[f]);
  }
};

/// x rounded to the nearest multiple of q (x itself if q = 0). The reciprocal is the
/// same for every particle of a loop, where the compiler hoists it out (no division per
/// contribution); a loop over several quanta kept in an array takes `Quantum`s, whose
/// division is done once where they are made.
KOKKOS_INLINE_FUNCTION double on_grid(double x, double q) { return Quantum(q).round(x); }

/// The power of two 2^(e - 40) with 2^e <= bound < 2^(e+1): contributions up to `bound`
/// become integers below 2^41 times it; 0 for a bound that is not positive.
inline double quantum_for(double bound) {
  if (!(bound > 0) || !std::isfinite(bound)) return 0.0;
  return std::ldexp(1.0, std::ilogb(bound) - 40);
}

/// The quanta of contributions bounded by `largest` (each kind's largest contribution,
/// e.g. particle_scatter_bounds after a global max): quantum_for of each, 0 where the
/// bound is 0.
inline SumQuanta quanta_for(const SumQuanta& largest) {
  SumQuanta q;
  q.mass = quantum_for(largest.mass);
  q.momentum = quantum_for(largest.momentum);
  q.heat = quantum_for(largest.heat);
  q.volume = quantum_for(largest.volume);
  q.external_force = quantum_for(largest.external_force);
  q.internal_force = quantum_for(largest.internal_force);
  q.energy = quantum_for(largest.energy);
  return q;
}

}  // namespace mpmice
