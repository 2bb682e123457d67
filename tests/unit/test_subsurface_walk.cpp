// The random walk (random_walk.h) and the slab estimator (slab_walk.h) against physics
// derived independently of them: Chandrasekhar's H-function for the index-matched
// half-space, Beer–Lambert for a slab that only absorbs.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gonio/bxdf/dielectric.h"
#include "gonio/subsurface/random_walk.h"
#include "gonio/subsurface/slab_walk.h"
#include "test_scale.h"

namespace gonio {
namespace {

// Gauss–Legendre nodes and weights on [0, 1] (Newton on P_n; Abramowitz & Stegun 25.4.29).
void gauss_legendre01(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(size_t(n));
  w.resize(size_t(n));
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
    x[size_t(i)] = (1 - z) / 2;
    w[size_t(i)] = 1 / ((1 - z * z) * dp * dp);  // 2/((1 − z²) P'²) on [−1, 1], halved
  }
}

// Chandrasekhar's H-function for isotropic scattering with albedo ϖ (Radiative Transfer,
// 1960, ch. V: H(μ) = 1 + (ϖ/2) μ H(μ) ∫₀¹ H(μ′)/(μ + μ′) dμ′), by fixed-point
// iteration on Gauss–Legendre nodes. (The "alternate" form 1/H = √(1 − ϖ) + (ϖ/2) ∫ μ′H/(μ + μ′)
// is not used: at ϖ = 1 its iteration from H = 1 settled on 6.44 for H(1).) At ϖ = 1 the
// iteration converges slowly, hence the many rounds; for ϖ < 1 it is geometric.
double chandrasekhar_h(double albedo, double mu, int nodes = 24) {
  std::vector<double> x, w;
  gauss_legendre01(nodes, x, w);
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

// ∫₀¹ H dμ, for the moment identity.
double h_moment0(double albedo) {
  std::vector<double> x, w;
  gauss_legendre01(24, x, w);
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += w[i] * chandrasekhar_h(albedo, x[i]);
  return s;
}

TEST(SubsurfaceWalk, HFunctionMatchesChandrasekhar) {
  // Chandrasekhar 1960, Table XI (conservative isotropic scattering): H(1) = 2.9078.
  EXPECT_NEAR(chandrasekhar_h(1.0, 1.0), 2.9078, 1e-3);
  // The zeroth moment: ∫₀¹ H dμ = (2/ϖ)(1 − √(1 − ϖ)) (Chandrasekhar 1960, ch. V).
  for (double a : {0.5, 0.9, 0.99}) EXPECT_NEAR(h_moment0(a), 2 / a * (1 - std::sqrt(1 - a)), 1e-6) << a;
}

Subsurface grey_medium(double albedo, double eta, double g = 0) {
  Subsurface s;
  s.eta = Float(eta);
  DielectricBxDF b;
  b.eta = Float(eta);
  s.boundary = b;
  s.medium.sigma_s = Color(Float(albedo));
  s.medium.sigma_a = Color(Float(1 - albedo));
  s.medium.g = Float(g);
  return s;
}

// η = 1, g = 0: the albedo of a half-space for light incident along μ0 is
// 1 − H(μ0) √(1 − ϖ) (Chandrasekhar 1960, §47; the sum rule for isotropic scattering).
TEST(SubsurfaceWalk, IndexMatchedHalfSpaceMatchesHFunction) {
  for (double albedo : {0.5, 0.9, 0.99}) {
    const double expected = 1 - chandrasekhar_h(albedo, 1.0) * std::sqrt(1 - albedo);
    const SlabResult r = slab_random_walk(grey_medium(albedo, 1.0), test::scaled(200000, 20000), 7, 2);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(r.stderr_[c], 0);
      EXPECT_NEAR(r.Rd[c], expected, 3 * r.stderr_[c] + 1e-4) << "albedo " << albedo;
    }
  }
}

}  // namespace
}  // namespace gonio
