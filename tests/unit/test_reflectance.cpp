// Reflectance ρ over the lecture's domain pairs (lecture §4) against closed forms:
// Lambert's ρ = ρ_dh = ρ_hh (eq. 19), the cone fraction sin²α, and glass's ρ_hh from
// REFERENCES.md. Monte Carlo estimates must land within a few standard errors.

#include <gtest/gtest.h>

#include <cmath>

#include "gonio/error.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/reflectance.h"
#include "test_scale.h"

namespace gonio {
namespace {

// The model of `inner`, hidden behind the extension point so no closed form is used and
// the Monte Carlo path (the model's own importance sampling) is exercised.
class Opaque final : public CustomBxDF {
 public:
  explicit Opaque(BxDF inner) : inner_(std::move(inner)) {}
  BxDFFlags flags() const override { return inner_.flags(); }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode m) const override { return inner_.f(wo, wi, m); }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode m) const override { return inner_.pdf(wo, wi, m); }
  std::optional<BSDFSample> sample(const Vec3& wo, Float a, Float b, Float c, TransportMode m) const override {
    return inner_.sample(wo, a, b, c, m);
  }
  Float relative_eta() const override { return inner_.relative_eta(); }

 private:
  BxDF inner_;
};

BxDF opaque(BxDF m) { return make_user_bxdf<Opaque>(std::move(m)); }

void expect_within(const ReflectanceEstimate& e, double expected, int channel = 0) {
  const double se = e.standard_error[channel];
  EXPECT_NEAR(e.value[channel], expected, 4 * se + 1e-6) << "se " << se;
}

const ReflectanceOptions kOpt{test::scaled(200000), 9};

TEST(Reflectance, LambertDirectionalHemisphericalIsRho) {
  const BxDF lambert = DiffuseBxDF{Color(0.2f, 0.5f, 0.8f)};
  const auto e = reflectance(lambert, DirectionDomain{direction_from_angles(0.7f, 0.2f)}, HemisphereDomain{}, kOpt);
  EXPECT_TRUE(e.exact);
  EXPECT_FLOAT_EQ(e.value[2], 0.8f);
  const auto mc = reflectance(opaque(lambert), DirectionDomain{direction_from_angles(0.7f, 0.2f)},
                              HemisphereDomain{}, kOpt);
  EXPECT_FALSE(mc.exact);
  // Cosine-weighted sampling of a Lambertian: every weight is ρ, zero variance.
  EXPECT_NEAR(mc.value[1], 0.5, 1e-6);
  // Transmission side: nothing.
  const auto t = reflectance(lambert, DirectionDomain{{0, 0, 1}}, HemisphereDomain{false}, kOpt);
  EXPECT_EQ(t.value[0], 0.f);
}

TEST(Reflectance, LambertHemisphericalAndConical) {
  const BxDF lambert = opaque(DiffuseBxDF{Color(0.6f)});
  // ρ_hh = ρ (lecture eq. 19).
  expect_within(reflectance(lambert, HemisphereDomain{}, HemisphereDomain{}, kOpt), 0.6);
  // Into a cone of half angle α about N: ∫cone (ρ/π) cos θ dω = ρ sin²α.
  const double alpha = 0.6;
  const double frac = std::sin(alpha) * std::sin(alpha);
  const auto dc = reflectance(lambert, DirectionDomain{direction_from_angles(1.0f, 0)},
                              ConeDomain{{0, 0, 1}, alpha}, kOpt);
  expect_within(dc, 0.6 * frac);
  EXPECT_GT(dc.standard_error[0], 0);
  // From a tilted cone into the hemisphere: ρ again, whatever the cone.
  expect_within(reflectance(lambert, ConeDomain{direction_from_angles(0.5f, 1), 0.3}, HemisphereDomain{}, kOpt), 0.6);
  // Cone to cone: ρ sin²α as the exitant cone is about N.
  expect_within(reflectance(lambert, ConeDomain{direction_from_angles(0.5f, 1), 0.3},
                            ConeDomain{{0, 0, 1}, alpha}, kOpt), 0.6 * frac);
  // Reflectance factor of a white Lambertian is 1 for every pair of directions.
  const auto rf = reflectance(DiffuseBxDF{Color(1.f)}, DirectionDomain{direction_from_angles(0.3f, 0)},
                              DirectionDomain{direction_from_angles(1.2f, 2)}, kOpt);
  EXPECT_NEAR(rf.value[0], 1, 1e-6);
}

TEST(Reflectance, GlassHemisphericalFromBothSides) {
  // REFERENCES.md: cosine-weighted average of R for η = 1.5: 0.09178 outside, 0.59635 inside.
  const BxDF glass = DielectricBxDF{1.5f};
  const auto out = reflectance(glass, HemisphereDomain{true}, HemisphereDomain{true}, kOpt);
  EXPECT_TRUE(out.exact);
  EXPECT_NEAR(out.value[0], 0.09178, 1e-5);
  const auto in = reflectance(glass, HemisphereDomain{false}, HemisphereDomain{false}, kOpt);
  EXPECT_NEAR(in.value[0], 0.59635, 1e-5);
  // Energy: what is not reflected is transmitted.
  const auto tr = reflectance(glass, HemisphereDomain{true}, HemisphereDomain{false}, kOpt);
  EXPECT_NEAR(out.value[0] + tr.value[0], 1, 1e-6);
  // The same through Monte Carlo with the model's own (delta) sampling.
  expect_within(reflectance(opaque(glass), HemisphereDomain{true}, HemisphereDomain{true}, kOpt), 0.09178);
  expect_within(reflectance(opaque(glass), HemisphereDomain{false}, HemisphereDomain{false}, kOpt), 0.59635);

  const auto hh = hemispherical_albedo(glass, /*inside=*/true, kOpt);
  EXPECT_NEAR(hh.reflectance[0], 0.59635, 1e-5);
  EXPECT_NEAR(hh.albedo[0], 1, 1e-6);
}

TEST(Reflectance, DirectionalAlbedoOfTheDeltaModels) {
  // Glass at 60° from outside: R = 0.089187 (REFERENCES.md), T = 1 − R in energy.
  const BxDF glass = DielectricBxDF{1.5f};
  const Vec3 wo = direction_from_angles(60 * float(kPiD) / 180, 0);
  const auto a = directional_albedo(glass, wo, kOpt);
  EXPECT_TRUE(a.exact);
  EXPECT_NEAR(a.reflectance[0], 0.089187, 1e-6);
  EXPECT_NEAR(a.transmittance[0], 1 - 0.089187, 1e-6);
  const auto mc = directional_albedo(opaque(glass), wo, kOpt);
  EXPECT_NEAR(mc.reflectance[0], 0.089187, 4 * mc.se_reflectance[0]);
  EXPECT_NEAR(mc.albedo[0], 1, 1e-6);  // importance mode: every weight is 1
}

TEST(Reflectance, BadDomainsAreInputErrors) {
  const BxDF m = DiffuseBxDF{};
  EXPECT_THROW(reflectance(m, DirectionDomain{{0, 0, 0}}, HemisphereDomain{}), InputError);
  EXPECT_THROW(reflectance(m, ConeDomain{{1, 0, 0.1f}, 0.5}, HemisphereDomain{}), InputError);
  EXPECT_THROW(reflectance(m, ConeDomain{{0, 0, 1}, -0.1}, HemisphereDomain{}), InputError);
  EXPECT_THROW(reflectance(m, HemisphereDomain{}, HemisphereDomain{}, {0, 1}), InputError);
  EXPECT_THROW(directional_albedo(m, Vec3{0, 0, 0}), InputError);
}

}  // namespace
}  // namespace gonio
