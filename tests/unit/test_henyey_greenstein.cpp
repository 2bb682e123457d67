// The Henyey–Greenstein sampler of the subsurface random walk against the phase function's
// moments, which follow from its definition and not from the code: the Legendre
// expansion p(μ) = Σ (2l + 1)/(4π) g^l P_l(μ) (Henyey & Greenstein 1941, eq. 3; e.g. Jensen
// et al. 2001 §2.1) gives ⟨μ⟩ = g and ⟨P2(μ)⟩ = ⟨(3μ² − 1)/2⟩ = g², μ the cosine between the
// directions of travel before and after scattering. A sign error in the sampler (μ drawn
// against the reversed direction) turns ⟨μ⟩ into −g.

#include <gtest/gtest.h>

#include <cmath>

#include "gonio/subsurface/henyey_greenstein.h"

namespace gonio {
namespace {

// Stratified ξ = (k + ½)/n: the sample means are midpoint-rule integrals of μ(ξ) over
// [0, 1], exact to O(1/n²) away from the steep end of the inverse CDF.
TEST(HenyeyGreenstein, SampledCosinesHaveMeanGAndSecondMomentOfHg) {
  constexpr int n = 200000;
  for (const double g : {0.9, 0.5, 0.05, -0.3, -0.8}) {
    double m1 = 0, p2 = 0;
    for (int k = 0; k < n; ++k) {
      const double mu = hg_sample_cos(Float((k + 0.5) / n), Float(g));
      m1 += mu;
      p2 += (3 * mu * mu - 1) / 2;
    }
    EXPECT_NEAR(m1 / n, g, 2e-3) << "g " << g;
    EXPECT_NEAR(p2 / n, g * g, 3e-3) << "g " << g;
  }
}

// The same for the sampled directions: the mean of cos(d, d') over the sphere is g, and
// the azimuth is uniform (the mean of d' is g d), for directions of travel d pointing
// every way (down into a medium, up, sideways).
TEST(HenyeyGreenstein, SampledDirectionsScatterForwardByG) {
  constexpr int n = 256;  // n × n stratified (u1, u2)
  const Vec3 dirs[] = {Vec3{0, 0, -1}, Vec3{0, 0, 1}, normalize(Vec3{0.6f, -0.3f, 0.2f})};
  for (const double g : {0.7, -0.5}) {
    for (const Vec3& d : dirs) {
      double mean[3] = {0, 0, 0};
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          const Vec3 w = hg_sample(d, Float(g), Float((a + 0.5) / n), Float((b + 0.5) / n));
          mean[0] += w.x, mean[1] += w.y, mean[2] += w.z;
        }
      const double nn = double(n) * n;
      EXPECT_NEAR(mean[0] / nn, g * d.x, 3e-3) << g;
      EXPECT_NEAR(mean[1] / nn, g * d.y, 3e-3) << g;
      EXPECT_NEAR(mean[2] / nn, g * d.z, 3e-3) << g;
    }
  }
}

}  // namespace
}  // namespace gonio
