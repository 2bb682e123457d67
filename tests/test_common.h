#pragma once
// Small helpers several test files need. One definition each, so that the test files can
// be compiled together (CMAKE_UNITY_BUILD, as scripts/test.sh builds them) without two
// copies colliding. They are the tests' own formulas, not gonio's.

#include <cmath>
#include <vector>

#include "gonio/math/constants.h"

namespace gonio {

inline constexpr double kDeg = kPiD / 180;

// Reflectance at normal incidence of an interface from air to a medium of complex index
// n + ik: |(n + ik − 1)/(n + ik + 1)|² (Born & Wolf, Principles of Optics, §14.2).
inline double normal_incidence_reflectance(double n, double k) {
  return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
}

// Gauss–Legendre nodes and weights on [a, b] (Newton on P_n; Abramowitz & Stegun 25.4.29),
// for the quadratures the tests write themselves.
inline void gauss_legendre(int n, double a, double b, std::vector<double>& x, std::vector<double>& w) {
  x.assign(size_t(n), 0);
  w.assign(size_t(n), 0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPiD * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[size_t(i)] = a + (b - a) * (z + 1) / 2;
    w[size_t(i)] = (b - a) / ((1 - z * z) * dp * dp);
  }
}

}  // namespace gonio
