#include "version_info.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <mpmice/kernels/version.hpp>

namespace mpmice {

std::string version_info() {
  std::string backends;
  auto add = [&](const char* name) { backends += backends.empty() ? name : std::string(", ") + name; };
#ifdef KOKKOS_ENABLE_SERIAL
  add("Serial");
#endif
#ifdef KOKKOS_ENABLE_OPENMP
  add("OpenMP");
#endif
#ifdef KOKKOS_ENABLE_THREADS
  add("Threads");
#endif
#ifdef KOKKOS_ENABLE_CUDA
  add("Cuda");
#endif
#ifdef KOKKOS_ENABLE_HIP
  add("HIP");
#endif
#ifdef KOKKOS_ENABLE_SYCL
  add("SYCL");
#endif
  char mpi_version[MPI_MAX_LIBRARY_VERSION_STRING] = {0};
  int len = 0;
  MPI_Get_library_version(mpi_version, &len);
  std::string mpi(mpi_version, len);
  if (auto cut = mpi.find_first_of("\n,"); cut != std::string::npos) mpi.resize(cut);
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);

  return fmt::format(
      "mpmice {}\n"
      "Kokkos {}.{}.{}: backends {}; default execution space {}; {} host threads\n"
      "MPI: {}; {} rank{}\n",
      MPMICE_VERSION_STRING, KOKKOS_VERSION / 10000, KOKKOS_VERSION / 100 % 100,
      KOKKOS_VERSION % 100, backends, Kokkos::DefaultExecutionSpace::name(),
      Kokkos::DefaultHostExecutionSpace().concurrency(), mpi, ranks, ranks == 1 ? "" : "s");
}

}  // namespace mpmice
