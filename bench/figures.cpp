// Figures for docs/microfacet.md: the variance of sample weights of visible-normal
// sampling against classic D·cos sampling, per model at a few (θ, roughness) points,
// and the white-furnace albedo with and without energy compensation.
// Prints Markdown. Run: build/bin/gonio_figures > docs/microfacet-figures.md

#include <cmath>
#include <cstdio>
#include <string>

#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/math/spherical.h"
#include "gonio/reflectance.h"
#include "gonio/rng.h"

using namespace gonio;

namespace {

constexpr int kSamples = 1 << 18;

struct Stats {
  double mean = 0, variance = 0;
};

// Mean and variance of the (first channel of the) sample weight, i.e. of the Monte Carlo
// estimator of the directional albedo with one sample.
template <typename SampleFn>
Stats weight_stats(SampleFn&& sample_weight) {
  Pcg32 rng(17);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double w = sample_weight(rng.next_float(), rng.next_float(), rng.next_float());
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / kSamples;
  return {mean, std::max(0.0, sum2 / kSamples - mean * mean)};
}

Vec3 at_theta(double deg) { return direction_from_angles(Float(deg * kPiD / 180), 0.3f); }

// F = 1 rough conductor, weight of one sample: visible normals (the model's own) or
// classic sampling of wm ∝ D cos θm, weighted by f cos θi / pdf.
void variance_table(MicrofacetType type, const char* name) {
  std::printf("\n### %s, F = 1: variance of the sample weight (visible normals / classic D cos)\n\n", name);
  std::printf("| α \\\\ θo | 0° | 45° | 75° | 85° |\n|---|---|---|---|---|\n");
  for (float alpha : {0.05f, 0.2f, 0.5f, 1.0f}) {
    const MicrofacetDistribution d{type, alpha, alpha};
    const RoughConductorBxDF m{d, {FresnelModel::Schlick, Color(1.f), Color(0.f), Color(1.f)}, std::nullopt};
    std::printf("| %.2f |", double(alpha));
    for (double th : {0.0, 45.0, 75.0, 85.0}) {
      const Vec3 wo = at_theta(th);
      const Stats vis = weight_stats([&](Float a, Float b, Float c) {
        const auto s = m.sample(wo, a, b, c);
        return s ? double(s->weight[0]) : 0.0;
      });
      const Stats classic = weight_stats([&](Float, Float b, Float c) {
        const Vec3 wm = d.sample_classic(b, c);
        const Vec3 wi = reflect(wo, wm);
        const Float dot_om = dot(wo, wm);
        if (!(wi.z > 0) || !(dot_om > 0)) return 0.0;
        const double pdf = d.pdf_classic(wm) / (4 * dot_om);
        return pdf > 0 ? double(m.f(wo, wi)[0]) * wi.z / pdf : 0.0;
      });
      std::printf(" %.2e / %.2e |", vis.variance, classic.variance);
    }
    std::printf("\n");
  }
}

void model_variance_table() {
  std::printf("\n### Every model with its own sampling: variance of the sample weight (first channel)\n\n");
  std::printf("| model | θo = 0° | 45° | 75° | 85° |\n|---|---|---|---|---|\n");
  const char* models[] = {
      R"({"type":"diffuse","reflectance":0.8})",
      R"({"type":"orennayar","reflectance":0.8,"sigma":30})",
      R"({"type":"roughconductor","alpha":0.2,"material":"Au"})",
      R"({"type":"roughconductor","alpha":0.2,"material":"Au","multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.2,"eta":1.5})",
      R"({"type":"roughdielectric","alpha":0.2,"eta":1.5,"distribution":"beckmann"})",
      R"({"type":"phong","kd":0.3,"ks":0.6,"exponent":50})",
      R"({"type":"blinnphong","kd":0.3,"ks":0.6,"exponent":50})",
      R"({"type":"ward","kd":0.3,"ks":0.6,"alpha":[0.1,0.3]})",
      R"({"type":"ashikhminshirley","rd":0.3,"rs":0.3,"nu":100,"nv":10})",
      R"({"type":"plastic","reflectance":0.5,"alpha":0.1})",
  };
  for (const char* json : models) {
    const BxDF m = parse_material(json);
    std::printf("| `%s` |", json);
    for (double th : {0.0, 45.0, 75.0, 85.0}) {
      const Vec3 wo = at_theta(th);
      const Stats st = weight_stats([&](Float a, Float b, Float c) {
        const auto s = m.sample(wo, a, b, c, TransportMode::Importance);
        return s ? double(s->weight[0]) : 0.0;
      });
      std::printf(" %.2e |", st.variance);
    }
    std::printf("\n");
  }
}

void furnace_table(const char* dist) {
  std::printf("\n### White furnace, %s, F = 1 rough conductor: albedo without / with `multiscatter`\n\n", dist);
  std::printf("| α \\\\ θo | 0° | 30° | 60° | 80° | 89° |\n|---|---|---|---|---|---|\n");
  for (double alpha : {0.1, 0.25, 0.5, 0.75, 1.0}) {
    std::printf("| %.2f |", alpha);
    for (double th : {0.0, 30.0, 60.0, 80.0, 89.0}) {
      double a[2];
      for (int ms = 0; ms < 2; ++ms) {
        const std::string json = std::string(R"({"type":"roughconductor","fresnel":"schlick","f0":1,"alpha":)") +
                                 std::to_string(alpha) + R"(,"distribution":")" + dist + R"(","multiscatter":)" +
                                 (ms ? "true" : "false") + "}";
        a[ms] = directional_albedo(parse_material(json), at_theta(th), {1u << 18, 3}).albedo[0];
      }
      std::printf(" %.4f / %.4f |", a[0], a[1]);
    }
    std::printf("\n");
  }
}

}  // namespace

int main() {
  std::printf("<!-- Generated by bench/figures.cpp (build/bin/gonio_figures); %d samples per entry. -->\n", kSamples);
  variance_table(MicrofacetType::GGX, "GGX");
  variance_table(MicrofacetType::Beckmann, "Beckmann");
  model_variance_table();
  furnace_table("ggx");
  furnace_table("beckmann");
  return 0;
}
