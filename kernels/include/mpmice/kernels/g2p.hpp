#pragma once
/// \file g2p.hpp
/// \brief Steps 21-22: grid-to-particle update of velocity (FLIP with an optional PIC
///        fraction) and position (E35), and the particle kinematics: velocity
///        gradient, deformation gradient and volume (E36). Weights use the old
///        positions.
#include <mpmice/kernels/particle_grid.hpp>
#include <mpmice/kernels/shape.hpp>
#include <mpmice/kernels/solid_models.hpp>

namespace mpmice {

/// The deformation over one step, (I + L dt/n)^n with n = min(max(1, 2 floor(|L| dt)),
/// 10000) sub-steps (E36): F_new = increment F_old.
KOKKOS_INLINE_FUNCTION Mat3 deformation_increment(const Mat3& L, double dt) {
  int nsub = int(2.0 * math::floor(L.norm() * dt));
  nsub = nsub < 1 ? 1 : (nsub > 10000 ? 10000 : nsub);
  const Mat3 step = Mat3::identity() + (dt / nsub) * L;
  Mat3 increment = Mat3::identity();
  for (int s = 0; s < nsub; ++s) increment = step * increment;
  return increment;
}

/// For the particles of material slot m: v_p <- (1-a)(v_p + dt sum S a_i) + a sum S v*_i,
/// x_p += dt sum S v*_i, T_p += dt sum S aT_i (E35; `temp_rate` may be empty),
/// L_p = sum v*_i (x) grad S_ip, F <- (I + L dt/n)^n F, V_p <- V_p J_new/J_old (E36).
/// A rigid material moves with `rigid_velocity`.
template <class Shape>
void g2p(const NodeGrid& grid, long count, const ParticleData& data, int m, double dt,
         double pic_fraction, bool rigid, Kokkos::Array<double, 3> rigid_velocity,
         const ConstVectorField4& vel_star, const ConstVectorField4& acc,
         const ConstField4& temp_rate = ConstField4()) {
  const bool heat = temp_rate.data() != nullptr;
  Kokkos::parallel_for(
      "mpmice::g2p", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(long p) {
        if (rigid) {
          for (int d = 0; d < 3; ++d) {
            data(p, column(ParticleField::vx) + d) = rigid_velocity[d];
            data(p, column(ParticleField::x) + d) += dt * rigid_velocity[d];
          }
          return;
        }
        double x[3], half[3];
        particle_position(data, p, x, half);
        const ParticleWeights<Shape> wt(x, grid.origin, grid.inv_h, grid.first_node, half);
        double vs[3] = {0, 0, 0}, as[3] = {0, 0, 0}, ts = 0;
        Mat3 L = Mat3::zero();
        for (int a = 0; a < Shape::nodes; ++a)
          for (int b = 0; b < Shape::nodes; ++b)
            for (int c = 0; c < Shape::nodes; ++c) {
              const double S = wt.weight(a, b, c);
              if (S == 0.0) continue;
              double g[3];
              wt.gradient(a, b, c, g);
              const int i = wt.first[0] + a, j = wt.first[1] + b, k = wt.first[2] + c;
              if (heat) ts += S * temp_rate(m, i, j, k);
              for (int d = 0; d < 3; ++d) {
                const double v = vel_star[d](m, i, j, k);
                vs[d] += S * v;
                as[d] += S * acc[d](m, i, j, k);
                for (int e = 0; e < 3; ++e) L(d, e) += v * g[e];
              }
            }
        for (int d = 0; d < 3; ++d) {
          double& v = data(p, column(ParticleField::vx) + d);
          v = (1.0 - pic_fraction) * (v + dt * as[d]) + pic_fraction * vs[d];
          data(p, column(ParticleField::x) + d) = x[d] + dt * vs[d];
        }
        data(p, column(ParticleField::temperature)) += dt * ts;
        const Mat3 F = load_tensor(data, p, ParticleField::F00);
        const Mat3 F_new = deformation_increment(L, dt) * F;
        data(p, column(ParticleField::volume)) *= F_new.det() / F.det();
        store_tensor(data, p, ParticleField::F00, F_new);
        store_tensor(data, p, ParticleField::L00, L);
      });
}

}  // namespace mpmice
