// Build-time generator of the microfacet albedo tables behind multiscatter.h:
// E(μ, α), the directional albedo of the single-scattering microfacet BRDF with F = 1,
// and E_avg(α) = 2 ∫ E(μ) μ dμ, for GGX and Beckmann.
//
// E(μ) = ∫ D_wo(wm) G2(wo, wi)/G1(wo) [wi.z > 0] dωm with wi = reflect(wo, wm): the
// expected weight of visible-normal sampling. The integrand is smooth in the sampling
// square except for the cut wi.z = 0, so a stratified grid of 96² points per entry, its
// columns staggered across that cut (mean_over_visible_normals), is accurate to ~1e-4.
// Also the rough dielectric's R + T tables and the plastic coat's reflection-only
// E_coat(μ, α, η) (multiscatter_table_layout.h). Every mean over μ is the exact
// cosine-weighted average of the table's linear interpolant (hemispherical_average.h),
// so that a lobe built on 1 − E integrates to exactly what the table says is missing.
//
// Usage: gonio_make_albedo_tables OUT.cpp

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "gonio/fresnel.h"
#include "gonio/hemispherical_average.h"
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
  // Each column i of the grid (u1: the azimuth of the GGX sampler) has its own offset in
  // u2 (the fractional part of i times the golden ratio): at normal incidence the cut
  // wi.z = 0 is a line u2 = const, which an aligned midpoint grid puts on the same side in
  // every column, an error of up to one stratum's mass (E_coat 0.4 % low at μ = 1,
  // α = 0.1, η = 100); staggered, the columns cross the cut at n different places.
  constexpr double kGolden = 0.61803398874989485;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double offset = std::fmod(0.5 + i * kGolden, 1.0);
    for (int j = 0; j < n; ++j)
      sum += weight(wo, d.sample_visible(wo, Float((i + 0.5) / n), Float((j + offset) / n)), g2_over_g1);
  }
  return sum / (double(n) * n);
}

// E(μ) of the F = 1 microfacet BRDF.
double albedo(MicrofacetType type, double alpha, double mu) {
  return mean_over_visible_normals(type, alpha, mu, 96, [](const Vec3& wo, const Vec3& wm, auto& g) {
    const Vec3 wi = reflect(wo, wm);
    return wi.z > 0 ? g(wi) : 0.0;
  });
}

// fn(i) for i < n on every core (each entry is computed alone, so the output does not
// depend on the number of threads): the tables below are most of the generator's time,
// which every build (Release, sanitizers, fuzzing) waits for.
template <typename Fn>
void parallel_rows(int n, Fn&& fn) {
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int i = t; i < n; i += threads) fn(i);
    });
  for (auto& th : pool) th.join();
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
  parallel_rows(2 * kAlbedoRoughnessSize, [&](int row) {
    const int side = row / kAlbedoRoughnessSize, a = row % kAlbedoRoughnessSize;
    for (int k = 0; k < kDielectricEtaSize; ++k) {
      const double eta = dielectric_table_eta(k);
      for (int m = 0; m < kDielectricCosineSize; ++m)
        e[side][a][k][m] = dielectric_albedo(type, albedo_table_alpha(a), side == 0 ? eta : 1 / eta, dielectric_table_mu(m));
    }
  });
  std::fprintf(out, "const DielectricAlbedoTable %sDielectricAlbedo = {\n", name);
  for (int side = 0; side < 2; ++side) {
    std::fprintf(out, " {\n");
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      std::fprintf(out, "  {\n");
      for (int k = 0; k < kDielectricEtaSize; ++k) {
        std::fprintf(out, "   {");
        for (int m = 0; m < kDielectricCosineSize; ++m) std::fprintf(out, "%s%.7g", m ? ", " : "", e[side][a][k][m]);
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
        double mu[kDielectricCosineSize];
        for (int m = 0; m < kDielectricCosineSize; ++m) mu[m] = m * h;
        const double acc = cosine_weighted_average_of_linear(mu, e[side][a][k], kDielectricCosineSize);
        std::fprintf(out, "%s%.9g", k ? ", " : "", acc);
      }
      std::fprintf(out, "},");
    }
    std::fprintf(out, "},\n");
  }
  std::fprintf(out, "};\n\n");
}

// E_coat(μ, α, η) for every η node at once: one pass over the visible normals of wo, the
// weight F(wo·wm) G2/G1(wo) [wi.z > 0] with each node's Fresnel (Walter et al. 2007,
// eq. 20 sampled by visible normals, Heitz & d'Eon 2014). The last node, z = 1, is η = ∞
// (F = 1).
void coat_albedos(MicrofacetType type, double alpha, double mu, double (&e)[kCoatEtaSize]) {
  double eta[kCoatEtaSize];
  for (int k = 0; k < kCoatEtaSize; ++k) {
    const double z2 = coat_table_z(k) * coat_table_z(k);
    eta[k] = k + 1 < kCoatEtaSize ? (1 + z2) / (1 - z2) : 0;
    e[k] = 0;
  }
  constexpr int n = 64;
  mean_over_visible_normals(type, alpha, mu, n, [&](const Vec3& wo, const Vec3& wm, auto& g) {
    const Vec3 wi = reflect(wo, wm);
    if (!(wi.z > 0)) return 0.0;
    const double c = dot(wo, wm), w = g(wi);
    for (int k = 0; k < kCoatEtaSize; ++k) e[k] += w * (eta[k] > 0 ? fresnel_dielectric(c, eta[k]) : 1.0);
    return 0.0;
  });
  for (double& x : e) x /= double(n) * n;
}

double complement_cdf(const double* mu, const float* e, int n, double* cdf, int& over);
void write_cdf_row(FILE* out, const double* cdf, int n);
float stored(const char* fmt, double v);

void write_coat_tables(FILE* out, const char* name, MicrofacetType type, int& over) {
  static double e[kCoatRoughnessSize][kCoatEtaSize][kCoatCosineSize];
  parallel_rows(kCoatRoughnessSize, [&](int a) {
    for (int m = 0; m < kCoatCosineSize; ++m) {
      double col[kCoatEtaSize];
      coat_albedos(type, coat_table_alpha(a), coat_table_mu(m), col);
      for (int k = 0; k < kCoatEtaSize; ++k) e[a][k][m] = col[k];
    }
  });
  std::fprintf(out, "const CoatAlbedoTable %sCoatAlbedo = {\n", name);
  for (int a = 0; a < kCoatRoughnessSize; ++a) {
    std::fprintf(out, " {\n");
    for (int k = 0; k < kCoatEtaSize; ++k) {
      std::fprintf(out, "  {");
      for (int m = 0; m < kCoatCosineSize; ++m) std::fprintf(out, "%s%.7g", m ? ", " : "", e[a][k][m]);
      std::fprintf(out, "},\n");
    }
    std::fprintf(out, " },\n");
  }
  std::fprintf(out, "};\n\nconst CoatAverageTable %sCoatAverage = {\n", name);
  double mu[kCoatCosineSize];
  for (int m = 0; m < kCoatCosineSize; ++m) mu[m] = coat_table_mu_node(m);
  for (int a = 0; a < kCoatRoughnessSize; ++a) {
    std::fprintf(out, " {");
    for (int k = 0; k < kCoatEtaSize; ++k) {
      // The stored values are rounded to float: average what the lookups will read.
      float stored[kCoatCosineSize];
      for (int m = 0; m < kCoatCosineSize; ++m) stored[m] = float(e[a][k][m]);
      std::fprintf(out, "%s%.9g", k ? ", " : "", cosine_weighted_average_of_linear(mu, stored, kCoatCosineSize));
    }
    std::fprintf(out, "},\n");
  }
  std::fprintf(out, "};\n\n");
  // The sampling tables of the base under the coat (coat_albedo.h), from the entries as
  // the generated source stores them ("%.7g" read back as the compiler does).
  static double loss[kCoatRoughnessSize][kCoatEtaSize];
  std::fprintf(out, "const CoatCdfTable %sCoatCdf = {\n", name);
  for (int a = 0; a < kCoatRoughnessSize; ++a) {
    std::fprintf(out, " {\n");
    for (int k = 0; k < kCoatEtaSize; ++k) {
      float row[kCoatCosineSize];
      double cdf[kCoatCosineSize];
      for (int m = 0; m < kCoatCosineSize; ++m) row[m] = ::stored("%.7g", e[a][k][m]);
      loss[a][k] = complement_cdf(mu, row, kCoatCosineSize, cdf, over);
      std::fprintf(out, "  ");
      write_cdf_row(out, cdf, kCoatCosineSize);
      std::fprintf(out, ",\n");
    }
    std::fprintf(out, " },\n");
  }
  std::fprintf(out, "};\n\nconst CoatLossTable %sCoatLoss = {\n", name);
  for (int a = 0; a < kCoatRoughnessSize; ++a) {
    std::fprintf(out, " {");
    for (int k = 0; k < kCoatEtaSize; ++k) std::fprintf(out, "%s%.9g", k ? ", " : "", loss[a][k]);
    std::fprintf(out, "},\n");
  }
  std::fprintf(out, "};\n\n");
}

// The float a table entry printed with `fmt` becomes in the generated source: the literal
// is read as a double and converted to float, as the compiler does.
float stored(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return float(std::strtod(buf, nullptr));
}

// The sampling table of the density ∝ (1 − E(μ)) μ for the stored values e at nodes mu:
// the normalised CDF at the nodes, and the loss 2 ∫₀¹ (1 − E) μ dμ. On [a, b] with 1 − E
// linear from A to B, ∫ (1 − E) μ dμ = (b − a)(A (2a + b) + B (a + 2b))/6 (exact).
// 1 − E is taken as max(0, 1 − E), as the lookups do; the count of entries above 1 is
// returned in `over` (0 for every table so far).
double complement_cdf(const double* mu, const float* e, int n, double* cdf, int& over) {
  double acc = 0;
  cdf[0] = 0;
  for (int m = 0; m + 1 < n; ++m) {
    const double a = mu[m], b = mu[m + 1];
    const double A = std::max(0.0, 1.0 - double(e[m])), B = std::max(0.0, 1.0 - double(e[m + 1]));
    over += e[m] > 1;
    acc += (b - a) * (A * (2 * a + b) + B * (a + 2 * b)) / 6;
    cdf[m + 1] = acc;
  }
  over += e[n - 1] > 1;
  for (int m = 1; m < n; ++m) cdf[m] = acc > 0 ? cdf[m] / acc : double(m) / (n - 1);
  cdf[n - 1] = 1;
  return 2 * acc;
}

void write_cdf_row(FILE* out, const double* cdf, int n) {
  std::fprintf(out, "{");
  for (int m = 0; m < n; ++m) std::fprintf(out, "%s%.9g", m ? ", " : "", cdf[m]);
  std::fprintf(out, "}");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.cpp\n", argv[0]);
    return 2;
  }
  if (std::abs(std::log(kCoatMaxAlpha / kCoatMinAlpha) - kCoatLogAlphaRange) > 1e-12) {
    std::fprintf(stderr, "%s: kCoatLogAlphaRange is not ln(kCoatMaxAlpha / kCoatMinAlpha)\n", argv[0]);
    return 1;
  }
  FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[1]);
    return 1;
  }
  std::fprintf(out, "// Generated by tools/make_albedo_tables.cpp at build time. Do not edit.\n");
  std::fprintf(out, "#include \"gonio/multiscatter_table_layout.h\"\n\nnamespace gonio::tables {\n\n");
  const char* names[2] = {"kGgx", "kBeckmann"};
  static float e_stored[kAlbedoRoughnessSize][kAlbedoCosineSize];
  int over = 0;  // stored albedos above 1 (none expected)
  const MicrofacetType types[2] = {MicrofacetType::GGX, MicrofacetType::Beckmann};
  for (int t = 0; t < 2; ++t) {
    std::fprintf(out, "const float %sAlbedo[kAlbedoRoughnessSize][kAlbedoCosineSize] = {\n", names[t]);
    double avg[kAlbedoRoughnessSize];
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      const double alpha = albedo_table_alpha(a);
      double e[kAlbedoCosineSize];
      for (int m = 0; m < kAlbedoCosineSize; ++m) e[m] = albedo(types[t], alpha, albedo_table_mu(m));
      // E_avg: the exact mean of the linear interpolant that microfacet_albedo() evaluates.
      double mu[kAlbedoCosineSize];
      for (int m = 0; m < kAlbedoCosineSize; ++m) mu[m] = double(m) / (kAlbedoCosineSize - 1);
      avg[a] = cosine_weighted_average_of_linear(mu, e, kAlbedoCosineSize);
      std::fprintf(out, "  {");
      for (int m = 0; m < kAlbedoCosineSize; ++m) std::fprintf(out, "%s%.9g", m ? ", " : "", e[m]);
      std::fprintf(out, "},\n");
      for (int m = 0; m < kAlbedoCosineSize; ++m) e_stored[a][m] = stored("%.9g", e[m]);
    }
    std::fprintf(out, "};\n\nconst float %sAverageAlbedo[kAlbedoRoughnessSize] = {", names[t]);
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) std::fprintf(out, "%s%.9g", a ? ", " : "", avg[a]);
    std::fprintf(out, "};\n\n");
    // The compensation lobe's sampling tables (multiscatter.h).
    double loss[kAlbedoRoughnessSize];
    std::fprintf(out, "const AlbedoCdfTable %sAlbedoCdf = {\n", names[t]);
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) {
      double mu[kAlbedoCosineSize], cdf[kAlbedoCosineSize];
      for (int m = 0; m < kAlbedoCosineSize; ++m) mu[m] = double(m) / (kAlbedoCosineSize - 1);
      loss[a] = complement_cdf(mu, e_stored[a], kAlbedoCosineSize, cdf, over);
      std::fprintf(out, "  ");
      write_cdf_row(out, cdf, kAlbedoCosineSize);
      std::fprintf(out, ",\n");
    }
    std::fprintf(out, "};\n\nconst AlbedoLossTable %sAlbedoLoss = {", names[t]);
    for (int a = 0; a < kAlbedoRoughnessSize; ++a) std::fprintf(out, "%s%.9g", a ? ", " : "", loss[a]);
    std::fprintf(out, "};\n\n");
  }
  write_dielectric_tables(out, "kGgx", MicrofacetType::GGX);
  write_dielectric_tables(out, "kBeckmann", MicrofacetType::Beckmann);
  write_coat_tables(out, "kGgx", MicrofacetType::GGX, over);
  write_coat_tables(out, "kBeckmann", MicrofacetType::Beckmann, over);
  if (over) std::fprintf(stderr, "%s: warning: %d stored albedos above 1 (sampled as 1)\n", argv[0], over);
  std::fprintf(out, "}  // namespace gonio::tables\n");
  return std::fclose(out) == 0 ? 0 : 1;
}
