#pragma once
/// \file eos.hpp
/// \brief Equations of state used by the pressure equilibration, pointwise: ideal gas
///        for ICE materials (9.1, E47, E48) and the solids' bulk law (9.2, E51, E52).
///
/// Each gives p(rhoM, T), dp/drho, dp/de, the inverse rhoM(p, T), the squared sound
/// speed and the thermal expansivity alpha = (1/v)(dv/dT)_p. Units: kg/m^3, K, Pa,
/// J/kg/K. Chosen per material by a tag, not by virtual calls.
#include <mpmice/kernels/math.hpp>

namespace mpmice {

enum class EosType : int {
  ideal_gas = 0,  ///< p = (gamma - 1) rhoM cv T (E48)
  solid = 1       ///< p = p_ref - (K/2)(J - 1/J), J = rho_0/rhoM (E51); (E52) in tension if `modified`
};

/// Parameters of one material's equation of state.
struct Eos {
  EosType type = EosType::ideal_gas;
  double gamma = 1.4;      ///< ratio of specific heats (gas)
  double cv = 717.5;       ///< specific heat at constant volume, J/kg/K
  double rho0 = 1000.0;    ///< reference density (solid), kg/m^3
  double bulk = 1e9;       ///< bulk modulus K (solid), Pa
  double p_ref = 101325;   ///< pressure of the unstressed solid, Pa
  bool modified = false;   ///< (E52) below rho_0 (solid)
};

/// The ideal gas (E47-E48) alone, for kernels that know every material is one (no
/// branch on the type, so they vectorise) and for the general functions below.
KOKKOS_INLINE_FUNCTION double ideal_gas_pressure(const Eos& e, double rho_micro, double temp) {
  return (e.gamma - 1.0) * rho_micro * e.cv * temp;
}
KOKKOS_INLINE_FUNCTION double ideal_gas_density(const Eos& e, double press, double temp) {
  return press / ((e.gamma - 1.0) * e.cv * temp);
}
/// c^2 = dp/drho + dp/de p / rhoM^2 (E47).
KOKKOS_INLINE_FUNCTION double ideal_gas_sound_speed_squared(const Eos& e, double rho_micro, double temp) {
  const double p = ideal_gas_pressure(e, rho_micro, temp);
  return (e.gamma - 1.0) * e.cv * temp + (e.gamma - 1.0) * rho_micro * p / (rho_micro * rho_micro);
}

/// Pressure from micro density and temperature (E48, E51, E52).
KOKKOS_INLINE_FUNCTION double eos_pressure(const Eos& e, double rho_micro, double temp) {
  if (e.type == EosType::ideal_gas) return ideal_gas_pressure(e, rho_micro, temp);
  if (e.modified && rho_micro < e.rho0) return e.p_ref * math::pow(rho_micro / e.rho0, e.bulk / e.p_ref);
  const double J = e.rho0 / rho_micro;
  return e.p_ref - 0.5 * e.bulk * (J - 1.0 / J);
}

/// dp/drho at constant internal energy.
KOKKOS_INLINE_FUNCTION double eos_dp_drho(const Eos& e, double rho_micro, double temp) {
  if (e.type == EosType::ideal_gas) return (e.gamma - 1.0) * e.cv * temp;
  if (e.modified && rho_micro < e.rho0)
    return e.bulk / rho_micro * math::pow(rho_micro / e.rho0, e.bulk / e.p_ref);
  const double J = e.rho0 / rho_micro;
  return 0.5 * e.bulk * (1.0 + J * J) / e.rho0;
}

/// dp/de at constant density (0 for the solid's bulk law).
KOKKOS_INLINE_FUNCTION double eos_dp_de(const Eos& e, double rho_micro, double /*temp*/) {
  return e.type == EosType::ideal_gas ? (e.gamma - 1.0) * rho_micro : 0.0;
}

/// Whether the material has the modified law in tension (E52): a `modified` solid.
KOKKOS_INLINE_FUNCTION bool eos_has_tension_law(const Eos& e) { return e.type == EosType::solid && e.modified; }

/// Whether the modified law in tension (E52) gives the material's density at `press`.
KOKKOS_INLINE_FUNCTION bool eos_tension_law(const Eos& e, double press) {
  return eos_has_tension_law(e) && press < e.p_ref;
}

/// Micro density from pressure and temperature where eos_tension_law does not hold
/// (E48, E51). Without the tension law's call to pow, a host loop over cells that uses
/// this vectorises; its cells in tension are then redone with eos_density (node_to_cell).
KOKKOS_INLINE_FUNCTION double eos_density_outside_tension(const Eos& e, double press, double temp) {
  if (e.type == EosType::ideal_gas) return ideal_gas_density(e, press, temp);
  const double x = (press - e.p_ref) / e.bulk;
  return e.rho0 * (x + math::sqrt(x * x + 1.0));
}

/// Micro density from pressure and temperature, the inverse of eos_pressure.
KOKKOS_INLINE_FUNCTION double eos_density(const Eos& e, double press, double temp) {
  if (eos_tension_law(e, press)) return e.rho0 * math::pow(press / e.p_ref, e.p_ref / e.bulk);
  return eos_density_outside_tension(e, press, temp);
}

/// Squared sound speed: dp/drho + dp/de p / rhoM^2 for a gas (E47); K / rhoM for the
/// solid (E51, Uintah's choice, see mpmice-algorithm.md 13), dp/drho in tension (E52).
KOKKOS_INLINE_FUNCTION double eos_sound_speed_squared(const Eos& e, double rho_micro, double temp) {
  if (e.type == EosType::solid) {
    if (e.modified && rho_micro < e.rho0) return eos_dp_drho(e, rho_micro, temp);
    return e.bulk / rho_micro;
  }
  return ideal_gas_sound_speed_squared(e, rho_micro, temp);
}

/// Thermal expansivity alpha = (1/v)(dv/dT)_p: 1/T for an ideal gas (E48), 0 for the
/// solid's bulk law.
KOKKOS_INLINE_FUNCTION double eos_alpha(const Eos& e, double /*rho_micro*/, double temp) {
  return e.type == EosType::ideal_gas ? 1.0 / temp : 0.0;
}

}  // namespace mpmice
