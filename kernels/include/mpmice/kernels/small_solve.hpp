#pragma once
/// \file small_solve.hpp
/// \brief Dense N x N solve by Gaussian elimination, for the
///        per-cell exchange systems (E19, E31). N is a compile-time constant (1 to
///        max_materials, chosen by `with_material_count` in materials.hpp), and every
///        loop is written out (`unrolled_for`), so the arrays live in registers and
///        a kernel calling these vectorises across cells.
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/math.hpp>
#include <mpmice/kernels/types.hpp>

namespace mpmice {

/// Solve A x = b in place for `NRHS` right-hand sides: on return b holds x. A is
/// row-major a[r * N + s]; b is b[k * N + r]. No pivoting: the exchange matrices are
/// strictly diagonally dominant by rows (diagonal 1 + sum_s beta_rs, off-diagonal
/// -beta_rs, beta >= 0), which elimination keeps, so every pivot is >= 1 and the growth
/// factor is at most 2 (Wilkinson). Fixed indices keep a and b in registers. Each
/// pivot is inverted once, and the back substitution multiplies by its inverse: N
/// divisions instead of N (1 + NRHS), the largest cost of the exchange with several
/// materials (a division costs what 10-20 multiply-adds do).
template <int N, int NRHS>
KOKKOS_INLINE_FUNCTION void solve_dense(double* a, double* b) {
  double inv_pivot[N];
  unrolled_for<N>([&](int col) {
    const double inv = 1.0 / a[col * N + col];
    inv_pivot[col] = inv;
    unrolled_for<N>([&](int r) {
      if (r <= col) return;
      const double f = a[r * N + col] * inv;
      unrolled_for<N>([&](int s) {
        if (s >= col) a[r * N + s] -= f * a[col * N + s];
      });
      unrolled_for<NRHS>([&](int k) { b[k * N + r] -= f * b[k * N + col]; });
    });
  });
  unrolled_for<NRHS>([&](int k) {
    unrolled_for<N>([&](int rr) {
      const int r = N - 1 - rr;
      double sum = b[k * N + r];
      unrolled_for<N>([&](int s) {
        if (s > r) sum -= a[r * N + s] * b[k * N + s];
      });
      b[k * N + r] = sum * inv_pivot[r];
    });
  });
}

/// implicit_exchange for two materials in closed form. Subtracting the two rows of the
/// system gives the new difference d = (q_1 - q_0) / (1 + beta_01 + beta_10), and the
/// rows then read dq_0 = beta_01 d and dq_1 = -beta_10 d: the same exact solution as
/// elimination, with one division per call instead of two in sequence and less than
/// half the arithmetic (on 1 thread 1.17-1.33x for the exchange and the face exchange
/// of two materials, docs/performance.md, session 35). The uniform shift that restores
/// sum_r w_r q_r is implicit_exchange's.
template <int NQ>
KOKKOS_INLINE_FUNCTION void implicit_exchange_pair(double beta_01, double beta_10, double* q, const double* weight) {
  const double inv_denominator = 1.0 / (1.0 + beta_01 + beta_10);
  const double inv_wsum = 1.0 / (weight[0] + weight[1]);
  unrolled_for<NQ>([&](int k) {
    const double d = (q[k * 2 + 1] - q[k * 2]) * inv_denominator;
    const double dq_0 = beta_01 * d, dq_1 = -beta_10 * d;
    const double shift = -(weight[0] * dq_0 + weight[1] * dq_1) * inv_wsum;  // sum_r w_r dq_r must vanish
    q[k * 2] += dq_0 + shift;
    q[k * 2 + 1] += dq_1 + shift;
  });
}

/// The exchange system of (E19)/(E31): with beta_rs = beta[r * N + s] given, solve
/// (1 + sum_s beta_rs) dq_r - sum_s beta_rs dq_s = sum_s beta_rs (q_s - q_r)
/// for `NQ` quantities q[k * N + r], and add dq to q. The matrix is A = I + L, L the
/// beta's Laplacian (L q)_r = sum_s beta_rs (q_r - q_s), and the right side is -L q, so
/// the new values q + dq solve A (q + dq) = q: elimination (solve_dense) solves that,
/// with no right side to form (1.12-1.19x with 4 materials, docs/performance.md,
/// session 35). Two materials take the closed form (implicit_exchange_pair).
///
/// `weight` w_r makes w_r beta_rs symmetric (a mass, for (E31)), so the exact solution
/// keeps sum_r w_r q_r. With a stiff coefficient (K = 1e15) the matrix is nearly
/// singular along the uniform vector (relative to its size) and elimination errs mostly
/// in that direction; shifting the result by a uniform amount restores sum_r w_r q_r to
/// round-off, which is the exact solution's property.
template <int N, int NQ>
KOKKOS_INLINE_FUNCTION void implicit_exchange(const double* beta, double* q, const double* weight) {
  if constexpr (N == 1) {
    return;  // nothing to exchange with
  } else if constexpr (N == 2) {
    implicit_exchange_pair<NQ>(beta[0 * 2 + 1], beta[1 * 2 + 0], q, weight);
  } else {
    double a[N * N];
    double b[NQ * N];
    unrolled_for<N>([&](int r) {
      double diag = 1.0;
      unrolled_for<N>([&](int s) {
        if (s == r) return;
        diag += beta[r * N + s];
        a[r * N + s] = -beta[r * N + s];
      });
      a[r * N + r] = diag;
    });
    unrolled_for<NQ * N>([&](int i) { b[i] = q[i]; });
    solve_dense<N, NQ>(a, b);
    double wsum = 0.0;
    unrolled_for<N>([&](int r) { wsum += weight[r]; });
    const double inv_wsum = 1.0 / wsum;
    unrolled_for<NQ>([&](int k) {
      double shift = 0.0;  // sum_r w_r (q_r - b_r) / sum_r w_r
      unrolled_for<N>([&](int r) { shift += weight[r] * (q[k * N + r] - b[k * N + r]); });
      shift *= inv_wsum;
      unrolled_for<N>([&](int r) { q[k * N + r] = b[k * N + r] + shift; });
    });
  }
}

}  // namespace mpmice
