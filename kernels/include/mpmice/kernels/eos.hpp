#pragma once
/// \file eos.hpp
/// \brief Equations of state of ICE materials, pointwise (mpmice-algorithm.md 9.1).
///
/// Each gives p(rhoM, T), dp/drho, dp/de, the inverse rhoM(p, T), the sound speed
/// (E47) and the thermal expansivity alpha = (1/v)(dv/dT)_p. Units: kg/m^3, K, Pa,
/// J/kg/K. Chosen per material by a tag, not by virtual calls.
#include <mpmice/kernels/math.hpp>

namespace mpmice {

enum class EosType : int { ideal_gas = 0 };

/// Parameters of one ICE material's equation of state.
struct Eos {
  EosType type = EosType::ideal_gas;
  double gamma = 1.4;  ///< ratio of specific heats
  double cv = 717.5;   ///< specific heat at constant volume, J/kg/K
};

/// Pressure from micro density and temperature (E48).
KOKKOS_INLINE_FUNCTION double eos_pressure(const Eos& e, double rho_micro, double temp) {
  return (e.gamma - 1.0) * rho_micro * e.cv * temp;
}

/// dp/drho at constant internal energy (E48).
KOKKOS_INLINE_FUNCTION double eos_dp_drho(const Eos& e, double /*rho_micro*/, double temp) {
  return (e.gamma - 1.0) * e.cv * temp;
}

/// dp/de at constant density (E48).
KOKKOS_INLINE_FUNCTION double eos_dp_de(const Eos& e, double rho_micro, double /*temp*/) {
  return (e.gamma - 1.0) * rho_micro;
}

/// Micro density from pressure and temperature, the inverse of eos_pressure (E48).
KOKKOS_INLINE_FUNCTION double eos_density(const Eos& e, double press, double temp) {
  return press / ((e.gamma - 1.0) * e.cv * temp);
}

/// Squared isentropic sound speed c^2 = dp/drho + dp/de p / rhoM^2 (E47).
KOKKOS_INLINE_FUNCTION double eos_sound_speed_squared(const Eos& e, double rho_micro,
                                                      double temp) {
  const double p = eos_pressure(e, rho_micro, temp);
  return eos_dp_drho(e, rho_micro, temp) + eos_dp_de(e, rho_micro, temp) * p / (rho_micro * rho_micro);
}

/// Thermal expansivity alpha = (1/v)(dv/dT)_p; 1/T for an ideal gas (E48).
KOKKOS_INLINE_FUNCTION double eos_alpha(const Eos& /*e*/, double /*rho_micro*/, double temp) {
  return 1.0 / temp;
}

}  // namespace mpmice
