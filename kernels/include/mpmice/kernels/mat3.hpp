#pragma once
/// \file mat3.hpp
/// \brief 3x3 matrices in registers for per-particle kinematics and stress.
#include <mpmice/kernels/math.hpp>

namespace mpmice {

struct Mat3 {
  double a[3][3];

  KOKKOS_INLINE_FUNCTION static Mat3 identity() {
    Mat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.a[i][j] = i == j ? 1.0 : 0.0;
    return m;
  }
  KOKKOS_INLINE_FUNCTION static Mat3 zero() {
    Mat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.a[i][j] = 0.0;
    return m;
  }
  KOKKOS_INLINE_FUNCTION double& operator()(int i, int j) { return a[i][j]; }
  KOKKOS_INLINE_FUNCTION double operator()(int i, int j) const { return a[i][j]; }
  KOKKOS_INLINE_FUNCTION double trace() const { return a[0][0] + a[1][1] + a[2][2]; }
  KOKKOS_INLINE_FUNCTION double det() const {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  }
  KOKKOS_INLINE_FUNCTION Mat3 inverse() const {
    Mat3 r;
    const double inv = 1.0 / det();
    r.a[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) * inv;
    r.a[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * inv;
    r.a[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * inv;
    r.a[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) * inv;
    r.a[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * inv;
    r.a[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * inv;
    r.a[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) * inv;
    r.a[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * inv;
    r.a[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * inv;
    return r;
  }
  KOKKOS_INLINE_FUNCTION Mat3 transpose() const {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.a[i][j] = a[j][i];
    return r;
  }
  /// Frobenius norm.
  KOKKOS_INLINE_FUNCTION double norm() const {
    double s = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s += a[i][j] * a[i][j];
    return math::sqrt(s);
  }
  /// The deviatoric part.
  KOKKOS_INLINE_FUNCTION Mat3 deviator() const {
    Mat3 r = *this;
    const double third = trace() / 3.0;
    for (int i = 0; i < 3; ++i) r.a[i][i] -= third;
    return r;
  }
};

KOKKOS_INLINE_FUNCTION Mat3 operator*(const Mat3& x, const Mat3& y) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.a[i][j] = x.a[i][0] * y.a[0][j] + x.a[i][1] * y.a[1][j] + x.a[i][2] * y.a[2][j];
  return r;
}
KOKKOS_INLINE_FUNCTION Mat3 operator*(double s, const Mat3& x) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.a[i][j] = s * x.a[i][j];
  return r;
}
KOKKOS_INLINE_FUNCTION Mat3 operator+(const Mat3& x, const Mat3& y) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.a[i][j] = x.a[i][j] + y.a[i][j];
  return r;
}
KOKKOS_INLINE_FUNCTION Mat3 operator-(const Mat3& x, const Mat3& y) { return x + (-1.0) * y; }

}  // namespace mpmice
