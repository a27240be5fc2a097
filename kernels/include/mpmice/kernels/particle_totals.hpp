#pragma once
/// \file particle_totals.hpp
/// \brief Totals of one MPM material over its particles for the conservation history:
///        mass, momentum, energy = stored strain energy + kinetic.
#include <mpmice/kernels/conserved_totals.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/solid_models.hpp>

namespace mpmice {

inline MaterialTotals particle_totals(long count, const ParticleData& data, const SolidModel& model) {
  MaterialTotals total;
  Kokkos::parallel_reduce(
      "mpmice::particle_totals", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, MaterialTotals& t) {
        const double m = data(p, column(ParticleField::mass));
        const double vx = data(p, column(ParticleField::vx)), vy = data(p, column(ParticleField::vy)),
                     vz = data(p, column(ParticleField::vz));
        t.value[0] += m;
        t.value[1] += m * vx;
        t.value[2] += m * vy;
        t.value[3] += m * vz;
        double strain = 0;
        if (model.type != SolidModelType::rigid) {
          const Mat3 F = load_tensor(data, p, ParticleField::F00);
          const double J = F.det();
          const Mat3 bbar = model.type == SolidModelType::neo_hookean_plastic
                                ? load_tensor(data, p, ParticleField::be00)
                                : math::pow(J, -2.0 / 3.0) * (F * F.transpose());
          // Energy per reference volume times the reference volume m / rho_0.
          const bool failed = data(p, column(ParticleField::plastic_strain)) >= model.failure_strain;
          strain = (failed ? failed_energy(J, model.bulk_modulus)
                           : neo_hookean_energy(J, bbar, model.bulk_modulus, model.shear_modulus)) *
                   m / model.density;
        }
        t.value[4] += 0.5 * m * (vx * vx + vy * vy + vz * vz) + strain;
      },
      Kokkos::Sum<MaterialTotals>(total));
  return total;
}

/// The largest P2G contribution of each kind over these particles (weights <= 1):
/// max m_p, max |m_p v_p,d|, max m_p T_p, max V_p, max |f_ext,d| (for SumQuanta).
inline SumQuanta particle_scatter_bounds(long count, const ParticleData& data) {
  SumQuanta b;
  const auto policy = Kokkos::RangePolicy<ExecSpace>(0, count);
  Kokkos::parallel_reduce(
      "mpmice::bound_mass", policy,
      KOKKOS_LAMBDA(long p, double& mx) {
        const double v = data(p, column(ParticleField::mass));
        mx = v > mx ? v : mx;
      },
      Kokkos::Max<double>(b.mass));
  Kokkos::parallel_reduce(
      "mpmice::bound_momentum", policy,
      KOKKOS_LAMBDA(long p, double& mx) {
        for (int d = 0; d < 3; ++d) {
          const double v = math::abs(data(p, column(ParticleField::mass)) * data(p, column(ParticleField::vx) + d));
          mx = v > mx ? v : mx;
        }
      },
      Kokkos::Max<double>(b.momentum));
  Kokkos::parallel_reduce(
      "mpmice::bound_heat", policy,
      KOKKOS_LAMBDA(long p, double& mx) {
        const double v = data(p, column(ParticleField::mass)) * data(p, column(ParticleField::temperature));
        mx = v > mx ? v : mx;
      },
      Kokkos::Max<double>(b.heat));
  Kokkos::parallel_reduce(
      "mpmice::bound_volume", policy,
      KOKKOS_LAMBDA(long p, double& mx) {
        const double v = data(p, column(ParticleField::volume));
        mx = v > mx ? v : mx;
      },
      Kokkos::Max<double>(b.volume));
  Kokkos::parallel_reduce(
      "mpmice::bound_force", policy,
      KOKKOS_LAMBDA(long p, double& mx) {
        for (int d = 0; d < 3; ++d) {
          const double v = math::abs(data(p, column(ParticleField::fext_x) + d));
          mx = v > mx ? v : mx;
        }
      },
      Kokkos::Max<double>(b.external_force));
  return b;
}

/// Internal (thermal) energy of a solid's particles, sum m_p c_v T_p (J): what a
/// reaction takes from the reactant into the products (E46).
inline double particle_thermal_energy(long count, const ParticleData& data, double cv) {
  double total = 0;
  Kokkos::parallel_reduce(
      "mpmice::particle_thermal_energy", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, double& t) {
        t += data(p, column(ParticleField::mass)) * cv * data(p, column(ParticleField::temperature));
      },
      total);
  return total;
}

}  // namespace mpmice
