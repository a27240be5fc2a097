#pragma once
/// \file small_solve.hpp
/// \brief Dense N x N solve by Gaussian elimination with partial pivoting, for the
///        per-cell exchange systems (E19, E31); N <= max_materials, in registers.
#include <mpmice/kernels/math.hpp>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

/// Solve A x = b in place for `nrhs` right-hand sides: on return b holds x. A is
/// row-major a[r * max_materials + s]; b is b[k * max_materials + r].
KOKKOS_INLINE_FUNCTION void solve_dense(int n, double* a, double* b, int nrhs) {
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int r = col + 1; r < n; ++r)
      if (math::abs(a[r * max_materials + col]) > math::abs(a[piv * max_materials + col])) piv = r;
    if (piv != col) {
      for (int s = 0; s < n; ++s) {
        const double t = a[col * max_materials + s];
        a[col * max_materials + s] = a[piv * max_materials + s];
        a[piv * max_materials + s] = t;
      }
      for (int k = 0; k < nrhs; ++k) {
        const double t = b[k * max_materials + col];
        b[k * max_materials + col] = b[k * max_materials + piv];
        b[k * max_materials + piv] = t;
      }
    }
    const double inv = 1.0 / a[col * max_materials + col];
    for (int r = col + 1; r < n; ++r) {
      const double f = a[r * max_materials + col] * inv;
      if (f == 0.0) continue;
      for (int s = col; s < n; ++s) a[r * max_materials + s] -= f * a[col * max_materials + s];
      for (int k = 0; k < nrhs; ++k) b[k * max_materials + r] -= f * b[k * max_materials + col];
    }
  }
  for (int k = 0; k < nrhs; ++k)
    for (int r = n - 1; r >= 0; --r) {
      double sum = b[k * max_materials + r];
      for (int s = r + 1; s < n; ++s) sum -= a[r * max_materials + s] * b[k * max_materials + s];
      b[k * max_materials + r] = sum / a[r * max_materials + r];
    }
}

/// The exchange system of (E19)/(E31): with beta_rs given, solve
/// (1 + sum_s beta_rs) dq_r - sum_s beta_rs dq_s = sum_s beta_rs (q_s - q_r)
/// for `nq` quantities q[k * max_materials + r], and add dq to q.
///
/// `weight` w_r makes w_r beta_rs symmetric (a mass, for (E31)), so the exact solution
/// keeps sum_r w_r q_r. With a stiff coefficient (K = 1e15) the matrix is nearly
/// singular along the uniform vector and elimination errs mostly in that direction;
/// shifting the result by a uniform amount restores sum_r w_r q_r to round-off, which
/// is the exact solution's property. Pass nullptr to skip the correction.
KOKKOS_INLINE_FUNCTION void implicit_exchange(int n, const double* beta, double* q, int nq,
                                              const double* weight) {
  double a[max_materials * max_materials];
  double b[3 * max_materials];
  for (int r = 0; r < n; ++r) {
    double diag = 1.0;
    for (int s = 0; s < n; ++s) {
      if (s == r) continue;
      diag += beta[r * max_materials + s];
      a[r * max_materials + s] = -beta[r * max_materials + s];
    }
    a[r * max_materials + r] = diag;
    for (int k = 0; k < nq; ++k) {
      double rhs = 0.0;
      for (int s = 0; s < n; ++s)
        if (s != r) rhs += beta[r * max_materials + s] * (q[k * max_materials + s] - q[k * max_materials + r]);
      b[k * max_materials + r] = rhs;
    }
  }
  solve_dense(n, a, b, nq);
  for (int k = 0; k < nq; ++k) {
    double shift = 0.0, wsum = 0.0;
    if (weight != nullptr) {
      // sum_r w_r dq_r must vanish.
      for (int r = 0; r < n; ++r) {
        shift -= weight[r] * b[k * max_materials + r];
        wsum += weight[r];
      }
      shift /= wsum;
    }
    for (int r = 0; r < n; ++r) q[k * max_materials + r] += b[k * max_materials + r] + shift;
  }
}

}  // namespace mpmice
