// gonio fit (gonio/fit/fit.h): tables made in the test from a known analytic material
// (gonio's model evaluated at the centre of each bin); the fit must give back the known
// parameters. The error it reports is recomputed here from docs/fitting.md's formula,
// written again from the paper's definitions (bin centres from SPEC §2, directions from
// Rusinkiewicz's angles, weights from the Jacobian) without the library's metric code.

#include <array>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/fit/fit.h"
#include "gonio/material.h"
#include "gonio/merl.h"
#include "test_scale.h"

namespace gonio {
namespace {

using json = nlohmann::json;

// SPEC §2: entry (i, j, k) at θh = ((i + ½)/90)² π/2, θd = (j + ½)°, φd = (k + ½)°.
double theta_h(int i) { return (i + 0.5) / 90 * ((i + 0.5) / 90) * kPiD / 2; }
double theta_d(int j) { return (j + 0.5) * kPiD / 180; }
double phi_d(int k) { return (k + 0.5) * kPiD / 180; }

// (wo, wi) of Rusinkiewicz's angles with φh = 0: d in the frame of h = (sin θh, 0, cos θh),
// wi = d rotated by θh about y, wo = wi mirrored about h.
void directions(double th, double td, double pd, double wo[3], double wi[3]) {
  const double d[3] = {std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td)};
  wi[0] = std::cos(th) * d[0] + std::sin(th) * d[2];
  wi[1] = d[1];
  wi[2] = -std::sin(th) * d[0] + std::cos(th) * d[2];
  const double h[3] = {std::sin(th), 0, std::cos(th)};
  const double hd = h[0] * wi[0] + h[2] * wi[2];
  for (int a = 0; a < 3; ++a) wo[a] = 2 * hd * h[a] - wi[a];
}

// A table of `material` at the bin centres; `noise` multiplies each value by 1 + N(0, noise),
// a fraction `missing` of the entries is marked missing. Below-horizon entries are missing
// (nothing can be measured there). To keep the tests cheap only a quarter of the table is
// measured, the entries of odd θd and even φd index: a superset of the fit's subsample
// (θd 3, 9, ..., φd 6, 18, ...) on which the full table's error differs from the subsample's.
MerlTable make_table(const std::string& material, double noise = 0, double missing = 0, unsigned seed = 1) {
  const BxDF m = parse_material(material);
  MerlTable t;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0, noise > 0 ? noise : 1);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        if (j % 2 == 0 || k % 2 == 1) {
          t.set_missing(i, j, k);
          continue;
        }
        double wo[3], wi[3];
        directions(theta_h(i), theta_d(j), phi_d(k), wo, wi);
        if (wo[2] <= 0 || wi[2] <= 0 || (missing > 0 && uni(rng) < missing)) {
          t.set_missing(i, j, k);
          continue;
        }
        Color f = m.f(Vec3{Float(wo[0]), Float(wo[1]), Float(wo[2])}, Vec3{Float(wi[0]), Float(wi[1]), Float(wi[2])});
        if (noise > 0)
          for (int c = 0; c < 3; ++c) f[c] = Float(f[c] * std::max(0.0, 1 + gauss(rng)));
        t.set(i, j, k, f);
      }
  return t;
}

const char* kGgx = R"({"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":[0.9,0.6,0.3]})";

const MerlTable& ggx_table() {
  static const MerlTable t = make_table(kGgx);
  return t;
}

// The subsample of the tests: every θh bin, 15 θd × 15 φd (the tool's default is 30 × 30);
// 9 × 9 under the sanitizers (GONIO_TEST_SCALE < 1). Strides 6 and 10 both land on the
// measured quarter of make_table.
FitOptions options(const std::string& model, FitMetric metric = FitMetric::Log) {
  FitOptions o;
  o.model = model;
  o.metric = metric;
  o.stride = test::scaled(100, 1) < 100 ? 10 : 6;
  return o;
}

void expect_roughconductor(const json& m, double alpha, std::array<double, 3> f0, double tolerance) {
  ASSERT_EQ(m.at("type"), "roughconductor") << m.dump();
  EXPECT_NEAR(m.at("alpha").get<double>(), alpha, tolerance * alpha) << m.dump();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.at("f0")[c].get<double>(), f0[c], tolerance * f0[c]) << m.dump();
}

TEST(Fit, NoiseFreeGgxTableGivesBackAlphaAndF0Within1Percent) {
  for (FitMetric metric : {FitMetric::Log, FitMetric::Ngan}) {
    const FitResult r = fit_merl(ggx_table(), options("roughconductor", metric));
    expect_roughconductor(r.material, 0.2, {0.9, 0.6, 0.3}, 0.01);
    EXPECT_EQ(r.material.at("distribution"), "ggx");
    EXPECT_LT(r.error, 1e-4);
    EXPECT_EQ(r.starts, 3);  // α from 0.05, 0.2 and 0.5
    EXPECT_GT(r.evaluations, 0);
  }
}

TEST(Fit, NoisyGgxTableWithMissingEntriesGivesBackAlphaAndF0Within5Percent) {
  const MerlTable t = make_table(kGgx, 0.05, 0.10, 7);
  const FitResult r = fit_merl(t, options("roughconductor"));
  expect_roughconductor(r.material, 0.2, {0.9, 0.6, 0.3}, 0.05);
}

TEST(Fit, AnEntryWithOneNegativeChannelIsMissing) {
  // A table made in memory may mark an entry missing in one channel only; such entries,
  // here with absurd values in the other two, must not count.
  MerlTable t = ggx_table();
  for (int i = 0; i < 90; i += 2)
    for (int j = 1; j < 90; j += 2)
      for (int k = 0; k < 180; k += 2) t.set(i, j, k, Color{100, -1, 100});
  const FitResult r = fit_merl(t, options("roughconductor"));
  expect_roughconductor(r.material, 0.2, {0.9, 0.6, 0.3}, 0.01);
}

TEST(Fit, BeckmannTableWithDistributionBeckmann) {
  const MerlTable t = make_table(
      R"({"type":"roughconductor","distribution":"beckmann","alpha":0.35,"fresnel":"schlick","f0":[0.95,0.8,0.5]})");
  FitOptions o = options("roughconductor");
  o.distribution = "beckmann";
  const FitResult r = fit_merl(t, o);
  EXPECT_EQ(r.material.at("distribution"), "beckmann");
  expect_roughconductor(r.material, 0.35, {0.95, 0.8, 0.5}, 0.01);
  // GGX cannot take Beckmann's shape: a visibly worse fit (started at the right values).
  FitOptions g = options("roughconductor");
  g.init = json::parse(R"({"alpha":0.35,"f0":[0.95,0.8,0.5]})");
  g.max_iterations = 20;
  const FitResult ggx = fit_merl(t, g);
  EXPECT_GT(ggx.error, 100 * r.error + 1e-4);
}

TEST(Fit, ExactFresnelFromInitFitsEtaAndK) {
  // An exact-Fresnel table; the init asks for η + k. The index is ill-determined by a
  // reflectance alone, so the test checks what is determined: α and the fit.
  const MerlTable t = make_table(R"({"type":"roughconductor","alpha":0.3,"eta":[0.2,0.9,1.1],"k":[3.9,2.4,2.2]})");
  FitOptions o = options("roughconductor");
  o.init = json::parse(R"({"fresnel":"exact","alpha":0.5})");  // one start, α far off
  const FitResult r = fit_merl(t, o);
  EXPECT_EQ(r.material.at("fresnel"), "exact");
  EXPECT_TRUE(r.material.contains("eta") && r.material.contains("k")) << r.material.dump();
  EXPECT_NEAR(r.material.at("alpha").get<double>(), 0.3, 0.003) << r.material.dump();
  EXPECT_LT(r.error, 1e-3);
}

TEST(Fit, MultiscatterFromInitFitsTheMultipleScatteringModel) {
  // A white rough conductor with Kulla–Conty's lobe: α = 0.6, where single scattering
  // loses about a tenth of the energy (docs/gonioreflectometer.md). Fitted with the lobe
  // (--init {"multiscatter": true}) the fit gives back α and f0; the single-scattering
  // model cannot take the extra light's shape and fits worse from the same start.
  const char* white = R"({"type":"roughconductor","alpha":0.6,"fresnel":"schlick","f0":1,"multiscatter":true})";
  const MerlTable t = make_table(white);
  FitOptions o = options("roughconductor");
  o.init = json::parse(R"({"multiscatter":true})");
  const FitResult r = fit_merl(t, o);
  EXPECT_EQ(r.material.at("multiscatter"), true) << r.material.dump();
  expect_roughconductor(r.material, 0.6, {0.995, 0.995, 0.995}, 0.01);
  EXPECT_LT(r.error, 1e-4);
  FitOptions single = options("roughconductor");
  single.init = json::parse(R"({"alpha":0.6,"f0":1})");
  const FitResult s = fit_merl(t, single);
  EXPECT_FALSE(s.material.contains("multiscatter")) << s.material.dump();
  EXPECT_GT(s.error, 30 * r.error + 1e-4) << s.material.dump();
}

// docs/fitting.md: E = sqrt(Σ w Σ_c (T(g_c) − T(f_c))² / (3 Σ w)) over the measured entries
// with both directions above the horizon, w = sin θh Δθh sin θd cos θd, Δθh ∝ 2i + 1.
double documented_error(const MerlTable& t, const json& material, bool log_metric) {
  const BxDF m = material_from_json(material);
  double sum = 0, weights = 0;
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        const Color f = t.at(i, j, k);
        if (f[0] < 0) continue;
        double wo[3], wi[3];
        directions(theta_h(i), theta_d(j), phi_d(k), wo, wi);
        if (wo[2] <= 0 || wi[2] <= 0) continue;
        const Color g = m.f(Vec3{Float(wo[0]), Float(wo[1]), Float(wo[2])}, Vec3{Float(wi[0]), Float(wi[1]), Float(wi[2])});
        const double w = std::sin(theta_h(i)) * (2 * i + 1) * std::sin(theta_d(j)) * std::cos(theta_d(j));
        for (int c = 0; c < 3; ++c) {
          const double a = g[c] * wi[2], b = f[c] * wi[2];
          const double d = log_metric ? std::log(1 + a) - std::log(1 + b) : a - b;
          sum += w * d * d;
        }
        weights += w;
      }
  return std::sqrt(sum / (3 * weights));
}

TEST(Fit, ReportedErrorIsTheDocumentedMetricOverTheWholeTable) {
  for (FitMetric metric : {FitMetric::Log, FitMetric::Ngan}) {
    const FitResult r = fit_merl(ggx_table(), options("ward", metric));
    const double e = documented_error(ggx_table(), r.material, metric == FitMetric::Log);
    EXPECT_GT(e, 1e-3);  // ward is not GGX: a real error to compare
    EXPECT_NEAR(r.error, e, 1e-6 * e) << fit_metric_name(metric) << " " << r.material.dump();
  }
}

// The metrics compare f cos θi (Ngan et al. 2005, §4: "cosine-weighted"; Löw et al. 2012,
// eq. 11, ln(1 + f cos θi)) whatever the weights are: against a table whose every entry is
// K / cos θi (θi of the entry's wi, from Rusinkiewicz's angles as `directions` above), a
// black model's error is exactly K (ngan) or ln(1 + K) (log), since each counted entry
// contributes the same. Without the cosine, or with θo's, the entries differ and the
// weighted mean is not K. A sparse table (every 3rd θd and φd bin) keeps it cheap.
TEST(Fit, MetricsCompareFTimesCosThetaI) {
  const double K = 0.4;
  MerlTable t;
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        double wo[3], wi[3];
        directions(theta_h(i), theta_d(j), phi_d(k), wo, wi);
        if (j % 3 != 1 || k % 3 != 1 || wo[2] <= 1e-3 || wi[2] <= 1e-3) {
          t.set_missing(i, j, k);
          continue;
        }
        t.set(i, j, k, Color(Float(K / wi[2])));
      }
  const BxDF black = parse_material(R"({"type":"diffuse","reflectance":0})");
  EXPECT_NEAR(fit_error(t, black, FitMetric::Ngan), K, 1e-4 * K);
  EXPECT_NEAR(fit_error(t, black, FitMetric::Log), std::log1p(K), 1e-4 * K);
  // The transform itself (metric.h): f cos θi and ln(1 + f cos θi).
  EXPECT_DOUBLE_EQ(fit_transform(FitMetric::Ngan, 2.0, 0.25), 0.5);
  EXPECT_DOUBLE_EQ(fit_transform(FitMetric::Log, 2.0, 0.25), std::log(1.5));
}

// Σ over the bins with both directions up of the weight × the constant factors dropped
// (4 · 2π · Δθd · Δφd, × 2 for φd folded into [0, π)) is the measure of the pairs (ωi, ωo)
// of two hemispheres, (2π)², up to the bins cut by the horizon.
TEST(Fit, EntryWeightsIntegrateToTheMeasureOfTwoHemispheres) {
  const double dtheta = kPiD / 180;
  double sum = 0;
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        const auto [wo, wi] = merl_directions(merl_theta_h(i), merl_theta_d(j), merl_phi_d(k));
        if (wo.z > 0 && wi.z > 0) sum += merl_entry_weight(i, j);
      }
  sum *= 4 * 2 * kPiD * dtheta * dtheta * 2;
  EXPECT_NEAR(sum, 4 * kPiD * kPiD, 0.01 * 4 * kPiD * kPiD);
}

// OpenPBR's fit model (issue 35): a table of a rough tinted metal and one of a dielectric
// over a coloured base give back their parameters.
TEST(Fit, OpenPbrTablesGiveBackTheirParameters) {
  {
    const MerlTable t = make_table(
        R"({"type":"openpbr","base_metalness":1,"base_color":[0.9,0.6,0.3],"specular_color":[1,0.9,0.8],"specular_roughness":0.4})");
    FitOptions o = options("openpbr");
    o.stride = 10;  // the sanitizers' subsample: an OpenPBR evaluation costs several other models'
    o.init = json::parse(R"({"specular_roughness":0.25})");  // one start (the multi-start's cost ×3)
    const FitResult r = fit_merl(t, o);
    const json& m = r.material;
    EXPECT_NEAR(m.at("base_metalness").get<double>(), 1, 0.02) << m.dump();
    EXPECT_NEAR(m.at("specular_roughness").get<double>(), 0.4, 0.01 * 0.4) << m.dump();
    // F0 within 0.03: a channel's F0 and its F82 tint trade against each other where the
    // table has few grazing entries (the tint itself is poorly determined, so not checked).
    const std::array<double, 3> colour{0.9, 0.6, 0.3};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.at("base_color")[c].get<double>(), colour[size_t(c)], 0.03) << m.dump();
  }
  {
    const MerlTable t = make_table(
        R"({"type":"openpbr","base_color":[0.2,0.5,0.7],"specular_roughness":0.3,"base_diffuse_roughness":0.5})");
    FitOptions o = options("openpbr");
    o.stride = 10;
    // base_diffuse_roughness is a fixed choice, not fitted; one start, as above.
    o.init = json::parse(R"({"base_diffuse_roughness":0.5,"specular_roughness":0.5})");
    const FitResult r = fit_merl(t, o);
    const json& m = r.material;
    EXPECT_EQ(m.at("base_diffuse_roughness").get<double>(), 0.5);
    EXPECT_NEAR(m.at("base_metalness").get<double>(), 0, 0.02) << m.dump();
    EXPECT_NEAR(m.at("specular_roughness").get<double>(), 0.3, 0.02 * 0.3) << m.dump();
    const std::array<double, 3> colour{0.2, 0.5, 0.7};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.at("base_color")[c].get<double>(), colour[size_t(c)], 0.03) << m.dump();
  }
}

TEST(Fit, EveryModelGivesAValidMaterialAndAFiniteError) {
  FitOptions o = options("");
  o.stride = 10;  // a cheap subsample: this checks the plumbing, not the quality
  o.max_iterations = 4;
  for (const auto& model : fit_model_names()) {
    o.model = model;
    const FitResult r = fit_merl(ggx_table(), o);
    EXPECT_EQ(r.material.at("type"), model);
    EXPECT_NO_THROW((void)material_from_json(json::parse(r.material.dump()))) << r.material.dump();
    EXPECT_TRUE(std::isfinite(r.error) && r.error >= 0) << model;
  }
}

TEST(Fit, TwoLobeModelsKeepKdPlusKsAtMostOne) {
  // A bright table pushes kd + ks to its bound.
  const MerlTable t = make_table(R"({"type":"phong","kd":0.5,"ks":0.5,"exponent":30})");
  const FitResult r = fit_merl(t, options("phong"));
  for (int c = 0; c < 3; ++c) EXPECT_LE(r.material["kd"][c].get<double>() + r.material["ks"][c].get<double>(), 1 + 1e-6);
  EXPECT_NEAR(r.material["exponent"].get<double>(), 30, 0.3);
}

TEST(Fit, BadOptionsAreInputErrors) {
  auto fails = [](FitOptions o, const char* mention) {
    try {
      check_fit_options(o);
      ADD_FAILURE() << "accepted " << o.model << " " << o.init.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  };
  FitOptions o = options("lambert");
  fails(o, "unknown model 'lambert'");
  o = options("ward");
  o.distribution = "beckmann";
  fails(o, "--distribution");
  o = options("roughconductor");
  o.init = json::parse(R"({"type":"plastic"})");
  fails(o, "type must be \"roughconductor\"");
  o.init = json::parse(R"({"alpha":-0.1})");
  fails(o, "alpha");
  o.init = json::parse(R"({"alpha":[0.1,0.2]})");
  fails(o, "isotropic");
  o.init = json::parse(R"({"colour":1})");
  fails(o, "unknown or unfitted field 'colour'");
  o.init = json::parse(R"([1,2])");
  fails(o, "JSON object");
  o.init = json::parse(R"({"multiscatter":1})");
  fails(o, "multiscatter must be true or false");
  // An empty table: nothing to fit.
  MerlTable empty;
  for (auto& v : empty.rgb) v = MerlTable::kMissing;
  EXPECT_THROW((void)fit_merl(empty, options("roughconductor")), InputError);
}

}  // namespace
}  // namespace gonio
