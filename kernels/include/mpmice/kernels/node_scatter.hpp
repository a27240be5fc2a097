#pragma once
/// \file node_scatter.hpp
/// \brief How particle loops add into nodes (p2g, internal_force): a block with a row
///        per node of the patch and the node's F fields side by side, one copy per
///        thread on the host (Kokkos ScatterView), added into the node fields after the
///        loop. The copies can be kept between calls (`ScatterScratch`), so that a step
///        does not allocate them, and fault their pages in, again.
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

namespace detail {
/// The sum of the copies of entry (row, f) in thread order, each zeroed once read.
template <class Copies>
KOKKOS_FORCEINLINE_FUNCTION double take_copies(const Copies& copies, long row, int f) {
  if constexpr (Copies::rank == 3) {  // one per thread
    double sum = copies(0, row, f);
    copies(0, row, f) = 0;
    for (long t = 1; t < long(copies.extent(0)); ++t) {
      sum += copies(t, row, f);
      copies(t, row, f) = 0;
    }
    return sum;
  } else {  // one, added into atomically
    const double sum = copies(row, f);
    copies(row, f) = 0;
    return sum;
  }
}
}  // namespace detail

/// dest[f](m, node) = start[f] + unit[f] times what the particle loop added into the
/// node's row through `scatter` (the threads' copies in thread order): p2g and
/// internal_force add each field counted in its quantum (quanta.hpp; unit 1 without
/// one), and multiply here, once per node instead of once per contribution. A sum of
/// whole counts is exact, so the product is the sum of the rounded contributions bit for
/// bit. The copies are zeroed on the way, ready for the next loop.
template <int F>
void add_scatter_into(const NodeScatter& scatter, const Kokkos::Array<Field4, F>& dest, int m,
                      const Kokkos::Array<double, F>& start, const Kokkos::Array<double, F>& unit) {
  const auto copies = scatter.copies();
  const IndexBox nodes{{0, 0, 0}, {int(dest[0].extent(1)), int(dest[0].extent(2)), int(dest[0].extent(3))}};
  const long nj = nodes.hi[1], nk = nodes.hi[2];
  for_each_index("mpmice::add_scatter_into", nodes, KOKKOS_LAMBDA(long i, long j, long k) {
    const long row = (i * nj + j) * nk + k;
    for (int f = 0; f < F; ++f) dest[f](m, i, j, k) = start[f] + unit[f] * detail::take_copies(copies, row, f);
  });
}

}  // namespace mpmice
