#pragma once
/// \file particle_totals.hpp
/// \brief Totals of one MPM material over its particles for the conservation history:
///        mass, momentum, energy = stored strain energy + kinetic.
#include <mpmice/kernels/conserved_totals.hpp>
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/quanta.hpp>
#include <mpmice/kernels/solid_models.hpp>

namespace mpmice {

/// The strain energy particle p stores, J: W per reference volume (E53, E54; a failed
/// particle only its compression) times its reference volume m / rho_0. 0 for a rigid
/// material.
KOKKOS_INLINE_FUNCTION double particle_strain_energy(const SolidModel& model, const ParticleData& data, long p) {
  if (model.type == SolidModelType::rigid) return 0.0;
  const Mat3 F = load_tensor(data, p, ParticleField::F00);
  const double J = F.det(), j13 = math::inverse_cube_root(J);
  const Mat3 bbar = model.type == SolidModelType::neo_hookean_plastic ? load_tensor(data, p, ParticleField::be00)
                                                                      : (j13 * j13) * (F * F.transpose());
  const bool failed = data(p, column(ParticleField::plastic_strain)) >= model.failure_strain;
  const double w = failed ? failed_energy(J, model.bulk_modulus)
                          : neo_hookean_energy(J, bbar, model.bulk_modulus, model.shear_modulus);
  return w * data(p, column(ParticleField::mass)) / model.density;
}

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
        const double strain = particle_strain_energy(model, data, p);
        t.value[4] += 0.5 * m * (vx * vx + vy * vy + vz * vz) + strain;
      },
      Kokkos::Sum<MaterialTotals>(total));
  return total;
}

/// Running maxima of the P2G contributions, in one reduction: Kokkos reduces a struct
/// through operator+= (as MaterialTotals), which here keeps the larger of each entry;
/// every entry is >= 0, so the sum's identity 0 is also the maximum's.
struct ScatterMaxima {
  double value[4] = {0, 0, 0, 0};  ///< |m v|, m T, V, |f_ext|
  KOKKOS_INLINE_FUNCTION ScatterMaxima& operator+=(const ScatterMaxima& o) {
    for (int q = 0; q < 4; ++q) value[q] = o.value[q] > value[q] ? o.value[q] : value[q];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile ScatterMaxima& o) volatile {
    for (int q = 0; q < 4; ++q) value[q] = o.value[q] > value[q] ? o.value[q] : value[q];
  }
};

}  // namespace mpmice

namespace Kokkos {
template <>
struct reduction_identity<mpmice::ScatterMaxima> {
  KOKKOS_FORCEINLINE_FUNCTION static mpmice::ScatterMaxima sum() { return {}; }
};
}  // namespace Kokkos

namespace mpmice {

/// The largest P2G contribution of each kind over these particles (weights <= 1):
/// max |m_p v_p,d|, max m_p T_p, max V_p, max |f_ext,d| (for SumQuanta; the mass
/// quantum is fixed for the run, `mass` stays 0), in one pass.
inline SumQuanta particle_scatter_bounds(long count, const ParticleData& data) {
  ScatterMaxima mx;
  Kokkos::parallel_reduce(
      "mpmice::particle_scatter_bounds", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, ScatterMaxima& t) {
        const double m = data(p, column(ParticleField::mass));
        ScatterMaxima here;
        for (int d = 0; d < 3; ++d) {
          const double mv = math::abs(m * data(p, column(ParticleField::vx) + d));
          const double f = math::abs(data(p, column(ParticleField::fext_x) + d));
          here.value[0] = mv > here.value[0] ? mv : here.value[0];
          here.value[3] = f > here.value[3] ? f : here.value[3];
        }
        here.value[1] = m * data(p, column(ParticleField::temperature));
        here.value[2] = data(p, column(ParticleField::volume));
        t += here;
      },
      Kokkos::Sum<ScatterMaxima>(mx));
  SumQuanta b;
  b.momentum = mx.value[0];
  b.heat = mx.value[1];
  b.volume = mx.value[2];
  b.external_force = mx.value[3];
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
