// STREAM triad a = b + s c: the machine's sustainable memory bandwidth, the roof for
// the memory-bound kernels. Bytes per item: 3 x 8 (read b, c; write a; no
// write-allocate counted, as STREAM reports it).
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>

#include "bench_setup.hpp"

namespace {

void BM_stream_triad(benchmark::State& state) {
  const long n = state.range(0);
  // The arrays are kept for the repetitions ci/bench runs (bench_setup.hpp).
  using Arrays = Kokkos::Array<Kokkos::View<double*>, 3>;
  const Arrays& abc = mpmice::bench::kept<Arrays>("triad " + std::to_string(n), [n] {
    Arrays made{Kokkos::View<double*>("a", n), Kokkos::View<double*>("b", n), Kokkos::View<double*>("c", n)};
    Kokkos::deep_copy(made[1], 1.0);
    Kokkos::deep_copy(made[2], 2.0);
    return made;
  });
  const Kokkos::View<double*> a = abc[0], b = abc[1], c = abc[2];
  const double s = 3.0;
  for (auto _ : state) {
    Kokkos::Timer timer;
    Kokkos::parallel_for("triad", n, KOKKOS_LAMBDA(long i) { a(i) = b(i) + s * c(i); });
    Kokkos::fence();
    state.SetIterationTime(timer.seconds());
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.SetBytesProcessed(state.iterations() * n * 3 * long(sizeof(double)));
}

}  // namespace

BENCHMARK(BM_stream_triad)->ArgName("n")->Arg(4096)->Arg(1 << 22)->Arg(1 << 25)->UseManualTime();
