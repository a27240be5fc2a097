// Index conventions of grid.hpp (mpmice-algorithm.md section 1.2).
#include <gtest/gtest.h>

#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/grid_state.hpp>
#include <mpmice/kernels/particles.hpp>

using namespace mpmice;

namespace {
Patch sample_patch() {
  Patch p;
  p.grid.lower = {-1.0, 0.0, 2.0};
  p.grid.spacing = {0.5, 0.25, 1.0};
  p.grid.cells = {10, 8, 1};
  p.lo = {4, 0, 0};
  p.hi = {7, 8, 1};
  p.ghosts = 2;
  p.owns_high_boundary = {false, true, true};
  return p;
}
}  // namespace

TEST(Grid, ExtentsPerLocation) {
  const Patch p = sample_patch();
  // Cells: owned + 2G; node-like directions one more.
  EXPECT_EQ(p.extent(Location::cell, 0), 3 + 4);
  EXPECT_EQ(p.extent(Location::node, 0), 3 + 4 + 1);
  EXPECT_EQ(p.extent(Location::x_face, 0), 3 + 4 + 1);
  EXPECT_EQ(p.extent(Location::x_face, 1), 8 + 4);
  EXPECT_EQ(p.extent(Location::y_face, 1), 8 + 4 + 1);
  EXPECT_EQ(p.extent(Location::z_face, 2), 1 + 4 + 1);
  EXPECT_EQ(p.extent(Location::z_face, 0), 3 + 4);
  Field4 f = make_field("f", p, Location::y_face, 3);
  EXPECT_EQ(f.extent(0), 3u);
  EXPECT_EQ(int(f.extent(2)), p.extent(Location::y_face, 1));
}

TEST(Grid, LocalGlobalAndPositions) {
  const Patch p = sample_patch();
  // Local G is global lo.
  EXPECT_EQ(p.global_index(2, 0), 4);
  EXPECT_EQ(p.local_index(4, 0), 2);
  EXPECT_EQ(p.global_index(0, 1), -2);  // ghost below the domain
  // Cell (i) centre lies half a cell above node (i), the cell's low corner.
  for (int l = 0; l < p.extent(Location::cell, 0); ++l)
    EXPECT_DOUBLE_EQ(p.cell_center(l, 0) - p.node_position(l, 0), 0.25);
  EXPECT_DOUBLE_EQ(p.node_position(2, 0), -1.0 + 4 * 0.5);
  EXPECT_DOUBLE_EQ(p.owned_lower(0), 1.0);
  EXPECT_DOUBLE_EQ(p.owned_upper(0), 2.5);
  EXPECT_DOUBLE_EQ(p.grid.upper(1), 2.0);
  EXPECT_DOUBLE_EQ(p.grid.cell_volume(), 0.125);
  EXPECT_DOUBLE_EQ(p.grid.face_area(0), 0.25);
}

TEST(Grid, OwnedAndGhostedBoxes) {
  const Patch p = sample_patch();
  const IndexBox cells = p.owned_cells();
  EXPECT_EQ(cells.lo[0], 2);
  EXPECT_EQ(cells.hi[0], 5);
  EXPECT_EQ(cells.size(), 3L * 8 * 1);
  // x: the shared high node belongs to the upper patch; y, z: domain boundary, owned.
  const IndexBox nodes = p.owned_nodes();
  EXPECT_EQ(nodes.hi[0] - nodes.lo[0], 3);
  EXPECT_EQ(nodes.hi[1] - nodes.lo[1], 9);
  EXPECT_EQ(nodes.hi[2] - nodes.lo[2], 2);
  // Ghosted boxes stay inside the allocated extents.
  for (Location loc : {Location::cell, Location::node, Location::x_face, Location::y_face,
                       Location::z_face}) {
    const IndexBox b = p.ghosted(loc, p.ghosts);
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(b.lo[d], 0);
      EXPECT_EQ(b.hi[d], p.extent(loc, d));
    }
  }
  // An x-face at local i lies between cells i-1 and i: face i's position is node i's.
  EXPECT_TRUE(cells.contains(2, 0 + 2, 2));
  EXPECT_FALSE(cells.contains(5, 2, 2));
}

TEST(Grid, WholeGridPatchOwnsEverything) {
  Grid g;
  g.cells = {4, 3, 2};
  const Patch p = whole_grid_patch(g, 1);
  EXPECT_EQ(p.owned_nodes().size(), 5L * 4 * 3);
  EXPECT_EQ(p.owned(Location::x_face).size(), 5L * 3 * 2);
  EXPECT_EQ(p.owned(Location::z_face).size(), 4L * 3 * 3);
}

TEST(Particles, ComponentsAreContiguousAndSurviveGrowth) {
  ParticleSet ps("solid", 4);
  ps.resize(4);
  auto vx = ps.get(ParticleField::vx);
  auto mass = ps.get(ParticleField::mass);
  EXPECT_EQ(vx.stride(0), 1u);  // structure of arrays
  Kokkos::parallel_for("fill", 4, KOKKOS_LAMBDA(int p) {
    vx(p) = 10.0 + p;
    mass(p) = 0.5 * p;
  });
  Kokkos::fence();
  ps.resize(1000);
  EXPECT_GE(ps.capacity(), 1000u);
  auto vx_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.get(ParticleField::vx));
  auto m_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.get(ParticleField::mass));
  for (int p = 0; p < 4; ++p) {
    EXPECT_EQ(vx_h(p), 10.0 + p);
    EXPECT_EQ(m_h(p), 0.5 * p);
  }
}
