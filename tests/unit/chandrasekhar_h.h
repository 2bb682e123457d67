#pragma once
// Chandrasekhar's H-function for isotropic scattering with albedo ϖ (Radiative Transfer,
// 1960, ch. V: H(μ) = 1 + (ϖ/2) μ H(μ) ∫₀¹ H(μ′)/(μ + μ′) dμ′), by fixed-point iteration
// on Gauss–Legendre nodes: the reference of the random walks' half-space tests
// (test_subsurface_walk.cpp, test_guided_walk.cpp). (The "alternate" form
// 1/H = √(1 − ϖ) + (ϖ/2) ∫ μ′H/(μ + μ′) is not used: at ϖ = 1 its iteration from H = 1
// settled on 6.44 for H(1).) At ϖ = 1 the iteration converges slowly, hence the many
// rounds; for ϖ < 1 it is geometric.

#include <algorithm>
#include <cmath>
#include <vector>

#include "../test_common.h"

namespace gonio::test {

inline double chandrasekhar_h(double albedo, double mu, int nodes = 24) {
  std::vector<double> x, w;
  gauss_legendre(nodes, 0, 1, x, w);
  std::vector<double> h(x.size(), 1.0), next(x.size());
  const auto integral = [&](double m) {
    double s = 0;
    for (size_t j = 0; j < x.size(); ++j) s += w[j] * h[j] / (m + x[j]);
    return s;
  };
  for (int it = 0; it < 40000; ++it) {
    double change = 0;
    for (size_t i = 0; i < x.size(); ++i) {
      next[i] = 1 / (1 - albedo / 2 * x[i] * integral(x[i]));
      change = std::max(change, std::abs(next[i] - h[i]));
    }
    h.swap(next);
    if (change < 1e-14) break;
  }
  return 1 / (1 - albedo / 2 * mu * integral(mu));
}

}  // namespace gonio::test
