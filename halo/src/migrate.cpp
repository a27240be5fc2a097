#include <mpmice/halo/migrate.hpp>

#include <map>
#include <string>
#include <vector>

#include <mpmice/kernels/errors.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {
namespace {

constexpr int stays = -1;        // destination: this rank
constexpr int outside = -2;      // destination: none, left the domain
constexpr int tag_count = 7201, tag_data = 7202, tag_id = 7203;

// Device-side description of the split, to find a particle's owner.
struct Owner {
  Kokkos::Array<double, 3> lower, spacing;
  Kokkos::Array<int, 3> cells, dims, periodic;
  Kokkos::View<int* [3], MemSpace> starts;  // block starts, row c, column d; row dims = cells
  int me;

  // Destination rank of a particle at x (wrapped in place across periodic sides).
  KOKKOS_INLINE_FUNCTION int operator()(double* x) const {
    int c[3];
    for (int d = 0; d < 3; ++d) {
      const double length = cells[d] * spacing[d];
      long cell = long(math::floor((x[d] - lower[d]) / spacing[d]));
      if (cell < 0 || cell >= cells[d]) {
        if (!periodic[d]) return outside;
        if (cell < 0) {
          x[d] += length;
        } else {
          x[d] -= length;
        }
        cell = long(math::floor((x[d] - lower[d]) / spacing[d]));
        if (cell < 0) cell = 0;  // round-off at the seam
        if (cell >= cells[d]) cell = cells[d] - 1;
      }
      int b = 0;
      while (b + 1 < dims[d] && starts(b + 1, d) <= cell) ++b;
      c[d] = b;
    }
    const int r = (c[0] * dims[1] + c[1]) * dims[2] + c[2];
    return r == me ? stays : r;
  }
};

}  // namespace

MigrationStats migrate(const Decomposition& dec, ParticleSet& particles) {
  const Grid& grid = dec.grid();
  Owner owner;
  int max_dims = 1;
  for (int d = 0; d < 3; ++d) {
    owner.lower[d] = grid.lower[d];
    owner.spacing[d] = grid.spacing[d];
    owner.cells[d] = grid.cells[d];
    owner.dims[d] = dec.dims()[d];
    owner.periodic[d] = dec.periodic()[d];
    if (dec.dims()[d] > max_dims) max_dims = dec.dims()[d];
  }
  owner.me = dec.rank();
  owner.starts = Kokkos::View<int* [3], MemSpace>("mpmice::migrate_starts", max_dims + 1);
  auto starts_h = Kokkos::create_mirror_view(owner.starts);
  for (int d = 0; d < 3; ++d)
    for (int c = 0; c <= max_dims; ++c) starts_h(c, d) = dec.block_start(d, std::min(c, dec.dims()[d]));
  Kokkos::deep_copy(owner.starts, starts_h);

  // 1. Destination of every live particle (positions wrapped across periodic sides).
  const long n = long(particles.size());
  Kokkos::View<int*, MemSpace> dest("mpmice::migrate_dest", n);
  {
    auto x = particles.get(ParticleField::x);
    auto y = particles.get(ParticleField::y);
    auto z = particles.get(ParticleField::z);
    Kokkos::parallel_for(
        "mpmice::migrate_destination", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(long p) {
          double pos[3] = {x(p), y(p), z(p)};
          dest(p) = owner(pos);
          x(p) = pos[0];
          y(p) = pos[1];
          z(p) = pos[2];
        });
  }
  auto dest_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dest);

  // 2. Group the leaving particles by neighbour rank.
  const std::vector<int>& nbrs = dec.neighbor_ranks();
  std::map<int, int> slot;
  for (std::size_t s = 0; s < nbrs.size(); ++s) slot[nbrs[s]] = int(s);
  std::vector<std::vector<long>> send_rows(nbrs.size());
  std::vector<long> keep_rows;
  keep_rows.reserve(n);
  MigrationStats stats;
  for (long p = 0; p < n; ++p) {
    const int r = dest_h(p);
    if (r == stays) {
      keep_rows.push_back(p);
    } else if (r == outside) {
      ++stats.left_domain;
    } else {
      auto it = slot.find(r);
      if (it == slot.end())
        throw InvariantError("particle migration: a particle of '" + particles.label() +
                             "' on rank " + std::to_string(dec.rank()) + " moved to rank " +
                             std::to_string(r) + ", which is not a neighbouring patch");
      send_rows[it->second].push_back(p);
      ++stats.sent;
    }
  }

  // 3. Exchange counts, then rows (all components) and ids, non-blocking.
  const int ncomp = particle_field_count;
  const std::size_t nn = nbrs.size();
  std::vector<long> send_count(nn), recv_count(nn);
  std::vector<MPI_Request> req;
  req.reserve(6 * nn);
  for (std::size_t s = 0; s < nn; ++s) {
    send_count[s] = long(send_rows[s].size());
    req.emplace_back();
    MPI_Irecv(&recv_count[s], 1, MPI_LONG, nbrs[s], tag_count, dec.comm(), &req.back());
  }
  for (std::size_t s = 0; s < nn; ++s) {
    req.emplace_back();
    MPI_Isend(&send_count[s], 1, MPI_LONG, nbrs[s], tag_count, dec.comm(), &req.back());
  }
  MPI_Waitall(int(req.size()), req.data(), MPI_STATUSES_IGNORE);
  req.clear();

  long total_recv = 0;
  std::vector<long> recv_offset(nn + 1, 0), send_offset(nn + 1, 0);
  for (std::size_t s = 0; s < nn; ++s) {
    recv_offset[s + 1] = recv_offset[s] + recv_count[s];
    send_offset[s + 1] = send_offset[s] + send_count[s];
  }
  total_recv = recv_offset[nn];
  stats.received = total_recv;
  // Nothing left this patch and nothing arrived (most steps): the particles stay as
  // they are, in their order, without the copy below.
  if (stats.sent == 0 && stats.left_domain == 0 && total_recv == 0) return stats;

  // Rows to send, packed per neighbour as (row, component) with components contiguous
  // per particle, so one message per neighbour carries whole particles.
  Kokkos::View<long*, Kokkos::HostSpace> send_idx_h("mpmice::migrate_send_idx", send_offset[nn]);
  for (std::size_t s = 0; s < nn; ++s)
    for (std::size_t q = 0; q < send_rows[s].size(); ++q) send_idx_h(send_offset[s] + q) = send_rows[s][q];
  auto send_idx = Kokkos::create_mirror_view_and_copy(MemSpace(), send_idx_h);
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> send_buf("mpmice::migrate_send", send_offset[nn], ncomp);
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> recv_buf("mpmice::migrate_recv", total_recv, ncomp);
  Kokkos::View<std::int64_t*, MemSpace> send_id("mpmice::migrate_send_id", send_offset[nn]);
  Kokkos::View<std::int64_t*, MemSpace> recv_id("mpmice::migrate_recv_id", total_recv);
  {
    auto data = particles.data();
    auto id = particles.id();
    Kokkos::parallel_for(
        "mpmice::migrate_pack", Kokkos::RangePolicy<ExecSpace>(0, send_offset[nn]),
        KOKKOS_LAMBDA(long q) {
          const long p = send_idx(q);
          for (int c = 0; c < ncomp; ++c) send_buf(q, c) = data(p, c);
          send_id(q) = id(p);
        });
    Kokkos::fence();
  }
  for (std::size_t s = 0; s < nn; ++s) {
    if (recv_count[s] == 0) continue;
    req.emplace_back();
    MPI_Irecv(recv_buf.data() + recv_offset[s] * ncomp, int(recv_count[s] * ncomp), MPI_DOUBLE,
              nbrs[s], tag_data, dec.comm(), &req.back());
    req.emplace_back();
    MPI_Irecv(recv_id.data() + recv_offset[s], int(recv_count[s]), MPI_INT64_T, nbrs[s], tag_id,
              dec.comm(), &req.back());
  }
  for (std::size_t s = 0; s < nn; ++s) {
    if (send_count[s] == 0) continue;
    req.emplace_back();
    MPI_Isend(send_buf.data() + send_offset[s] * ncomp, int(send_count[s] * ncomp), MPI_DOUBLE,
              nbrs[s], tag_data, dec.comm(), &req.back());
    req.emplace_back();
    MPI_Isend(send_id.data() + send_offset[s], int(send_count[s]), MPI_INT64_T, nbrs[s], tag_id,
              dec.comm(), &req.back());
  }

  // 4. Meanwhile, compact the particles that stay (a gather into fresh views).
  const long nkeep = long(keep_rows.size());
  Kokkos::View<long*, Kokkos::HostSpace> keep_h(keep_rows.data(), nkeep);
  auto keep = Kokkos::create_mirror_view_and_copy(MemSpace(), keep_h);
  ParticleSet out(particles.label(), std::size_t(nkeep + total_recv));
  out.resize(std::size_t(nkeep + total_recv));
  {
    auto src = particles.data();
    auto src_id = particles.id();
    auto dst = out.data();
    auto dst_id = out.id();
    Kokkos::parallel_for(
        "mpmice::migrate_compact", Kokkos::RangePolicy<ExecSpace>(0, nkeep),
        KOKKOS_LAMBDA(long q) {
          const long p = keep(q);
          for (int c = 0; c < ncomp; ++c) dst(q, c) = src(p, c);
          dst_id(q) = src_id(p);
        });
  }
  MPI_Waitall(int(req.size()), req.data(), MPI_STATUSES_IGNORE);
  {
    auto dst = out.data();
    auto dst_id = out.id();
    Kokkos::parallel_for(
        "mpmice::migrate_unpack", Kokkos::RangePolicy<ExecSpace>(0, total_recv),
        KOKKOS_LAMBDA(long q) {
          for (int c = 0; c < ncomp; ++c) dst(nkeep + q, c) = recv_buf(q, c);
          dst_id(nkeep + q) = recv_id(q);
        });
    Kokkos::fence();
  }
  particles = std::move(out);
  return stats;
}

}  // namespace mpmice
