// Ghost exchange fills every ghost entry of a globally defined field exactly, for
// cells, nodes and the three face kinds, depth 1 and 2, with and without periodic
// directions; and the reverse sum adds ghost contributions into their owners.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <mpmice/halo/decomposition.hpp>
#include <mpmice/halo/halo.hpp>
#include <mpmice/kernels/grid_state.hpp>

using namespace mpmice;

namespace {

constexpr double sentinel = -12345.0;
const Location all_locations[] = {Location::cell, Location::node, Location::x_face,
                                  Location::y_face, Location::z_face};

// For the reverse sum: global entry g in direction d, wrapped if periodic, -1 beyond a
// non-periodic boundary (contributions there belong to no patch).
int wrap(int g, int d, Location loc, const Decomposition& dec) {
  const int n = dec.grid().cells[d];
  if (dec.periodic()[d]) return ((g % n) + n) % n;
  const int last = n - 1 + (on_cell_boundary(loc, d) ? 1 : 0);
  return (g < 0 || g > last) ? -1 : g;
}

// An exactly representable value unique to (material, global entry), also for
// entries beyond the domain (indices -G..N+G).
double analytic(int m, int gi, int gj, int gk) {
  return 1.0 + 0.5 * m + 4.0 * gi + 256.0 * gj + 65536.0 * gk;
}

// The analytic value of local entry (i,j,k): periodic indices wrapped, others as
// they are (beyond a non-periodic boundary they name extra cells).
double value_at(const Decomposition& dec, int m, int i, int j, int k) {
  const Patch& p = dec.patch();
  const int l[3] = {i, j, k};
  int g[3];
  for (int d = 0; d < 3; ++d) {
    const int n = dec.grid().cells[d];
    g[d] = p.global_index(l[d], d);
    if (dec.periodic()[d]) g[d] = ((g[d] % n) + n) % n;
  }
  return analytic(m, g[0], g[1], g[2]);
}

// What a patch computes itself: owned entries and, beyond a non-periodic domain
// boundary, the extra layers its boundary conditions fill.
IndexBox computed(const Patch& p, Location loc) { return p.with_extra(loc, p.ghosts); }

// Set the computed entries to the analytic value, everything else to the sentinel.
void set_owned(const Field4& f, const Decomposition& dec, Location loc) {
  const IndexBox own = computed(dec.patch(), loc);
  auto h = Kokkos::create_mirror_view(f);
  for (int m = 0; m < int(f.extent(0)); ++m)
    for (int i = 0; i < int(f.extent(1)); ++i)
      for (int j = 0; j < int(f.extent(2)); ++j)
        for (int k = 0; k < int(f.extent(3)); ++k)
          h(m, i, j, k) = own.contains(i, j, k) ? value_at(dec, m, i, j, k) : sentinel;
  Kokkos::deep_copy(f, h);
}

// Every entry within `depth` of the patch must hold its analytic value: ghosts from
// the neighbours, periodic images, and the extra cells beyond the domain that the
// neighbours' boundary conditions filled, all of them along a domain face (edges and
// corners included). Every other entry must be untouched.
int count_wrong(const Field4& f, const Decomposition& dec, Location loc, int depth) {
  const Patch& p = dec.patch();
  const IndexBox own = computed(p, loc);
  IndexBox reach = p.ghosted(loc, depth);
  for (int d = 0; d < 3; ++d) {
    reach.lo[d] = std::min(reach.lo[d], own.lo[d]);
    reach.hi[d] = std::max(reach.hi[d], own.hi[d]);
  }
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f);
  int wrong = 0;
  for (int m = 0; m < int(f.extent(0)); ++m)
    for (int i = 0; i < int(f.extent(1)); ++i)
      for (int j = 0; j < int(f.extent(2)); ++j)
        for (int k = 0; k < int(f.extent(3)); ++k) {
          const bool filled = reach.contains(i, j, k) || own.contains(i, j, k);
          const double want = filled ? value_at(dec, m, i, j, k) : sentinel;
          if (h(m, i, j, k) != want) ++wrong;
        }
  return wrong;
}

struct Case {
  std::array<bool, 3> periodic;
};

// Fill `materials` material slots of every location on a grid of `cells`, depth 1 and 2;
// count the wrong entries.
void expect_fills_every_ghost(const Case& c, int materials, std::array<int, 3> cells = {10, 9, 7}) {
  Grid grid;
  grid.cells = cells;
  DecompositionOptions opt;
  opt.periodic = c.periodic;
  opt.ghosts = 2;
  Decomposition dec(MPI_COMM_WORLD, grid, opt);
  Halo halo(dec);
  for (Location loc : all_locations)
    for (int depth : {1, 2}) {
      Field4 f = make_field("f", dec.patch(), loc, materials);
      set_owned(f, dec, loc);
      halo.fill(f, loc, depth);
      EXPECT_EQ(count_wrong(f, dec, loc, depth), 0)
          << "location " << int(loc) << " depth " << depth << " rank " << dec.rank();
      // A material-independent field goes through the same path.
      Field3 s = make_field("s", dec.patch(), loc);
      Field4 s4(s.data(), 1, s.extent(0), s.extent(1), s.extent(2));
      set_owned(s4, dec, loc);
      halo.fill(s, loc, depth);
      EXPECT_EQ(count_wrong(s4, dec, loc, depth), 0) << "shared field, location " << int(loc);
    }
}

// Reverse sum: every rank writes the analytic value into its owned entries and its
// ghosts (a scatter would), then sums. An owned entry then holds the value times the
// number of patches (and periodic images) whose ghosted box covers it.
void expect_sums_every_contribution(const Case& c, int materials, std::array<int, 3> cells = {10, 9, 7}) {
  Grid grid;
  grid.cells = cells;
  DecompositionOptions opt;
  opt.periodic = c.periodic;
  Decomposition dec(MPI_COMM_WORLD, grid, opt);
  Halo halo(dec);
  const Patch& p = dec.patch();
  for (Location loc : all_locations)
    for (int depth : {1, 2}) {
      Field4 f = make_field("f", p, loc, materials);
      const IndexBox reach = p.ghosted(loc, depth);
      auto h = Kokkos::create_mirror_view(f);
      Kokkos::deep_copy(h, 0.0);
      for (int m = 0; m < materials; ++m)
        for (int i = reach.lo[0]; i < reach.hi[0]; ++i)
          for (int j = reach.lo[1]; j < reach.hi[1]; ++j)
            for (int k = reach.lo[2]; k < reach.hi[2]; ++k) {
              const int gi = wrap(p.global_index(i, 0), 0, loc, dec);
              const int gj = wrap(p.global_index(j, 1), 1, loc, dec);
              const int gk = wrap(p.global_index(k, 2), 2, loc, dec);
              if (gi >= 0 && gj >= 0 && gk >= 0) h(m, i, j, k) = analytic(m, gi, gj, gk);
            }
      Kokkos::deep_copy(f, h);
      halo.sum_into_owned(f, loc, depth);
      Kokkos::deep_copy(h, f);

      // Patches covering global entry g in direction d (ghosted boxes, periodic images).
      auto covers = [&](int g, int d) {
        const int n = grid.cells[d], nl = on_cell_boundary(loc, d) ? 1 : 0;
        int count = 0;
        for (int c = 0; c < dec.dims()[d]; ++c) {
          const int lo = dec.block_start(d, c) - depth;
          const int hi = dec.block_start(d, c + 1) + depth + nl;
          for (int shift : {-n, 0, n}) {
            if (shift != 0 && !dec.periodic()[d]) continue;
            const int img = g + shift;
            if (img < lo || img >= hi) continue;
            if (!dec.periodic()[d] && (img < 0 || img > n - 1 + nl)) continue;
            ++count;
          }
        }
        return count;
      };
      const IndexBox own = p.owned(loc);
      int wrong = 0;
      for (int m = 0; m < materials; ++m)
        for (int i = own.lo[0]; i < own.hi[0]; ++i)
          for (int j = own.lo[1]; j < own.hi[1]; ++j)
            for (int k = own.lo[2]; k < own.hi[2]; ++k) {
              const int gi = p.global_index(i, 0), gj = p.global_index(j, 1),
                        gk = p.global_index(k, 2);
              const double want = analytic(m, gi, gj, gk) * covers(gi, 0) * covers(gj, 1) *
                                  covers(gk, 2);
              if (h(m, i, j, k) != want) ++wrong;
            }
      EXPECT_EQ(wrong, 0) << "location " << int(loc) << " depth " << depth << " rank "
                          << dec.rank();
    }
}

}  // namespace

class Exchange : public ::testing::TestWithParam<Case> {};

TEST_P(Exchange, FillsEveryGhostExactly) { expect_fills_every_ghost(GetParam(), 2); }
TEST_P(Exchange, SumIntoOwnedAddsEveryContribution) { expect_sums_every_contribution(GetParam(), 2); }

// Slabs over the size that halo.cpp copies on one thread (serial_slab_entries, 2^15
// entries), whose pack and unpack run in parallel over their longest index: 256 material
// slots (on one rank at depth 2, the y and z sweeps' slabs of cells are 256 x 14 x 2 x 7
// and 256 x 14 x 13 x 2 entries, in parallel over material and i), and one slot on a
// grid wide in y and z (the x sweep's slab 1 x 2 x 134 x 134, in parallel over j). The
// thinnest slabs, and most on more ranks, stay on one thread.
TEST_P(Exchange, FillsEveryGhostOfLargeSlabs) {
  expect_fills_every_ghost(GetParam(), 256);
  expect_fills_every_ghost(GetParam(), 1, {3, 130, 130});
}
TEST_P(Exchange, SumsEveryContributionOfLargeSlabs) {
  expect_sums_every_contribution(GetParam(), 256);
  expect_sums_every_contribution(GetParam(), 1, {3, 130, 130});
}

INSTANTIATE_TEST_SUITE_P(Periodicity, Exchange,
                         ::testing::Values(Case{{false, false, false}}, Case{{true, true, true}},
                                           Case{{true, false, false}}, Case{{false, true, true}}));
