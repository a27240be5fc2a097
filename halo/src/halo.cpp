#include <mpmice/halo/halo.hpp>

#include <algorithm>
#include <string>

#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/loops.hpp>

namespace mpmice {
namespace {

using Field4U = Halo::Field4U;

// A slab of a 4D field: materials [0, nm) times an index box.
struct Slab {
  int nm = 0;
  IndexBox box;
  long size() const { return long(nm) * box.size(); }
};

// A slab's rows for for_each_index (kernels/loops.hpp): its (m, i) pairs folded into
// one index mi, so that the rows (mi, j) run in parallel and k, the contiguous index, as
// a vector loop.
struct SlabRows {
  long ni, nj, nk, lo_i, lo_j, lo_k;
  IndexBox box;  ///< (mi, j, k)

  explicit SlabRows(const Slab& s)
      : ni(s.box.extent(0)), nj(s.box.extent(1)), nk(s.box.extent(2)), lo_i(s.box.lo[0]), lo_j(s.box.lo[1]),
        lo_k(s.box.lo[2]), box{{0, s.box.lo[1], s.box.lo[2]}, {s.nm * s.box.extent(0), s.box.hi[1], s.box.hi[2]}} {}
  KOKKOS_INLINE_FUNCTION long m(long mi) const { return mi / ni; }
  KOKKOS_INLINE_FUNCTION long i(long mi) const { return lo_i + mi % ni; }
  /// The place of (m, i, j, k) in the buffer: m, i, j, k order, k fastest.
  KOKKOS_INLINE_FUNCTION long at(long mi, long j, long k) const { return (mi * nj + j - lo_j) * nk + k - lo_k; }
};

// Slabs of fewer entries than for_each_index_light's threshold are copied by the
// calling thread alone: for them the threads' start and join cost more than the copy (a
// fill of 16^3-64^3 cells ran 0.44-0.82x as fast on 2 threads as on 1 when every slab
// was a parallel loop). The rows are plain inline loops here, not for_each_index_light's
// row calls: a slab across k has rows of 2-3 entries.
constexpr long serial_slab_entries = detail::light_serial_indices;

// Runs f(mi, j, k) over the slab's rows (SlabRows). On the host: on the calling thread
// for a slab under `serial_slab_entries`, else in parallel over mi or j, whichever is
// longer, the other indices as plain loops (k innermost, a vector loop). A slab is
// thin in its sweep's direction (2-3 layers), so the slab across k has rows of 2-3
// entries, one call each through for_each_index. On a GPU: for_each_index.
template <class F>
void over_slab(const std::string& label, const SlabRows& r, const F& f) {
#if defined(MPMICE_DEVICE_BACKEND)
  for_each_index(label, r.box, f);
#else
  const IndexBox b = r.box;
  const auto rows = [=](long mi_lo, long mi_hi, long j_lo, long j_hi) {
    for (long mi = mi_lo; mi < mi_hi; ++mi)
      for (long j = j_lo; j < j_hi; ++j) {
        MPMICE_PRAGMA_SIMD
        for (long k = b.lo[2]; k < b.hi[2]; ++k) f(mi, j, k);
      }
  };
  if (b.size() < serial_slab_entries)
    rows(b.lo[0], b.hi[0], b.lo[1], b.hi[1]);
  else if (b.extent(0) >= b.extent(1))
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(b.lo[0], b.hi[0]),
                         [=](long mi) { rows(mi, mi + 1, b.lo[1], b.hi[1]); });
  else
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(b.lo[1], b.hi[1]),
                         [=](long j) { rows(b.lo[0], b.hi[0], j, j + 1); });
#endif
}

// Pack the slab of `f` into `buf`.
void pack(const Field4U& f, const Slab& s, const Kokkos::View<double*, MemSpace>& buf) {
  const SlabRows r(s);
  over_slab("mpmice::halo_pack", r, KOKKOS_LAMBDA(long mi, long j, long k) {
    buf(r.at(mi, j, k)) = f(r.m(mi), r.i(mi), j, k);
  });
}

// Unpack `buf` into the slab of `f`, replacing (fill) or adding (reverse sum).
void unpack(const Field4U& f, const Slab& s, const Kokkos::View<double*, MemSpace>& buf,
            bool add) {
  const SlabRows r(s);
  if (add)
    over_slab("mpmice::halo_unpack_add", r, KOKKOS_LAMBDA(long mi, long j, long k) {
      f(r.m(mi), r.i(mi), j, k) += buf(r.at(mi, j, k));
    });
  else
    over_slab("mpmice::halo_unpack", r, KOKKOS_LAMBDA(long mi, long j, long k) {
      f(r.m(mi), r.i(mi), j, k) = buf(r.at(mi, j, k));
    });
}

void ensure_size(Kokkos::View<double*, MemSpace>& v, long n) {
  if (long(v.extent(0)) < n) v = Kokkos::View<double*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mpmice::halo_buffer"), n);
}

Field4U as_field4(const Field3& f) {
  if (!f.span_is_contiguous())
    throw std::logic_error("mpmice::Halo: a material-independent field must be contiguous");
  return Field4U(f.data(), 1, f.extent(0), f.extent(1), f.extent(2));
}

}  // namespace

void Halo::fill(const Field4& field, Location loc, int depth) {
  exchange(field, loc, depth, false);
}
void Halo::fill(const Field3& field, Location loc, int depth) {
  exchange(as_field4(field), loc, depth, false);
}
void Halo::sum_into_owned(const Field4& field, Location loc, int depth) {
  exchange(field, loc, depth, true);
}
void Halo::sum_into_owned(const Field3& field, Location loc, int depth) {
  exchange(as_field4(field), loc, depth, true);
}

void Halo::exchange(const Field4U& f, Location loc, int depth, bool reverse) {
  const Patch& p = m_decomp.patch();
  const int G = p.ghosts;
  if (depth < 1 || depth > G)
    throw std::logic_error("mpmice::Halo: ghost depth " + std::to_string(depth) +
                           " outside 1.." + std::to_string(G));
  for (int d = 0; d < 3; ++d)
    if (int(f.extent(d + 1)) != p.extent(loc, d))
      throw std::logic_error("mpmice::Halo: field '" + f.label() +
                             "' does not have the extents of its location on this patch");
  const int nm = f.extent(0);

  for (int d = 0; d < 3; ++d) {
    const int low = m_decomp.neighbor(d == 0 ? -1 : 0, d == 1 ? -1 : 0, d == 2 ? -1 : 0);
    const int high = m_decomp.neighbor(d == 0 ? 1 : 0, d == 1 ? 1 : 0, d == 2 ? 1 : 0);
    if (low == MPI_PROC_NULL && high == MPI_PROC_NULL) continue;

    // Extents in the other directions. Fill: directions already swept carry their
    // ghosts; later ones their interior; both carry every extra layer beyond a domain
    // boundary (boundary values the owner computed, which no other sweep would bring: a
    // reader of `depth` ghosts across a rank may read all the extra layers along the
    // domain's face, as the cell-to-node average onto the extra nodes does).
    // Reverse: directions not yet swept carry their ghosts, the others what is owned
    // (extra layers included).
    Slab base;
    base.nm = nm;
    const IndexBox computed = p.with_extra(loc, reverse ? depth : G);
    for (int e = 0; e < 3; ++e) {
      if (e == d) continue;
      const int nl = on_cell_boundary(loc, e) ? 1 : 0;
      const bool with_ghosts = reverse ? (e > d) : (e < d);
      const int reach = with_ghosts ? depth : 0;
      if (reverse && !with_ghosts) {
        // Owned and extra entries: a contribution to an extra node beyond a domain
        // boundary (GIMP near the boundary) belongs to the patch it borders.
        base.box.lo[e] = computed.lo[e];
        base.box.hi[e] = computed.hi[e];
      } else if (reverse) {
        base.box.lo[e] = G - reach;
        base.box.hi[e] = G + p.owned_cells(e) + nl + reach;
      } else {
        base.box.lo[e] = std::min(computed.lo[e], G - reach);
        base.box.hi[e] = std::max(computed.hi[e], G + p.owned_cells(e) + nl + reach);
      }
    }
    const int n = p.owned_cells(d);
    const int nl = on_cell_boundary(loc, d) ? 1 : 0;
    // side 0: toward the low neighbour, side 1: toward the high neighbour.
    // Owned layers a neighbour needs, and the ghost layers that mirror them.
    Slab owned_for[2] = {base, base}, ghost_of[2] = {base, base};
    owned_for[0].box.lo[d] = G;                 owned_for[0].box.hi[d] = G + depth + nl;
    owned_for[1].box.lo[d] = G + n - depth;     owned_for[1].box.hi[d] = G + n;
    ghost_of[0].box.lo[d] = G - depth;          ghost_of[0].box.hi[d] = G;
    ghost_of[1].box.lo[d] = G + n;              ghost_of[1].box.hi[d] = G + n + depth + nl;
    // Fill sends owned layers and receives into ghosts; reverse sends ghost layers and
    // adds them into the owned layers they shadow.
    const Slab* send_slab = reverse ? ghost_of : owned_for;
    const Slab* recv_slab = reverse ? owned_for : ghost_of;
    const int to[2] = {low, high};
    // Side s sends to neighbour to[s]; what arrives from to[s] lands on side s. The
    // tag says which side of the receiver a message is for, so that one rank that is
    // both neighbours (two ranks, periodic) keeps the two messages apart.
    const int tag_base = 7100 + 4 * d;
    MPI_Request req[4];
    int nreq = 0;
    for (int s = 0; s < 2; ++s) {
      ensure_size(m_send[s], send_slab[s].size());
      ensure_size(m_recv[s], recv_slab[s].size());
    }
    for (int s = 0; s < 2; ++s) {
      if (to[s] == MPI_PROC_NULL || to[s] == m_decomp.rank()) continue;
      MPI_Irecv(m_recv[s].data(), int(recv_slab[s].size()), MPI_DOUBLE, to[s], tag_base + s,
                m_decomp.comm(), &req[nreq++]);
    }
    for (int s = 0; s < 2; ++s) {
      if (to[s] == MPI_PROC_NULL) continue;
      // Periodic, one rank across: what side s sends arrives on side 1-s, packed there
      // directly (the slabs of the two sides have the same size).
      pack(f, send_slab[s], to[s] == m_decomp.rank() ? m_recv[1 - s] : m_send[s]);
    }
    Kokkos::fence();
    for (int s = 0; s < 2; ++s) {
      if (to[s] == MPI_PROC_NULL || to[s] == m_decomp.rank()) continue;
      // A message sent toward side s arrives on the receiver's side 1-s.
      MPI_Isend(m_send[s].data(), int(send_slab[s].size()), MPI_DOUBLE, to[s], tag_base + (1 - s),
                m_decomp.comm(), &req[nreq++]);
      m_bytes_sent += 8.0 * send_slab[s].size();
    }
    MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
    for (int s = 0; s < 2; ++s) {
      if (to[s] == MPI_PROC_NULL) continue;
      unpack(f, recv_slab[s], m_recv[s], reverse);
    }
    Kokkos::fence();
  }
}

}  // namespace mpmice
