// The loop shapes of loops.hpp: for_each_index, for_each_index_light and
// reduce_over_index visit every index of a box exactly once, whichever index their rows
// follow (Rows::along_k, or Rows::longest, which runs a box thin along k along i or j).
#include <gtest/gtest.h>

#include <vector>

#include <mpmice/kernels/loops.hpp>

using namespace mpmice;

namespace {

IndexBox box_of(int i0, int i1, int j0, int j1, int k0, int k1) {
  IndexBox b;
  b.lo[0] = i0, b.hi[0] = i1, b.lo[1] = j0, b.hi[1] = j1, b.lo[2] = k0, b.hi[2] = k1;
  return b;
}

// Boxes thin along k and longer along i (in 3 pieces of detail::row_piece), along j (in
// one piece, and in 3), or both equally; thin in every direction; long along k; empty.
// None starts at 0, so a lost lower corner shows.
std::vector<IndexBox> sample_boxes() {
  return {box_of(2, 150, 1, 4, 3, 4),  box_of(1, 4, 5, 37, 2, 7),  box_of(1, 3, 3, 143, 1, 3),
          box_of(1, 13, 1, 13, 2, 4),  box_of(1, 6, 2, 7, 3, 8),   box_of(1, 4, 1, 4, 2, 22),
          box_of(3, 12, 2, 3, 1, 8),   box_of(3, 3, 1, 10, 1, 2)};  // the last one empty
}

// How often each index of a 160 x 150 x 24 array was visited by for_each_index with
// rows `Choice`, or with `Light` by for_each_index_light.
template <Rows Choice, bool Light = false>
Kokkos::View<int***>::HostMirror visits(const IndexBox& box) {
  Kokkos::View<int***> count("count", 160, 150, 24);
  const auto visit = KOKKOS_LAMBDA(long i, long j, long k) { Kokkos::atomic_add(&count(i, j, k), 1); };
  if constexpr (Light)
    for_each_index_light("test::visits", box, visit);
  else
    for_each_index<Choice>("test::visits", box, visit);
  auto h = Kokkos::create_mirror_view(count);
  Kokkos::deep_copy(h, count);
  return h;
}

template <Rows Choice, bool Light = false>
void expect_each_index_once(std::vector<IndexBox> boxes = sample_boxes()) {
  for (const IndexBox& box : boxes) {
    const auto h = visits<Choice, Light>(box);
    long wrong = 0;
    for (int i = 0; i < 160; ++i)
      for (int j = 0; j < 150; ++j)
        for (int k = 0; k < 24; ++k) wrong += h(i, j, k) != (box.contains(i, j, k) ? 1 : 0);
    EXPECT_EQ(wrong, 0) << "box " << box.lo[0] << ".." << box.hi[0] << " x " << box.lo[1] << ".." << box.hi[1]
                        << " x " << box.lo[2] << ".." << box.hi[2];
  }
}

// A value that names its index; the sums below are of integers below 2^53, so exact in
// any order, and the rows' direction cannot change them.
KOKKOS_INLINE_FUNCTION double code(long i, long j, long k) { return double(i * 10000 + j * 100 + k); }

template <Rows Choice>
void expect_sum_and_max() {
  for (const IndexBox& box : sample_boxes()) {
    double sum = 0, max = 0;
    for (int i = box.lo[0]; i < box.hi[0]; ++i)
      for (int j = box.lo[1]; j < box.hi[1]; ++j)
        for (int k = box.lo[2]; k < box.hi[2]; ++k) {
          sum += code(i, j, k);
          max = code(i, j, k) > max ? code(i, j, k) : max;
        }
    const auto f = KOKKOS_LAMBDA(long i, long j, long k) { return code(i, j, k); };
    EXPECT_EQ((reduce_over_index<Reduction::sum, Choice>("test::sum", box, f)), sum);
    EXPECT_EQ((reduce_over_index<Reduction::max, Choice>("test::max", box, f)), max);
  }
}

}  // namespace

// Which index the rows follow: i or j (the longer, i on a tie) only for Rows::longest,
// fewer than 8 cells along k and at least 8 along i or j; rows along i or j in pieces.
TEST(Loops, RowDirection) {
  const auto along = [](const IndexBox& b, Rows c) { return detail::BoxRows(b, c).along; };
  EXPECT_EQ(along(box_of(0, 20, 0, 10, 0, 1), Rows::longest), 0);
  EXPECT_EQ(along(box_of(0, 10, 0, 20, 0, 1), Rows::longest), 1);
  EXPECT_EQ(along(box_of(0, 20, 0, 20, 0, 2), Rows::longest), 0);
  EXPECT_EQ(along(box_of(0, 20, 0, 20, 0, 8), Rows::longest), 2);
  EXPECT_EQ(along(box_of(0, 7, 0, 7, 0, 2), Rows::longest), 2);
  EXPECT_EQ(along(box_of(0, 400, 0, 1, 0, 1), Rows::along_k), 2);
  const detail::BoxRows tube(box_of(2, 402, 2, 3, 2, 3), Rows::longest);
  EXPECT_EQ(tube.along, 0);
  EXPECT_EQ(tube.rows, (400 + detail::row_piece - 1) / detail::row_piece);
  EXPECT_EQ(tube.lo(0), 2);
  EXPECT_EQ(tube.hi(tube.rows - 1), 402);
}

TEST(Loops, EveryIndexOnceAlongK) { expect_each_index_once<Rows::along_k>(); }
TEST(Loops, EveryIndexOnceAlongTheLongest) { expect_each_index_once<Rows::longest>(); }
// The light loop: the sample boxes run on the calling thread (fewer indices than
// detail::light_serial_indices), a large box as for_each_index.
TEST(Loops, EveryIndexOnceInLightLoops) {
  std::vector<IndexBox> boxes = sample_boxes();
  boxes.push_back(box_of(2, 150, 1, 149, 1, 23));
  EXPECT_GE(boxes.back().size(), detail::light_serial_indices);
  expect_each_index_once<Rows::along_k, true>(boxes);
}
TEST(Loops, ReductionsAlongK) { expect_sum_and_max<Rows::along_k>(); }
TEST(Loops, ReductionsAlongTheLongest) { expect_sum_and_max<Rows::longest>(); }
