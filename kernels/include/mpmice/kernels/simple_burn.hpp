#pragma once
/// \file simple_burn.hpp
/// \brief Step 4: the solid -> gas reaction of the seed paper (eqs. 5-8), Simple Burn:
///        a reactant (MPM material) burns on its surface into a product gas (ICE
///        material) above a threshold temperature and pressure: the burning area and
///        the mass to burn per cell (E44-E45). particle_burn.hpp moves it (E46).
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/math.hpp>

namespace mpmice {

/// Parameters of one reactant -> product pair (mpmice-algorithm.md section 8).
struct SimpleBurn {
  int reactant = -1;           ///< cell material of the reactant (an MPM material)
  int reactant_slot = -1;      ///< its node slot
  int product = -1;            ///< cell material of the product (an ICE material)
  double threshold_temperature = 450;  ///< T_thr, K
  double threshold_pressure = 50000;   ///< p_thr, Pa
  double enthalpy = 2.0e6;             ///< dh released per kg burned, J/kg
  double coefficient = 75.3;           ///< B, kg m^-2 s^-1
  double reference_pressure = 101325;  ///< p_0, Pa
  double exponent = 0.778;             ///< n (HMX)
};

/// The burning surface area in a cell from the reactant's node masses M at its 8
/// corners (E44): 0 unless (Mmax - Mmin)/Mmax lies strictly between 0.4 and 1 and
/// Mmax > 1e-12; else A = V / [(dx|n_x| + dy|n_y| + dz|n_z|) (1/max_d |n_d|)^{1/3}]
/// with n the normalised mass gradient. `M[a][b][c]` is the corner (i+a, j+b, k+c).
KOKKOS_INLINE_FUNCTION double burn_area(const double M[2][2][2], const double h[3]) {
  double mmax = M[0][0][0], mmin = M[0][0][0];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        mmax = M[a][b][c] > mmax ? M[a][b][c] : mmax;
        mmin = M[a][b][c] < mmin ? M[a][b][c] : mmin;
      }
  if (!(mmax > 1e-12)) return 0.0;
  const double spread = (mmax - mmin) / mmax;
  if (!(spread > 0.4 && spread < 1.0)) return 0.0;
  double g[3] = {0, 0, 0};
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        const double sign[3] = {a ? -1.0 : 1.0, b ? -1.0 : 1.0, c ? -1.0 : 1.0};
        for (int d = 0; d < 3; ++d) g[d] += 0.25 * sign[d] * M[a][b][c] / h[d];
      }
  const double norm = math::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(norm > 0)) return 0.0;
  double n[3], nmax = 0, across = 0;
  for (int d = 0; d < 3; ++d) {
    n[d] = math::abs(g[d]) / norm;
    nmax = n[d] > nmax ? n[d] : nmax;
    across += h[d] * n[d];
  }
  return h[0] * h[1] * h[2] / (across * math::pow(1.0 / nmax, 1.0 / 3.0));
}

/// Simple Burn's rate on `cells` (E44-E45): in every cell whose reactant surface is
/// found from the node masses w_i m_i (`weight`, `node_mass` slot reactant_slot), with
/// T_b = max T_r^n over materials with theta_r > 0.2 and T_r^n > T_thr, and p_eq > p_thr,
/// the reactant is to lose dm = dt A B (p_eq/p_0)^n, at most its cell mass rho_s V.
/// Writes dm (kg) into slot `reactant` of `burn_dm` on `cells` (0 where nothing burns)
/// and returns the sum over `cells`. The particles lose it and the product gains it in
/// `burn_particles` (E46).
inline double burn_rate(const IndexBox& cells, const double h[3], double dt, int materials, const SimpleBurn& burn,
                        const ConstField3& weight, const ConstField4& node_mass, const ConstField4& rho,
                        const ConstField4& temp, const ConstField4& vol_frac, const ConstField3& press_eq,
                        const Field4& burn_dm) {
  const double hx = h[0], hy = h[1], hz = h[2], V = h[0] * h[1] * h[2];
  const SimpleBurn b = burn;
  double burned = 0;
  Kokkos::parallel_reduce(
      "mpmice::burn_rate", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, double& total) {
        burn_dm(b.reactant, i, j, k) = 0;
        double M[2][2][2];
        for (int a = 0; a < 2; ++a)
          for (int c = 0; c < 2; ++c)
            for (int e = 0; e < 2; ++e)
              M[a][c][e] = weight(i + a, j + c, k + e) * node_mass(b.reactant_slot, i + a, j + c, k + e);
        const double hh[3] = {hx, hy, hz};
        const double area = burn_area(M, hh);
        if (area <= 0) return;
        double t_burn = 0;
        for (int m = 0; m < materials; ++m) {
          const double t = temp(m, i, j, k);
          if (vol_frac(m, i, j, k) > 0.2 && t > b.threshold_temperature && t > t_burn) t_burn = t;
        }
        const double p = press_eq(i, j, k);
        if (!(t_burn > b.threshold_temperature && p > b.threshold_pressure)) return;
        const double available = rho(b.reactant, i, j, k) * V;
        double dm = dt * area * b.coefficient * math::pow(p / b.reference_pressure, b.exponent);
        dm = dm < available ? dm : available;
        burn_dm(b.reactant, i, j, k) = dm;
        total += dm;
      },
      burned);
  return burned;
}

}  // namespace mpmice
