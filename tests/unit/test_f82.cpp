// F82-tint conductor Fresnel (Hoffman 2023; SPEC §2; fresnel_f82 in fresnel.h) against
// this file's own arithmetic: Schlick's curve computed here, the defining condition
// F(1/7) = f82 × Schlick(F0, 1/7), F(1) = F0, the hemispherical average (20 F0 + 1)/21 −
// a/126 against Simpson's rule on 2∫F μ dμ, and the parser's errors. Values against the
// Python reference are in tests/reference/data/conductor.jsonl and roughconductor.jsonl.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/validate.h"

namespace gonio {
namespace f82_test {

double schlick(double f0, double mu) { return f0 + (1 - f0) * std::pow(1 - mu, 5); }

// Unclamped F82 from its definition, here by solving for a at μ̄ = 1/7.
double f82_unclamped(double f0, double tint, double mu) {
  const double mb = 1.0 / 7;
  const double a = (schlick(f0, mb) * (1 - tint)) / (mb * std::pow(1 - mb, 6));
  return schlick(f0, mu) - a * mu * std::pow(1 - mu, 6);
}

ConductorFresnel f82(Color f0, Color tint) {
  ConductorFresnel fr;
  fr.model = FresnelModel::F82;
  fr.f0 = f0;
  fr.f82 = tint;
  fr.prepare();  // the material's a (ConductorFresnelT::prepare)
  return fr;
}

TEST(F82, TintAtOneSeventhAndF0AtNormalIncidence) {
  const Color f0(0.95f, 0.64f, 0.54f), tint(0.9f, 0.6f, 0.3f);
  const ConductorFresnel fr = f82(f0, tint);
  const Color at_bar = fr(Float(1.0 / 7)), at_one = fr(1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(at_bar[c], tint[c] * schlick(f0[c], 1.0 / 7), 2e-6) << c;
    EXPECT_NEAR(at_one[c], f0[c], 1e-7) << c;
  }
  // Grazing: 1 (both the Schlick term and the dip's μ (1 − μ)⁶ meet there).
  EXPECT_NEAR(fr(0)[0], 1, 1e-7);
  // f82 = 1 is Schlick's curve.
  const ConductorFresnel plain = f82(f0, Color(1));
  for (double mu : {0.0, 0.05, 0.3, 0.7, 1.0}) EXPECT_NEAR(plain(Float(mu))[1], schlick(f0[1], mu), 1e-6) << mu;
}

TEST(F82, ValuesAndClampAgainstTheDefinition) {
  for (double f0 : {0.0, 0.04, 0.5, 0.9, 1.0})
    for (double tint : {0.0, 0.3, 0.8, 1.0})
      for (double mu : {0.0, 0.02, 0.1, 1.0 / 7, 0.25, 0.5, 0.9, 1.0}) {
        const double want = std::clamp(f82_unclamped(f0, tint, mu), 0.0, 1.0);
        EXPECT_NEAR(f82(Color(Float(f0)), Color(Float(tint)))(Float(mu))[0], want, 2e-6)
            << "f0=" << f0 << " f82=" << tint << " mu=" << mu;
      }
}

// The closed-form average against composite Simpson (2000 panels) of 2∫F μ dμ, where F
// stays in [0, 1] (the formula is that of the unclamped F; SPEC §2).
TEST(F82, HemisphericalAverageIsTheClosedForm) {
  for (double f0 : {0.3, 0.6, 0.95, 1.0})
    for (double tint : {0.5, 0.8, 1.0}) {
      const int n = 2000;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double mu = double(i) / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * 2 * mu * f82_unclamped(f0, tint, mu);
      }
      const double want = sum / (3.0 * n);
      const ConductorFresnel fr = f82(Color(Float(f0)), Color(Float(tint)));
      EXPECT_NEAR(conductor_average_fresnel(fr)[0], want, 2e-6) << "f0=" << f0 << " f82=" << tint;
      // The same numbers as SPEC §2 writes them.
      const double a = schlick(f0, 1.0 / 7) * (1 - tint) / ((1.0 / 7) * std::pow(6.0 / 7, 6));
      EXPECT_NEAR(want, (20 * f0 + 1) / 21 - a / 126, 1e-9);
    }
}

// The rough conductor uses the same Fresnel: at α → smooth its delta lobe carries F82, and
// its multiscatter lobe the closed-form average.
TEST(F82, ConductorsCarryIt) {
  const BxDF smooth = parse_material(R"({"type":"conductor","fresnel":"f82","f0":[0.9,0.5,0.2],"f82":[0.3,0.6,1]})");
  const Vec3 wo{std::sqrt(1 - Float(1.0 / 49)), 0, Float(1.0 / 7)};
  const auto s = smooth.sample(wo, 0.5f, 0.5f, 0.5f);
  ASSERT_TRUE(s && s->delta);
  EXPECT_NEAR(s->weight[0], 0.3 * schlick(0.9, 1.0 / 7), 2e-6);
  EXPECT_NEAR(s->weight[2], 1.0 * schlick(0.2, 1.0 / 7), 2e-6);
  const BxDF rough =
      parse_material(R"({"type":"roughconductor","alpha":0.5,"fresnel":"f82","f0":0.8,"f82":0.7,"multiscatter":true})");
  const auto* m = std::get_if<RoughConductorBxDF>(&rough.models());
  ASSERT_TRUE(m && m->multiscatter);
  const double a = schlick(0.8, 1.0 / 7) * 0.3 / ((1.0 / 7) * std::pow(6.0 / 7, 6));
  EXPECT_NEAR(m->multiscatter->f_avg[0], (20 * 0.8 + 1) / 21 - a / 126, 1e-6);
}

std::string error_of(const std::string& json) {
  try {
    parse_material(json);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(F82, ParserErrorsNameTheField) {
  std::string e = error_of(R"({"type":"conductor","fresnel":"f82","f0":0.9,"f82":1.2})");
  EXPECT_NE(e.find("f82"), std::string::npos) << e;
  EXPECT_NE(e.find("1.2"), std::string::npos) << e;
  e = error_of(R"({"type":"roughconductor","alpha":0.2,"fresnel":"f82","f0":0.9,"f82":[0.5,-0.1,0.5]})");
  EXPECT_NE(e.find("f82"), std::string::npos) << e;
  EXPECT_NE(e.find("-0.1"), std::string::npos) << e;
  e = error_of(R"({"type":"conductor","fresnel":"f82","f82":0.5})");
  EXPECT_NE(e.find("f0"), std::string::npos) << e;
  e = error_of(R"({"type":"conductor","f0":0.9,"f82":0.5,"fresnel":"schlick"})");
  EXPECT_NE(e.find("f82"), std::string::npos) << e;
  e = error_of(R"({"type":"conductor","material":"Au","f82":0.5})");
  EXPECT_NE(e.find("f82"), std::string::npos) << e;
  e = error_of(R"({"type":"conductor","fresnel":"f82","material":"Au"})");
  EXPECT_NE(e.find("f82"), std::string::npos) << e;
  e = error_of(R"({"type":"conductor","fresnel":"f82","f0":0.9,"eta":1.5})");
  EXPECT_FALSE(e.empty());
  // Defaults: f82 = 1.
  const BxDF d = parse_material(R"({"type":"conductor","fresnel":"f82","f0":0.5})");
  const auto* c = std::get_if<ConductorBxDF>(&d.models());
  ASSERT_TRUE(c);
  EXPECT_EQ(c->fresnel.f82[0], 1);
  EXPECT_EQ(c->fresnel.model, FresnelModel::F82);
}

}  // namespace f82_test
}  // namespace gonio
