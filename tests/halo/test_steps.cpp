// The step mechanism: declared ghost needs are refreshed before a step runs, no
// more often than needed, and undeclared access is refused.
#include <gtest/gtest.h>

#include <sstream>

#include <mpmice/halo/steps.hpp>
#include <mpmice/kernels/grid_state.hpp>

using namespace mpmice;

namespace {

struct Fixture {
  Grid grid;
  std::unique_ptr<Decomposition> dec;
  std::unique_ptr<Halo> halo;
  FieldRegistry fields;
  Fixture() {
    grid.cells = {12, 6, 5};
    DecompositionOptions opt;
    opt.periodic = {true, true, true};
    dec = std::make_unique<Decomposition>(MPI_COMM_WORLD, grid, opt);
    halo = std::make_unique<Halo>(*dec);
    fields.add("a", make_field("a", dec->patch(), Location::cell, 2), Location::cell);
    fields.add("b", make_field("b", dec->patch(), Location::cell, 2), Location::cell);
    fields.add("p", make_field("p", dec->patch(), Location::cell), Location::cell);
  }
};

// a(m, i, j, k) = m + global i (periodic: wrapped), on owned cells only.
Step write_a(const Patch& patch) {
  return Step{"write_a", {}, {{"a"}}, [patch](const StepContext& ctx) {
                auto a = ctx.write<Field4>("a");
                const int G = patch.ghosts, lo = patch.lo[0];
                Kokkos::parallel_for("write_a", patch.owned_cells().policy(),
                                     KOKKOS_LAMBDA(int i, int j, int k) {
                                       for (int m = 0; m < 2; ++m) a(m, i, j, k) = m + (i - G + lo);
                                     });
              }};
}

// b = a(i+2) - a(i-1): reads two ghost layers on the high side, one on the low side.
Step stencil(const Patch& patch, int declared_depth) {
  return Step{"stencil", {{"a", declared_depth}}, {{"b"}}, [patch](const StepContext& ctx) {
                auto a = ctx.read<Field4>("a");
                auto b = ctx.write<Field4>("b");
                Kokkos::parallel_for("stencil", patch.owned_cells().policy(),
                                     KOKKOS_LAMBDA(int i, int j, int k) {
                                       for (int m = 0; m < 2; ++m)
                                         b(m, i, j, k) = a(m, i + 2, j, k) - a(m, i - 1, j, k);
                                     });
              }};
}

// b(i) - 3 where the stencil did not wrap; at the periodic seam the difference jumps.
int stencil_errors(const Fixture& f) {
  const Patch& p = f.dec->patch();
  auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.fields.get<Field4>("b"));
  const int n = f.grid.cells[0];
  int wrong = 0;
  const IndexBox own = p.owned_cells();
  for (int m = 0; m < 2; ++m)
    for (int i = own.lo[0]; i < own.hi[0]; ++i)
      for (int j = own.lo[1]; j < own.hi[1]; ++j)
        for (int k = own.lo[2]; k < own.hi[2]; ++k) {
          const int g = p.global_index(i, 0);
          const double want = double((g + 2) % n) - double((g - 1 + n) % n);
          if (b(m, i, j, k) != want) ++wrong;
        }
  return wrong;
}

}  // namespace

TEST(Steps, DeclaredGhostsAreRefreshedOnlyWhenStale) {
  Fixture f;
  StepRunner runner(*f.halo, f.fields);
  runner.run(write_a(f.dec->patch()));
  EXPECT_EQ(runner.ghost_refreshes(), 0);
  runner.run(stencil(f.dec->patch(), 2));
  EXPECT_EQ(runner.ghost_refreshes(), 1);
  EXPECT_EQ(stencil_errors(f), 0);
  EXPECT_EQ(f.fields.valid_ghosts("a"), 2);
  EXPECT_EQ(f.fields.valid_ghosts("b"), 0);
  // Nothing wrote `a` since: no refresh.
  runner.run(stencil(f.dec->patch(), 2));
  EXPECT_EQ(runner.ghost_refreshes(), 1);
  // A new `a` makes its ghosts stale again.
  runner.run(write_a(f.dec->patch()));
  EXPECT_EQ(f.fields.valid_ghosts("a"), 0);
  runner.run(stencil(f.dec->patch(), 2));
  EXPECT_EQ(runner.ghost_refreshes(), 2);
  // Timers were collected per step, in first-run order.
  ASSERT_EQ(runner.timings().size(), 2u);
  EXPECT_EQ(runner.timings()[0].name, "write_a");
  EXPECT_EQ(runner.timings()[1].calls, 3);
  std::ostringstream table;
  runner.print_timings(table);
  if (f.dec->rank() == 0) EXPECT_NE(table.str().find("stencil"), std::string::npos);
}

TEST(Steps, LargerDeclaredDepthIsRefreshedInFull) {
  Fixture f;
  StepRunner runner(*f.halo, f.fields);
  runner.run(write_a(f.dec->patch()));
  // A step that declares 2 layers but reads only 1 (a(i-1) ... a(i+1)).
  Step reads_one{"reads_one", {{"a", 2}}, {{"b"}}, [&](const StepContext& ctx) {
                   auto a = ctx.read<Field4>("a");
                   auto b = ctx.write<Field4>("b");
                   Kokkos::parallel_for("reads_one", f.dec->patch().owned_cells().policy(),
                                        KOKKOS_LAMBDA(int i, int j, int k) {
                                          b(0, i, j, k) = a(0, i + 1, j, k) - a(0, i - 1, j, k);
                                        });
                 }};
  runner.run(reads_one);
  // Both ghost layers of `a` are valid: a later two-layer step needs no exchange and
  // gets the right answer.
  EXPECT_EQ(f.fields.valid_ghosts("a"), 2);
  const long before = runner.ghost_refreshes();
  runner.run(stencil(f.dec->patch(), 2));
  EXPECT_EQ(runner.ghost_refreshes(), before);
  EXPECT_EQ(stencil_errors(f), 0);
  // A depth-1 refresh does not satisfy a depth-2 need.
  runner.run(write_a(f.dec->patch()));
  runner.run(Step{"one", {{"a", 1}}, {}, [](const StepContext&) {}});
  EXPECT_EQ(f.fields.valid_ghosts("a"), 1);
  runner.run(stencil(f.dec->patch(), 2));
  EXPECT_EQ(runner.ghost_refreshes(), before + 2);
  EXPECT_EQ(stencil_errors(f), 0);
}

TEST(Steps, UndeclaredAccessIsCaught) {
  Fixture f;
  StepRunner runner(*f.halo, f.fields);
  Step sneaky_read{"sneaky_read", {}, {{"b"}},
                   [](const StepContext& ctx) { ctx.read<Field4>("a"); }};
  EXPECT_THROW(runner.run(sneaky_read), std::logic_error);
  Step sneaky_write{"sneaky_write", {{"a", 1}}, {},
                    [](const StepContext& ctx) { ctx.write<Field4>("a"); }};
  EXPECT_THROW(runner.run(sneaky_write), std::logic_error);
  Step too_deep{"too_deep", {{"a", 3}}, {}, [](const StepContext&) {}};
  EXPECT_THROW(runner.run(too_deep), std::logic_error);
  Step unknown{"unknown", {{"no_such_field", 1}}, {}, [](const StepContext&) {}};
  EXPECT_THROW(runner.run(unknown), std::logic_error);
  // Reading one's own write and a shared (3D) field work.
  Step fine{"fine", {{"p", 1}}, {{"b"}}, [](const StepContext& ctx) {
              ctx.read<Field3>("p");
              ctx.read<Field4>("b");
            }};
  EXPECT_NO_THROW(runner.run(fine));
}
