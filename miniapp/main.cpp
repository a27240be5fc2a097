// mpmice: the MPM-ICE mini-app. MPI and Kokkos live for the whole run; everything
// else is in cli.cpp.
#include <malloc.h>
#include <mpi.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include <Kokkos_Core.hpp>

#include "cli.hpp"

int main(int argc, char* argv[]) {
#if defined(__GLIBC__)
  // The fields from the heap, not each from a memory map of its own: glibc maps every
  // allocation above 128 KiB at a page boundary, so the fields of a patch all start at
  // the same place modulo 4 KiB, and a kernel that reads and writes many of them at one
  // index touches addresses in the same L1 cache sets (8 ways), which the core's
  // store-to-load checks also confuse (4 KiB aliasing): the likely cause of the
  // slowdown measured. From the heap they start at staggered places. Measured in
  // session 30 (docs/performance.md) on 2 threads: the coarse container's
  // grid_acceleration 4.3x and lagrangian_values 1.5x faster, the whole run 1.08x; the
  // 32^3 blast 1.15x. Arrays above 32 MiB, glibc's largest threshold, are still
  // mapped. A user's MALLOC_MMAP_THRESHOLD_ stands.
  if (std::getenv("MALLOC_MMAP_THRESHOLD_") == nullptr) mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
#endif
  // Open MPI's MPI-IO opens every file with its shared-file-pointer component `sm`,
  // which guards the file with a POSIX semaphore named after the file's base name
  // (/dev/shm/sem.OMPIO_checkpoint_000087.h5.tmp). A run killed while writing leaves
  // it taken, and a restart that writes the same checkpoint again waits on it forever.
  // The run never uses a shared file pointer; the other components (no semaphore) are
  // kept. A user's own choice stands; other MPIs ignore the variable.
  setenv("OMPI_MCA_sharedfp", "^sm", /*overwrite=*/0);
  MPI_Init(&argc, &argv);
  // The OpenMP runtime has read its environment already; an unset OMP_PROC_BIND
  // means no binding. Saying so explicitly keeps Kokkos from warning about it on
  // every run. A user's own setting is kept.
  setenv("OMP_PROC_BIND", "false", /*overwrite=*/0);
  // Kokkos gets only its --kokkos-* options (it would also take --help for itself);
  // the command line parser gets the rest.
  std::vector<char*> kokkos_args{argv[0]}, app_args{argv[0]};
  for (int i = 1; i < argc; ++i)
    (std::strncmp(argv[i], "--kokkos-", 9) == 0 ? kokkos_args : app_args).push_back(argv[i]);
  int kokkos_argc = int(kokkos_args.size()), app_argc = int(app_args.size());
  kokkos_args.push_back(nullptr);
  app_args.push_back(nullptr);

  int status = 0;
  {
    Kokkos::ScopeGuard kokkos(kokkos_argc, kokkos_args.data());
    status = mpmice::run_cli(app_argc, app_args.data());
  }
  MPI_Finalize();
  return status;
}
