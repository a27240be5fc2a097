#pragma once
/// \file node_reads.hpp
/// \brief How a particle loop that reads node values (g2p) reads them: each particle
///        its own nodes (`ReadOwnNodes`; across a vector of particles, one gather per
///        node and field), or, for a group of particles whose windows of nodes are one
///        of two (`ReadTwoWindows`; the particles of a set sorted by window,
///        particle_sort.hpp), both windows' values, the same for every particle, and a
///        select. `reduce_over_particle_groups` chooses between them group by group.
#include <cstdint>
#include <cstring>
#include <string>

#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {

/// Each particle reads node (first + step) of its own, or its `middle` node where the
/// node's weight S is zero: such a node adds nothing, and a particle loop without
/// branches then reads no node outside the particle's reach (GIMP's nodes of zero weight
/// can lie past the patch's ghost nodes). Arithmetic, not a select: GCC turned the select
/// into masked loads, which it could not vectorise here.
struct ReadOwnNodes {
  struct Node {
    long place;
    KOKKOS_FORCEINLINE_FUNCTION double operator()(const ConstNodeArray& field) const { return field(place); }
  };
  KOKKOS_FORCEINLINE_FUNCTION Node node(long first, long middle, long step, double S) const {
    return {middle + long(S != 0.0) * (first + step - middle)};
  }
};

/// The place of a window's first node for `reduce_over_particle_groups`'s
/// `body.first(p)`: `nodes.at(first)` when the window's Nodes^3 nodes from `first` all lie
/// in node arrays of extents `extent` (i, j, k), else -1. ReadTwoWindows reads every
/// node of a window, also those of zero weight, which ReadOwnNodes does not: for GIMP
/// they can lie past the node arrays (a particle deep in the ghost cells), and a group
/// with such a particle then reads particle by particle. Checked for GIMP only: the
/// linear window is the particle's cell, whose nodes all exist for a particle in the
/// patch or its ghost cells (where migrate keeps them), and the check cost linear g2p
/// 2-10%.
template <int Nodes>
KOKKOS_INLINE_FUNCTION long window_place(const NodeStencil<Nodes>& nodes, const NodeOffset* first,
                                         const Kokkos::Array<long, 3>& extent) {
  if constexpr (Nodes == 2) {
    return nodes.at(first);
  } else {
    long outside = 0;
    for (int d = 0; d < 3; ++d) outside |= long(first[d] < 0) | long(first[d] + Nodes > extent[d]);
    return outside != 0 ? -1 : nodes.at(first);
  }
}

#if !defined(MPMICE_DEVICE_BACKEND)
/// Every particle of the group has its window's first node at `first_lo` or at
/// `first_hi`, and reads node (first + step) of it: both values are loaded, the same for
/// the whole group (in a vector loop two broadcasts, hoisted out of it, instead of a
/// gather), and selected. A node of zero weight (GIMP's far nodes; with the linear
/// shape, a particle on a node plane) is read where ReadOwnNodes reads the particle's
/// middle node, and, its value finite, adds nothing either way (with an infinite or NaN
/// value there the particle would get NaN). Both windows must lie in the node arrays
/// (window_place: checked for GIMP, true for a linear particle in the patch or its
/// ghost cells). Host only (reduce_over_particle_groups).
struct ReadTwoWindows {
  long first_lo, first_hi;
  struct Node {
    long at_lo, at_hi;
    std::uint64_t lower;  ///< all bits set for a particle whose first node is first_lo, else 0
    KOKKOS_FORCEINLINE_FUNCTION double operator()(const ConstNodeArray& field) const {
      // The select on the values' bits: written as `?:`, GCC 12 moved the two loads
      // into its arms, as masked loads of one place for the whole vector, which it
      // cannot vectorise.
      const double a = field(at_lo), b = field(at_hi);
      std::uint64_t bits_a, bits_b;
      std::memcpy(&bits_a, &a, sizeof a);
      std::memcpy(&bits_b, &b, sizeof b);
      const std::uint64_t bits = (bits_a & lower) | (bits_b & ~lower);
      double value;
      std::memcpy(&value, &bits, sizeof value);
      return value;
    }
  };
  KOKKOS_FORCEINLINE_FUNCTION Node node(long first, long /*middle*/, long step, double /*S*/) const {
    return {first_lo + step, first_hi + step, std::uint64_t(0) - std::uint64_t(first == first_lo)};
  }
};

namespace detail {
/// Particles per group of `reduce_over_particle_groups`: 8 doubles, one 512-bit vector
/// (two 256-bit ones). Runs of `particle_run` particles hold whole groups.
constexpr long particle_group = 8;
static_assert(particle_run % particle_group == 0, "runs of whole groups");

/// One run [lo, hi) of `reduce_over_particle_groups`, flattened (loops.hpp). A group
/// reads both windows when every particle's first node is the first or the last
/// particle's (the others counted in a double, as loops.hpp's reductions count) and
/// both lie in the node arrays; the run's last, partial group reads its own nodes.
template <Reduction R, class Body>
MPMICE_FLATTEN double grouped_run_reduce(const Body& particle_body, long lo, long hi) {
  const Body body = particle_body;  // its own copy, as simd_run_reduce
  const auto own = [&](long p) { return body(p, ReadOwnNodes{}); };
  double acc = 0;
  long g = lo;
  for (; g + particle_group <= hi; g += particle_group) {
    const long first_lo = body.first(g), first_hi = body.first(g + particle_group - 1);
    double elsewhere = 0;
#if defined(MPMICE_HOST_SIMD)
#pragma omp simd reduction(+ : elsewhere)
#endif
    for (long l = 0; l < particle_group; ++l) {
      const long first = body.first(g + l);
      elsewhere += first != first_lo && first != first_hi ? 1.0 : 0.0;
    }
    // The group as one vector loop of known length, particle_group: no remainder.
    const ReadTwoWindows two{first_lo, first_hi};
    const auto two_windows = [&](long p) { return body(p, two); };
    const bool in_two = elsewhere == 0.0 && first_lo >= 0 && first_hi >= 0;
    combine<R>(acc, in_two ? simd_run_reduce<R>(two_windows, g, g + particle_group)
                           : simd_run_reduce<R>(own, g, g + particle_group));
  }
  combine<R>(acc, simd_run_reduce<R>(own, g, hi));
  return acc;
}
}  // namespace detail
#endif

/// Like `reduce_over_particles`, for a body with `body(p, read)`, particle p's value,
/// which reads its node values through `read` (ReadOwnNodes or ReadTwoWindows), and
/// `body.first(p)`, the place of particle p's first node as `window_place` gives it. On
/// the host the particles go in groups of 8 consecutive ones: a group whose first nodes
/// are all its first or its last particle's, inside the node arrays, reads
/// ReadTwoWindows, else ReadOwnNodes. On a GPU every particle reads its own (each thread
/// loads its values: no vector gather to save). The sum's order differs from
/// reduce_over_particles's.
template <Reduction R, class Body>
double reduce_over_particle_groups(const std::string& label, long count, const Body& body) {
#if defined(MPMICE_DEVICE_BACKEND)
  return reduce_over_particles<R>(label, count, KOKKOS_LAMBDA(long p) { return body(p, ReadOwnNodes{}); });
#else
  return detail::reduce_runs<R>(label, Kokkos::RangePolicy<ExecSpace>(0, detail::particle_runs(count)), [=](long r) {
    return detail::grouped_run_reduce<R>(body, r * detail::particle_run, detail::particle_run_end(r, count));
  });
#endif
}

}  // namespace mpmice
