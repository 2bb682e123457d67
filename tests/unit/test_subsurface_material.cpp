// The `subsurface` material (SPEC §2, issue 14): its boundary is the dielectric of the
// same parameters, its media are the paper's numbers (typed here from Jensen et al. 2001,
// Fig. 5), bad media are InputErrors that name field and value, and the artist's albedo
// comes back from the slab (Rd / (1 − F(0)) within noise of what was asked).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/material.h"
#include "gonio/subsurface/slab_walk.h"
#include "gonio/subsurface/subsurface.h"
#include "test_scale.h"

namespace gonio {
namespace {

using nlohmann::json;

Subsurface parse(const std::string& text) { return subsurface_from_json(json::parse(text)); }

// As a BSDF it is its boundary: eval and sample agree exactly with the dielectric or
// roughdielectric of the same eta (and alpha, distribution), whose reference records
// test_reference_values.cpp checks.
TEST(SubsurfaceMaterial, BsdfIsTheBoundary) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"type":"subsurface","sigma_s":1,"sigma_a":0.1})", R"({"type":"dielectric","eta":1.33})"},
      {R"({"type":"subsurface","medium":"skin1"})", R"({"type":"dielectric","eta":1.3})"},
      {R"({"type":"subsurface","eta":1.5,"alpha":0.3,"distribution":"beckmann","albedo":0.5,"mfp":2})",
       R"({"type":"roughdielectric","eta":1.5,"alpha":0.3,"distribution":"beckmann"})"},
      {R"({"type":"subsurface","eta":1.5,"alpha":0.3,"multiscatter":true,"sigma_s":1,"sigma_a":0})",
       R"({"type":"roughdielectric","eta":1.5,"alpha":0.3,"multiscatter":true})"},
  };
  const Vec3 dirs[] = {normalize(Vec3{0.3f, 0.1f, 1}), normalize(Vec3{-0.2f, 0.4f, -1}), normalize(Vec3{0.7f, 0, 0.2f})};
  for (const auto& [ss, ref] : cases) {
    const BxDF a = parse_material(ss), b = parse_material(ref);
    EXPECT_EQ(a.name(), b.name()) << ss;
    EXPECT_EQ(a.relative_eta(), b.relative_eta()) << ss;
    EXPECT_EQ(parse(ss).boundary.name(), b.name());
    for (const Vec3& wo : dirs) {
      for (const Vec3& wi : dirs) {
        EXPECT_EQ(a.f(wo, wi), b.f(wo, wi)) << ss;
        EXPECT_EQ(a.pdf(wo, wi), b.pdf(wo, wi)) << ss;
      }
      const auto sa = a.sample(wo, 0.3f, 0.6f, 0.2f), sb = b.sample(wo, 0.3f, 0.6f, 0.2f);
      ASSERT_EQ(bool(sa), bool(sb));
      if (sa) {
        EXPECT_EQ(sa->weight, sb->weight);
      }
    }
  }
}

TEST(SubsurfaceMaterial, CoefficientsAndDefaults) {
  const Subsurface s = parse(R"({"type":"subsurface","sigma_s":[1,2,3],"sigma_a":[0.1,0,0.3],"g":0.4})");
  EXPECT_EQ(s.eta, 1.33f);
  EXPECT_EQ(s.medium.sigma_s, Color(1, 2, 3));
  EXPECT_EQ(s.medium.sigma_a, Color(0.1f, 0, 0.3f));
  EXPECT_EQ(s.medium.g, 0.4f);
  EXPECT_EQ(s.method, SubsurfaceMethod::RandomWalk);
  EXPECT_EQ(parse(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"method":"diffusion"})").method,
            SubsurfaceMethod::Diffusion);
  EXPECT_EQ(parse(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"eta":1.5})").eta, 1.5f);
}

// Jensen, Marschner, Levoy & Hanrahan 2001, Figure 5: σs′ and σa in mm⁻¹ (R, G, B),
// typed here from the paper's table.
TEST(SubsurfaceMaterial, NamedMediaAreThePapersNumbers) {
  struct Row {
    const char* name;
    double sp[3], sa[3];
  };
  const Row rows[] = {
      {"apple", {2.29, 2.39, 1.97}, {0.0030, 0.0034, 0.046}},
      {"chicken1", {0.15, 0.21, 0.38}, {0.015, 0.077, 0.19}},
      {"chicken2", {0.19, 0.25, 0.32}, {0.018, 0.088, 0.20}},
      {"cream", {7.38, 5.47, 3.15}, {0.0002, 0.0028, 0.0163}},
      {"ketchup", {0.18, 0.07, 0.03}, {0.061, 0.97, 1.45}},
      {"marble", {2.19, 2.62, 3.00}, {0.0021, 0.0041, 0.0071}},
      {"potato", {0.68, 0.70, 0.55}, {0.0024, 0.0090, 0.12}},
      {"skimmilk", {0.70, 1.22, 1.90}, {0.0014, 0.0025, 0.0142}},
      {"skin1", {0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}},
      {"skin2", {1.09, 1.59, 1.79}, {0.013, 0.070, 0.145}},
      {"wholemilk", {2.55, 3.21, 3.77}, {0.0011, 0.0024, 0.014}},
  };
  for (const Row& r : rows) {
    const Subsurface s = parse(std::string(R"({"type":"subsurface","medium":")") + r.name + "\"}");
    EXPECT_EQ(s.eta, 1.3f) << r.name;
    EXPECT_EQ(s.medium.g, 0.0f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_FLOAT_EQ(s.medium.sigma_s[c], float(r.sp[c])) << r.name;
      EXPECT_FLOAT_EQ(s.medium.sigma_a[c], float(r.sa[c])) << r.name;
    }
  }
  // scale = scene units per mm (a scene in metres: 0.001), g: σs = σs′ / (1 − g).
  const Subsurface m = parse(R"({"type":"subsurface","medium":"marble","scale":0.001,"g":0.5,"eta":1.5})");
  EXPECT_EQ(m.eta, 1.5f);
  EXPECT_FLOAT_EQ(m.medium.sigma_s[0], 2.19f / 0.5f * 1000);
  EXPECT_FLOAT_EQ(m.medium.sigma_a[2], 0.0071f * 1000);
}

void expect_error(const std::string& text, const std::vector<std::string>& parts) {
  try {
    subsurface_from_json(json::parse(text), "scene.json: materials[0]");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind("scene.json: materials[0]: ", 0), 0u) << what;
    for (const auto& p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  }
  // material_from_json rejects the same description.
  EXPECT_THROW(material_from_json(json::parse(text)), InputError) << text;
}

TEST(SubsurfaceMaterial, BadMediaNameFieldAndValue) {
  expect_error(R"({"type":"subsurface","sigma_s":-1,"sigma_a":0})", {"sigma_s", "-1"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":[0,-0.5,0]})", {"sigma_a", "-0.5"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"g":1})", {"g", "1"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"multiscatter":true})", {"multiscatter", "alpha"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"g":-1.5})", {"g", "-1.5"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"g":0.999999999})", {"g", "0.999999999"});
  expect_error(R"({"type":"subsurface","albedo":1,"mfp":1})", {"albedo", "1"});
  expect_error(R"({"type":"subsurface","albedo":0.5,"mfp":0})", {"mfp", "0"});
  expect_error(R"({"type":"subsurface","medium":"jade"})", {"medium", "jade", "marble", "skin1", "wholemilk"});
  expect_error(R"({"type":"subsurface","medium":"marble","sigma_s":1,"sigma_a":0})", {"one form", "sigma_s", "medium"});
  expect_error(R"({"type":"subsurface","albedo":0.5,"mfp":1,"sigma_s":1,"sigma_a":1})", {"one form"});
  expect_error(R"({"type":"subsurface"})", {"missing", "sigma_s", "albedo", "medium"});
  expect_error(R"({"type":"subsurface","sigma_s":1})", {"sigma_s needs sigma_a"});
  expect_error(R"({"type":"subsurface","albedo":0.5})", {"albedo needs mfp"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"scale":2})", {"scale needs medium"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"distribution":"ggx"})", {"distribution needs alpha"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"method":"dipole"})", {"method", "dipole", "randomwalk"});
  expect_error(R"({"type":"subsurface","sigma_s":1,"sigma_a":0,"sigma":1})", {"unknown parameter 'sigma'"});
  // subsurface_from_json wants a subsurface.
  EXPECT_THROW(subsurface_from_json(json::parse(R"({"type":"dielectric"})")), InputError);
}

// A spectrum for a coefficient is read at the channels' wavelengths (650, 550, 450 nm),
// as an index is, not as a reflectance (which would clamp and average it).
TEST(SubsurfaceMaterial, CoefficientSpectrumIsReadAtTheChannelWavelengths) {
  const Subsurface s = parse(R"({"type":"subsurface","sigma_s":{"spectrum":[[400,4],[700,1]]},"sigma_a":0})");
  EXPECT_NEAR(s.medium.sigma_s[0], 4 - 3 * 250.0 / 300, 1e-4);
  EXPECT_NEAR(s.medium.sigma_s[1], 4 - 3 * 150.0 / 300, 1e-4);
  EXPECT_NEAR(s.medium.sigma_s[2], 4 - 3 * 50.0 / 300, 1e-4);
}

// The artist's albedo A = Rd / (1 − F(0)) (docs/subsurface.md): the medium found for
// (albedo, mfp) gives back A in the slab. The inversion's table is itself a Monte Carlo
// estimate of kAlbedoTablePaths paths whose contributions lie in [0, 1] (smooth boundary),
// so its standard error is at most √(A(1 − A)/N) / (1 − F(0)) of A; the test allows three
// of the combined error.
TEST(SubsurfaceMaterial, AlbedoRoundTrip) {
  struct Case {
    double albedo, eta, g;
  };
  for (const Case c : {Case{0.2, 1.33, 0}, Case{0.5, 1.33, 0}, Case{0.8, 1.33, 0}, Case{0.6, 1.5, 0.6}}) {
    char text[200];
    std::snprintf(text, sizeof text, R"({"type":"subsurface","albedo":%g,"mfp":0.5,"eta":%g,"g":%g})", c.albedo,
                  c.eta, c.g);
    const Subsurface s = parse(text);
    EXPECT_NEAR(s.medium.sigma_t()[0], 2, 1e-5);  // 1 / mfp
    const SlabResult r = slab_random_walk(s, test::scaled(40000, 8000), 1234, 2);
    const double f0 = std::pow((c.eta - 1) / (c.eta + 1), 2);
    const double table_se = std::sqrt(c.albedo * (1 - c.albedo) / 8192.0) / (1 - f0);
    const double walk_se = r.stderr_[0] / (1 - f0);
    EXPECT_NEAR(r.Rd[0] / (1 - f0), c.albedo, 3 * std::hypot(table_se, walk_se)) << text;
  }
}

}  // namespace
}  // namespace gonio
