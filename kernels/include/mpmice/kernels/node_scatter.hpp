#pragma once
/// \file node_scatter.hpp
/// \brief How particle loops add into nodes (p2g, internal_force): a block with a row
///        per node of the patch and the node's F fields side by side, one copy per
///        thread on the host (Kokkos ScatterView), added into the node fields after the
///        loop. The copies can be kept between calls (`ScatterScratch`), so that a step
///        does not allocate them, and fault their pages in, again.
#include <stdexcept>
#include <string>

#include <Kokkos_ScatterView.hpp>

#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/particle_grid.hpp>

namespace mpmice {

/// How the scatter adds: on the host each thread into its own copy (duplicated, also
/// for Serial, whose ScatterView default is not), on a GPU atomically into one block.
/// Chosen here, not left to Kokkos's default, because `copies()` reads them differently.
#if defined(MPMICE_DEVICE_BACKEND)
using ScatterDuplication = Kokkos::Experimental::ScatterNonDuplicated;
#else
using ScatterDuplication = Kokkos::Experimental::ScatterDuplicated;
#endif

/// The one scatter: Kokkos's ScatterView over a block (row, field) with a row per node,
/// (i, j, k) at row (i n_j + j) n_k + k (`block_stencil`). A particle finds a node's row
/// once for all its fields. On the host each thread adds into its own copy; on a GPU
/// the adds are atomic into one block (docs/performance.md, bench_scatter.cpp).
/// `copies()` lets `add_scatter_into` read the copies in the pass that writes the node
/// fields (ScatterView's own `contribute` sums them into a block first: one pass more).
class NodeScatter : public Kokkos::Experimental::ScatterView<double**, Kokkos::LayoutRight, ExecSpace,
                                                             Kokkos::Experimental::ScatterSum, ScatterDuplication> {
  using Base = Kokkos::Experimental::ScatterView<double**, Kokkos::LayoutRight, ExecSpace,
                                                 Kokkos::Experimental::ScatterSum, ScatterDuplication>;

 public:
  NodeScatter() = default;
  /// Zeroed copies of a block of `rows` x `fields`.
  NodeScatter(const std::string& label, long rows, int fields) : Base(label, std::size_t(rows), std::size_t(fields)) {}
  /// The copies: (thread, row, field) when duplicated (the ScatterView's protected
  /// member), the block (row, field) when not (there the member is private; `subview()`
  /// is the block itself).
#if defined(MPMICE_DEVICE_BACKEND)
  auto copies() const { return this->subview(); }
#else
  auto copies() const { return this->internal_view; }
#endif
};

/// Nodes of the patch (rows of the block) of a node field shaped like `like`.
inline long node_rows(const ConstField4& like) { return long(like.extent(1) * like.extent(2) * like.extent(3)); }

/// Where a particle's nodes are in the block over the nodes of `like`.
template <int Nodes>
NodeStencil<Nodes> block_stencil(const ConstField4& like) {
  return NodeStencil<Nodes>(0, long(like.extent(2) * like.extent(3)), long(like.extent(3)), 1);
}

/// A NodeScatter kept between calls of a particle loop: reallocated only when the
/// patch's nodes or the number of fields change, and left zeroed by `add_scatter_into`.
/// A driver keeps one per scatter kernel; a call without one allocates its own.
class ScatterScratch {
 public:
  /// Zeroed copies of `fields` fields over the nodes of `like`.
  const NodeScatter& zeroed(const char* label, const ConstField4& like, int fields) {
    const long rows = node_rows(like);
    if (rows != m_rows || fields != m_fields) {
      m_scatter = NodeScatter(label, rows, fields);
      m_rows = rows;
      m_fields = fields;
    }
    return m_scatter;
  }

 private:
  NodeScatter m_scatter;
  long m_rows = -1;
  int m_fields = -1;
};

/// dest[f](m, node) = start[f] + unit[f] times what the particle loop added into the
/// node's row through `scatter` (the threads' copies in thread order): p2g and
/// internal_force add each field counted in its quantum (quanta.hpp; unit 1 without
/// one), and multiply here, once per node instead of once per contribution. A sum of
/// whole counts is exact, so the product is the sum of the rounded contributions bit for
/// bit. The copies are zeroed on the way, ready for the next loop.
///
/// On the host a row of nodes (i, j) at a time: a vector loop along k over the nodes'
/// fields (their rows of F values read as strided vectors), then each copy's rows
/// zeroed as one contiguous stretch. Until session 45 a node at a time, field by
/// field, with the copies' loop inside: a scalar loop that recomputed each field's
/// address, 16% of p2g's time on 1 thread at 1e6 particles (since then p2g 1.07-1.14x
/// faster at 1e6-4e6, docs/performance.md, session 45). With more than two copies
/// (threads) the later ones add into `dest` row by row, in thread order, before the
/// scaling: the same sums. On a GPU the one block, added into atomically, node by node.
template <int F>
void add_scatter_into(const NodeScatter& scatter, const Kokkos::Array<Field4, F>& dest, int m,
                      const Kokkos::Array<double, F>& start, const Kokkos::Array<double, F>& unit) {
  const auto copies = scatter.copies();
  const long ni = dest[0].extent(1), nj = dest[0].extent(2), nk = dest[0].extent(3);
#if defined(MPMICE_DEVICE_BACKEND)
  const IndexBox nodes{{0, 0, 0}, {int(ni), int(nj), int(nk)}};
  for_each_index("mpmice::add_scatter_into", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const long row = (i * nj + j) * nk + k;
    for (int f = 0; f < F; ++f) {
      dest[f](m, i, j, k) = start[f] + unit[f] * copies(row, f);
      copies(row, f) = 0;
    }
  });
#else
  // Each copy's rows, one after another (a LayoutRight block without padding), a row
  // for every node of `dest`.
  const long count = copies.extent(0), rows = copies.extent(1);
  if (copies.stride(1) != F || copies.stride(2) != 1 || rows < ni * nj * nk)
    throw std::logic_error("add_scatter_into: the scatter's copies are not a row of F values per node of dest");
  const Kokkos::View<double**, Kokkos::LayoutRight, ExecSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> entries(
      copies.data(), count, rows * F);
  const IndexBox lines{{0, 0, 0}, {int(ni), int(nj), 1}};
  for_each_index("mpmice::add_scatter_into", lines, KOKKOS_LAMBDA(long i, long j, long) {
    const long row0 = (i * nj + j) * nk;
    if (count == 1) {
      MPMICE_PRAGMA_SIMD
      for (long k = 0; k < nk; ++k)
        unrolled_for<F>([&](int f) { dest[f](m, i, j, k) = start[f] + unit[f] * copies(0, row0 + k, f); });
    } else if (count == 2) {
      MPMICE_PRAGMA_SIMD
      for (long k = 0; k < nk; ++k)
        unrolled_for<F>([&](int f) {
          dest[f](m, i, j, k) = start[f] + unit[f] * (copies(0, row0 + k, f) + copies(1, row0 + k, f));
        });
    } else {
      MPMICE_PRAGMA_SIMD
      for (long k = 0; k < nk; ++k)
        unrolled_for<F>([&](int f) { dest[f](m, i, j, k) = copies(0, row0 + k, f) + copies(1, row0 + k, f); });
      for (long t = 2; t < count - 1; ++t) {
        MPMICE_PRAGMA_SIMD
        for (long k = 0; k < nk; ++k) unrolled_for<F>([&](int f) { dest[f](m, i, j, k) += copies(t, row0 + k, f); });
      }
      MPMICE_PRAGMA_SIMD
      for (long k = 0; k < nk; ++k)
        unrolled_for<F>([&](int f) {
          dest[f](m, i, j, k) = start[f] + unit[f] * (dest[f](m, i, j, k) + copies(count - 1, row0 + k, f));
        });
    }
    for (long t = 0; t < count; ++t) {
      MPMICE_PRAGMA_SIMD
      for (long e = row0 * F; e < (row0 + nk) * F; ++e) entries(t, e) = 0;
    }
  });
#endif
}

}  // namespace mpmice
