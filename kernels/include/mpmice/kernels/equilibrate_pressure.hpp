#pragma once
/// \file equilibrate_pressure.hpp
/// \brief Step 3: the single pressure at which the materials of a cell fill it,
///        sum_r theta_r(p) = 1 (E14-E16), by Newton from last step's pressure with a
///        bisection fallback; in closed form when every material is an ideal gas.
#include <cfloat>

#include <mpmice/kernels/constants.hpp>
#include <mpmice/kernels/grid.hpp>
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// Inputs of the equilibration (state at t^n, extra cells filled).
struct EquilibrationIn {
  ConstField4 rho;     ///< bulk density rho_r, kg/m^3
  ConstField4 temp;    ///< T_r, K
  ConstField4 sp_vol;  ///< specific volume v_r at t^n, m^3/kg
  ConstField3 press;   ///< p^n, Pa (first Newton guess)
};

/// Outputs (E16).
struct EquilibrationOut {
  Field3 press_eq;     ///< p_eq, Pa
  Field4 vol_frac;     ///< theta_r
  Field4 sp_vol;       ///< v_r = 1/rhoM_r at p_eq, m^3/kg
  Field4 speed_sound;  ///< c_r, m/s
  Field4 kappa;        ///< compressibility v_r/c_r^2, 1/Pa
  Field3 sum_kappa;    ///< SK = sum theta_r kappa_r, 1/Pa
  Field3 tmv;          ///< total material volume sum_r m_r/rhoM_r, m^3
};

/// Where the equilibration failed: one failing cell (local index), if any.
struct EquilibrationFailure {
  bool failed = false;
  int cell[3] = {0, 0, 0};
};

namespace detail {

// Every material's micro density at pressure `press` and its volume fraction
// rhoB/rhoM; returns their sum. N = mats.count, known at compile time.
template <int N>
KOKKOS_INLINE_FUNCTION double fractions_at(const MaterialTable& mats, double press, const double* temp,
                                           const double* rho_bulk, double* rho_micro, double* theta) {
  double sum = 0;
  for (int r = 0; r < N; ++r) {
    rho_micro[r] = eos_density(mats.eos[r], press, temp[r]);
    theta[r] = rho_bulk[r] / rho_micro[r];
    sum += theta[r];
  }
  return sum;
}

// Residual-corrected Newton (E15); returns false if not converged.
template <int N>
KOKKOS_INLINE_FUNCTION bool equilibrate_newton(const MaterialTable& mats, const double* temp,
                                               const double* rho_bulk, double* rho_micro,
                                               double* theta, double& press) {
  for (int it = 0; it < equilibration_max_iterations; ++it) {
    double A = 0, B = 0, C = 0;
    for (int r = 0; r < N; ++r) {
      const double p_r = eos_pressure(mats.eos[r], rho_micro[r], temp[r]);
      const double dpdrho = eos_dp_drho(mats.eos[r], rho_micro[r], temp[r]);
      const double y = theta[r] * theta[r] / (dpdrho * rho_bulk[r] + small_number);
      A += theta[r];
      B += (press - p_r) * y;
      C += y;
    }
    const double dp = (A - 1.0 - B) / C;
    press += dp;
    if (press < equilibration_tolerance) press = math::abs(dp);
    const double sum = fractions_at<N>(mats, press, temp, rho_bulk, rho_micro, theta);
    if (math::abs(sum - 1.0) < equilibration_tolerance) return true;
  }
  return false;
}

// Bisection on 1 - sum_r rhoB_r / rhoM_r(P) over [DBL_EPSILON, 1/DBL_EPSILON].
template <int N>
KOKKOS_INLINE_FUNCTION bool equilibrate_bisection(const MaterialTable& mats, const double* temp,
                                                  const double* rho_bulk, double* rho_micro,
                                                  double* theta, double& press) {
  double lo = DBL_EPSILON, hi = 1.0 / DBL_EPSILON;
  for (int it = 0; it < 200; ++it) {
    const double sum = fractions_at<N>(mats, press, temp, rho_bulk, rho_micro, theta);
    if (math::abs(sum - 1.0) < equilibration_tolerance) return true;
    // sum theta falls as the pressure rises.
    if (sum > 1.0)
      lo = press;
    else
      hi = press;
    press = 0.5 * (lo + hi);
  }
  return false;
}

// One cell of ideal gases in closed form (E14-E16 with p_r = rhoM_r e_r, where
// e_r = (gamma_r - 1) c_v,r T_r, E48). With m_r = rho_r V, (E14) gives
// theta_r = m_r v_r^n / TMV^n and so rhoB_r = theta_r / v_r^n = m_r / TMV^n, and
// sum_r rhoB_r / rhoM_r(p) = 1 has the root p = S / TMV^n, S = sum_r m_r e_r, at which
//   v_r = e_r / p = e_r TMV^n / S,   theta_r = rhoB_r v_r = m_r e_r / S,
//   c_r^2 = gamma_r e_r (E47),      kappa_r = v_r / c_r^2 = 1 / (gamma_r p).
// Two divisions per cell (1/S and p) and a square root per material; taken through the
// micro densities, as the general path does, the same values cost 8 divisions per
// material (docs/performance.md, session 29). The Newton iteration would reach this root
// to its tolerance (100 ulps). No branch: the loop over cells vectorises.
template <int N>
struct IdealGasesCell {
  double cell_volume;
  Kokkos::Array<double, N> e_per_kelvin, gamma, inv_gamma;  ///< (gamma_r - 1) c_v,r; gamma_r; 1/gamma_r
  EquilibrationIn in;
  EquilibrationOut out;

  IdealGasesCell(const MaterialTable& mats, double cell_volume_, const EquilibrationIn& in_,
                 const EquilibrationOut& out_)
      : cell_volume(cell_volume_), in(in_), out(out_) {
    for (int r = 0; r < N; ++r) {
      e_per_kelvin[r] = (mats.eos[r].gamma - 1.0) * mats.eos[r].cv;
      gamma[r] = mats.eos[r].gamma;
      inv_gamma[r] = 1.0 / mats.eos[r].gamma;
    }
  }

  /// Equilibrates cell (i, j, k); returns whether its state is sane, as the general
  /// path judges it (rhoM_r = 1/v_r > 0 is v_r >= 0 here, an infinite rhoM_r included).
  KOKKOS_INLINE_FUNCTION bool operator()(long i, long j, long k) const {
    double mass[N], e[N];
    double tmv = 0, S = 0;
    unrolled_for<N>([&](int r) {
      mass[r] = in.rho(r, i, j, k) * cell_volume;
      e[r] = e_per_kelvin[r] * in.temp(r, i, j, k);
      tmv += mass[r] * in.sp_vol(r, i, j, k);
      S += mass[r] * e[r];
    });
    const double inv_S = 1.0 / S, press = S / tmv, inv_press = tmv * inv_S;
    bool sane = (press > 0.0) & math::isfinite(press);
    double sum_kappa = 0, tmv_eq = 0;
    unrolled_for<N>([&](int r) {
      const double theta = mass[r] * e[r] * inv_S, v = e[r] * inv_press, kappa = inv_press * inv_gamma[r];
      sane = sane & (v >= 0.0) & (theta >= 0.0);
      out.vol_frac(r, i, j, k) = theta;
      out.sp_vol(r, i, j, k) = v;
      out.speed_sound(r, i, j, k) = math::sqrt(gamma[r] * e[r]);
      out.kappa(r, i, j, k) = kappa;
      sum_kappa += theta * kappa;
      tmv_eq += mass[r] * v;
    });
    out.press_eq(i, j, k) = press;
    out.sum_kappa(i, j, k) = sum_kappa;
    out.tmv(i, j, k) = tmv_eq;
    return sane;
  }
};

// equilibrate_pressure() for N materials; returns 1 + the linear index of a failing
// cell, 0 if none. With only ideal gases (AllIdeal), in closed form (IdealGasesCell).
template <int N, bool AllIdeal>
long equilibrate_pressure_n(const IndexBox& cells, double cell_volume, const MaterialTable& mats,
                            const EquilibrationIn& in, const EquilibrationOut& out) {
  const long nj = in.rho.extent(2), nk = in.rho.extent(3);
  const IdealGasesCell<N> ideal_gases(mats, cell_volume, in, out);
  // One cell's equilibration; true if its state is sane.
  const auto equilibrate_cell = KOKKOS_LAMBDA(long i, long j, long k) {
    if constexpr (AllIdeal) {
      return ideal_gases(i, j, k);
    } else {
      double temp[N], rho_bulk[N], rho_micro[N], theta[N];
      // (E14): start from last step's micro densities.
      double tmv = 0;
      unrolled_for<N>([&](int r) {
        temp[r] = in.temp(r, i, j, k);
        rho_micro[r] = 1.0 / in.sp_vol(r, i, j, k);
        theta[r] = in.rho(r, i, j, k) * cell_volume / rho_micro[r];
        tmv += theta[r];
      });
      unrolled_for<N>([&](int r) {
        theta[r] /= tmv;
        rho_bulk[r] = theta[r] * rho_micro[r];
      });
      double press = in.press(i, j, k);
      bool ok = equilibrate_newton<N>(mats, temp, rho_bulk, rho_micro, theta, press);
      if (!ok) {
        press = in.press(i, j, k);
        ok = equilibrate_bisection<N>(mats, temp, rho_bulk, rho_micro, theta, press);
      }
      bool sane = ok & (press > 0.0) & math::isfinite(press);
      // (E16)
      double sum_kappa = 0, tmv_eq = 0;
      unrolled_for<N>([&](int r) {
        sane = sane & (rho_micro[r] > 0.0) & (theta[r] >= 0.0);
        const double c2 = eos_sound_speed_squared(mats.eos[r], rho_micro[r], temp[r]);
        const double v = 1.0 / rho_micro[r];
        const double kappa = v / c2;
        out.vol_frac(r, i, j, k) = theta[r];
        out.sp_vol(r, i, j, k) = v;
        out.speed_sound(r, i, j, k) = math::sqrt(c2);
        out.kappa(r, i, j, k) = kappa;
        sum_kappa += theta[r] * kappa;
        tmv_eq += in.rho(r, i, j, k) * cell_volume * v;
      });
      out.press_eq(i, j, k) = press;
      out.sum_kappa(i, j, k) = sum_kappa;
      out.tmv(i, j, k) = tmv_eq;
      return sane;
    }
  };
  // Whether any cell failed, as a vectorisable max of 0/1 (a cell index would need a
  // long -> double conversion that AVX2 lacks, and the loop would stay scalar).
  const double failed = reduce_over_index<Reduction::max, Rows::longest>(
      "mpmice::equilibrate_pressure", cells,
      KOKKOS_LAMBDA(long i, long j, long k) { return equilibrate_cell(i, j, k) ? 0.0 : 1.0; });
  if (failed == 0.0) return 0;
  // Rarely: find a failing cell, by equilibrating again (the same inputs, the same outputs).
  long bad = 0;
  Kokkos::parallel_reduce(
      "mpmice::equilibrate_pressure_failure", cells.policy(),
      KOKKOS_LAMBDA(int i, int j, int k, long& b) {
        const long id = (long(i) * nj + j) * nk + k + 1;
        if (!equilibrate_cell(i, j, k) && id > b) b = id;
      },
      Kokkos::Max<long>(bad));
  return bad;
}

}  // namespace detail

/// Equilibrate every cell of `cells`; volume `cell_volume` in m^3.
inline EquilibrationFailure equilibrate_pressure(const IndexBox& cells, double cell_volume,
                                                 const MaterialTable& mats,
                                                 const EquilibrationIn& in,
                                                 const EquilibrationOut& out) {
  const int nj = int(in.rho.extent(2)), nk = int(in.rho.extent(3));
  long bad_cell = 0;  // 1 + linear index of a failing cell, 0 if none
  bool all_ideal = true;
  for (int r = 0; r < mats.count; ++r) all_ideal = all_ideal && mats.eos[r].type == EosType::ideal_gas;
  with_material_count(mats.count, [&](auto n) {
    constexpr int N = decltype(n)::value;
    with_flag(all_ideal, [&](auto ideal) {
      bad_cell = detail::equilibrate_pressure_n<N, decltype(ideal)::value>(cells, cell_volume, mats, in, out);
    });
  });
  EquilibrationFailure f;
  if (bad_cell > 0) {
    const long id = bad_cell - 1;
    f.failed = true;
    f.cell[0] = int(id / (long(nj) * nk));
    f.cell[1] = int((id / nk) % nj);
    f.cell[2] = int(id % nk);
  }
  return f;
}

}  // namespace mpmice
