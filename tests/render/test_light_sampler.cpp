// Light selection (render/light_sampler.h), against what each strategy promises and not
// against numbers the code printed: the BVH's pmf sums to 1 over the lights (enumerated
// through pmf()) and matches the frequencies of its choices (a χ² test written here); the
// node importance is Conty Estevez & Kulla 2018's bound, recomputed here in double from
// the angles themselves; power selection gives Φ_i / ΣΦ with the powers written here from
// their definitions; and images rendered with every strategy agree within their standard
// errors (the MIS weights use the selection's own pmf), for any thread count.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gonio/error.h"
#include "gonio/render/light_sampler.h"
#include "gonio/rng.h"
#include "render_test_util.h"

namespace gonio::render::test {
namespace {

constexpr double kPiD_ = 3.14159265358979323846;

// A few hundred emitters of powers over three decades: spheres, one-sided quads facing
// down and two-sided quads, above the plane y = 0.
std::vector<AreaLight> many_lights(int n, std::uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<AreaLight> lights;
  for (int i = 0; i < n; ++i) {
    const Vec3 c{4 * rng.next_float() - 2, 0.5f + 1.5f * rng.next_float(), 4 * rng.next_float() - 2};
    const Float L = std::pow(Float(10), 3 * rng.next_float());
    const Float s = 0.02f + 0.08f * rng.next_float();
    if (i % 3 == 0) {
      lights.emplace_back(SphereLight{c, s, Color(L), {}});
    } else {
      QuadLight q;
      q.corner = c;
      // e1 × e2 = (0, −s², 0) for the one-sided ones: they face the floor; the others lean.
      q.edge1 = i % 3 == 1 ? Vec3{s, 0, 0} : Vec3{s, s * (rng.next_float() - 0.5f), 0};
      q.edge2 = {0, 0, s};
      q.two_sided = i % 3 == 2;
      q.radiance = Color(L);
      lights.emplace_back(q);
    }
  }
  return lights;
}

Vec3 random_point(Pcg32& rng) { return {5 * rng.next_float() - 2.5f, 0.6f * rng.next_float(), 5 * rng.next_float() - 2.5f}; }
Vec3 random_normal(Pcg32& rng) {
  const Float z = 2 * rng.next_float() - 1, phi = 2 * kPi * rng.next_float();
  const Float r = std::sqrt(std::max(Float(0), 1 - z * z));
  return {r * std::cos(phi), z, r * std::sin(phi)};
}

TEST(LightSampler, NamesRoundTrip) {
  for (LightSamplerType t : {LightSamplerType::Bvh, LightSamplerType::Power, LightSamplerType::Uniform})
    EXPECT_EQ(light_sampler_type_from_name(light_sampler_type_name(t)), t);
  EXPECT_FALSE(light_sampler_type_from_name("BVH").has_value());
}

// Σ_i pmf(p, n, i) = 1 at random shading points, with and without the environment; at
// every point where the tree finds no light (sum 0) sample() must find none either.
TEST(LightSampler, BvhPmfSumsToOne) {
  const std::vector<AreaLight> lights = many_lights(300, 1);
  const Environment sky(Color(0.2f));
  for (const Environment* env : {static_cast<const Environment*>(nullptr), &sky}) {
    const LightSampler ls(lights, env, 5, LightSamplerType::Bvh);
    Pcg32 rng(2);
    for (int k = 0; k < 64; ++k) {
      const Vec3 p = random_point(rng), n = k % 4 == 3 ? Vec3{0, 0, 0} : random_normal(rng);
      double sum = 0;
      for (int i = 0; i < ls.count(); ++i) sum += double(ls.pmf(p, n, i));
      EXPECT_NEAR(sum, 1.0, 2e-5) << "point " << k << (env ? " with" : " without") << " environment";
    }
  }
}

// The frequencies of sample()'s choices against pmf() by Pearson's χ² (cells of expected
// count < 5 pooled), and the pmf each choice reports equal to pmf() of that light.
TEST(LightSampler, BvhSelectionFrequenciesMatchPmf) {
  const std::vector<AreaLight> lights = many_lights(300, 3);
  const Environment sky(Color(0.2f));
  const LightSampler ls(lights, &sky, 5, LightSamplerType::Bvh);
  Pcg32 rng(4);
  constexpr int kDraws = 200000;
  for (int k = 0; k < 4; ++k) {
    const Vec3 p = random_point(rng), n = random_normal(rng);
    std::vector<double> count(size_t(ls.count()), 0.0);
    int mismatched = 0;
    for (int d = 0; d < kDraws; ++d) {
      const LightSampler::Choice c = ls.sample(p, n, rng.next_float());
      ASSERT_GE(c.light, 0);
      count[size_t(c.light)] += 1;
      if (!(std::abs(c.pmf - ls.pmf(p, n, c.light)) <= 1e-6f * c.pmf)) ++mismatched;
    }
    EXPECT_EQ(mismatched, 0);
    double chi2 = 0, pooled_expected = 0, pooled_count = 0;
    int cells = 0;
    for (int i = 0; i < ls.count(); ++i) {
      const double e = double(ls.pmf(p, n, i)) * kDraws;
      if (e < 5) {
        pooled_expected += e;
        pooled_count += count[size_t(i)];
        if (e == 0) {
          EXPECT_EQ(count[size_t(i)], 0) << "light " << i << " chosen with pmf 0";
        }
        continue;
      }
      chi2 += (count[size_t(i)] - e) * (count[size_t(i)] - e) / e;
      ++cells;
    }
    if (pooled_expected >= 5) {
      chi2 += (pooled_count - pooled_expected) * (pooled_count - pooled_expected) / pooled_expected;
      ++cells;
    }
    const double dof = cells - 1;
    // The χ² distribution's mean is dof, its sd sqrt(2 dof): 6 sd is p < 1e-6.
    EXPECT_LT(chi2, dof + 6 * std::sqrt(2 * dof)) << "point " << k << ", " << cells << " cells";
    EXPECT_GT(cells, 30);
  }
}

// Conty Estevez & Kulla 2018, eq. 3 (§4.3's bounded form), from the angles in double:
// Φ cos θ' cos θ'_i / d², θ' = max(0, θw − θo − θb), θ'_i = max(0, θi − θb), zero when
// θ' ≥ θe.
double importance_reference(const LightBounds& b, const Vec3& p, const Vec3& n) {
  const double cx = (double(b.lo.x) + b.hi.x) / 2, cy = (double(b.lo.y) + b.hi.y) / 2, cz = (double(b.lo.z) + b.hi.z) / 2;
  const double dx = p.x - cx, dy = p.y - cy, dz = p.z - cz;
  const double d2 = dx * dx + dy * dy + dz * dz, d = std::sqrt(d2);
  const double ex = double(b.hi.x) - b.lo.x, ey = double(b.hi.y) - b.lo.y, ez = double(b.hi.z) - b.lo.z;
  const double r = std::sqrt(ex * ex + ey * ey + ez * ez) / 2;
  if (d <= r) return b.phi / (r * r);
  const double theta_b = std::asin(r / d);
  const double theta_w = std::acos(std::clamp((b.w.x * dx + b.w.y * dy + b.w.z * dz) / d, -1.0, 1.0));
  const double theta_o = std::acos(double(b.cos_o)), theta_e = std::acos(double(b.cos_e));
  const double t = std::max(0.0, theta_w - theta_o - theta_b);
  if (t >= theta_e) return 0;
  const double nl = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
  double ci = 1;
  if (nl > 0) {
    const double theta_i = std::acos(std::min(1.0, std::abs(-(n.x * dx + n.y * dy + n.z * dz)) / (nl * d)));
    ci = std::cos(std::max(0.0, theta_i - theta_b));
  }
  return b.phi * std::cos(t) * ci / d2;
}

TEST(LightSampler, NodeImportanceIsTheConeBound) {
  const std::vector<AreaLight> lights = many_lights(40, 5);
  Pcg32 rng(6);
  int positive = 0, zero = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    const LightBounds b = light_bounds(lights[i]);
    for (int k = 0; k < 20; ++k) {
      // Points below and above the lights, so that one-sided quads are seen from both sides.
      Vec3 p = random_point(rng);
      if (k % 2) p.y += 2.5f;
      const Vec3 n = k % 5 == 4 ? Vec3{0, 0, 0} : random_normal(rng);
      const double want = importance_reference(b, p, n);
      const double got = b.importance(p, n);
      EXPECT_NEAR(got, want, 1e-4 * want + 1e-9) << "light " << i << " point " << k;
      (want > 0 ? positive : zero)++;
    }
  }
  EXPECT_GT(positive, 100);
  EXPECT_GT(zero, 20);  // the one-sided quads seen from above
}

// A merged cone holds both cones: every axis of a child lies within θo of the parent's.
TEST(LightSampler, MergedBoundsHoldTheirChildren) {
  const std::vector<AreaLight> lights = many_lights(60, 7);
  for (size_t i = 0; i + 1 < lights.size(); ++i) {
    const LightBounds a = light_bounds(lights[i]), b = light_bounds(lights[i + 1]);
    const LightBounds m = merge(a, b);
    for (const LightBounds* c : {&a, &b}) {
      // (Beyond π the cone is the whole sphere.)
      const double angle =
          std::min(kPiD_, std::acos(std::clamp(double(dot(m.w, c->w)), -1.0, 1.0)) + std::acos(double(c->cos_o)));
      EXPECT_LE(angle, std::acos(double(m.cos_o)) + 1e-4) << i;
      EXPECT_LE(m.lo.x, c->lo.x);
      EXPECT_GE(m.hi.y, c->hi.y);
    }
    EXPECT_FLOAT_EQ(m.phi, a.phi + b.phi);
  }
}

// Power selection: Φ_i / ΣΦ, the powers written here from their definitions
// (π L A for a one-sided quad, twice that two-sided, π L 4π r² for a sphere, π L̄ 4π R²
// for the environment seen through a sphere of radius R).
TEST(LightSampler, PowerSelectionIsPowerOverTotal) {
  const std::vector<AreaLight> lights = many_lights(50, 8);
  const Environment sky(Color(0.1f, 0.2f, 0.3f));
  const double R = 4;
  const LightSampler ls(lights, &sky, Float(R), LightSamplerType::Power);
  std::vector<double> phi;
  for (const AreaLight& l : lights) {
    if (const auto* q = std::get_if<QuadLight>(&l)) {
      const Vec3 c = cross(q->edge1, q->edge2);
      const double area = std::sqrt(double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z);
      phi.push_back(kPiD_ * q->radiance[0] * area * (q->two_sided ? 2 : 1));
    } else {
      const auto& s = std::get<SphereLight>(l);
      phi.push_back(kPiD_ * s.radiance[0] * 4 * kPiD_ * double(s.radius) * s.radius);
    }
  }
  phi.push_back(kPiD_ * 0.2 * 4 * kPiD_ * R * R);
  double total = 0;
  for (double f : phi) total += f;
  ASSERT_EQ(ls.count(), int(phi.size()));
  double sum = 0;
  const Vec3 p{0, 0, 0}, n{0, 1, 0};
  for (int i = 0; i < ls.count(); ++i) {
    // The pmf is the length of the light's interval in a float CDF: within 2^-23 of it.
    EXPECT_NEAR(ls.pmf(p, n, i), phi[size_t(i)] / total, 1.2e-7 + 1e-6 * phi[size_t(i)] / total) << i;
    sum += double(ls.pmf(p, n, i));
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  // And its choices follow it: the light whose interval holds u.
  Pcg32 rng(9);
  for (int k = 0; k < 1000; ++k) {
    const LightSampler::Choice c = ls.sample(p, n, rng.next_float());
    ASSERT_GE(c.light, 0);
    EXPECT_EQ(c.pmf, ls.pmf(p, n, c.light));
  }
}

TEST(LightSampler, UniformIsOneOverCount) {
  const std::vector<AreaLight> lights = many_lights(10, 10);
  const LightSampler ls(lights, nullptr, 1, LightSamplerType::Uniform);
  for (int i = 0; i < 10; ++i) EXPECT_FLOAT_EQ(ls.pmf({0, 0, 0}, {0, 1, 0}, i), 0.1f);
  EXPECT_EQ(ls.sample({0, 0, 0}, {0, 1, 0}, 0.95f).light, 9);
}

// A tiny scene of 24 small lights (spheres, and quads facing down) of powers over three
// decades over a diffuse floor, with a glossy sphere and a glossy floor patch (where BSDF
// samples hit the lights, so that the MIS weights matter) and a dim sky.
std::string tiny_scene(const std::string& light_sampler, int seed, int spp) {
  std::string lights;
  Pcg32 rng(11);
  for (int i = 0; i < 24; ++i) {
    const double x = 3 * rng.next_float() - 1.5, y = 0.4 + 1.0 * rng.next_float(), z = 3 * rng.next_float() - 1.5;
    const double L = 0.3 * std::pow(10.0, 3 * rng.next_float());
    if (!lights.empty()) lights += ", ";
    if (i % 2)
      lights += R"({"type": "sphere", "center": [)" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                R"(], "radius": 0.06, "radiance": )" + std::to_string(L) + "}";
    else
      lights += R"({"type": "quad", "corner": [)" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                R"(], "edge1": [0.12, 0, 0], "edge2": [0, 0, 0.12], "radiance": )" + std::to_string(L) + "}";
  }
  return R"({"camera": {"position": [0, 3, 2.5], "look_at": [0, 0, 0], "fov": 50, "width": 16, "height": 16},
    "render": {"spp": )" + std::to_string(spp) + R"(, "seed": )" + std::to_string(seed) + R"(, "max_depth": 3, "light_sampler": ")" +
         light_sampler + R"("},
    "shapes": [{"type": "quad", "corner": [-3, 0, -3], "edge1": [0, 0, 6], "edge2": [6, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}},
               {"type": "quad", "corner": [0.2, 0.001, 0.2], "edge1": [0, 0, 1.2], "edge2": [1.2, 0, 0], "material": {"type": "roughconductor", "material": "Ag", "alpha": 0.08}},
               {"type": "sphere", "center": [-0.5, 0.35, 0.3], "radius": 0.35, "material": {"type": "roughconductor", "material": "Au", "alpha": 0.15}}],
    "lights": [)" + lights + R"(], "environment": {"radiance": 0.05}})";
}

// Quadrant means over seeds: mean and standard error per sampler.
struct Stats {
  std::array<double, 12> mean{}, se2{};
};
Stats quadrant_stats(const std::string& sampler, int seeds, int spp) {
  std::vector<std::array<double, 12>> per_seed;
  for (int s = 0; s < seeds; ++s) {
    const Image img = render_text(tiny_scene(sampler, s + 1, spp));
    std::array<double, 12> q{};
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int c = 0; c < 3; ++c) q[size_t((y / 8 * 2 + x / 8) * 3 + c)] += img.at(x, y)[c] / 64.0;
    per_seed.push_back(q);
  }
  Stats st;
  for (size_t k = 0; k < 12; ++k) {
    double m = 0, v = 0;
    for (const auto& q : per_seed) m += q[k] / seeds;
    for (const auto& q : per_seed) v += (q[k] - m) * (q[k] - m) / (seeds - 1);
    st.mean[k] = m;
    st.se2[k] = v / seeds;
  }
  return st;
}

// Unbiased: the BVH's and the power sampler's images agree with the uniform choice's
// within their standard errors (estimated from the spread over seeds). A MIS weight that
// used another pmf than the selection's, or a selection pmf not divided out exactly,
// shifts the means.
TEST(LightSampler, BvhAndPowerImagesMatchUniform) {
  const int seeds = 10, spp = 16;
  const Stats uniform = quadrant_stats("uniform", seeds, spp);
  for (const char* other : {"bvh", "power"}) {
    const Stats st = quadrant_stats(other, seeds, spp);
    for (size_t k = 0; k < 12; ++k) {
      const double se = std::sqrt(uniform.se2[k] + st.se2[k]);
      EXPECT_NEAR(st.mean[k], uniform.mean[k], 5 * se) << other << " quadrant " << k / 3 << " channel " << k % 3;
    }
  }
}

// ∫ cos θ dω over a convex polygon seen from p with normal n (wholly above p's plane):
// Lambert's formula, Σ_i β_i (n · ĉ_i) / 2 (Arvo 1995, "Applications of irradiance
// tensors", eq. 6 with n = 0), β_i the angle between the directions to vertices i and
// i + 1, ĉ_i the unit normal of the plane through them.
double projected_solid_angle(const std::vector<std::array<double, 3>>& v, const std::array<double, 3>& p) {
  auto unit = [&](const std::array<double, 3>& q) {
    const double x = q[0] - p[0], y = q[1] - p[1], z = q[2] - p[2], l = std::sqrt(x * x + y * y + z * z);
    return std::array<double, 3>{x / l, y / l, z / l};
  };
  double sum = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const auto a = unit(v[i]), b = unit(v[(i + 1) % v.size()]);
    const double beta = std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0));
    const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
    sum += beta * cy / std::sqrt(cx * cx + cy * cy + cz * cz);  // n = +y
  }
  return std::abs(sum) / 2;
}

// The MIS weights must use the selection's own pmf where a BSDF sample hits a light, as
// at the vertex that chose it. A Lambertian plane (ρ = 0.5) seen from above, lit by two
// 1 × 1 quads facing down, low and just outside the view on either side, one 40× the
// other's radiance: the strategies give the dim one a pmf far from 1/2 that varies over
// the plane, and both BSDF samples and light samples carry much of its light. The closed
// form is Lambert's (ρ/π · L · ∫cos dω); 8 × 8-pixel blocks within 3 %: at 128 spp over
// seeds 1–7 the worst block was off by 0.9–2.0 % (power) and 0.7–2.7 % (bvh), so at 256
// by less (0.6 % at seed 3), while a MIS pmf of 1/N, or one evaluated without the receiver's
// normal, moves blocks by 8 % or more.
TEST(LightSampler, MisWithTheSelectionPmfMatchesClosedForm) {
  const double rho = 0.5, h = 0.35, L[2] = {40, 1}, w = 1;
  const double x0[2] = {-1.25 - w, 1.25}, hw = w / 2;
  auto quad = [&](int i) {
    return std::vector<std::array<double, 3>>{
        {x0[i], h, -hw}, {x0[i] + w, h, -hw}, {x0[i] + w, h, hw}, {x0[i], h, hw}};
  };
  std::string lights;
  for (int i = 0; i < 2; ++i)
    lights += std::string(i ? ", " : "") + R"({"type": "quad", "corner": [)" + std::to_string(x0[i]) + ", " + std::to_string(h) +
              ", " + std::to_string(-hw) + R"(], "edge1": [)" + std::to_string(w) + R"(, 0, 0], "edge2": [0, 0, )" + std::to_string(w) + R"(], "radiance": )" + std::to_string(L[i]) + "}";
  constexpr int kSize = 32;
  const double tan_half = std::tan(20 * kPiD_ / 180), cam = 3;
  for (const char* strategy : {"power", "bvh"}) {
    const Image img = render_text(
        R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 32, "height": 32},
        "render": {"spp": 256, "seed": 3, "max_depth": 1, "light_sampler": ")" +
        std::string(strategy) + R"("},
        "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}}],
        "lights": [)" + lights + "]}");
    for (int by = 0; by < kSize; by += 8)
      for (int bx = 0; bx < kSize; bx += 8) {
        double got = 0, want = 0;
        for (int py = by; py < by + 8; ++py)
          for (int px = bx; px < bx + 8; ++px) {
            got += img.at(px, py)[0];
            // The pixel's mean by the midpoint rule on 4 × 4 points of its film square.
            for (int j = 0; j < 4; ++j)
              for (int i = 0; i < 4; ++i) {
                const double sx = (2 * (px + (i + 0.5) / 4) / kSize - 1) * tan_half;
                const double sy = (1 - 2 * (py + (j + 0.5) / 4) / kSize) * tan_half;
                const std::array<double, 3> p{sx * cam, 0, -sy * cam};
                double E = 0;
                for (int k = 0; k < 2; ++k) E += L[k] * projected_solid_angle(quad(k), p);
                want += rho / kPiD_ * E / 16;
              }
          }
        EXPECT_NEAR(got, want, 0.03 * want) << strategy << " block " << bx / 8 << "," << by / 8;
      }
  }
}

TEST(LightSampler, BvhImageIsTheSameForAnyThreadCount) {
  const std::string scene = tiny_scene("bvh", 3, 8);
  const Image one = render_text(scene, 1), two = render_text(scene, 2), three = render_text(scene, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(one.at(x, y)[c], two.at(x, y)[c]) << x << "," << y;
        ASSERT_EQ(one.at(x, y)[c], three.at(x, y)[c]) << x << "," << y;
      }
}

TEST(LightSampler, SceneRejectsAnUnknownName) {
  try {
    parse_scene(R"({"render": {"light_sampler": "tree"}})", "s.json", "");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(R"(s.json: /render/light_sampler: must be "bvh", "power" or "uniform", got "tree")"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(parse_scene("{}", "s.json", "").settings.light_sampler, LightSamplerType::Bvh);
  EXPECT_EQ(parse_scene(R"({"render": {"light_sampler": "power"}})", "s.json", "").settings.light_sampler,
            LightSamplerType::Power);
}

}  // namespace
}  // namespace gonio::render::test
