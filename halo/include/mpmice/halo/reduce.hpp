#pragma once
/// \file reduce.hpp
/// \brief Global reductions over all ranks (timestep minimum, diagnostic sums).
#include <mpi.h>

#include <vector>

namespace mpmice {

inline double global_min(MPI_Comm comm, double x) {
  double r = x;
  MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_MIN, comm);
  return r;
}

inline double global_max(MPI_Comm comm, double x) {
  double r = x;
  MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_MAX, comm);
  return r;
}

inline double global_sum(MPI_Comm comm, double x) {
  double r = x;
  MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_SUM, comm);
  return r;
}

inline long global_sum(MPI_Comm comm, long x) {
  long r = x;
  MPI_Allreduce(&x, &r, 1, MPI_LONG, MPI_SUM, comm);
  return r;
}

/// Element-wise maximum of `v` over all ranks, in place.
inline void global_max(MPI_Comm comm, std::vector<double>& v) {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), int(v.size()), MPI_DOUBLE, MPI_MAX, comm);
}

/// Element-wise sum of `v` over all ranks, in place.
inline void global_sum(MPI_Comm comm, std::vector<double>& v) {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), int(v.size()), MPI_DOUBLE, MPI_SUM, comm);
}

}  // namespace mpmice
