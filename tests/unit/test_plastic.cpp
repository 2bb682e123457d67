// Rough plastic and the microfacet models at the edges (issue 9): the white furnace of a
// white base under a non-absorbing rough coat (albedo 1 at every angle, grazing included:
// a physical value, not one the code printed), finite output at cosines down to the
// smallest denormal, and anisotropic energy compensation rejected. Pointwise values of
// rough plastic come from tests/reference/plastic_reference.py (data/plastic_rough.jsonl).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "../test_common.h"
#include "gonio/bxdf.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/math/spherical.h"
#include "gonio/microfacet.h"
#include "gonio/reflectance.h"
#include "test_scale.h"

namespace gonio {
namespace {


// White base (ρ = 1) under a coat that absorbs nothing: every joule that arrives leaves,
// so the directional albedo is 1 at every θ (issue 9: within [0.99, 1.005]). Before the
// fix the base was coupled through the smooth interface's 1 − F: 0.358 at 88° for α = 0.3.
TEST(Plastic, WhiteFurnaceIsOneAtEveryAngle) {
  const ReflectanceOptions opt{test::scaled(40000), 11};
  struct Case { const char* dist; double alpha, eta; };
  // α and η between the tables' nodes as well as on them; α > 1; η up to 4. The nearly
  // smooth coats and the η just above 1 were 2.5–3% off near grazing with tables linear
  // in √α, z and √μ (0.975 at 89.94° for GGX α = 1e-3, η = 1.5; 0.970 at 89.5° for
  // α = 1e-3, η = 1 + 1e-5; 1.016 at 89° for α = 0.01, η = 1.01).
  const Case cases[] = {{"ggx", 0.3, 1.5},  {"ggx", 1, 1.5},      {"ggx", 0.05, 2.4}, {"ggx", 3.7, 1.33},
                        {"beckmann", 0.3, 1.5}, {"beckmann", 0.8, 1.33}, {"beckmann", 0.12, 4},
                        {"ggx", 0.47, 1.05}, {"ggx", 1e-3, 1.5}, {"ggx", 1e-3, 1.00001}, {"ggx", 0.01, 1.01},
                        {"beckmann", 1.5e-3, 1.0003}};
  for (const auto& c : cases) {
    const std::string material_json = std::string(R"({"type":"plastic","reflectance":1,"distribution":")") + c.dist +
                             R"(","alpha":)" + std::to_string(c.alpha) + R"(,"eta":)" + std::to_string(c.eta) + "}";
    const BxDF m = parse_material(material_json);
    for (double th : {0.0, 30.0, 60.0, 75.0, 85.0, 88.0, 89.0, 89.5, 89.8, 89.9, 89.97}) {
      const auto a = directional_albedo(m, direction_from_angles(Float(th * kDeg), 0.4f), opt);
      EXPECT_GE(a.albedo[0] + 4 * a.se_albedo[0], 0.99) << material_json << " theta " << th;
      EXPECT_LE(a.albedo[0] - 4 * a.se_albedo[0], 1.005) << material_json << " theta " << th;
    }
  }
}

// Cosines from 1e-45 (the smallest float denormal) to 1e-2, both signs: eval, pdf and
// sample stay finite and non-negative, and f is bounded (below 1e6 here: a diffuse base cannot exceed
// ρ/π times a bounded coupling; the coat lobe is fully shadowed there). Before the fix,
// rough plastic (GGX) gave NaN between |cos θ| ~1e-22 and 1e-19 (the issue's command:
// wo = (0.3, 0.1, 0.9), wi = (0.6, 0.8, 1e-20)) and grew without bound below.
TEST(Microfacet, FiniteAtTinyCosines) {
  const char* materials[] = {
      R"({"type":"plastic","alpha":0.2})",
      R"({"type":"plastic","eta":2.4,"reflectance":1})",  // 1 − F must not round below 0 at grazing
      R"({"type":"plastic","alpha":0.3,"distribution":"beckmann","reflectance":1})",
      R"({"type":"roughconductor","alpha":0.2,"material":"Au"})",
      R"({"type":"roughconductor","alpha":[0.01,1],"distribution":"beckmann","material":"Cu"})",
      R"({"type":"roughconductor","alpha":0.5,"material":"Al","multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.2,"eta":1.5})",
      R"({"type":"roughdielectric","alpha":0.7,"eta":1.5,"distribution":"beckmann","multiscatter":true})",
  };
  std::vector<Float> zs = {0.f, -0.f};
  for (double e = -45; e <= -2; e += 0.5) zs.push_back(Float(std::pow(10.0, e)));
  // The distribution's own public functions: Λ must not become ∞/∞ where cos²θ leaves
  // float range.
  for (auto type : {MicrofacetType::GGX, MicrofacetType::Beckmann})
    for (Float z : zs) {
      const MicrofacetDistribution d{type, 0.2f, 0.5f};
      const Vec3 w{0.6f, 0.8f, z}, up{0.3f, 0.1f, 0.9f};
      for (Float v : {d.Lambda(w), d.G1(w), d.G2(w, up), d.G2(up, w), d.D_visible(w, normalize(w + up)), d.smith_t(w)})
        ASSERT_TRUE(std::isfinite(v) && v >= 0) << int(type) << " z " << z << " value " << v;
    }
  for (const char* material_json : materials) {
    const BxDF m = parse_material(material_json);
    const std::string name = material_json;
    for (Float z : zs)
      for (Float sign : {1.f, -1.f}) {
        const Vec3 tiny{0.6f, 0.8f, sign * z};
        for (const Vec3& other : {Vec3{0.3f, 0.1f, 0.9f}, Vec3{-0.6f, -0.8f, 1e-3f}, Vec3{0.6f, 0.8f, sign * z}}) {
          for (const auto& [wo, wi] : {std::pair{other, tiny}, std::pair{tiny, other}})
            for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
              const BSDFEval e = m.eval(wo, wi, mode);
              ASSERT_TRUE(e.f.is_finite() && e.f.min_component() >= 0 && e.f.max_component() < 1e6f)
                  << name << " z " << z << " f " << e.f[0];
              ASSERT_TRUE(std::isfinite(e.pdf) && e.pdf >= 0) << name << " z " << z;
            }
        }
        for (Float u : {0.f, 0.3f, 0.7f, kOneMinusEpsilon}) {
          const auto s = m.sample(tiny, u, 0.5f, u);
          if (!s) continue;
          ASSERT_TRUE(s->weight.is_finite() && s->weight.min_component() >= 0 && std::isfinite(s->pdf))
              << name << " z " << z;
        }
      }
  }
}

// Kulla–Conty's tables are isotropic; sqrt(αx αy) standing in lost 40 % of the energy in
// a white furnace at α = [0.05, 1]. Anisotropic multiscatter is an input error (exit 2 on
// the command line), as for the rough dielectric.
// Anisotropic roughness: the lobe tabulates the distribution's own E(μ, φ)
// (anisotropic_albedo.h; issue 55 §4). With sqrt(αx αy) standing in, this white metal kept
// 0.60 at normal incidence; it returns 1 now, by its own sampling at three angles.
TEST(Multiscatter, AnisotropicCompensationHoldsTheWhiteFurnace) {
  const BxDF m =
      parse_material(R"({"type":"roughconductor","alpha":[0.05,1],"fresnel":"schlick","f0":1,"multiscatter":true})");
  for (double th : {0.0, 60.0, 85.0}) {
    const auto a = directional_albedo(m, direction_from_angles(Float(th * kDeg), 0.4f), {200'000, 3});
    EXPECT_NEAR(a.albedo[0], 1, 0.01 + 4 * a.se_albedo[0]) << "theta " << th;
  }
  EXPECT_NO_THROW(parse_material(R"({"type":"roughconductor","alpha":0.3,"material":"Au","multiscatter":true})"));
  EXPECT_NO_THROW(parse_material(R"({"type":"roughconductor","alpha":[0.05,1],"material":"Au"})"));
}

// The rough plastic's coat tables are isotropic too: an anisotropic coat gained energy at
// grazing (white furnace 1.028 at 89.9 deg for GGX [0.05, 0.6]), so it is refused.
TEST(Plastic, AnisotropicCoatIsRejected) {
  try {
    parse_material(R"({"type":"plastic","reflectance":1,"alpha":[0.05,0.6]})");
    ADD_FAILURE() << "anisotropic coat accepted";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("plastic"), std::string::npos) << w;
    EXPECT_NE(w.find("isotropic"), std::string::npos) << w;
  }
}

}  // namespace
}  // namespace gonio
