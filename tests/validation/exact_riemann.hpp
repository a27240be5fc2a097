#pragma once
// Exact solution of the ideal-gas Riemann problem (Toro, chapter 4), as written in
// mpmice-algorithm.md section 11.4: the star pressure from f_L(p) + f_R(p) + u_R - u_L
// = 0 (bisection: the left side increases with p), then sampling of the fan, contact
// and shock at x/t.
#include <cmath>

namespace mpmice::validation {

struct GasState {
  double rho, u, p;
};

class ExactRiemann {
 public:
  ExactRiemann(GasState left, GasState right, double gamma) : L(left), R(right), g(gamma) {
    double lo = 1e-14, hi = 10.0 * std::max(L.p, R.p);
    for (int it = 0; it < 300; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (f(mid, L) + f(mid, R) + R.u - L.u > 0) hi = mid;
      else lo = mid;
    }
    p_star = 0.5 * (lo + hi);
    u_star = 0.5 * (L.u + R.u) + 0.5 * (f(p_star, R) - f(p_star, L));
  }

  /// The state at similarity coordinate s = (x - x0)/t.
  GasState sample(double s) const {
    if (s <= u_star) return side(s, L, -1.0);
    return side(s, R, 1.0);
  }
  double p_star = 0, u_star = 0;

 private:
  double f(double p, const GasState& k) const {
    const double ck = std::sqrt(g * k.p / k.rho);
    if (p > k.p) {
      const double a = 2.0 / ((g + 1.0) * k.rho), b = (g - 1.0) / (g + 1.0) * k.p;
      return (p - k.p) * std::sqrt(a / (p + b));
    }
    return 2.0 * ck / (g - 1.0) * (std::pow(p / k.p, (g - 1.0) / (2.0 * g)) - 1.0);
  }
  // sign = -1 for the left wave family, +1 for the right; mirror formulas (Toro 4.5).
  GasState side(double s, const GasState& k, double sign) const {
    const double ck = std::sqrt(g * k.p / k.rho), ratio = p_star / k.p;
    if (p_star > k.p) {  // shock
      const double speed = k.u + sign * ck * std::sqrt((g + 1) / (2 * g) * ratio + (g - 1) / (2 * g));
      if (sign * (s - speed) > 0) return k;
      const double rho = k.rho * (ratio + (g - 1) / (g + 1)) / ((g - 1) / (g + 1) * ratio + 1);
      return {rho, u_star, p_star};
    }
    const double head = k.u + sign * ck;
    const double tail = u_star + sign * ck * std::pow(ratio, (g - 1) / (2 * g));
    if (sign * (s - head) > 0) return k;
    if (sign * (s - tail) < 0) return {k.rho * std::pow(ratio, 1 / g), u_star, p_star};
    const double u = 2 / (g + 1) * (-sign * ck + (g - 1) / 2 * k.u + s);
    const double c = 2 / (g + 1) * (ck - sign * (g - 1) / 2 * (k.u - s));
    return {k.rho * std::pow(c / ck, 2 / (g - 1)), u, k.p * std::pow(c / ck, 2 * g / (g - 1))};
  }
  GasState L, R;
  double g;
};

}  // namespace mpmice::validation
