#pragma once
// Upper tail of the χ² distribution, Q(k/2, x/2), through the regularized incomplete
// gamma function: its power series for x < a + 1 and its continued fraction (modified
// Lentz) otherwise (Abramowitz & Stegun 6.5.29 and 6.5.31; Press et al., Numerical
// Recipes, 3rd ed., §6.2).

#include <cmath>

namespace gonio::validation {

inline double regularized_gamma_q(double a, double x) {
  if (x <= 0) return 1;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1 - sum * std::exp(log_prefix));
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int n = 1; n < 10000; ++n) {
    const double an = -n * (n - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-15) break;
  }
  return std::min(1.0, std::exp(log_prefix) * h);
}

// P(X ≥ x) for X ~ χ² with `dof` degrees of freedom.
inline double chi2_survival(double x, double dof) { return regularized_gamma_q(dof / 2, x / 2); }

}  // namespace gonio::validation
