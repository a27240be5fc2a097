#pragma once
/// \file loops.hpp
/// \brief The loop shapes of the cell and particle kernels: `for_each_index` runs a
///        body over every index of a box in parallel, `reduce_over_index` also sums or
///        maximises what the body returns, `for_each_particle` and
///        `reduce_over_particles` do the same over particles, `unrolled_for` writes
///        out a short loop whose length is known at compile time (a cell's materials,
///        a small solve's rows, a particle's nodes). Together they let
///        the compiler vectorise a kernel across cells or particles (docs/design.md,
///        "Cell loops that vectorise"). Their bodies must be `KOKKOS_LAMBDA`s: on a GPU
///        they run on the device, and nvcc lets the helpers wrap them in lambdas of
///        their own only when they are extended (device) lambdas.
#include <string>
#include <type_traits>
#include <utility>

#include <mpmice/kernels/types.hpp>

// `omp simd` on the host only: never in a GPU backend's device pass (a CUDA or HIP
// build with OpenMP on the host defines _OPENMP there too). MPMICE_OPENMP_SIMD: the
// compiler honours `omp simd` without OpenMP (-fopenmp-simd, set by kernels/CMakeLists.txt
// for a Kokkos without OpenMP).
#if (defined(_OPENMP) || defined(MPMICE_OPENMP_SIMD)) && !defined(__CUDA_ARCH__) && \
    !defined(__HIP_DEVICE_COMPILE__) && !defined(__SYCL_DEVICE_ONLY__)
#define MPMICE_HOST_SIMD 1
#define MPMICE_PRAGMA_SIMD _Pragma("omp simd")
#else
#define MPMICE_PRAGMA_SIMD
#endif
// MPMICE_ROW: a row function of its own, flattened and never inlined into its caller:
// inlined (GCC 12 did so for some kernels once the rows' direction became a choice),
// its flattening was lost and the body stayed a call per cell, the loop scalar.
#if defined(__GNUC__)
#define MPMICE_FLATTEN __attribute__((flatten))
#define MPMICE_ROW __attribute__((flatten, noinline))
#else
#define MPMICE_FLATTEN
#define MPMICE_ROW
#endif
// MPMICE_WIDE_VECTORS: the loop functions below (simd_run, simd_row, ...) are
// vectorised by GCC in 256-bit vectors where its tuning prefers 128 bits with AVX2 (AMD
// Zen 1: -march=znver1, or native there); the bodies flattened into them take their
// setting. Other CPUs and compilers keep their own choice. Why these functions and not
// the whole build: docs/design.md, "Vector width"; what it gained: docs/performance.md,
// session 32.
#if defined(MPMICE_HOST_SIMD) && defined(__GNUC__) && !defined(__clang__) && defined(__AVX2__) && \
    defined(__tune_znver1__)
#define MPMICE_WIDE_VECTORS __attribute__((target("prefer-vector-width=256")))
#define MPMICE_WIDE_VECTORS_ARE_WIDER 1
#else
#define MPMICE_WIDE_VECTORS
#define MPMICE_WIDE_VECTORS_ARE_WIDER 0
#endif

namespace mpmice {

/// What `reduce_over_index` and `reduce_over_particles` compute: the sum, or the largest
/// value and 0.
enum class Reduction { sum, max };

/// Whether the loop functions' vectors are wider than the compiler's own choice here
/// (MPMICE_WIDE_VECTORS).
constexpr bool wide_vectors_are_wider = MPMICE_WIDE_VECTORS_ARE_WIDER;

/// Which index `for_each_index` and `reduce_over_index` run as the vector loop on the
/// host. `along_k`: always k, the contiguous one. `longest`: k, unless the box is thin
/// along k (fewer than `detail::short_row` cells: a quasi-1D or 2D problem, a face's
/// slab) and has at least that many along i or j; then the longer of those (i on a
/// tie), with strided reads and writes (gathers), in pieces of `detail::row_piece`.
/// For bodies with much arithmetic per value they touch (the ICE cell kernels), which
/// rows of a few cells along k leave scalar; streaming bodies (copies, averages of
/// neighbours) keep k, where strided access costs more than vectors save
/// (docs/design.md, "Cell loops that vectorise").
enum class Rows { along_k, longest };

namespace detail {
/// Adds `value` into the partial result v as reduction R does.
template <Reduction R>
KOKKOS_FORCEINLINE_FUNCTION void combine(double& v, double value) {
  if constexpr (R == Reduction::sum)
    v += value;
  else
    v = value > v ? value : v;
}

/// f(n, a, b) (Along = 0, a row along i) or f(a, n, b) (Along = 1, along j): the row's
/// index n in its place among the row's fixed indices a and b.
template <int Along, class F>
KOKKOS_FORCEINLINE_FUNCTION decltype(auto) call_in_row(const F& f, long n, long a, long b) {
  if constexpr (Along == 0)
    return f(n, a, b);
  else
    return f(a, n, b);
}

/// One run of `for_each_index` or `for_each_particle`: f(fixed..., k) for k from lo to
/// hi (a row (i, j) of cells, or a chunk of particles). Flattened (every call inside
/// inlined), because a call left in the loop keeps it from vectorising.
template <class F, class... Fixed>
MPMICE_FLATTEN MPMICE_WIDE_VECTORS void simd_run(const F& f, long lo, long hi, Fixed... fixed) {
  MPMICE_PRAGMA_SIMD
  for (long k = lo; k < hi; ++k) f(fixed..., k);
}

/// With Rows::longest, a box with fewer cells than this along k runs along i or j.
constexpr long short_row = 8;

/// Cells per piece of a row along i or j: a quasi-1D box (the Sod tube, 400 x 1 x 1)
/// has one such row, which whole would run on one thread.
constexpr long row_piece = 64;

/// The rows of a box as `for_each_index` runs them on the host: along index `along`,
/// row r from lo(r) to hi(r) with fixed indices a(r) and b(r) (the other two, in
/// order). Rows along k are whole; rows along i or j come in pieces of row_piece cells.
struct BoxRows {
  int along;
  long rows;
  long first, last, pieces;  // the rows' extent along `along`, and the pieces of each
  long a_lo, b_lo, b_count;

  BoxRows(const IndexBox& box, Rows choice) {
    const long n0 = box.extent(0), n1 = box.extent(1), n2 = box.extent(2);
    const bool thin = choice == Rows::longest && n2 < short_row;
    along = thin && n0 >= short_row && n0 >= n1 ? 0 : thin && n1 >= short_row ? 1 : 2;
    const int ia = along == 0 ? 1 : 0, ib = along == 2 ? 1 : 2;
    first = box.lo[along];
    last = box.hi[along];
    pieces = along == 2 ? 1 : (last - first + row_piece - 1) / row_piece;
    a_lo = box.lo[ia];
    b_lo = box.lo[ib];
    b_count = box.extent(ib);
    rows = box.extent(ia) * b_count * pieces;
  }
  long lo(long r) const { return first + (r % pieces) * row_piece; }
  long hi(long r) const { return pieces == 1 || lo(r) + row_piece > last ? last : lo(r) + row_piece; }
  long a(long r) const { return a_lo + r / pieces / b_count; }
  long b(long r) const { return b_lo + r / pieces % b_count; }
};

/// launch(std::integral_constant<int, A>) for the box's row direction A: only k when
/// the choice is Rows::along_k (no other instantiations).
template <Rows Choice, class Launch>
void with_row_direction(const BoxRows& rows, const Launch& launch) {
  if constexpr (Choice == Rows::longest) {
    if (rows.along == 0) return launch(std::integral_constant<int, 0>{});
    if (rows.along == 1) return launch(std::integral_constant<int, 1>{});
  }
  return launch(std::integral_constant<int, 2>{});
}

/// One run of `scatter_from_particles`: like simd_run, without the `omp simd`. Not in
/// wide vectors: p2g with GIMP weights, its one user of note, ran 0.95x in them.
template <class F>
MPMICE_FLATTEN void serial_run(const F& f, long lo, long hi) {
  for (long p = lo; p < hi; ++p) f(p);
}

/// f(lo, hi), flattened: a run of `scatter_from_particle_runs`.
template <class F>
MPMICE_FLATTEN MPMICE_WIDE_VECTORS void flat_run(const F& f, long lo, long hi) {
  f(lo, hi);
}

/// One run of `reduce_over_index` or `reduce_over_particles`. It works on its own copy
/// of the body: with the `omp simd` reduction, GCC did not hoist the views' addresses
/// out of the loop when the body reads them through a reference and also stores to a view.
template <Reduction R, class F, class... Fixed>
MPMICE_FLATTEN MPMICE_WIDE_VECTORS double simd_run_reduce(const F& body, long lo, long hi, Fixed... fixed) {
  const F f = body;
  double acc = 0;
  if constexpr (R == Reduction::sum) {
#if defined(MPMICE_HOST_SIMD)
#pragma omp simd reduction(+ : acc)
#endif
    for (long k = lo; k < hi; ++k) acc += f(fixed..., k);
  } else {
#if defined(MPMICE_HOST_SIMD)
#pragma omp simd reduction(max : acc)
#endif
    for (long k = lo; k < hi; ++k) {
      const double v = f(fixed..., k);
      acc = v > acc ? v : acc;
    }
  }
  return acc;
}

/// A row of `for_each_index` as a row function of its own (MPMICE_ROW): simd_run along
/// k, or the same vector loop with the row's index n in place `Along` (i or j).
template <int Along, class F>
MPMICE_ROW MPMICE_WIDE_VECTORS void simd_row(const F& f, long lo, long hi, long a, long b) {
  if constexpr (Along == 2) {
    simd_run(f, lo, hi, a, b);
  } else {
    MPMICE_PRAGMA_SIMD
    for (long n = lo; n < hi; ++n) call_in_row<Along>(f, n, a, b);
  }
}

/// The body f(i, j, k) of a row along i or j as a body of the row's index alone.
template <int Along, class F>
struct RowBody {
  F f;
  long a, b;
  KOKKOS_FORCEINLINE_FUNCTION decltype(auto) operator()(long n) const { return call_in_row<Along>(f, n, a, b); }
};

/// A row of `reduce_over_index`: simd_run_reduce as a row function of its own.
template <Reduction R, int Along, class F>
MPMICE_ROW MPMICE_WIDE_VECTORS double simd_row_reduce(const F& f, long lo, long hi, long a, long b) {
  if constexpr (Along == 2)
    return simd_run_reduce<R>(f, lo, hi, a, b);
  else
    return simd_run_reduce<R>(RowBody<Along, F>{f, a, b}, lo, hi);
}

/// Kokkos's reduction of the runs' values: their sum, or their largest and 0.
template <Reduction R, class Policy, class Run>
double reduce_runs(const std::string& label, const Policy& runs, const Run& run) {
  double result = 0;
  const auto add = KOKKOS_LAMBDA(long r, double& v) { combine<R>(v, run(r)); };
  if constexpr (R == Reduction::sum)
    Kokkos::parallel_reduce(label, runs, add, result);
  else
    Kokkos::parallel_reduce(label, runs, add, Kokkos::Max<double>(result));
  if constexpr (R == Reduction::max) return result > 0 ? result : 0;  // Max starts from the lowest double
  return result;
}

/// Particles per run of `for_each_particle` on the host: long enough for the vector
/// loop, short enough that the threads share the work evenly.
constexpr long particle_run = 256;

/// How many runs cover `count` particles, and where run r ends.
inline long particle_runs(long count) { return (count + particle_run - 1) / particle_run; }
KOKKOS_INLINE_FUNCTION long particle_run_end(long r, long count) {
  const long end = (r + 1) * particle_run;
  return end < count ? end : count;
}

/// Calls run(lo, hi) for every run of particles, in parallel (host).
template <class Run>
void over_particle_runs(const std::string& label, long count, const Run& run) {
  Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, particle_runs(count)),
                       [=](long r) { run(r * particle_run, particle_run_end(r, count)); });
}
}  // namespace detail

/// Runs f(i, j, k) for every index of `box`, in parallel; the indices are `long`.
/// On a GPU this is the MDRange policy. On the host (OpenMP, Serial) each thread
/// takes whole rows (i, j) and runs k, the contiguous index, as an `omp simd` loop
/// (with `Rows::longest`, a box thin along k runs rows along i or j instead).
/// GCC 12 vectorises that loop when the body has no branches or inner loops left
/// after inlining (materials and small solves written out with `unrolled_for`) and
/// indexes its views with `long` (an `int` index converted to the view's size_t
/// offset defeats its stride analysis); it does not vectorise through an MDRange's
/// tiles. A body that cannot vectorise (a loop over a run-time number of slots, a
/// library call) still gains the rows' long indices and no tile bookkeeping; some
/// such kernels keep `IndexBox::policy()`. `Choice`: see `Rows` (the host only).
template <Rows Choice = Rows::along_k, class F>
void for_each_index(const std::string& label, const IndexBox& box, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  Kokkos::parallel_for(label, box.policy(), f);
#else
  if (box.size() == 0) return;
  const detail::BoxRows rows(box, Choice);
  detail::with_row_direction<Choice>(rows, [&](auto along) {
    constexpr int A = decltype(along)::value;
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, rows.rows), [=](long r) {
      detail::simd_row<A>(f, rows.lo(r), rows.hi(r), rows.a(r), rows.b(r));
    });
  });
#endif
}

namespace detail {
/// Boxes of fewer indices than this run on the calling thread in `for_each_index_light`
/// (and the halo's slabs, halo.cpp): for a copy of so few values the threads' start and
/// join cost more than the copy (a face exchange of one material, a copy of 4,352 values
/// at 16^3 cells, ran 0.64-0.72x as fast on 2 threads as on 1; docs/performance.md).
constexpr long light_serial_indices = 1L << 15;
}  // namespace detail

/// `for_each_index` (rows along k) for a body that moves a few values per index and
/// computes little, such as a copy: on the host a box of fewer than
/// `detail::light_serial_indices` indices runs its rows on the calling thread.
template <class F>
void for_each_index_light(const std::string& label, const IndexBox& box, const F& f) {
#if !defined(MPMICE_DEVICE_BACKEND)
  if (box.size() < detail::light_serial_indices) {
    const detail::BoxRows rows(box, Rows::along_k);
    for (long r = 0; r < rows.rows; ++r) detail::simd_row<2>(f, rows.lo(r), rows.hi(r), rows.a(r), rows.b(r));
    return;
  }
#endif
  for_each_index(label, box, f);
}

/// Like `for_each_index`, for a body f(i, j, k) that returns a double: returns the
/// sum of the values, or the largest of them and 0 (e.g. a 0/1 failure flag). Within a
/// row the sum's order depends only on the row's length (and, with `Rows::longest`, on
/// which index the rows follow, from the box's shape); the rows' sums are combined
/// as any Kokkos parallel_reduce combines them. A double returned by value, not a long
/// raised through a reference: with either, GCC 12 did not vectorise the loop (AVX2 has
/// no 64-bit integer max or long -> double conversion).
template <Reduction R, Rows Choice = Rows::along_k, class F>
double reduce_over_index(const std::string& label, const IndexBox& box, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  double result = 0;
  const auto body = KOKKOS_LAMBDA(int i, int j, int k, double& v) { detail::combine<R>(v, f(i, j, k)); };
  if constexpr (R == Reduction::sum)
    Kokkos::parallel_reduce(label, box.policy(), body, result);
  else
    Kokkos::parallel_reduce(label, box.policy(), body, Kokkos::Max<double>(result));
  if constexpr (R == Reduction::max) return result > 0 ? result : 0;
  return result;
#else
  if (box.size() == 0) return 0;
  const detail::BoxRows rows(box, Choice);
  double result = 0;
  detail::with_row_direction<Choice>(rows, [&](auto along) {
    constexpr int A = decltype(along)::value;
    result = detail::reduce_runs<R>(label, Kokkos::RangePolicy<ExecSpace>(0, rows.rows), [=](long r) {
      return detail::simd_row_reduce<R, A>(f, rows.lo(r), rows.hi(r), rows.a(r), rows.b(r));
    });
  });
  return result;
#endif
}

/// Runs f(p) for particles p = 0 .. count - 1, in parallel; p is `long`. On the host
/// each thread takes runs of `detail::particle_run` particles as `omp simd` loops: a
/// particle kernel vectorises across particles when its body has no branches or
/// loops of unknown length left (its nodes written out with `unrolled_for`), the node
/// values then loaded by gathers. On a GPU this is a plain range.
template <class F>
void for_each_particle(const std::string& label, long count, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, count), f);
#else
  detail::over_particle_runs(label, count, [=](long lo, long hi) { detail::simd_run(f, lo, hi); });
#endif
}

/// Runs f(p) for particles p = 0 .. count - 1 whose bodies add into shared sums (a
/// scatter through a ScatterView): like `for_each_particle`, but a run is not a vector
/// loop, since two particles of one run may add into one node. Its body is still
/// flattened, so a particle's nodes written out with `unrolled_for` become straight
/// code (a body left as calls ran 3x slower).
template <class F>
void scatter_from_particles(const std::string& label, long count, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, count), f);
#else
  detail::over_particle_runs(label, count, [=](long lo, long hi) { detail::serial_run(f, lo, hi); });
#endif
}

/// Runs f(lo, hi) over runs of consecutive particles [lo, hi) covering 0 .. count - 1,
/// in parallel, for scatters that add a run's particles together before adding into
/// shared sums (p2g: neighbours in a sorted set share their nodes). On the host a run
/// is `detail::particle_run` particles, its body flattened (as `scatter_from_particles`);
/// on a GPU one particle.
template <class F>
void scatter_from_particle_runs(const std::string& label, long count, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) { f(p, p + 1); });
#else
  detail::over_particle_runs(label, count, [=](long lo, long hi) { detail::flat_run(f, lo, hi); });
#endif
}

/// Like `for_each_particle`, for a body f(p) that returns a double: their sum, or
/// their largest and 0 (as `reduce_over_index`).
template <Reduction R, class F>
double reduce_over_particles(const std::string& label, long count, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  return detail::reduce_runs<R>(label, Kokkos::RangePolicy<ExecSpace>(0, count), f);
#else
  return detail::reduce_runs<R>(label, Kokkos::RangePolicy<ExecSpace>(0, detail::particle_runs(count)), [=](long r) {
    return detail::simd_run_reduce<R>(f, r * detail::particle_run, detail::particle_run_end(r, count));
  });
#endif
}

namespace detail {
template <class F, int... I>
KOKKOS_FORCEINLINE_FUNCTION void unrolled_calls(const F& f, std::integer_sequence<int, I...>) {
  (f(I), ...);
}
}  // namespace detail

/// Calls f(0), f(1), ..., f(N - 1), written out: each call sees its index as a
/// constant, so conditions on it fold away and arrays indexed by it live in registers.
template <int N, class F>
KOKKOS_FORCEINLINE_FUNCTION void unrolled_for(const F& f) {
  detail::unrolled_calls(f, std::make_integer_sequence<int, N>{});
}

}  // namespace mpmice
