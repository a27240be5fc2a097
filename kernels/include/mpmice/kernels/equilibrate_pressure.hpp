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

// The N materials' equations of state as the Newton iteration (E15) uses them: in
// the specific volume v = 1/rhoM, at the cell's temperatures, with the reciprocals it
// needs made once. A gas's v at pressure P is e/P with e = (gamma - 1) c_v T (E48),
// from one 1/P per iteration for all gases; a solid's, outside tension, with
// x = (P - p_ref)/K and s = sqrt(x^2 + 1), is (s - x)/rho_0, since (E51) gives
// rhoM = rho_0 (x + s) and (s - x)(s + x) = 1 (for x > 1/2 as rho_0^-1/(x + s), which
// does not cancel); in tension (E52) rho_0^-1 (P/p_ref)^(-p_ref/K). At such a state
// dp/drho is e for a gas, K/2 (1 + J^2)/rho_0 with J = rho_0 v for a solid outside
// tension, and K v P/p_ref in tension. Taken through rhoM with eos.hpp's functions, as
// Uintah writes it, the same iteration divided about 18 times per iteration with 4
// materials, against N + 2 here (docs/performance.md, session 39).
template <int N>
struct NewtonEos {
  Kokkos::Array<Eos, N> eos;
  Kokkos::Array<double, N> inv_rho0, inv_bulk, half_bulk;
  Kokkos::Array<double, N> volume_exponent, pressure_exponent;  ///< -p_ref/K and -K/p_ref (E52)
  explicit NewtonEos(const MaterialTable& mats) {
    for (int r = 0; r < N; ++r) {
      const Eos& q = mats.eos[r];
      eos[r] = q;
      inv_rho0[r] = 1.0 / q.rho0;
      inv_bulk[r] = 1.0 / q.bulk;
      half_bulk[r] = 0.5 * q.bulk;
      volume_exponent[r] = -q.p_ref / q.bulk;
      pressure_exponent[r] = -q.bulk / q.p_ref;
    }
  }
  KOKKOS_INLINE_FUNCTION bool gas(int r) const { return eos[r].type == EosType::ideal_gas; }
  /// A gas's e = (gamma - 1) c_v T (p = rhoM e), 0 for a solid.
  KOKKOS_INLINE_FUNCTION double gas_energy(int r, double temp) const {
    return gas(r) ? (eos[r].gamma - 1.0) * eos[r].cv * temp : 0.0;
  }
  /// v at pressure P (1/P given), e from gas_energy.
  KOKKOS_INLINE_FUNCTION double volume_at(int r, double e, double P, double inv_P) const {
    const Eos& q = eos[r];
    if (gas(r)) return e * inv_P;
    if (eos_tension_law(q, P)) return inv_rho0[r] * math::pow(P / q.p_ref, volume_exponent[r]);
    const double x = (P - q.p_ref) * inv_bulk[r], root = math::sqrt(x * x + 1.0);
    return x > 0.5 ? inv_rho0[r] / (x + root) : (root - x) * inv_rho0[r];
  }
  /// dp/drho at v = volume_at(P).
  KOKKOS_INLINE_FUNCTION double dp_drho_at(int r, double e, double P, double v) const {
    const Eos& q = eos[r];
    if (gas(r)) return e;
    if (eos_tension_law(q, P)) return q.bulk * v * (P / q.p_ref);
    const double J = q.rho0 * v;
    return half_bulk[r] * (1.0 + J * J) * inv_rho0[r];
  }
  /// The pressure p_r and dp/drho of a state v not made from a pressure (the iteration's
  /// start): eos_pressure and eos_dp_drho at rhoM = 1/v.
  KOKKOS_INLINE_FUNCTION void state_of(int r, double e, double v, double& p, double& dp_drho) const {
    const Eos& q = eos[r];
    if (gas(r)) {
      p = e / v;
      dp_drho = e;
      return;
    }
    const double J = q.rho0 * v;  // rho_0 / rhoM
    if (q.modified && J > 1.0) {
      p = q.p_ref * math::pow(J, pressure_exponent[r]);
      dp_drho = q.bulk * v * (p / q.p_ref);
      return;
    }
    p = q.p_ref - half_bulk[r] * (J - 1.0 / J);
    dp_drho = half_bulk[r] * (1.0 + J * J) * inv_rho0[r];
  }
  /// The squared sound speed at v = volume_at(P) (eos_sound_speed_squared: E47 for a
  /// gas, p/rhoM^2 being P v / rhoM; K/rhoM for a solid, dp/drho in tension).
  KOKKOS_INLINE_FUNCTION double sound_speed_squared_at(int r, double e, double P, double v) const {
    const Eos& q = eos[r];
    if (gas(r)) return e + (q.gamma - 1.0) * P * v;
    if (eos_tension_law(q, P)) return dp_drho_at(r, e, P, v);
    return q.bulk * v;
  }
};

// Every material's specific volume at pressure `press` and its volume fraction
// rhoB v; returns their sum.
template <int N>
KOKKOS_INLINE_FUNCTION double fractions_at(const NewtonEos<N>& eos, double press, const double* e,
                                           const double* rho_bulk, double* v, double* theta) {
  const double inv_press = 1.0 / press;
  double sum = 0;
  for (int r = 0; r < N; ++r) {
    v[r] = eos.volume_at(r, e[r], press, inv_press);
    theta[r] = rho_bulk[r] * v[r];
    sum += theta[r];
  }
  return sum;
}

// Residual-corrected Newton (E15) from the state (v, theta) and pressure `press`; returns
// false if not converged. Only the start's state is not the materials' at the iterate's
// pressure: after the first step each p_r is the iterate itself (the residual P - p_r,
// zero but for round-off, is left out).
template <int N>
KOKKOS_INLINE_FUNCTION bool equilibrate_newton(const NewtonEos<N>& eos, const double* e, const double* rho_bulk,
                                               double* v, double* theta, double& press) {
  for (int it = 0; it < equilibration_max_iterations; ++it) {
    double A = 0, B = 0, C = 0;
    for (int r = 0; r < N; ++r) {
      double p_r = press, dpdrho;
      if (it == 0)
        eos.state_of(r, e[r], v[r], p_r, dpdrho);
      else
        dpdrho = eos.dp_drho_at(r, e[r], press, v[r]);
      const double y = theta[r] * theta[r] / (dpdrho * rho_bulk[r] + small_number);
      A += theta[r];
      B += (press - p_r) * y;
      C += y;
    }
    const double dp = (A - 1.0 - B) / C;
    press += dp;
    if (press < equilibration_tolerance) press = math::abs(dp);
    const double sum = fractions_at<N>(eos, press, e, rho_bulk, v, theta);
    if (math::abs(sum - 1.0) < equilibration_tolerance) return true;
  }
  return false;
}

// Bisection on 1 - sum_r rhoB_r v_r(P) over [DBL_EPSILON, 1/DBL_EPSILON].
template <int N>
KOKKOS_INLINE_FUNCTION bool equilibrate_bisection(const NewtonEos<N>& eos, const double* e, const double* rho_bulk,
                                                  double* v, double* theta, double& press) {
  double lo = DBL_EPSILON, hi = 1.0 / DBL_EPSILON;
  for (int it = 0; it < 200; ++it) {
    const double sum = fractions_at<N>(eos, press, e, rho_bulk, v, theta);
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
  const NewtonEos<N> newton_eos(mats);
  // One cell's equilibration; true if its state is sane.
  const auto equilibrate_cell = KOKKOS_LAMBDA(long i, long j, long k) {
    if constexpr (AllIdeal) {
      return ideal_gases(i, j, k);
    } else {
      // (E14): last step's specific volumes (a solid's from its EOS at p^n, set in
      // Step 2), the volume fractions over the total material volume, and the bulk
      // densities held during the iteration.
      double mass[N], e[N], rho_bulk[N], v[N], theta[N];
      double tmv = 0;
      unrolled_for<N>([&](int r) {
        mass[r] = in.rho(r, i, j, k) * cell_volume;
        e[r] = newton_eos.gas_energy(r, in.temp(r, i, j, k));
        v[r] = in.sp_vol(r, i, j, k);
        theta[r] = mass[r] * v[r];
        tmv += theta[r];
      });
      const double inv_tmv = 1.0 / tmv;
      unrolled_for<N>([&](int r) {
        theta[r] *= inv_tmv;
        rho_bulk[r] = mass[r] * inv_tmv;
      });
      double press = in.press(i, j, k);
      bool ok = equilibrate_newton<N>(newton_eos, e, rho_bulk, v, theta, press);
      if (!ok) {
        press = in.press(i, j, k);
        ok = equilibrate_bisection<N>(newton_eos, e, rho_bulk, v, theta, press);
      }
      bool sane = ok & (press > 0.0) & math::isfinite(press);
      // (E16)
      double sum_kappa = 0, tmv_eq = 0;
      unrolled_for<N>([&](int r) {
        sane = sane & (v[r] >= 0.0) & (v[r] <= DBL_MAX) & (theta[r] >= 0.0);  // rhoM in (0, inf]
        const double c2 = newton_eos.sound_speed_squared_at(r, e[r], press, v[r]);
        const double kappa = v[r] / c2;
        out.vol_frac(r, i, j, k) = theta[r];
        out.sp_vol(r, i, j, k) = v[r];
        out.speed_sound(r, i, j, k) = math::sqrt(c2);
        out.kappa(r, i, j, k) = kappa;
        sum_kappa += theta[r] * kappa;
        tmv_eq += mass[r] * v[r];
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

#ifdef MPMICE_KERNEL_INSTANCES
// Compiled once for the project's own programs, in kernels/instances/ (g2p.hpp says why).
namespace detail {
#define MPMICE_EQUILIBRATE_PRESSURE_N(N, AllIdeal)                                                      \
  long equilibrate_pressure_n<N, AllIdeal>(const IndexBox&, double, const MaterialTable&, const EquilibrationIn&, \
                                           const EquilibrationOut&)
MPMICE_EACH_COUNT_AND_FLAG(extern template, MPMICE_EQUILIBRATE_PRESSURE_N)
}  // namespace detail
#endif

}  // namespace mpmice
