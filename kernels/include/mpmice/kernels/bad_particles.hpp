#pragma once
/// \file bad_particles.hpp
/// \brief The particles' counterpart of (E38)'s stop condition: after the particle
///        update (Steps 21-23), every particle's position, velocity, deformation
///        gradient and stress must be finite, its mass and volume not negative, its
///        temperature positive. A particle that breaks this would send the next step's
///        kernels to a cell that does not exist; the driver stops first.
#include <mpmice/kernels/math.hpp>
#include <mpmice/kernels/particles.hpp>

namespace mpmice {

/// What one particle broke, in the order the check tries them.
enum class ParticleQuantity : int { position, velocity, mass, volume, temperature, deformation, stress, count };

inline const char* quantity_name(ParticleQuantity q) {
  static const char* names[] = {"position",    "velocity", "mass", "volume", "temperature",
                                "deformation gradient", "stress"};
  return names[static_cast<int>(q)];
}

/// The particles that broke the conditions: how many, and one of them (the last in
/// row order) with the first quantity it broke.
struct BadParticle {
  long count = 0;
  long row = -1;
  ParticleQuantity quantity = ParticleQuantity::position;
};

/// Checks the first `count` rows of `data`.
inline BadParticle find_bad_particles(long count, const ParticleData& data) {
  constexpr int nq = static_cast<int>(ParticleQuantity::count);
  long bad = 0, code = -1;  // code: row * nq + quantity
  Kokkos::parallel_reduce(
      "mpmice::find_bad_particles", Kokkos::RangePolicy<ExecSpace>(0, count),
      KOKKOS_LAMBDA(long p, long& n, long& where) {
        auto finite_run = [&](ParticleField first, int length) {
          bool ok = true;
          for (int c = 0; c < length; ++c) ok = ok && math::isfinite(data(p, column(first) + c));
          return ok;
        };
        const double m = data(p, column(ParticleField::mass));
        const double v = data(p, column(ParticleField::volume));
        const double t = data(p, column(ParticleField::temperature));
        int q = -1;
        if (!finite_run(ParticleField::x, 3)) q = int(ParticleQuantity::position);
        else if (!finite_run(ParticleField::vx, 3)) q = int(ParticleQuantity::velocity);
        else if (!(m >= 0) || !math::isfinite(m)) q = int(ParticleQuantity::mass);
        else if (!(v >= 0) || !math::isfinite(v)) q = int(ParticleQuantity::volume);
        else if (!(t > 0) || !math::isfinite(t)) q = int(ParticleQuantity::temperature);
        else if (!finite_run(ParticleField::F00, 9)) q = int(ParticleQuantity::deformation);
        else if (!finite_run(ParticleField::s00, 9)) q = int(ParticleQuantity::stress);
        if (q < 0) return;
        ++n;
        if (p * nq + q > where) where = p * nq + q;
      },
      bad, Kokkos::Max<long>(code));
  BadParticle b;
  b.count = bad;
  if (bad > 0) {
    b.row = code / nq;
    b.quantity = static_cast<ParticleQuantity>(code % nq);
  }
  return b;
}

}  // namespace mpmice
