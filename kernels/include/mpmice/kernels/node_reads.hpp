#pragma once
/// \file node_reads.hpp
/// \brief How a particle loop that reads node values (g2p) reads them: each particle
///        its own nodes (`ReadOwnNodes`; across a vector of particles, one gather per
///        node and field), or, for a group of particles whose windows of nodes are one
///        of two or three (`ReadWindows`; the particles of a set sorted by window,
///        particle_sort.hpp), every window's values, the same for every particle, and
///        selects. `reduce_over_particle_groups` chooses between them group by group.
///        Particles whose node values are the same for a whole cell (the linear shape)
///        take them once per run of one cell's particles: `reduce_over_cell_runs`.
#include <cstdint>
#include <string>

#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/math.hpp>
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
/// in node arrays of extents `extent` (i, j, k), else -1. ReadWindows reads every
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
/// Every particle of the group has its window's first node at one of `Windows` places,
/// `first[0..Windows)`, and reads node (first + step) of it: each window's value is
/// loaded, the same for the whole group (in a vector loop a broadcast, hoisted out of
/// it, instead of a gather), and the particle's is selected. A GIMP node of zero weight
/// (its far nodes) is read where ReadOwnNodes reads the particle's middle node, and,
/// its value finite, adds nothing either way (with an infinite or NaN value there the
/// particle would get NaN). Every window must lie in the node arrays (window_place:
/// checked for GIMP, true for a linear particle in the patch or its ghost cells). Host
/// only (reduce_over_particle_groups).
template <int Windows>
struct ReadWindows {
  Kokkos::Array<long, Windows> first;
  struct Node {
    Kokkos::Array<long, Windows> at;
    /// is[w] has all bits set for a particle whose first node is first[w], else 0; a
    /// particle in none of the others is in the last.
    Kokkos::Array<std::uint64_t, Windows - 1> is;
    KOKKOS_FORCEINLINE_FUNCTION double operator()(const ConstNodeArray& field) const {
      // The selects on the values' bits: written as `?:`, GCC 12 moved the loads into
      // its arms, as masked loads of one place for the whole vector, which it cannot
      // vectorise.
      std::uint64_t bits = math::as_bits(field(at[Windows - 1]));
      for (int w = Windows - 2; w >= 0; --w) bits = (math::as_bits(field(at[w])) & is[w]) | (bits & ~is[w]);
      return math::from_bits(bits);
    }
  };
  KOKKOS_FORCEINLINE_FUNCTION Node node(long particle_first, long /*middle*/, long step, double /*S*/) const {
    Node n;
    for (int w = 0; w < Windows; ++w) n.at[w] = first[w] + step;
    for (int w = 0; w < Windows - 1; ++w) n.is[w] = std::uint64_t(0) - std::uint64_t(particle_first == first[w]);
    return n;
  }
};

namespace detail {
/// Particles per group of `reduce_over_particle_groups`: 8 doubles, one 512-bit vector
/// (two 256-bit ones). Runs of `particle_run` particles hold whole groups.
constexpr long particle_group = 8;
static_assert(particle_run % particle_group == 0, "runs of whole groups");

/// One run [lo, hi) of `reduce_over_particle_groups`, flattened (loops.hpp). A group
/// whose particles' first nodes are at most three places, all in the node arrays, reads
/// each window once (ReadWindows): two when every first node is its first or its last
/// particle's, three when the others (sorted by window, the particles between) share
/// one. Other groups, and the run's last, partial group, read their own nodes.
template <Reduction R, class Body>
MPMICE_FLATTEN double grouped_run_reduce(const Body& particle_body, long lo, long hi) {
  const Body body = particle_body;  // its own copy, as simd_run_reduce
  const auto own = [&](long p) { return body(p, ReadOwnNodes{}); };
  double acc = 0;
  long g = lo;
  for (; g + particle_group <= hi; g += particle_group) {
    // The group's first nodes in one vector loop, then sorted into windows by a scalar
    // pass over the 8 values. Not as one vector loop with `omp simd reduction(min : ...)
    // reduction(max : ...)` over the others' places, as before session 29: on AVX2 (no
    // 64-bit vector min or max) GCC 12 compiled it, inlined here, so that the least
    // place came out as the largest, and a group of four places read three windows
    // (`Transfer.GimpNodePlaneParticlesGetTheVelocityGradient`).
    long first[particle_group];
#if defined(MPMICE_HOST_SIMD)
#pragma omp simd
#endif
    for (long l = 0; l < particle_group; ++l) first[l] = body.first(g + l);
    const long first_lo = first[0], first_hi = first[particle_group - 1];
    // `other`: the place of the particles in neither window, if they share one.
    long other = first_lo;
    bool two = true, three = true;
    for (long l = 1; l < particle_group - 1; ++l) {
      if (first[l] == first_lo || first[l] == first_hi) continue;
      three = three && (two || first[l] == other);
      other = first[l];
      two = false;
    }
    three = three && !two;
    const bool inside = first_lo >= 0 && first_hi >= 0 && other >= 0;
    // Each group as one vector loop of known length, particle_group: no remainder.
    double value;
    if (!(two || three) || !inside) {
      value = simd_run_reduce<R>(own, g, g + particle_group);
    } else if (two) {
      const ReadWindows<2> in_two{{first_lo, first_hi}};
      value = simd_run_reduce<R>([&](long p) { return body(p, in_two); }, g, g + particle_group);
    } else {
      const ReadWindows<3> in_three{{first_lo, other, first_hi}};
      value = simd_run_reduce<R>([&](long p) { return body(p, in_three); }, g, g + particle_group);
    }
    combine<R>(acc, value);
  }
  combine<R>(acc, simd_run_reduce<R>(own, g, hi));
  return acc;
}
}  // namespace detail
#endif

/// Like `reduce_over_particles`, for a body with `body(p, read)`, particle p's value,
/// which reads its node values through `read` (ReadOwnNodes or ReadWindows), and
/// `body.first(p)`, the place of particle p's first node as `window_place` gives it. On
/// the host the particles go in groups of 8 consecutive ones: a group whose first nodes
/// are at most three places, inside the node arrays, reads ReadWindows, else
/// ReadOwnNodes. On a GPU every particle reads its own (each thread
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

namespace detail {
#if !defined(MPMICE_DEVICE_BACKEND)
/// Particles per vector block of `reduce_over_cell_runs`: four doubles, a 256-bit vector.
constexpr long cell_block = 4;
/// Cells whose node values `reduce_over_cell_runs` takes at once: consecutive cells along
/// k, in one vector loop (their nodes' values are neighbours in memory).
constexpr int cell_batch = 4;

/// One run [lo, hi) of `reduce_over_cell_runs`, flattened (loops.hpp): for each run of
/// one cell's particles its fields, from a batch of cell_batch cells formed when the
/// cell is not in the last one, and the particles in blocks of cell_block and then 2
/// as vector loops of known length (a loop over a cell's few particles, of a length
/// known only at run time, GCC ran scalar), the last one alone. Every particle gets the
/// same arithmetic.
template <Reduction R, class Body>
MPMICE_FLATTEN MPMICE_WIDE_VECTORS double cell_run_reduce(const Body& particle_body, long lo, long hi) {
  const Body body = particle_body;  // its own copy, as simd_run_reduce
  typename Body::template CellFields<cell_batch> batch;
  long batch_start = -1;  // none yet
  double acc = 0;
  long p = lo;
  while (p < hi) {
    const long place = body.first(p);
    long end = p + 1;
    while (end < hi && body.first(end) == place) ++end;
    if (batch_start < 0 || place < batch_start || place >= batch_start + cell_batch)
      batch_start = body.cell_fields(place, batch);
    const long w = place - batch_start;
    const auto in_cell = [&](long q) { return body.in_cell(q, batch, w); };
    for (; p + cell_block <= end; p += cell_block) combine<R>(acc, simd_run_reduce<R>(in_cell, p, p + cell_block));
    if (p + 2 <= end) {
      combine<R>(acc, simd_run_reduce<R>(in_cell, p, p + 2));
      p += 2;
    }
    for (; p < end; ++p) combine<R>(acc, in_cell(p));
  }
  return acc;
}
#endif
}  // namespace detail

/// Like `reduce_over_particles`, for particles whose node values are the same for every
/// particle of a cell (the linear shape), sorted by cell (particle_sort.hpp):
/// `body.first(p)` gives the place of particle p's cell, `body.cell_fields(place, f)`
/// puts what the particles of W cells from `place` read of the nodes into a
/// `Body::CellFields<W>` and returns where the W start (`place`, or lower near the end
/// of the node arrays), and `body.in_cell(p, f, w)` is particle p's value, in cell w of
/// f. On the host a run of consecutive particles of one cell takes its fields once and
/// goes as vector loops (detail::cell_run_reduce); unsorted particles are runs of one.
/// On a GPU every particle takes its own cell's (W = 1; the same values).
template <Reduction R, class Body>
double reduce_over_cell_runs(const std::string& label, long count, const Body& body) {
#if defined(MPMICE_DEVICE_BACKEND)
  return reduce_over_particles<R>(label, count, KOKKOS_LAMBDA(long p) {
    typename Body::template CellFields<1> fields;
    body.cell_fields(body.first(p), fields);
    return body.in_cell(p, fields, 0);
  });
#else
  return detail::reduce_runs<R>(label, Kokkos::RangePolicy<ExecSpace>(0, detail::particle_runs(count)), [=](long r) {
    return detail::cell_run_reduce<R>(body, r * detail::particle_run, detail::particle_run_end(r, count));
  });
#endif
}

}  // namespace mpmice
