// The Dwivedi-guided random walk (guided_walk.h) against references derived without it:
// Case's dispersion relation for ν0, the Dwivedi pdf integrated here, Chandrasekhar's
// H-function for the index-matched half-space, Beer–Lambert for a slab that only absorbs,
// and the classic walk (random_walk.h) on a finite anisotropic slab, where the two are
// independent estimators of the same integral.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_common.h"
#include "gonio/subsurface/guided_walk.h"
#include "gonio/error.h"
#include "gonio/subsurface/random_walk.h"
#include "gonio/subsurface/subsurface.h"
#include "chandrasekhar_h.h"
#include "test_scale.h"

namespace gonio {
namespace {

// The medium −depth ≤ z ≤ 0 between two index-matched planes.
struct GuideSlab {
  struct Hit {
    Float t = 0;
    bool bottom = false;
  };
  Float depth = 1;
  bool nearest(const Vec3& o, const Vec3& d, Hit& hit) const {
    if (d.z > 0) {
      hit = {-o.z / d.z, false};
      return true;
    }
    if (d.z < 0) {
      hit = {(-depth - o.z) / d.z, true};
      return true;
    }
    return false;
  }
};

struct MeanSe {
  double mean[3], se[3];
};

// Reflected (top) or transmitted (bottom) weight per channel of n walks entering at the
// origin along d0; guided with probability q, or the classic walk when q < 0.
MeanSe slab_estimate(const Medium& m, Float depth, Vec3 d0, double q, bool top, std::uint64_t n, std::uint64_t seed) {
  const GuideSlab slab{depth};
  WalkGuide guide;
  guide.normal = {0, 0, 1};
  guide.probability = Float(std::max(q, 0.0));
  Pcg32 rng(seed, 17);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (std::uint64_t i = 0; i < n; ++i) {
    Color beta(1);
    GuideSlab::Hit hit;
    const bool ok = q < 0 ? walk_to_boundary(m, slab, Vec3{0, 0, 0}, d0, beta, rng, hit)
                          : walk_to_boundary_guided(m, slab, guide, Vec3{0, 0, 0}, d0, beta, rng, hit);
    if (!ok || hit.bottom == top) continue;
    for (int c = 0; c < 3; ++c) {
      sum[c] += beta[c];
      sum2[c] += double(beta[c]) * beta[c];
    }
  }
  MeanSe r;
  for (int c = 0; c < 3; ++c) {
    r.mean[c] = sum[c] / double(n);
    r.se[c] = std::sqrt(std::max(0.0, sum2[c] / double(n) - r.mean[c] * r.mean[c]) / double(n - 1));
  }
  return r;
}

// κ = 1/ν0 solves Case's relation 1 = (ϖ ν0 / 2) ln((ν0 + 1)/(ν0 − 1)) (written here in
// that form), and tends to the diffusion value √(3(1 − ϖ)) as ϖ → 1.
TEST(GuidedWalk, Nu0SolvesTheDispersionRelation) {
  for (const double albedo : {0.2, 0.5, 0.9, 0.99, 0.999, 0.99999}) {
    const double nu0 = 1 / dwivedi_kappa(albedo);
    EXPECT_NEAR(albedo * nu0 / 2 * std::log((nu0 + 1) / (nu0 - 1)), 1.0, 1e-9) << albedo;
  }
  EXPECT_NEAR(dwivedi_kappa(0.99999), std::sqrt(3 * 1e-5), 1e-4 * std::sqrt(3 * 1e-5) * 100);
  EXPECT_EQ(dwivedi_kappa(1.0), 0.0);
}

// p(μ) = 1/(ln((ν0+1)/(ν0−1)) (ν0 − μ)) integrates to 1, and the sampled μ follow it:
// a histogram of 200,000 draws against the pdf integrated over each bin in closed form.
TEST(GuidedWalk, DwivediDirectionsFollowTheirPdf) {
  for (const double albedo : {0.5, 0.9, 0.999}) {
    const double kappa = dwivedi_kappa(albedo), nu0 = 1 / kappa;
    const auto pdf = [&](double mu) { return 1 / (std::log((nu0 + 1) / (nu0 - 1)) * (nu0 - mu)); };
    double total = 0;
    const int steps = 20000;
    for (int i = 0; i < steps; ++i) {
      const double a = -1 + 2.0 * i / steps, b = a + 2.0 / steps;
      total += (b - a) / 6 * (pdf(a) + 4 * pdf((a + b) / 2) + pdf(b));
      EXPECT_NEAR(dwivedi_pdf_mu((a + b) / 2, kappa), pdf((a + b) / 2), 1e-9 * pdf((a + b) / 2));
    }
    EXPECT_NEAR(total, 1.0, 1e-9) << albedo;
    constexpr int kBins = 20;
    const std::uint64_t n = test::scaled(200000, 20000);
    std::vector<double> count(kBins, 0);
    Pcg32 rng(21, std::uint64_t(albedo * 1000));
    for (std::uint64_t i = 0; i < n; ++i) {
      const double mu = dwivedi_sample_mu(rng.next_float(), kappa);
      count[std::min(kBins - 1, int((mu + 1) / 2 * kBins))] += 1;
    }
    for (int k = 0; k < kBins; ++k) {
      const double a = -1 + 2.0 * k / kBins, b = a + 2.0 / kBins;
      // ∫_a^b p dμ = ln((ν0 − a)/(ν0 − b)) / ln((ν0 + 1)/(ν0 − 1))
      const double expected = double(n) * std::log((nu0 - a) / (nu0 - b)) / std::log((nu0 + 1) / (nu0 - 1));
      EXPECT_NEAR(count[k], expected, 5 * std::sqrt(expected)) << "albedo " << albedo << " bin " << k;
    }
  }
}

// The index-matched half-space at normal incidence: Rd = 1 − H(1) √(1 − ϖ)
// (Chandrasekhar 1960, ch. V), for three albedos and extinctions in one chromatic medium
// and for several guide probabilities (q = 1: the guided technique alone).
TEST(GuidedWalk, IndexMatchedHalfSpaceMatchesHFunction) {
  const double albedo[3] = {0.5, 0.9, 0.99}, sigma_t[3] = {1, 2, 0.5};
  Medium m;
  for (int c = 0; c < 3; ++c) {
    m.sigma_s[c] = Float(albedo[c] * sigma_t[c]);
    m.sigma_a[c] = Float((1 - albedo[c]) * sigma_t[c]);
  }
  for (const double q : {0.5, 0.25, 1.0}) {
    const MeanSe r = slab_estimate(m, 1e30f, Vec3{0, 0, -1}, q, true, test::scaled(200000, 20000), 31);
    for (int c = 0; c < 3; ++c) {
      const double expected = 1 - test::chandrasekhar_h(albedo[c], 1.0) * std::sqrt(1 - albedo[c]);
      EXPECT_GT(r.se[c], 0);
      EXPECT_NEAR(r.mean[c], expected, 4 * r.se[c]) << "albedo " << albedo[c] << " q " << q;
    }
  }
}

// σs = 0: Beer–Lambert through a slab of thickness L along cos θ, e^{−σa L / cos θ}.
TEST(GuidedWalk, AbsorbingSlabFollowsBeerLambert) {
  Medium m;
  m.sigma_s = Color(0);
  m.sigma_a = Color(0.5f, 1.0f, 2.0f);
  for (const double cos_theta : {1.0, 0.6}) {
    const Vec3 d = normalize(Vec3{Float(std::sqrt(1 - cos_theta * cos_theta)), 0, Float(-cos_theta)});
    const MeanSe r = slab_estimate(m, 1.5f, d, 0.5, false, test::scaled(100000, 10000), 41);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(r.mean[c], std::exp(-double(m.sigma_a[c]) * 1.5 / cos_theta), 4 * r.se[c] + 1e-6) << c;
  }
}

// A finite anisotropic slab, reflection and transmission, oblique entry: the guided walk
// and the classic walk estimate the same integral independently (different sampling, other
// seeds) and agree within their standard errors.
TEST(GuidedWalk, FiniteSlabAgreesWithTheClassicWalk) {
  Medium m;
  m.sigma_s = Color(1.9f, 3.8f, 0.95f);  // albedos 0.95, 0.95, 0.95 at σt 2, 4, 1
  m.sigma_a = Color(0.1f, 0.2f, 0.05f);
  for (const Float g : {0.0f, 0.6f}) {
    m.g = g;
    const Vec3 d = normalize(Vec3{0.6f, 0, -0.8f});
    const std::uint64_t n = test::scaled(100000, 20000);
    for (const bool top : {true, false}) {
      const MeanSe a = slab_estimate(m, 2.0f, d, 0.5, top, n, 51), b = slab_estimate(m, 2.0f, d, -1, top, n, 52);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a.mean[c], b.mean[c], 4 * std::hypot(a.se[c], b.se[c]))
            << "g " << g << (top ? " reflection" : " transmission") << " channel " << c;
    }
  }
}

// Without absorption (κ = 0) the guided technique is the classic isotropic one and every
// weight stays exactly 1.
TEST(GuidedWalk, ConservativeWeightsStayExactlyOne) {
  Medium m;
  m.sigma_s = Color(1);
  m.sigma_a = Color(0);
  const GuideSlab slab{2.0f};
  WalkGuide guide;
  Pcg32 rng(6, 2);
  for (int i = 0; i < 20000; ++i) {
    Color beta(1);
    GuideSlab::Hit hit;
    ASSERT_TRUE(walk_to_boundary_guided(m, slab, guide, Vec3{0, 0, -1}, Vec3{0, 0, -1}, beta, rng, hit)) << i;
    ASSERT_EQ(beta, Color(1)) << "path " << i;
  }
}

// The material's "guide": 0.5 by default, [0, 1], one error line naming the field.
TEST(GuidedWalk, GuideFieldIsReadAndChecked) {
  const auto parse = [](const char* text) { return subsurface_from_json(nlohmann::json::parse(text)); };
  EXPECT_EQ(parse(R"({"type":"subsurface","sigma_s":1,"sigma_a":0})").guide, 0.5f);
  EXPECT_EQ(parse(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"guide":0})").guide, 0.0f);
  for (const char* bad : {R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"guide":1.5})",
                          R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"guide":-0.1})"}) {
    try {
      parse(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("guide"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace gonio
