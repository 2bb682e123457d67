// Build-time generator of the microfacet albedo tables behind multiscatter.h:
// E(μ, α), the directional albedo of the single-scattering microfacet BRDF with F = 1,
// and E_avg(α) = 2 ∫ E(μ) μ dμ, for GGX and Beckmann.
//
// E(μ) = ∫ D_wo(wm) G2(wo, wi)/G1(wo) [wi.z > 0] dωm with wi = reflect(wo, wm): the
// expected weight of visible-normal sampling. The integrand is smooth in the sampling
// square, so a stratified midpoint rule of 96² points per entry is accurate to ~1e-5.
//
// Usage: gonio_make_albedo_tables OUT.cpp

#include <cmath>
#include <cstdio>
#include <string>

#include "gonio/fresnel.h"
#include "gonio/microfacet.h"
#include "gonio/multiscatter_table_layout.h"

using namespace gonio;
using namespace gonio::tables;

namespace {

// The mean over an n × n midpoint grid of the visible-normal sampling square of
// weight(wm, G2/G1 as a function of wi), for wo at cos θ = mu on an isotropic surface.
template <typename Weight>
double mean_over_visible_normals(MicrofacetType type, double alpha, double mu, int n, Weight&& weight) {
  const MicrofacetDistribution d{type, Float(alpha), Float(alpha)};
  const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  const Vec3 wo{Float(s), 0, Float(mu)};
  const double lo = d.Lambda(wo);
  // G2(wo, wi)/G1(wo) of the height-correlated Smith model (Heitz 2014).
  auto g2_over_g1 = [&](const Vec3& wi) { return (1 + lo) / (1 + lo + d.Lambda(wi)); };
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      sum += weight(wo, d.sample_visible(wo, Float((i + 0.5) / n), Float((j + 0.5) / n)), g2_over_g1);
  return sum / (double(n) * n);
}

// E(μ) of the F = 1 microfacet BRDF.
double albedo(MicrofacetType type, double alpha, double mu) {
  return mean_over_visible_normals(type, alpha, mu, 96, [](const Vec3& wo, const Vec3& wm, auto& g) {
    const Vec3 wi = reflect(wo, wm);
    return wi.z > 0 ? g(wi) : 0.0;
  });
}

// Importance-mode R + T of the single-scattering rough dielectric for wo on top with
// relative index e = n(far side) / n(wo's side): the expected weight of visible-normal
// sampling, F G2/G1(wo) for the reflection and (1 − F) G2/G1(wo) for the refraction
// (Walter et al. 2007, eqs. 20, 21 with the Jacobians of eqs. 14, 17 cancelling).
double dielectric_albedo(MicrofacetType type, double alpha, double e, double mu) {
  return mean_over_visible_normals(type, alpha, mu, 40, [e](const Vec3& wo, const Vec3& wm, auto& g) {
    const double c = dot(wo, wm);
    if (!(c > 0)) return 0.0;
    const double F = fresnel_dielectric(c, e);
    double sum = 0;
    const Vec3 wr = reflect(wo, wm);
    if (wr.z > 0) sum += F * g(wr);
    if (F < 1) {
      const auto t = refract(wo, wm, Float(e));
      if (t && t->wt.z < 0) sum += (1 - F) * g(-t->wt);
    }
    return sum;
  });
}

void write_dielectric_tables(FILE* out, const char* name, MicrofacetType type) {
  static double e[2][kAlbedoRoughnessSize][kDielectricEtaSize][kDielectricCosineSize];
  std::fprintf(out, "const DielectricAlbedoTable %sDielectricAlbedo = {\n", name);
  for (int side = 0; side < 2; ++side) {
    std::fprintf(out, " {\n");
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      std::fprintf(out, "  {\n");
      for (int k = 0; k < kDielectricEtaSize; ++k) {
        const double eta = dielectric_table_eta(k);
        std::fprintf(out, "   {");
        for (int m = 0; m < kDielectricCosineSize; ++m) {
          e[side][a][k][m] = dielectric_albedo(type, albedo_table_alpha(a), side == 0 ? eta : 1 / eta, dielectric_table_mu(m));
          std::fprintf(out, "%s%.7g", m ? ", " : "", e[side][a][k][m]);
        }
        std::fprintf(out, "},\n");
      }
      std::fprintf(out, "  },\n");
    }
    std::fprintf(out, " },\n");
  }
  std::fprintf(out, "};\n\nconst DielectricAverageTable %sDielectricAverage = {\n", name);
  const double h = 1.0 / (kDielectricCosineSize - 1);
  for (int side = 0; side < 2; ++side) {
    std::fprintf(out, " {");
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      std::fprintf(out, "{");
      for (int k = 0; k < kDielectricEtaSize; ++k) {
        // 2 ∫ E(μ) μ dμ of the linear interpolant, exactly: on [μa, μa + h] with
        // E = Ea + (Eb − Ea)(μ − μa)/h the integral of E μ is h (Ea (2μa + μb) + Eb (μa + 2μb)) / 6.
        double acc = 0;
        for (int m = 0; m + 1 < kDielectricCosineSize; ++m) {
          const double ma = m * h, mb = (m + 1) * h;
          acc += h * (e[side][a][k][m] * (2 * ma + mb) + e[side][a][k][m + 1] * (ma + 2 * mb)) / 6;
        }
        std::fprintf(out, "%s%.9g", k ? ", " : "", 2 * acc);
      }
      std::fprintf(out, "},");
    }
    std::fprintf(out, "},\n");
  }
  std::fprintf(out, "};\n\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.cpp\n", argv[0]);
    return 2;
  }
  FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[1]);
    return 1;
  }
  std::fprintf(out, "// Generated by tools/make_albedo_tables.cpp at build time. Do not edit.\n");
  std::fprintf(out, "#include \"gonio/multiscatter_table_layout.h\"\n\nnamespace gonio::tables {\n\n");
  const char* names[2] = {"kGgx", "kBeckmann"};
  const MicrofacetType types[2] = {MicrofacetType::GGX, MicrofacetType::Beckmann};
  for (int t = 0; t < 2; ++t) {
    std::fprintf(out, "const float %sAlbedo[kAlbedoRoughnessSize][kAlbedoCosineSize] = {\n", names[t]);
    double avg[kAlbedoRoughnessSize];
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      const double alpha = albedo_table_alpha(a);
      double e[kAlbedoCosineSize];
      for (int m = 0; m < kAlbedoCosineSize; ++m) e[m] = albedo(types[t], alpha, albedo_table_mu(m));
      // E_avg = 2 ∫ E(μ) μ dμ by Simpson's rule on the table's own nodes (an even number
      // of intervals).
      double acc = 0;
      const double h = 1.0 / (kAlbedoCosineSize - 1);
      for (int m = 0; m < kAlbedoCosineSize; ++m) {
        const double w = (m == 0 || m == kAlbedoCosineSize - 1) ? 1 : (m % 2 ? 4 : 2);
        acc += w * 2 * (m * h) * e[m];
      }
      avg[a] = acc * h / 3;
      std::fprintf(out, "  {");
      for (int m = 0; m < kAlbedoCosineSize; ++m) std::fprintf(out, "%s%.9g", m ? ", " : "", e[m]);
      std::fprintf(out, "},\n");
    }
    std::fprintf(out, "};\n\nconst float %sAverageAlbedo[kAlbedoRoughnessSize] = {", names[t]);
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) std::fprintf(out, "%s%.9g", a ? ", " : "", avg[a]);
    std::fprintf(out, "};\n\n");
  }
  write_dielectric_tables(out, "kGgx", MicrofacetType::GGX);
  write_dielectric_tables(out, "kBeckmann", MicrofacetType::Beckmann);
  std::fprintf(out, "}  // namespace gonio::tables\n");
  return std::fclose(out) == 0 ? 0 : 1;
}
