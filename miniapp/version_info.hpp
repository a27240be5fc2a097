#pragma once
#include <string>
namespace mpmice {
/// mpmice's version, the Kokkos version with its backends and thread count, and
/// the MPI library version, one item per line.
std::string version_info();
}  // namespace mpmice
