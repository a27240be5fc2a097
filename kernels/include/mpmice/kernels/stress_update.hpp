#pragma once
/// \file stress_update.hpp
/// \brief Step 23: the particles' Cauchy stress at t^{n+1} from their deformation
///        (E53, E54), and the MPM stable timestep (E58).
#include <mpmice/kernels/g2p.hpp>

namespace mpmice {

namespace detail {
// What a particle's (E58) limit needs of its material and the grid, made once per call:
// c_dil^2 per unit J and 1 / h_d.
struct StepRateTerms {
  double wave_speed_squared_per_J;
  Kokkos::Array<double, 3> inv_h;
  StepRateTerms(const SolidModel& model, const Kokkos::Array<double, 3>& h)
      : wave_speed_squared_per_J(model.wave_speed_squared_per_J()), inv_h{1.0 / h[0], 1.0 / h[1], 1.0 / h[2]} {}
};

// Particle p's max_d (c_dil + |v_d|) / h_d, the inverse of its (E58) limit, with the
// wave speed at the current density rho_0 / J, without a division (the elastic update
// is a vector loop, where a division costs about 10 products).
KOKKOS_INLINE_FUNCTION double step_rate(const StepRateTerms& terms, double J, const ParticleData& data, long p) {
  const double c = math::sqrt(terms.wave_speed_squared_per_J * J);
  double rate = 0;
  unrolled_for<3>([&](int d) {
    const double r = (c + math::abs(data(p, column(ParticleField::vx) + d))) * terms.inv_h[d];
    rate = r > rate ? r : rate;
  });
  return rate;
}

// The elastic neo-Hookean update (E53) as a vector loop over particles (loops.hpp):
// writes the stress, returns the largest step_rate.
inline double neo_hookean_update(long count, const ParticleData& data, const SolidModel& model,
                                 const Kokkos::Array<double, 3>& h) {
  const SolidModel mat = model;
  const StepRateTerms terms(model, h);
  return reduce_over_particles<Reduction::max>("mpmice::stress_update", count, KOKKOS_LAMBDA(long p) {
    const Mat3 F = load_tensor(data, p, ParticleField::F00);
    store_tensor(data, p, ParticleField::s00, neo_hookean_stress(F, mat.bulk_modulus, mat.shear_modulus));
    return step_rate(terms, F.det(), data, p);
  });
}

// J2 plasticity (E54) as a plain reduction (its return map branches and its increment
// sub-steps): writes stress, bbar_e, plastic strain and the plastic heat, returns the
// largest step_rate.
inline double neo_hookean_plastic_update(long count, const ParticleData& data, const SolidModel& model,
                                         const Kokkos::Array<double, 3>& h, double dt) {
  const StepRateTerms terms(model, h);
  double rate = 0;
  Kokkos::parallel_reduce(
      "mpmice::stress_update", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& largest) {
        const double J = load_tensor(data, p, ParticleField::F00).det();
        const Mat3 f = deformation_increment(load_tensor(data, p, ParticleField::L00), dt);
        Mat3 be = load_tensor(data, p, ParticleField::be00);
        double& eps = data(p, column(ParticleField::plastic_strain));
        const double eps_old = eps;
        const Mat3 sigma = neo_hookean_plastic_stress(f, J, be, eps, model);
        store_tensor(data, p, ParticleField::be00, be);
        // Plastic work and the energy released by failure heat the particle:
        // dT = heat / (rho_0 c_v), heat per reference volume.
        data(p, column(ParticleField::temperature)) +=
            plastic_heat(eps_old, eps, J, be, model) / (model.density * model.cv);
        store_tensor(data, p, ParticleField::s00, sigma);
        const double r = step_rate(terms, J, data, p);
        if (r > largest) largest = r;
      },
      Kokkos::Max<double>(rate));
  return rate;
}
}  // namespace detail

/// Updates stress (and bbar_e, plastic strain, and the temperature by the plastic
/// work, `plastic_heat`) of the `count` particles of one material; returns min over
/// particles and directions of h_d / (c_dil + |v_d|), the dilatational wave speed at
/// the current density rho_0 / J (E58); a rigid material does not limit the step
/// (returns a huge value). The elastic model runs as a vector loop, the plastic one as
/// a plain reduction; both reduce the limit's inverse (detail::step_rate).
inline double stress_update(const NodeGrid& grid, long count, const ParticleData& data,
                            const SolidModel& model, double dt) {
  if (model.type == SolidModelType::rigid) return 1e300;
  const Kokkos::Array<double, 3> h = {grid.h[0], grid.h[1], grid.h[2]};
  const double rate = model.type == SolidModelType::neo_hookean
                          ? detail::neo_hookean_update(count, data, model, h)
                          : detail::neo_hookean_plastic_update(count, data, model, h, dt);
  return rate > 0 ? 1.0 / rate : 1e300;
}

}  // namespace mpmice
