#pragma once
/// \file constants.hpp
/// \brief Constants of mpmice-algorithm.md section 1.7.
#include <cfloat>

namespace mpmice {

constexpr double tiny_rho = 1.0e-12;           ///< minimum density of a material, kg/m^3
constexpr double small_number = 1.0e-100;      ///< guards divisions
constexpr double equilibration_tolerance = 100 * DBL_EPSILON;  ///< on |sum theta - 1|
constexpr int equilibration_max_iterations = 100;

}  // namespace mpmice
