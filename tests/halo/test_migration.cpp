// Particle migration: random particles moved by random displacements of up to one
// cell keep the global count, and every component of every particle bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include <mpmice/halo/decomposition.hpp>
#include <mpmice/halo/migrate.hpp>
#include <mpmice/halo/reduce.hpp>

using namespace mpmice;

namespace {

constexpr int ncomp = particle_field_count;
constexpr int ix = int(ParticleField::x);

// The same global particle list on every rank: components and displacements.
struct GlobalParticles {
  std::vector<std::array<double, ncomp>> values;
  std::vector<std::array<double, 3>> shift;
};

GlobalParticles make_particles(const Grid& g, long n, double margin, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  GlobalParticles gp;
  gp.values.resize(n);
  gp.shift.resize(n);
  for (long p = 0; p < n; ++p) {
    for (int c = 0; c < ncomp; ++c) gp.values[p][c] = u01(rng) * 1e3 - 5e2;
    for (int d = 0; d < 3; ++d) {
      const double lo = g.lower[d] + margin * g.spacing[d];
      const double hi = g.upper(d) - margin * g.spacing[d];
      gp.values[p][ix + d] = lo + (hi - lo) * u01(rng);
      gp.shift[p][d] = (2.0 * u01(rng) - 1.0) * g.spacing[d];  // up to one cell
    }
  }
  return gp;
}

bool inside_owned(const Patch& p, const double* x) {
  for (int d = 0; d < 3; ++d)
    if (x[d] < p.owned_lower(d) || x[d] >= p.owned_upper(d)) return false;
  return true;
}

// Load this rank's share of the global list into a ParticleSet.
ParticleSet load(const Decomposition& dec, const GlobalParticles& gp) {
  std::vector<long> mine;
  for (long p = 0; p < long(gp.values.size()); ++p)
    if (inside_owned(dec.patch(), &gp.values[p][ix])) mine.push_back(p);
  ParticleSet ps("solid", mine.size());
  ps.resize(mine.size());
  auto data = Kokkos::create_mirror_view(ps.data());
  auto id = Kokkos::create_mirror_view(ps.id());
  for (std::size_t q = 0; q < mine.size(); ++q) {
    for (int c = 0; c < ncomp; ++c) data(q, c) = gp.values[mine[q]][c];
    id(q) = mine[q];
  }
  Kokkos::deep_copy(ps.data(), data);
  Kokkos::deep_copy(ps.id(), id);
  return ps;
}

// Move every local particle by its displacement (on the device, as the physics would).
void displace(ParticleSet& ps, const GlobalParticles& gp) {
  const long n = long(ps.size());
  Kokkos::View<double* [3], Kokkos::HostSpace> s_h("shift", n);
  auto id_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
  for (long q = 0; q < n; ++q)
    for (int d = 0; d < 3; ++d) s_h(q, d) = gp.shift[id_h(q)][d];
  auto s = Kokkos::create_mirror_view_and_copy(MemSpace(), s_h);
  auto data = ps.data();
  Kokkos::parallel_for("displace", n, KOKKOS_LAMBDA(long q) {
    for (int d = 0; d < 3; ++d) data(q, ix + d) += s(q, d);
  });
  Kokkos::fence();
}

// Expected position after the move: the same arithmetic as the physics plus the
// periodic wrap of migrate().
double expected_position(const Grid& g, const Decomposition& dec, double x, double dx, int d) {
  double y = x + dx;
  if (dec.periodic()[d]) {
    const double length = g.cells[d] * g.spacing[d];
    if (y < g.lower[d]) y += length;
    else if (y >= g.upper(d)) y -= length;
  }
  return y;
}

void check_after_migration(const Decomposition& dec, const ParticleSet& ps,
                           const GlobalParticles& gp, long expected_total) {
  const Grid& g = dec.grid();
  auto data = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.data());
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id());
  long bad = 0;
  std::vector<long> ids(ps.size());
  for (std::size_t q = 0; q < ps.size(); ++q) {
    const long p = id(q);
    ids[q] = p;
    double x[3];
    for (int d = 0; d < 3; ++d) x[d] = data(q, ix + d);
    if (!inside_owned(dec.patch(), x)) ++bad;
    for (int c = 0; c < ncomp; ++c) {
      double want = gp.values[p][c];
      if (c >= ix && c < ix + 3)
        want = expected_position(g, dec, gp.values[p][c], gp.shift[p][c - ix], c - ix);
      if (data(q, c) != want) ++bad;  // bit for bit
    }
  }
  EXPECT_EQ(bad, 0) << "rank " << dec.rank();
  // Every id exactly once across ranks.
  const long total = global_sum(dec.comm(), long(ps.size()));
  EXPECT_EQ(total, expected_total);
  int size = 1;
  MPI_Comm_size(dec.comm(), &size);
  std::vector<int> counts(size), displs(size);
  int mine = int(ids.size());
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, dec.comm());
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<long> all(displs[size - 1] + counts[size - 1]);
  MPI_Allgatherv(ids.data(), mine, MPI_LONG, all.data(), counts.data(), displs.data(), MPI_LONG,
                 dec.comm());
  std::sort(all.begin(), all.end());
  EXPECT_TRUE(std::adjacent_find(all.begin(), all.end()) == all.end()) << "a particle was duplicated";
}

}  // namespace

TEST(Migration, NonPeriodicKeepsEveryParticleBitForBit) {
  Grid g;
  g.lower = {-0.3, 0.1, 2.0};
  g.spacing = {0.1, 0.05, 0.2};
  g.cells = {12, 10, 8};
  Decomposition dec(MPI_COMM_WORLD, g, DecompositionOptions{});
  // One cell of margin: no particle leaves the domain.
  const GlobalParticles gp = make_particles(g, 4000, 1.0, 42);
  ParticleSet ps = load(dec, gp);
  EXPECT_EQ(global_sum(dec.comm(), long(ps.size())), 4000);
  displace(ps, gp);
  const MigrationStats st = migrate(dec, ps);
  EXPECT_EQ(st.left_domain, 0);
  EXPECT_EQ(global_sum(dec.comm(), st.sent), global_sum(dec.comm(), st.received));
  check_after_migration(dec, ps, gp, 4000);
}

TEST(Migration, PeriodicWrapsAndKeepsEveryParticle) {
  Grid g;
  g.spacing = {0.1, 0.1, 0.1};
  g.cells = {12, 9, 8};
  DecompositionOptions opt;
  opt.periodic = {true, true, true};
  Decomposition dec(MPI_COMM_WORLD, g, opt);
  const GlobalParticles gp = make_particles(g, 4000, 0.0, 7);
  ParticleSet ps = load(dec, gp);
  displace(ps, gp);
  const MigrationStats st = migrate(dec, ps);
  EXPECT_EQ(st.left_domain, 0);
  check_after_migration(dec, ps, gp, 4000);
}

TEST(Migration, ParticlesLeavingTheDomainAreCounted) {
  Grid g;
  g.spacing = {0.1, 0.1, 0.1};
  g.cells = {12, 9, 8};
  Decomposition dec(MPI_COMM_WORLD, g, DecompositionOptions{});
  GlobalParticles gp = make_particles(g, 1000, 0.0, 3);
  // Push the first 25 particles out through the +x side.
  long leaving = 0;
  for (long p = 0; p < 1000; ++p) {
    if (p < 25) gp.shift[p] = {g.upper(0) - gp.values[p][ix] + 0.01, 0.0, 0.0};
    const double x = gp.values[p][ix] + gp.shift[p][0], y = gp.values[p][ix + 1] + gp.shift[p][1],
                 z = gp.values[p][ix + 2] + gp.shift[p][2];
    if (x < 0 || x >= g.upper(0) || y < 0 || y >= g.upper(1) || z < 0 || z >= g.upper(2)) ++leaving;
  }
  ParticleSet ps = load(dec, gp);
  displace(ps, gp);
  const MigrationStats st = migrate(dec, ps);
  EXPECT_EQ(global_sum(dec.comm(), st.left_domain), leaving);
  EXPECT_GE(leaving, 25);
  EXPECT_EQ(global_sum(dec.comm(), long(ps.size())), 1000 - leaving);
}
