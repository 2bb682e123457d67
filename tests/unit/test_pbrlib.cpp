// MaterialX pbrlib's BSDF nodes as gonio materials (issue 57; bxdf/pbr_node.h) against
// MaterialX's own formulas, evaluated here from its specification
// (documents/Specification/MaterialX.PBRSpec.md): the qualitative Oren-Nayar, the GGX
// microfacet BRDF with height-correlated Smith G2, the dielectric (Lagarde) and conductor
// Fresnel equations; the layer's throughput against the top's albedo integrated here;
// the white furnace of a layer over a white base; the operators' identities; sampling
// (χ², pdf integral, consistency) through the validator; spectral mode; and each refusal.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "gonio/bxdf.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/reflectance.h"
#include "gonio/spectral_material.h"
#include "gonio/validate.h"
#include "test_scale.h"

namespace gonio {
namespace pbrlib_test {

using nlohmann::json;

BxDF mx(const std::string& text) { return material_from_json(json::parse(text), "test"); }

Vec3 dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPiD / 180, p = phi_deg * kPiD / 180;
  return Vec3(Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)), Float(std::cos(t)));
}

// MaterialX PBR spec, "Qualitative Oren-Nayar Reflectance Equations".
double mx_oren_nayar(const Vec3& wo, const Vec3& wi, double rho, double sigma) {
  const double s2 = sigma * sigma;
  const double A = 1 - 0.5 * s2 / (s2 + 0.33), B = 0.45 * s2 / (s2 + 0.09);
  const double ti = std::acos(double(wi.z)), to = std::acos(double(wo.z));
  const double dphi = std::atan2(double(wi.y), double(wi.x)) - std::atan2(double(wo.y), double(wo.x));
  const double g = std::max(0.0, std::cos(dphi)) * std::sin(std::max(ti, to)) * std::tan(std::min(ti, to));
  return rho / kPiD * (A + B * g);
}

// MaterialX PBR spec, "GGX Normal Distribution Function" and "Height-Correlated Smith".
double mx_ggx_brdf_no_fresnel(const Vec3& wo, const Vec3& wi, double alpha) {
  double h[3] = {double(wo.x) + wi.x, double(wo.y) + wi.y, double(wo.z) + wi.z};
  const double n = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  for (double& c : h) c /= n;
  const double a2 = alpha * alpha;
  const double q = (h[0] * h[0] + h[1] * h[1]) / a2 + h[2] * h[2];
  const double D = 1 / (kPiD * a2 * q * q);
  const double ci = wi.z, co = wo.z;
  const auto lambda = [a2](double c) { return std::sqrt(a2 + (1 - a2) * c * c); };
  const double G = 2 * ci * co / (lambda(co) * ci + lambda(ci) * co);
  return D * G / (4 * ci * co);
}
double half_cos(const Vec3& wo, const Vec3& wi) {
  const double h[3] = {double(wo.x) + wi.x, double(wo.y) + wi.y, double(wo.z) + wi.z};
  return (h[0] * wo.x + h[1] * wo.y + h[2] * wo.z) / std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
}
// "Dielectric Fresnel Equations" (Lagarde 2013).
double mx_fresnel_dielectric(double c, double eta) {
  const double g2 = eta * eta + c * c - 1;
  if (g2 < 0) return 1;
  const double g = std::sqrt(g2);
  const double a = (g - c) / (g + c), b = (c * (g + c) - 1) / (c * (g - c) + 1);
  return 0.5 * a * a * (1 + b * b);
}
// "Conductor Fresnel Equations" (Lagarde 2013).
double mx_fresnel_conductor(double c, double eta, double k) {
  const double s2 = 1 - c * c;
  const double t = eta * eta - k * k - s2;
  const double ab = std::sqrt(t * t + 4 * eta * eta * k * k);
  const double a = std::sqrt(std::max(0.0, 0.5 * (ab + t)));
  const double rs = (ab - 2 * a * c + c * c) / (ab + 2 * a * c + c * c);
  const double rp = rs * (c * c * ab - 2 * a * c * s2 + s2 * s2) / (c * c * ab + 2 * a * c * s2 + s2 * s2);
  return 0.5 * (rs + rp);
}

// ∫ f(wo, wi) cos θi dωi over the upper hemisphere by the midpoint rule in (cos θi, φi).
double hemisphere_albedo(const BxDF& b, const Vec3& wo, int channel = 1) {
  constexpr int kMu = 400, kPhi = 200;
  double sum = 0;
  for (int i = 0; i < kMu; ++i) {
    const double mu = (i + 0.5) / kMu, s = std::sqrt(1 - mu * mu);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = (j + 0.5) * 2 * kPiD / kPhi;
      const Vec3 wi(Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(mu));
      sum += double(b.f(wo, wi)[channel]) * mu;
    }
  }
  return sum * 2 * kPiD / (kMu * kPhi);
}

TEST(Pbrlib, OrenNayarQualitativeIsMaterialXFormula) {
  const BxDF b = mx(R"({"type": "oren_nayar_diffuse_bsdf", "weight": 0.7, "color": [0.2, 0.5, 0.9], "roughness": 0.6})");
  const double rho[3] = {0.2, 0.5, 0.9};
  for (double to : {0.0, 20.0, 60.0, 85.0})
    for (double ti : {10.0, 45.0, 80.0})
      for (double dphi : {0.0, 40.0, 120.0}) {
        const Vec3 wo = dir(to, 30), wi = dir(ti, 30 + dphi);
        const Color f = b.f(wo, wi);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(f[c], 0.7 * mx_oren_nayar(wo, wi, rho[c], 0.6), 1e-5) << to << " " << ti << " " << dphi;
      }
}

TEST(Pbrlib, OrenNayarEnergyCompensationIsWeightTimesEon) {
  const BxDF b = mx(R"({"type": "oren_nayar_diffuse_bsdf", "weight": 0.5, "color": 0.8, "roughness": 0.9,
                        "energy_compensation": true})");
  const BxDF eon = mx(R"({"type": "eon", "reflectance": 0.8, "roughness": 0.9})");
  const Vec3 wo = dir(50, 0), wi = dir(70, 150);
  EXPECT_NEAR(b.f(wo, wi)[0], 0.5 * eon.f(wo, wi)[0], 1e-6);
  // White and weight 1: EON keeps every bit (furnace): albedo 1 at every angle.
  const BxDF white = mx(R"({"type": "oren_nayar_diffuse_bsdf", "color": 1, "roughness": 1, "energy_compensation": true})");
  for (double t : {0.0, 45.0, 80.0}) EXPECT_NEAR(hemisphere_albedo(white, dir(t, 0)), 1.0, 2e-3) << t;
}

TEST(Pbrlib, DielectricReflectionIsMaterialXMicrofacet) {
  // alpha 0.05: the energy compensation adds less than 1e-3 of the lobe.
  const BxDF b = mx(R"({"type": "dielectric_bsdf", "weight": 0.8, "tint": [1, 0.5, 0.25], "ior": 1.7,
                        "roughness": 0.05})");
  const double tint[3] = {1, 0.5, 0.25};
  for (const auto& [wo, wi] : {std::pair{dir(30, 0), dir(32, 182)}, std::pair{dir(60, 10), dir(58, 188)},
                               std::pair{dir(5, 0), dir(8, 170)}}) {
    const double ref = mx_ggx_brdf_no_fresnel(wo, wi, 0.05) * mx_fresnel_dielectric(half_cos(wo, wi), 1.7);
    const Color f = b.f(wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], 0.8 * tint[c] * ref, 2e-3 * 0.8 * tint[c] * ref);
  }
  // R only: nothing below.
  EXPECT_EQ(b.f(dir(30, 0), dir(150, 180))[0], 0);
}

TEST(Pbrlib, ConductorIsMaterialXMicrofacet) {
  const BxDF b = mx(R"({"type": "conductor_bsdf", "weight": 0.9, "roughness": 0.05})");  // gold, MaterialX's default
  const double n[3] = {0.183, 0.421, 1.373}, k[3] = {3.424, 2.346, 1.770};
  for (const auto& [wo, wi] : {std::pair{dir(30, 0), dir(32, 182)}, std::pair{dir(75, 10), dir(74, 189)}}) {
    const Color f = b.f(wo, wi);
    for (int c = 0; c < 3; ++c) {
      const double ref = 0.9 * mx_ggx_brdf_no_fresnel(wo, wi, 0.05) * mx_fresnel_conductor(half_cos(wo, wi), n[c], k[c]);
      EXPECT_NEAR(f[c], ref, 2e-3 * ref) << c;
    }
  }
  // A perfect reflector (k = 1000: F > 1 - 1e-5) at alpha 0.7 keeps its energy: the
  // compensation restores what single scattering loses (about 20 % at grazing).
  const BxDF white = mx(R"({"type": "conductor_bsdf", "ior": 1, "extinction": 1000, "roughness": 0.7})");
  for (double t : {0.0, 60.0, 80.0}) EXPECT_NEAR(hemisphere_albedo(white, dir(t, 0)), 1.0, 1e-2) << t;
}

// The layer: f = f_top + (1 - w E_top(v)) f_base, E_top the top's untinted albedo,
// integrated here from the top's own f.
TEST(Pbrlib, LayerScalesTheBaseByTheTopsThroughput) {
  const std::string top = R"({"type": "dielectric_bsdf", "weight": 0.6, "tint": 0.5, "ior": 1.5, "roughness": 0.3})";
  const std::string top_white = R"({"type": "dielectric_bsdf", "weight": 1, "ior": 1.5, "roughness": 0.3})";
  const BxDF layer = mx(R"({"type": "layer", "top": )" + top + R"(, "base": {"type": "oren_nayar_diffuse_bsdf", "color": 0.5}})");
  const BxDF t = mx(top), tw = mx(top_white);
  for (double to : {0.0, 40.0, 75.0}) {
    const Vec3 wo = dir(to, 0), wi = dir(35, 100);
    const double e = hemisphere_albedo(tw, wo);  // untinted, unweighted
    const double expected = t.f(wo, wi)[1] + (1 - 0.6 * e) * 0.5 / kPiD;
    EXPECT_NEAR(layer.f(wo, wi)[1], expected, 2e-3 * expected) << to;
  }
}

// White furnace: a weight-1 dielectric over a white Lambertian base reflects everything,
// E + (1 - E) = 1, at every angle (MaterialX's albedo scaling is exact for the view
// direction's albedo).
TEST(Pbrlib, LayerOverWhiteBaseIsAWhiteFurnace) {
  for (const char* top : {R"({"type": "dielectric_bsdf", "ior": 1.5, "roughness": 0.4})",
                          R"({"type": "sheen_bsdf", "mode": "zeltner", "roughness": 0.5})"}) {
    const BxDF layer = mx(std::string(R"({"type": "layer", "top": )") + top +
                          R"(, "base": {"type": "oren_nayar_diffuse_bsdf", "color": 1}})");
    for (double t : {0.0, 30.0, 60.0, 85.0}) {
      const double a = hemisphere_albedo(layer, dir(t, 20));
      EXPECT_NEAR(a, 1.0, 6e-3) << top << " at " << t;
    }
  }
}

TEST(Pbrlib, SheenThroughputIsThePublishedAlbedo) {
  // R(mu, r) of Zeltner et al.'s fit as MaterialX publishes it (mx_microfacet_sheen.glsl),
  // typed in again: the throughput is 1 - w R(mu_v).
  const auto R = [](double mu, double r) {
    const double s = r * (0.0206607 + 1.58491 * r) / (0.0379424 + r * (1.32227 + r));
    const double m = r * (-0.193854 + r * (-1.14885 + r * (1.7932 - 0.95943 * r * r))) / (0.046391 + r);
    const double o = r * (0.000654023 + (-0.0207818 + 0.119681 * r) * r) / (1.26264 + r * (-1.92021 + r));
    return std::max(0.0, std::exp(-0.5 * (mu - m) * (mu - m) / (s * s)) / (s * std::sqrt(2 * kPiD)) + o);
  };
  const BxDF b = mx(R"({"type": "sheen_bsdf", "mode": "zeltner", "weight": 0.8, "color": [1, 0.2, 0.2], "roughness": 0.4})");
  const auto* n = std::get_if<PbrNodeBxDF>(&b.models());
  ASSERT_NE(n, nullptr);
  for (double mu : {0.0625, 0.25, 0.5625, 0.765625, 1.0}) {  // grid points of the table, (i / 64)^2
    const Vec3 v(Float(std::sqrt(1 - mu * mu)), 0, Float(mu));
    EXPECT_NEAR(n->throughput(v)[0], 1 - 0.8 * R(mu, 0.4), 2e-3) << mu;
  }
}

TEST(Pbrlib, OperatorsAreTheirDefinitions) {
  const std::string a = R"({"type": "oren_nayar_diffuse_bsdf", "color": 0.6, "roughness": 0.3})";
  const std::string c = R"({"type": "conductor_bsdf", "roughness": 0.2})";
  const BxDF fa = mx(a), fc = mx(c);
  const BxDF mix = mx(R"({"type": "mix", "fg": )" + a + R"(, "bg": )" + c + R"(, "mix": 0.3})");
  const BxDF add = mx(R"({"type": "add", "in1": )" + a + R"(, "in2": )" + c + "}");
  const BxDF mul = mx(R"({"type": "multiply", "in1": )" + c + R"(, "in2": [0.5, 1, 0.25]})");
  const Vec3 wo = dir(40, 0), wi = dir(38, 175);
  for (int ch = 0; ch < 3; ++ch) {
    const double x = fa.f(wo, wi)[ch], y = fc.f(wo, wi)[ch];
    EXPECT_NEAR(mix.f(wo, wi)[ch], 0.3 * x + 0.7 * y, 1e-5 * (x + y));
    EXPECT_NEAR(add.f(wo, wi)[ch], x + y, 1e-5 * (x + y));
    EXPECT_NEAR(mul.f(wo, wi)[ch], (ch == 0 ? 0.5 : ch == 1 ? 1 : 0.25) * y, 1e-5 * y);
  }
}

// Sampling of every operator against its pdf (χ², pdf integral, weights), on a tree that
// holds each: mix(layer(sheen, add(conductor, dielectric R)), multiply(oren_nayar)).
TEST(Pbrlib, SamplingMatchesPdf) {
  const BxDF b = mx(R"({"type": "mix", "mix": 0.6,
    "fg": {"type": "layer", "top": {"type": "sheen_bsdf", "mode": "zeltner", "roughness": 0.4},
           "base": {"type": "add", "in1": {"type": "conductor_bsdf", "weight": 0.5, "roughness": [0.2, 0.4]},
                    "in2": {"type": "dielectric_bsdf", "ior": 1.4, "roughness": 0.1}}},
    "bg": {"type": "multiply", "in1": {"type": "oren_nayar_diffuse_bsdf", "color": 0.9, "roughness": 0.5}, "in2": 0.8}})");
  ValidationOptions o;
  o.scale = 0.08 * double(test::scaled(1000)) / 1000;
  for (const auto& r : check_sampling(b, o)) EXPECT_TRUE(r.pass) << r.name << ": " << r.detail;
  const auto c = check_consistency(b, o);
  EXPECT_TRUE(c.pass) << c.detail;
}

TEST(Pbrlib, RoughTransmissionRTSamplesAndConserves) {
  const BxDF b = mx(R"({"type": "dielectric_bsdf", "ior": 1.5, "roughness": 0.3, "scatter_mode": "RT"})");
  ValidationOptions o;
  o.scale = 0.08 * double(test::scaled(1000)) / 1000;
  for (const auto& r : check_sampling(b, o)) EXPECT_TRUE(r.pass) << r.name << ": " << r.detail;
  // White furnace: a lossless rough interface, energy-compensated, keeps everything.
  ReflectanceOptions ro;
  ro.samples = test::scaled(1u << 15);
  for (double t : {0.0, 50.0, 80.0}) EXPECT_NEAR(directional_albedo(b, dir(t, 0), ro).albedo[1], 1.0, 0.01) << t;
}

TEST(Pbrlib, SpectralModeMatchesRgbForGreyMaterials) {
  const MaterialWithSpectra m = material_with_spectra_from_json(json::parse(R"({"type": "layer",
    "top": {"type": "dielectric_bsdf", "ior": 1.5, "roughness": 0.3, "weight": 0.7},
    "base": {"type": "multiply", "in1": {"type": "oren_nayar_diffuse_bsdf", "color": 0.5}, "in2": 0.5}})"), "test");
  SpectralScratch scratch;
  SampledWavelengths w = SampledWavelengths::sample_uniform(Float(0.3));
  const SpectralBxDF s = to_spectral(m.bxdf, m.spectra, w, scratch);
  const Vec3 wo = dir(30, 0), wi = dir(50, 120);
  const Float rgb = m.bxdf.f(wo, wi)[1];
  for (int j = 0; j < SampledSpectrum::size(); ++j) EXPECT_NEAR(s.f(wo, wi)[j], rgb, 1e-3 * rgb);
}

TEST(Pbrlib, RefusalsNameTheProblem) {
  const auto refused = [](const std::string& text, const std::string& needle) {
    try {
      mx(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(needle), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  };
  refused(R"({"type": "layer", "top": 3, "base": {"type": "oren_nayar_diffuse_bsdf"}})", "top must be a material");
  refused(R"({"type": "conductor_bsdf", "retroreflective": true})", "retroreflective");
  refused(R"({"type": "dielectric_bsdf", "scatter_mode": "T"})", "scatter_mode \"T\"");
  refused(R"({"type": "dielectric_bsdf", "scatter_mode": "X"})", "scatter_mode must be");
  refused(R"({"type": "sheen_bsdf", "mode": "charlie"})", "mode must be \"conty_kulla\" or \"zeltner\"");
  refused(R"({"type": "mix", "fg": {"type": "oren_nayar_diffuse_bsdf"}, "bg": {"type": "oren_nayar_diffuse_bsdf"}, "mix": 2})",
          "mix must be in [0, 1]");
  refused(R"({"type": "add", "in1": {"type": "oren_nayar_diffuse_bsdf"}})", "missing parameter 'in2'");
  // Too deep: nine nested multiplies.
  std::string deep = R"({"type": "oren_nayar_diffuse_bsdf"})";
  for (int i = 0; i < 8; ++i) deep = R"({"type": "multiply", "in1": )" + deep + "}";
  refused(deep, "nested deeper than 8");
}

// MaterialX's definitions break two properties; the figures docs/materialx.md publishes.
TEST(Pbrlib, MeasuredFiguresOfMaterialXsDefinitions) {
  // layer: not reciprocal. Over a white Lambertian base, f(wo, wi) - f(wi, wo) =
  // (E(wi) - E(wo)) / pi with E the top's albedo (integrated here); the largest relative
  // error |f(wo, wi) - f(wi, wo)| / max over a grid of angles is published.
  const std::string top = R"({"type": "dielectric_bsdf", "ior": 1.5, "roughness": 0.2})";
  const BxDF layer = mx(R"({"type": "layer", "top": )" + top + R"(, "base": {"type": "oren_nayar_diffuse_bsdf", "color": 1}})");
  const BxDF t = mx(top);
  double worst = 0;
  for (double a = 5; a < 90; a += 10)
    for (double b = 5; b < 90; b += 10) {
      const Vec3 wo = dir(a, 0), wi = dir(b, 90);
      const double x = layer.f(wo, wi)[1], y = layer.f(wi, wo)[1];
      worst = std::max(worst, std::abs(x - y) / std::max(x, y));
      if (a == 5 || a == 85) {
        EXPECT_NEAR(x - y, (hemisphere_albedo(t, wi) - hemisphere_albedo(t, wo)) / kPiD, 2e-3) << a << " " << b;
      }
    }
  std::printf("layer reciprocity error (dielectric 1.5, alpha 0.2, over white): %.3f\n", worst);
  // add: not energy-bounded: two white diffuse nodes reflect twice the light.
  const BxDF add = mx(R"({"type": "add", "in1": {"type": "oren_nayar_diffuse_bsdf", "color": 1},
                          "in2": {"type": "oren_nayar_diffuse_bsdf", "color": 1}})");
  EXPECT_NEAR(hemisphere_albedo(add, dir(30, 0)), 2.0, 1e-3);
}

// Conty-Kulla ("Charlie") sheen: the specification's equations typed in, the albedo
// against MaterialX's published rational fit of it (mx_imageworks_sheen_dir_albedo_analytic),
// reciprocity, and sampling.
TEST(Pbrlib, ContyKullaSheenIsTheSpecification) {
  const BxDF b = mx(R"({"type": "sheen_bsdf", "weight": 0.9, "color": [1, 0.5, 0.2], "roughness": 0.3})");
  const double col[3] = {1, 0.5, 0.2};
  const auto spec_f = [](const Vec3& wo, const Vec3& wi, double r) {
    double h[3] = {double(wo.x) + wi.x, double(wo.y) + wi.y, double(wo.z) + wi.z};
    const double n = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const double cos_h = h[2] / n, sin2 = 1 - cos_h * cos_h;
    const double D = (2 + 1 / r) * std::pow(sin2, 1 / (2 * r)) / (2 * kPiD);
    return D / (4 * (double(wi.z) + wo.z - double(wi.z) * wo.z));
  };
  for (const auto& [wo, wi] : {std::pair{dir(30, 0), dir(60, 170)}, std::pair{dir(80, 0), dir(85, 20)},
                               std::pair{dir(10, 0), dir(45, 90)}}) {
    const Color f = b.f(wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], 0.9 * col[c] * spec_f(wo, wi, 0.3), 1e-4 * f[c] + 1e-7);
    EXPECT_NEAR(b.f(wi, wo)[0], f[0], 1e-6 * f[0]);  // reciprocal
  }
  const auto fit = [](double mu, double r) {
    const double x = 13.67300 - 68.78018 * mu + 799.08825 * r - 905.00061 * mu * r + 60.28956 * mu * mu + 1086.96473 * r * r;
    const double y = 1.0 + 61.57746 * mu + 442.78211 * r + 2597.49308 * mu * r + 121.81241 * mu * mu + 3045.55075 * r * r;
    return x / y;
  };
  for (double r : {0.2, 0.5, 0.9}) {
    const BxDF w = mx(R"({"type": "sheen_bsdf", "roughness": )" + std::to_string(r) + "}");
    for (double t : {0.0, 45.0, 75.0}) {
      const double mu = std::cos(t * kPiD / 180);
      EXPECT_NEAR(hemisphere_albedo(w, dir(t, 0)), fit(mu, r), 0.02) << r << " " << t;
    }
  }
  ValidationOptions o;
  o.scale = 0.08 * double(test::scaled(1000)) / 1000;
  for (const auto& r : check_sampling(b, o)) EXPECT_TRUE(r.pass) << r.name << ": " << r.detail;
  EXPECT_TRUE(check_energy(b, o).pass);
}

}  // namespace pbrlib_test
}  // namespace gonio
