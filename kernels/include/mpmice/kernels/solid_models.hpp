#pragma once
/// \file solid_models.hpp
/// \brief Constitutive models of MPM materials, pointwise (mpmice-algorithm.md 9.3):
///        compressible neo-Hookean (E53), neo-Hookean with J2 plasticity and linear
///        hardening (E54), and a rigid material with prescribed velocity. Cauchy
///        stress, tension positive, Pa.
#include <mpmice/kernels/mat3.hpp>

#include <cmath>

namespace mpmice {

enum class SolidModelType : int { neo_hookean = 0, neo_hookean_plastic = 1, rigid = 2 };

struct SolidModel {
  SolidModelType type = SolidModelType::neo_hookean;
  double density = 1000.0;        ///< reference density rho_0, kg/m^3
  double bulk_modulus = 1e9;      ///< K, Pa
  double shear_modulus = 1e9;     ///< G, Pa
  double yield_stress = 1e300;    ///< sigma_y, Pa (plastic)
  double hardening_modulus = 0;   ///< H, Pa (plastic)
  double failure_strain = 1e300;  ///< eps_f: plastic strain at which it fails (plastic)
  double cv = 1000.0;             ///< specific heat, J/kg/K
  double prescribed_velocity[3] = {0, 0, 0};  ///< m/s (rigid)
  double stop_time = 1e300;       ///< after this the rigid material stops, s
  double ramp_time = 0;           ///< rigid speed rises from 0 (and falls to 0 at stop_time) over this, s

  /// Rigid speed as a fraction of `prescribed_velocity` at time t: a sin^2 rise over
  /// [0, ramp_time], 1, a cos^2 fall over [stop_time - ramp_time, stop_time], 0 after.
  /// Each ramp integrates to ramp_time / 2, so the stroke is |v| (stop_time - ramp_time).
  /// Host-side (the driver passes the resulting velocity to the kernels).
  double rigid_speed_fraction(double t) const {
    if (t >= stop_time || t < 0) return 0.0;
    if (ramp_time <= 0) return 1.0;
    const double half_pi = 1.5707963267948966;
    const double rise = t < ramp_time ? std::sin(half_pi * t / ramp_time) : 1.0;
    const double left = stop_time - t;
    const double fall = left < ramp_time ? std::sin(half_pi * left / ramp_time) : 1.0;
    return rise * rise * fall * fall;
  }
  /// The rigid body's velocity at time t, m/s (host-side, as rigid_speed_fraction).
  Kokkos::Array<double, 3> rigid_velocity(double t) const {
    const double f = rigid_speed_fraction(t);
    return {f * prescribed_velocity[0], f * prescribed_velocity[1], f * prescribed_velocity[2]};
  }

  /// The P-wave (dilatational) modulus K + 4G/3, Pa (E58).
  KOKKOS_INLINE_FUNCTION double dilatational_modulus() const { return bulk_modulus + 4.0 * shear_modulus / 3.0; }
  /// Dilatational wave speed at density rho, m/s (E58).
  KOKKOS_INLINE_FUNCTION double wave_speed(double rho) const { return math::sqrt(dilatational_modulus() / rho); }
  /// The same squared per unit J, m^2/s^2: at the density rho_0 / J, c_dil = sqrt(J times
  /// this), without a division (the stress update's step limit).
  KOKKOS_INLINE_FUNCTION double wave_speed_squared_per_J() const { return dilatational_modulus() / density; }
};

/// Volumetric (pressure) part of the Cauchy stress, (K/2)(J - 1/J) (E53), with 1/J given.
KOKKOS_INLINE_FUNCTION double neo_hookean_mean_stress(double J, double inv_J, double K) {
  return 0.5 * K * (J - inv_J);
}
/// The same, dividing.
KOKKOS_INLINE_FUNCTION double neo_hookean_mean_stress(double J, double K) {
  return neo_hookean_mean_stress(J, 1.0 / J, K);
}

/// sigma = (K/2)(J - 1/J) I + (G/J) dev(J^{-2/3} F F^T) (E53), with 1/J divided once
/// (in the vector loop of the stress update a division costs about 10 products).
KOKKOS_INLINE_FUNCTION Mat3 neo_hookean_stress(const Mat3& F, double K, double G) {
  const double J = F.det(), inv_J = 1.0 / J;
  const double j13 = math::inverse_cube_root(J);
  const Mat3 bbar = (j13 * j13) * (F * F.transpose());
  Mat3 sigma = (G * inv_J) * bbar.deviator();
  const double p = neo_hookean_mean_stress(J, inv_J, K);
  for (int i = 0; i < 3; ++i) sigma(i, i) += p;
  return sigma;
}

/// Stored energy per reference volume, (K/2)((J^2 - 1)/2 - ln J) + (G/2)(tr bbar - 3),
/// whose derivatives give (E53); `bbar` is the (elastic) isochoric left Cauchy-Green,
/// taken at det 1: (E54)'s return map keeps the trial's trace, so bbar_e drifts off
/// det 1 while yielding, and its raw trace would count the plastic work as stored.
KOKKOS_INLINE_FUNCTION double neo_hookean_energy(double J, const Mat3& bbar, double K, double G) {
  const double tr = bbar.trace() * math::inverse_cube_root(bbar.det());
  return 0.5 * K * (0.5 * (J * J - 1.0) - math::log(J)) + 0.5 * G * (tr - 3.0);
}

/// Stored energy per reference volume of a failed particle: only the bulk law's, and
/// only in compression (the potential of `failed_stress`).
KOKKOS_INLINE_FUNCTION double failed_energy(double J, double K) {
  return J < 1.0 ? 0.5 * K * (0.5 * (J * J - 1.0) - math::log(J)) : 0.0;
}

/// Heat per reference volume, J/m^3, that one step of (E54) releases in a particle
/// whose plastic strain went from eps_old to eps_new: the plastic work
/// (sigma_y + H eps_p) d eps_p, integrated exactly over the step (all of it: the model
/// stores no cold work), and, in the step it fails, the elastic energy it can no longer
/// hold, W(J, bbar_e) - failed_energy(J). A failed particle deforms without work.
KOKKOS_INLINE_FUNCTION double plastic_heat(double eps_old, double eps_new, double J, const Mat3& bbar_e,
                                           const SolidModel& model) {
  if (eps_old >= model.failure_strain) return 0.0;
  double heat = (model.yield_stress + model.hardening_modulus * 0.5 * (eps_old + eps_new)) * (eps_new - eps_old);
  if (eps_new >= model.failure_strain)
    heat += neo_hookean_energy(J, bbar_e, model.bulk_modulus, model.shear_modulus) -
            failed_energy(J, model.bulk_modulus);
  return heat;
}

/// Cauchy stress from the Kirchhoff deviator s and the mean stress p (tension > 0).
KOKKOS_INLINE_FUNCTION Mat3 stress_from(const Mat3& s, double J, double p) {
  Mat3 sigma = (1.0 / J) * s;
  for (int i = 0; i < 3; ++i) sigma(i, i) += p;
  return sigma;
}

/// A failed particle (plastic strain at or past `failure_strain`) carries neither shear
/// nor tension, only its bulk law's pressure in compression (Uintah's erosion
/// "AllowNoTension"): the material breaks up and the gas behind it goes through. Not in
/// mpmice-algorithm.md; docs/design.md, "Failure".
KOKKOS_INLINE_FUNCTION Mat3 failed_stress(double p) {
  Mat3 sigma = Mat3::zero();
  if (p < 0.0)
    for (int i = 0; i < 3; ++i) sigma(i, i) = p;
  return sigma;
}

/// One step of J2 plasticity on the neo-Hookean model (E54, Simo's return map):
/// `f` = F_new F_old^{-1}, bbar_e and eps_p updated in place; returns the Cauchy
/// stress for det F_new = J (`failed_stress` once eps_p >= failure_strain).
KOKKOS_INLINE_FUNCTION Mat3 neo_hookean_plastic_stress(const Mat3& f, double J, Mat3& bbar_e,
                                                       double& eps_p, const SolidModel& model) {
  const double G = model.shear_modulus;
  const Mat3 fbar = math::inverse_cube_root(f.det()) * f;
  const Mat3 b_trial = fbar * bbar_e * fbar.transpose();
  const double tr3 = b_trial.trace() / 3.0;
  const double mubar = G * tr3;
  Mat3 s = G * b_trial.deviator();
  const double s_norm = s.norm();
  const double phi = s_norm - math::sqrt(2.0 / 3.0) * (model.yield_stress + model.hardening_modulus * eps_p);
  if (phi > 0.0) {
    const double dgamma = (phi / (2.0 * mubar)) / (1.0 + model.hardening_modulus / (3.0 * mubar));
    s = (1.0 - 2.0 * mubar * dgamma / s_norm) * s;
    eps_p += math::sqrt(2.0 / 3.0) * dgamma;
    bbar_e = (1.0 / G) * s;
    for (int i = 0; i < 3; ++i) bbar_e(i, i) += tr3;
  } else {
    bbar_e = b_trial;
  }
  const double p = neo_hookean_mean_stress(J, model.bulk_modulus);
  return eps_p >= model.failure_strain ? failed_stress(p) : stress_from(s, J, p);
}

}  // namespace mpmice
