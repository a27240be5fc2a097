// What misaligned rows cost a loop over many arrays (docs/performance.md, session 18):
// `groups` times the exchange's arrays for one material (8 read, 5 written), each
// group's inputs summed and the sum scaled into its outputs, over rows of 64 cells as a
// cell kernel runs them: rows contiguous and starting on a cache line, the same rows
// shifted by one double (every 64-byte vector load and store then spans two lines), and
// aligned rows with a gap of 8 doubles. One thread, plain C++ (no Kokkos), best of 20.
// Bytes counted: 8 per array and cell. Usage: mpmice_row_alignment (prints a table).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

template <int Groups>
double gigabytes_per_second(long shift, long gap) {
  constexpr int inputs = 8, outputs = 5, arrays = Groups * (inputs + outputs);
  // About 110 MB in all, and at least 2.1 MB per array (a 64^3 patch's field).
  constexpr long row = 64, rows = 4096 * (4 / Groups);
  const long stride = row + gap, length = rows * stride + 64;
  std::vector<double*> in(Groups * inputs), out(Groups * outputs), raw;
  for (int a = 0; a < arrays; ++a) {
    const std::size_t bytes = (std::size_t(length) * 8 + 4096 + 4095) / 4096 * 4096;  // a multiple of 4096
    auto* p = static_cast<double*>(std::aligned_alloc(4096, bytes));
    for (long i = 0; i < length; ++i) p[i] = 1.0 + a + 1e-9 * i;
    raw.push_back(p);
    (a < Groups * inputs ? in[a] : out[a - Groups * inputs]) = p + shift;
  }
  double best = 1e30;
  for (int repeat = 0; repeat < 20; ++repeat) {
    const auto start = std::chrono::steady_clock::now();
    for (long r = 0; r < rows; ++r) {
      const long first = r * stride;
#pragma omp simd
      for (long k = first; k < first + row; ++k) {
        for (int g = 0; g < Groups; ++g) {
          double sum = 0;
          for (int f = 0; f < inputs; ++f) sum += in[g * inputs + f][k];
          for (int f = 0; f < outputs; ++f) out[g * outputs + f][k] = (f + 1) * sum;
        }
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = seconds < best ? seconds : best;
  }
  for (double* p : raw) std::free(p);
  return double(rows) * row * arrays * 8 / best / 1e9;
}

template <int Groups>
void print_row() {
  std::printf("| %d | %.1f | %.1f | %.1f |\n", Groups * 13, gigabytes_per_second<Groups>(0, 0),
              gigabytes_per_second<Groups>(1, 0), gigabytes_per_second<Groups>(0, 8));
}

}  // namespace

int main() {
  std::printf("| arrays | aligned, contiguous GB/s | shifted by one double | aligned, gap of 8 |\n");
  std::printf("|---:|---:|---:|---:|\n");
  print_row<1>();
  print_row<2>();
  print_row<4>();
  return 0;
}
