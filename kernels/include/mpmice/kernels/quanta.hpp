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
#include <cstdint>
#include <type_traits>

#include <mpmice/kernels/math.hpp>

// Quantum's rounding (below) is two additions that only IEEE arithmetic keeps; a
// compiler allowed to reassociate would fold them away. GCC and Clang define
// __FAST_MATH__ under -ffast-math, icpx under its default -fp-model=fast (the
// mpmice::kernels target sets -fp-model=precise for it). -fassociative-math alone does
// not show here: do not use it.
#if defined(__FAST_MATH__)
#error "mpmice's kernels need IEEE arithmetic (quanta.hpp): build them without -ffast-math (icpx: -fp-model=precise)"
#endif

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

/// A power-of-two quantum q (quantum_for, 0 for none) with what rounding to it takes.
///
/// Rounding adds and subtracts 1.5 2^52 (`magic`): doubles between 2^52 and 2^53 are
/// whole numbers, so t = x/q + 1.5 2^52 rounds x/q to the nearest whole number (ties to
/// even) and t - 1.5 2^52 is that number, exactly, for |x/q| <= 2^51 (the quanta are
/// made for contributions below 2^41 q). Two vector operations, against four for
/// floor(x/q + 1/2) with a select for q = 0; with q = 0 the magic number is 0 and x
/// passes through (as x + 0: -0 becomes +0, and a target that flushes subnormals to zero,
/// as nvcc's --use_fast_math does, flushes x too). This needs IEEE arithmetic
/// (the #error above).
struct Quantum {
  double q = 0;
  double unrounded = 1;  ///< 1 if q = 0, else 0
  double unit = 1;       ///< what `in_units` counts in: q, or 1 if q = 0
  double scale = 1;      ///< 1/unit, exact (a power of two)
  double magic = 0;      ///< 1.5 2^52 if q > 0, else 0
  Quantum() = default;
  KOKKOS_INLINE_FUNCTION Quantum(double quantum)
      : q(quantum), unrounded(quantum > 0 ? 0.0 : 1.0), unit(quantum > 0 ? quantum : 1.0),
        scale(quantum > 0 ? 1.0 / quantum : 1.0), magic(quantum > 0 ? 0x1.8p52 : 0.0) {}
  /// x rounded to the nearest multiple of q (x itself if q = 0).
  KOKKOS_INLINE_FUNCTION double round(double x) const { return unit * in_units(x); }
  /// `round(x)` counted in `unit`s, without a branch: a whole number with q > 0 (for
  /// |x| <= 2^51 q), x itself with q = 0. `unit` times it is round(x) bit for bit, and so is
  /// `unit` times a sum of them the sum of the rounded values: a loop adding many
  /// contributions adds their counts and multiplies once (p2g and internal_force, in
  /// add_scatter_into).
  KOKKOS_INLINE_FUNCTION double in_units(double x) const { return nearest_whole(x * scale, magic); }
  /// `in_units(x)` of x given in units already: x_in_units = x * scale, or a product
  /// with a factor given in units, S (v scale), which is (S v) scale bit for bit (scale a
  /// power of two), so that a particle's values are scaled once for all its nodes.
  KOKKOS_INLINE_FUNCTION double whole_units(double x_in_units) const { return nearest_whole(x_in_units, magic); }

  /// A value counted in units (x/q, exact), rounded to the nearest whole number with a
  /// quantum's `magic` (x itself for magic = 0). The mass's rounding, which p2g and
  /// internal_force both make ("does this node get mass" must agree), is always passed
  /// as `x * scale`, never a product folded into the scale: x * scale + magic is then the
  /// same whether or not the compiler fuses it into an FMA. Other contributions may come
  /// as S (v scale) (`whole_units`): bit for bit the same without FMA contraction
  /// (MPMICE_REPRODUCIBLE, the default), and a whole number of units either way.
  KOKKOS_FORCEINLINE_FUNCTION static double nearest_whole(double x_in_units, double magic) {
    const double t = x_in_units + magic;
    return t - magic;
  }
};

/// Whole units counted in integers. With q > 0, t = x_in_units + magic is a double
/// between 2^52 and 2^53 (for |x_in_units| <= 2^51), where doubles are a unit apart: t's
/// bits are the magic number's bits plus the whole number x rounds to. A sum of k such
/// bit patterns in 64-bit integers (wrapping) is therefore k times the magic number's
/// bits plus the exact sum of the whole numbers: one integer add per contribution in
/// place of the rounding's subtraction and a floating-point add. `total` gives the sum
/// back as a double (exact below 2^53). Needs q > 0: with no quantum the magic number
/// is 0 and t is x itself, not a count.
struct UnitCount {
  static constexpr std::uint64_t magic_bits = 0x4338000000000000ull;  ///< the bits of 1.5 2^52
  /// The bits of t = x_in_units + magic, to be added as integers.
  KOKKOS_FORCEINLINE_FUNCTION static std::uint64_t bits(double t) { return math::as_bits(t); }
  /// The whole number that `terms` added `bits` sum to.
  KOKKOS_FORCEINLINE_FUNCTION static double total(std::uint64_t sum, std::uint64_t terms) {
    return double(std::int64_t(sum - terms * magic_bits));
  }
  /// `total(sum, terms)` bit for bit, for a vector loop: x86 converts 64-bit integers to
  /// doubles in vectors only with AVX-512, and GCC 12 left p2g's loop over a node's 8
  /// fields scalar for that conversion alone (docs/performance.md, session 49).
  KOKKOS_FORCEINLINE_FUNCTION static double total_in_vector(std::uint64_t sum, std::uint64_t terms) {
    return to_double(sum - terms * magic_bits);
  }
  /// double(int64_t(n)) from n's two 32-bit halves, in bit operations and two additions,
  /// which vectorise without AVX-512. With the exponent bits 0x433 above it, the low
  /// half reads as the double 2^52 + low; with 0x453 above it, the high half (its sign
  /// bit flipped, so that it counts from 0) reads as 2^84 + 2^63 + 2^32 high. Taking
  /// 2^84 + 2^63 + 2^52 from the second is exact; adding the first then rounds once, as
  /// the conversion does.
  KOKKOS_FORCEINLINE_FUNCTION static double to_double(std::uint64_t n) {
    const double low = math::from_bits((n & 0xFFFFFFFFull) | 0x4330000000000000ull);
    const double high = math::from_bits(((n ^ 0x8000000000000000ull) >> 32) | 0x4530000000000000ull);
    return (high - 0x1.00000801p84) + low;
  }
};

/// How a loop adds contributions counted in units, each given as t = x_in_units + magic:
/// `Counted` (every quantum it sums positive) as t's bits in 64-bit integers
/// (UnitCount), else as the doubles t - magic (as Quantum::nearest_whole). The same sums
/// either way; p2g's and internal_force's cell runs take one or the other.
template <bool Counted>
struct UnitSums {
  using Sum = std::conditional_t<Counted, std::uint64_t, double>;
  /// What t adds to a sum.
  KOKKOS_FORCEINLINE_FUNCTION static Sum term(double t, double magic) {
    if constexpr (Counted)
      return UnitCount::bits(t);
    else
      return t - magic;
  }
  /// The count that `terms` added `term`s sum to, as a Sum.
  KOKKOS_FORCEINLINE_FUNCTION static Sum count(Sum sum, std::uint64_t terms) {
    if constexpr (Counted)
      return sum - terms * UnitCount::magic_bits;
    else
      return sum;
  }
  /// The same as a double (exact below 2^53).
  KOKKOS_FORCEINLINE_FUNCTION static double total(Sum sum, std::uint64_t terms) {
    if constexpr (Counted)
      return UnitCount::total(sum, terms);
    else
      return sum;
  }
  /// The same, for a vector loop (UnitCount::total_in_vector).
  KOKKOS_FORCEINLINE_FUNCTION static double total_in_vector(Sum sum, std::uint64_t terms) {
    if constexpr (Counted)
      return UnitCount::total_in_vector(sum, terms);
    else
      return sum;
  }
  /// `sum` where `here`, else 0, without a branch: integers as a mask (with a select
  /// GCC 12 left internal_force's loop over the nodes scalar), doubles as a select.
  KOKKOS_FORCEINLINE_FUNCTION static Sum only_where(bool here, Sum sum) {
    if constexpr (Counted)
      return sum & (std::uint64_t(0) - std::uint64_t(here));
    else
      return here ? sum : 0.0;
  }
};

/// F quanta part by part (a structure of arrays), so that a loop over them is a vector
/// loop: `whole_units(f, x)` is q[f].whole_units(x) bit for bit.
template <int F>
struct QuantumArray {
  Kokkos::Array<double, F> scale, magic, unit;
  explicit QuantumArray(const Kokkos::Array<Quantum, F>& q) {
    for (int f = 0; f < F; ++f) {
      scale[f] = q[f].scale;
      magic[f] = q[f].magic;
      unit[f] = q[f].unit;
    }
  }
  /// q[f].whole_units(x_in_units) bit for bit.
  KOKKOS_FORCEINLINE_FUNCTION double whole_units(int f, double x_in_units) const {
    return Quantum::nearest_whole(x_in_units, magic[f]);
  }
  /// Whether every part from `first` on has a quantum, so that their units can be
  /// counted in integers (UnitCount).
  bool counted_from(int first) const {
    for (int f = first; f < F; ++f)
      if (magic[f] == 0.0) return false;
    return true;
  }
};

/// x rounded to the nearest multiple of q (x itself if q = 0). The reciprocal is the
/// same for every particle of a loop, where the compiler hoists it out (no division per
/// contribution); a loop over several quanta kept in an array takes `Quantum`s, whose
/// division is done once where they are made.
KOKKOS_INLINE_FUNCTION double on_grid(double x, double q) { return Quantum(q).round(x); }

/// The power of two 2^(e - 40) with 2^e <= bound < 2^(e+1): contributions up to `bound`
/// become integers below 2^41 times it. A bound of 0 (every contribution 0, which any
/// quantum keeps as 0) gets 1, so that the kernels count its units in integers as the
/// others' (UnitCount; with 0 they would take their path for unrounded sums, which gives
/// the same zeros more slowly). 0, no rounding, for a negative or non-finite bound.
inline double quantum_for(double bound) {
  if (bound == 0.0) return 1.0;
  if (!(bound > 0) || !std::isfinite(bound)) return 0.0;
  return std::ldexp(1.0, std::ilogb(bound) - 40);
}

/// The quanta of contributions bounded by `largest` (each kind's largest contribution,
/// e.g. particle_scatter_bounds after a global max): quantum_for of each.
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
