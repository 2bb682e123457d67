// Spectral mode's materials (issue 11, item 7; spectral_material.h): to_spectral() against
// expectations made here without gonio's spectral code — grey parameters that must give
// the RGB model at every wavelength, colours reduced to XYZ by this file's own Simpson
// quadrature of data/cie/*.csv (read by tests/data_csv.h), the Schott Sellmeier formula
// for BK7, the normal-incidence Fresnel reflectance of data/metals/Au.csv, and finiteness
// (and sample/pdf/f consistency) at the ends of the visible range and at grazing and
// below-horizon directions.

#include <gtest/gtest.h>

#include "../test_common.h"
#include "../merl_files.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "../data_csv.h"
#include "gonio/material.h"
#include "gonio/rgl/write.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/cie.h"

namespace gonio {
namespace {

using gonio_test_data::lerp_rows;
using gonio_test_data::read_data;

// Wavelengths whose hero λ_0 is `lambda` (uniform sampling: λ_j = 360 + 470 frac(u + j/4)).
SampledWavelengths at(double lambda) {
  return SampledWavelengths::sample_uniform(Float((lambda - 360) / 470));
}

SpectralBxDF spectral(const MaterialWithSpectra& m, SampledWavelengths& w, SpectralScratch& scratch,
                      TexturedColours textured = 0) {
  scratch.reset();
  return to_spectral(m.bxdf, m.spectra, w, scratch, textured);
}

Vec3 dir_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPiD / 180, p = phi_deg * kPiD / 180;
  return Vec3{Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)), Float(std::cos(t))};
}

// Linear sRGB of the reflectance spectrum R(λ) under D65:
//   XYZ = ∫ R D65 (x̄, ȳ, z̄) dλ / ∫ D65 ȳ dλ over 360–830 nm (CIE 15:2004 §7.1),
// the tables linearly interpolated between their rows, by composite Simpson with h = 0.25 nm;
// XYZ → linear sRGB by IEC 61966-2-1:1999 eq. 5.2.
std::array<double, 3> srgb_under_d65(const std::function<double(double)>& R) {
  static const auto cmf = read_data("cie/cie1931_2deg_cmf.csv");
  static const auto d65 = read_data("cie/cie_illuminant_d65.csv");
  const double a = 360, b = 830, h = 0.25;
  const int steps = int((b - a) / h);
  double xyz[3] = {0, 0, 0}, white = 0;
  for (int i = 0; i <= steps; ++i) {
    const double l = a + i * h;
    const double wgt = (i == 0 || i == steps) ? 1 : (i % 2 ? 4 : 2);
    const double e = lerp_rows(d65, l), r = R(l);
    for (int j = 0; j < 3; ++j) xyz[j] += wgt * r * e * lerp_rows(cmf, l, size_t(j) + 1);
    white += wgt * e * lerp_rows(cmf, l, 2);
  }
  const double m[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  std::array<double, 3> rgb{};
  for (int j = 0; j < 3; ++j) rgb[size_t(j)] = (m[j][0] * xyz[0] + m[j][1] * xyz[1] + m[j][2] * xyz[2]) / white;
  return rgb;
}

// Normal incidence from vacuum onto n + ik (Born & Wolf §14.2, eq. 21 at θ = 0).

// Schott N-BK7, Sellmeier formula n² − 1 = Σ B_i λ² / (λ² − C_i), λ in µm, C in µm²
// (SCHOTT optical glass data sheet N-BK7, 2014: B = 1.03961212, 0.231792344, 1.01046945;
// C = 0.00600069867, 0.0200179144, 103.560653).
double bk7_sellmeier(double lambda_nm) {
  const double B[3] = {1.03961212, 0.231792344, 1.01046945};
  const double C[3] = {0.00600069867, 0.0200179144, 103.560653};
  const double x = (lambda_nm / 1000) * (lambda_nm / 1000);
  double s = 1;
  for (int i = 0; i < 3; ++i) s += B[i] * x / (x - C[i]);
  return std::sqrt(s);
}

// One material of every type of SPEC §2 that gonio has, every colour parameter the grey
// `g` (so that the spectral model must be the RGB one at every wavelength), indices
// constant.
// A grey diffuse written as an RGL file (small resolution): its spectra are the grey at
// every wavelength, so spectral mode gives the RGB model.
std::string grey_rgl_file(double g) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("gonio_test_grey_" + std::to_string(::getpid()) + "_" + std::to_string(int(g * 1000)) + ".bsdf"))
                               .string();
  if (!std::filesystem::exists(path)) {
    RglWriteOptions o;
    o.n_theta_i = 4;
    o.n_ndf = 8;
    o.n_sample = 6;
    o.wavelengths = {360, 600, 830};
    const std::vector<std::uint8_t> bytes =
        tabulate_rgl(parse_material(R"({"type":"diffuse","reflectance":)" + std::to_string(g) + "}"), o);
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  return path;
}

std::map<std::string, std::string> grey_materials(double g) {
  const std::string G = std::to_string(g), H = std::to_string(g / 2);
  return {
      {"diffuse", R"({"type":"diffuse","reflectance":)" + G + "}"},
      {"mirror", R"({"type":"mirror","reflectance":)" + G + "}"},
      {"conductor", R"({"type":"conductor","eta":1.3,"k":2.5})"},
      {"dielectric", R"({"type":"dielectric","eta":1.5})"},
      {"roughconductor", R"({"type":"roughconductor","alpha":0.3,"eta":0.4,"k":3})"},
      {"roughdielectric", R"({"type":"roughdielectric","alpha":0.3,"eta":1.4})"},
      {"orennayar", R"({"type":"orennayar","reflectance":)" + G + R"(,"sigma":20})"},
      {"eon", R"({"type":"eon","reflectance":)" + G + R"(,"roughness":0.6})"},
      {"phong", R"({"type":"phong","kd":)" + H + R"(,"ks":)" + H + R"(,"exponent":20})"},
      {"blinnphong", R"({"type":"blinnphong","kd":)" + H + R"(,"ks":)" + H + R"(,"exponent":20})"},
      {"ward", R"({"type":"ward","kd":)" + H + R"(,"ks":)" + H + R"(,"alpha":[0.2,0.4]})"},
      {"ashikhminshirley", R"({"type":"ashikhminshirley","rd":)" + G + R"(,"rs":)" + H + R"(,"nu":10,"nv":100})"},
      {"plastic", R"({"type":"plastic","reflectance":)" + G + R"(,"eta":1.5,"alpha":0.2})"},
      {"blend", R"({"type":"blend","weight":0.3,"bsdfs":[{"type":"diffuse","reflectance":)" + G +
                    R"(},{"type":"roughconductor","alpha":0.2,"fresnel":"schlick","f0":)" + G + "}]}"},
      {"measured", R"({"type":"measured","file":")" + gonio_test_merl::lambert_table() + R"("})"},
      {"rgl", R"({"type":"rgl","file":")" + grey_rgl_file(g) + R"("})"},
      {"subsurface", R"({"type":"subsurface","eta":1.33,"alpha":0.2,"sigma_s":)" + G + R"(,"sigma_a":)" + H + "}"},
      {"sheen", R"({"type":"sheen","color":)" + G + R"(,"roughness":0.3})"},
      {"layered", R"({"type":"layered","top":{"type":"roughdielectric","alpha":0.3,"eta":1.4},"bottom":{"type":"diffuse","reflectance":)" +
                      G + R"(},"thickness":0.2,"albedo":)" + H + "}"},
      {"thindielectric", R"({"type":"thindielectric","eta":1.4})"},
      {"gltf_pbr", R"({"type":"gltf_pbr","base_color":)" + G + R"(,"metallic":0.3,"roughness":0.4,"clearcoat":0.5,"sheen_color":)" + H +
                       R"(,"transmission":0.4,"specular_color":)" + G + "}"},
      {"openpbr", R"({"type":"openpbr","base_color":)" + G + R"(,"base_diffuse_roughness":0.4,"coat_weight":0.5,"fuzz_weight":0.3,"fuzz_color":)" +
                      G + R"(,"base_metalness":0.3,"transmission_weight":0.2})"},
      {"oren_nayar_diffuse_bsdf", R"({"type":"oren_nayar_diffuse_bsdf","color":)" + G + R"(,"roughness":0.3})"},
      {"conductor_bsdf", R"({"type":"conductor_bsdf","ior":1.3,"extinction":2.5,"roughness":0.3})"},
      {"dielectric_bsdf", R"({"type":"dielectric_bsdf","tint":)" + G + R"(,"roughness":0.2,"scatter_mode":"RT"})"},
      {"sheen_bsdf", R"({"type":"sheen_bsdf","color":)" + G + R"(,"roughness":0.4,"mode":"conty_kulla"})"},
      {"mix", R"({"type":"mix","mix":0.4,"fg":{"type":"sheen_bsdf","color":)" + G +
                  R"(},"bg":{"type":"oren_nayar_diffuse_bsdf","color":)" + G + "}}"},
      {"add", R"({"type":"add","in1":{"type":"sheen_bsdf","color":)" + H + R"(},"in2":{"type":"oren_nayar_diffuse_bsdf","color":)" +
                  H + "}}"},
      {"multiply", R"({"type":"multiply","in1":{"type":"oren_nayar_diffuse_bsdf","color":)" + G + R"(},"in2":0.5})"},
      {"layer", R"({"type":"layer","top":{"type":"dielectric_bsdf","roughness":0.2},"base":{"type":"oren_nayar_diffuse_bsdf","color":)" +
                    G + "}}"},
      {"hair", R"({"type":"hair","tint_R":)" + G + R"(,"sigma_a":0.4,"alpha":3})"},
      {"chiang_hair_bsdf", R"({"type":"chiang_hair_bsdf","tint_TT":)" + G + R"(,"absorption_coefficient":0.2})"},
  };
}

// Coloured, measured and dispersive materials of every type (for finiteness).
std::vector<std::string> coloured_materials() {
  return {
      R"({"type":"diffuse","reflectance":[0.9,0.2,0.05]})",
      R"({"type":"diffuse","reflectance":{"spectrum":[[360,0],[600,1],[830,0.3]]}})",
      R"({"type":"mirror","reflectance":[1,0,0]})",
      R"({"type":"conductor","material":"Au"})",
      R"({"type":"conductor","material":"Cu"})",
      R"({"type":"conductor","fresnel":"schlick","f0":[1,0.8,0.3]})",
      R"({"type":"conductor","eta":[0.2,0.5,1.4],"k":[3,2.5,1.8]})",
      R"({"type":"dielectric","eta":"BK7"})",
      R"({"type":"dielectric","eta":"SF11"})",
      R"({"type":"dielectric","eta":0.75})",
      R"({"type":"roughconductor","alpha":0.2,"material":"Au"})",
      R"({"type":"roughconductor","alpha":0.45,"material":"Cu","multiscatter":true})",
      R"({"type":"roughconductor","alpha":[0.05,0.5],"distribution":"beckmann","material":"Ag"})",
      R"({"type":"roughdielectric","alpha":0.2,"eta":"SF11"})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":"BK7","multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.1,"distribution":"beckmann","eta":1.33})",
      R"({"type":"orennayar","reflectance":[0.1,0.9,0.3],"sigma":60})",
      R"({"type":"eon","reflectance":[0.1,0.9,0.3],"roughness":1})",
      R"({"type":"eon","reflectance":{"spectrum":[[360,1],[830,0]]},"roughness":0.3})",
      R"({"type":"conductor","fresnel":"f82","f0":[0.95,0.64,0.54],"f82":[0.9,0.5,0.1]})",
      R"({"type":"roughconductor","alpha":0.3,"fresnel":"f82","f0":[0.9,0.2,0.05],"f82":0,"multiscatter":true})",
      R"({"type":"phong","kd":[0.5,0.1,0],"ks":[0.5,0.2,0.1],"exponent":2000})",
      R"({"type":"blinnphong","kd":[0,0.3,0.6],"ks":[0.4,0.3,0.4],"exponent":1})",
      R"({"type":"ward","kd":[0.2,0.5,0.1],"ks":[0.1,0.4,0.2],"alpha":[0.01,0.5]})",
      R"({"type":"ashikhminshirley","rd":[0.8,0.2,0.1],"rs":[0.05,0.5,1],"nu":1,"nv":10000})",
      R"({"type":"plastic","reflectance":[0.9,0.1,0.1],"eta":1.5})",
      R"({"type":"plastic","reflectance":[0.1,0.1,0.9],"eta":"BK7","alpha":0.3})",
      R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"dielectric","eta":"SF11"},{"type":"conductor","material":"Au"}]})",
      R"({"type":"sheen","color":[0.9,0.3,0.05],"roughness":0.05})",
      R"({"type":"sheen","color":{"spectrum":[[360,0],[600,1],[830,0.3]]},"roughness":1})",
      R"({"type":"openpbr","base_color":[0.9,0.3,0.05],"coat_weight":1,"coat_color":{"spectrum":[[360,0],[600,1],[830,0.3]]},"fuzz_weight":0.5,"thin_film_weight":1,"geometry_opacity":0.5})",
  };
}

// --- 5. Every type converts; grey parameters give the RGB model at every wavelength -----

TEST(SpectralMaterial, EveryTypeConvertsAndGreyGivesTheRgbModelAtEveryWavelength) {
  for (double g : {0.25, 1.0}) {
    const auto materials = grey_materials(g);
    for (auto name : material_type_names())
      EXPECT_TRUE(materials.count(std::string(name))) << "no test material for type " << name;
    SpectralScratch scratch;
    for (const auto& [name, material_json] : materials) {
      const MaterialWithSpectra m = parse_material_with_spectra(material_json);
      for (double lambda : {360.0, 455.5, 550.0, 700.0, 829.0}) {
        SampledWavelengths w = at(lambda);
        const SpectralBxDF s = spectral(m, w, scratch);
        EXPECT_EQ(s.name(), m.bxdf.name()) << material_json;
        EXPECT_FALSE(w.secondary_terminated()) << material_json << ": a constant index must not terminate";
        for (double to : {0.0, 30.0, 75.0, 89.0, 150.0}) {
          for (double ti : {10.0, 45.0, 85.0, 120.0, 179.0}) {
            const Vec3 wo = dir_deg(to, 20), wi = dir_deg(ti, 200);
            const Color fr = m.bxdf.f(wo, wi);
            const SampledSpectrum fs = s.f(wo, wi);
            for (int j = 0; j < 4; ++j)
              EXPECT_NEAR(fs[j], fr[0], 2e-5 * std::max(1.0, double(fr[0])))
                  << material_json << " λ=" << w[j] << " θo=" << to << " θi=" << ti;
            EXPECT_NEAR(s.pdf(wo, wi), m.bxdf.pdf(wo, wi), 2e-5 * std::max(1.0, double(m.bxdf.pdf(wo, wi)))) << material_json;
          }
          // Sampling with the same random numbers: same direction, same weight per λ.
          for (double u : {0.1, 0.5, 0.93}) {
            const Vec3 wo = dir_deg(to, 20);
            const auto r = m.bxdf.sample(wo, Float(u), Float(0.3), Float(0.7));
            const auto q = s.sample(wo, Float(u), Float(0.3), Float(0.7));
            ASSERT_EQ(bool(r), bool(q)) << material_json;
            if (!r) continue;
            EXPECT_NEAR(q->wi.z, r->wi.z, 1e-5) << material_json;
            for (int j = 0; j < 4; ++j)
              EXPECT_NEAR(q->weight[j], r->weight[0], 2e-5 * std::max(1.0, double(r->weight[0]))) << material_json;
          }
        }
      }
    }
  }
}

// A grey reflectance c upsamples to exactly c at every wavelength (the sigmoid-polynomial
// of a grey is the constant c; Jakob & Hanika 2019 §3).
TEST(SpectralMaterial, GreyReflectanceIsFlat) {
  SpectralScratch scratch;
  for (double c : {0.0, 0.01, 0.18, 0.5, 0.9, 1.0}) {
    const auto m = parse_material_with_spectra(R"({"type":"diffuse","reflectance":)" + std::to_string(c) + "}");
    for (int i = 0; i <= 47; ++i) {
      SampledWavelengths w = at(360 + 10 * i);
      const SampledSpectrum f = spectral(m, w, scratch).f(dir_deg(0, 0), dir_deg(30, 90));
      for (int j = 0; j < 4; ++j) EXPECT_NEAR(f[j] * kPiD, c, 1e-6) << "c=" << c << " λ=" << w[j];
    }
  }
}

// The spectral value of colour parameter given as RGB, read off the spectral model at λ:
// ρ(λ) = π f for a diffuse model, the normal-incidence sample weight for a mirror.
double diffuse_rho(const MaterialWithSpectra& m, double lambda, TexturedColours textured = 0) {
  SpectralScratch scratch;
  SampledWavelengths w = at(lambda);
  return double(spectral(m, w, scratch, textured).f(dir_deg(0, 0), dir_deg(40, 0))[0]) * kPiD;
}

// An RGB reflectance's spectrum, reduced to linear sRGB under D65 by this file's own
// quadrature, is the RGB again (issue 11 item 7: ≤ 2e-3 for reflectances).
TEST(SpectralMaterial, RgbColoursRoundTripThroughTheirSpectrum) {
  const std::vector<std::array<double, 3>> colours = {
      {0.8, 0.3, 0.1}, {0.1, 0.6, 0.9}, {0.05, 0.05, 0.05}, {0.95, 0.9, 0.2}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}};
  for (const auto& c : colours) {
    std::string rgb = "[";  // appended piecewise: `"[" + std::string` trips GCC 12's bug 105651
    rgb += std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "]";
    const auto diffuse = parse_material_with_spectra(R"({"type":"diffuse","reflectance":)" + rgb + "}");
    const auto mirror = parse_material_with_spectra(R"({"type":"mirror","reflectance":)" + rgb + "}");
    const auto on = parse_material_with_spectra(R"({"type":"orennayar","sigma":0,"reflectance":)" + rgb + "}");
    const auto back = srgb_under_d65([&](double l) { return diffuse_rho(diffuse, l); });
    const auto back_mirror = srgb_under_d65([&](double l) {
      SpectralScratch scratch;
      SampledWavelengths w = at(l);
      return double(spectral(mirror, w, scratch).sample(dir_deg(0, 0), 0.5f, 0.5f, 0.5f)->weight[0]);
    });
    const auto back_on = srgb_under_d65([&](double l) { return diffuse_rho(on, l); });
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(back[size_t(k)], c[size_t(k)], 2e-3) << rgb << " channel " << k;
      EXPECT_NEAR(back_mirror[size_t(k)], c[size_t(k)], 2e-3) << rgb << " mirror, channel " << k;
      EXPECT_NEAR(back_on[size_t(k)], c[size_t(k)], 2e-3) << rgb << " orennayar, channel " << k;
    }
    // And through the film's estimator: to_xyz of ρ(λ) D65(λ) over stratified hero
    // wavelengths, then xyz_to_linear_srgb.
    const auto d65 = read_data("cie/cie_illuminant_d65.csv");
    double sum[3] = {0, 0, 0};
    const int n = 2048;
    SpectralScratch scratch;
    for (int i = 0; i < n; ++i) {
      SampledWavelengths w = SampledWavelengths::sample_visible(Float((i + 0.5) / n));
      const SampledSpectrum rho = spectral(diffuse, w, scratch).f(dir_deg(0, 0), dir_deg(40, 0)) * Float(kPiD);
      SampledSpectrum d;
      for (int j = 0; j < 4; ++j) d[j] = Float(lerp_rows(d65, w[j]));
      const Color out = xyz_to_linear_srgb(to_xyz(rho * d, w));
      for (int k = 0; k < 3; ++k) sum[k] += out[k];
    }
    // D65 from the CSV is not normalised to Y = 1: the white (ρ = 1) gives its scale.
    double white = 0;
    for (int i = 0; i < n; ++i) {
      SampledWavelengths w = SampledWavelengths::sample_visible(Float((i + 0.5) / n));
      SampledSpectrum d;
      for (int j = 0; j < 4; ++j) d[j] = Float(lerp_rows(d65, w[j]));
      white += to_xyz(d, w).y;
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(sum[k] / white, c[size_t(k)], 3e-3) << rgb << " via to_xyz, channel " << k;
  }
}

// Every colour parameter of every type given as RGB is its upsampled spectrum: at λ, the
// spectral model equals the RGB model whose parameters are the grey values ρ_A(λ), ρ_B(λ)
// — read off a diffuse model of the same RGB (π f) — in every channel.
TEST(SpectralMaterial, EveryColourParameterIsItsUpsampledSpectrum) {
  const std::string A = "[0.45,0.1,0.05]", B = "[0.1,0.3,0.5]";
  const auto da = parse_material_with_spectra(R"({"type":"diffuse","reflectance":)" + A + "}");
  const auto db = parse_material_with_spectra(R"({"type":"diffuse","reflectance":)" + B + "}");
  // JSON with the colour parameters as @A and @B.
  const std::vector<std::string> templates = {
      R"({"type":"diffuse","reflectance":@A})",
      R"({"type":"mirror","reflectance":@A})",
      R"({"type":"orennayar","reflectance":@A,"sigma":30})",
      R"({"type":"phong","kd":@A,"ks":@B,"exponent":15})",
      R"({"type":"blinnphong","kd":@A,"ks":@B,"exponent":15})",
      R"({"type":"ward","kd":@A,"ks":@B,"alpha":0.3})",
      R"({"type":"ashikhminshirley","rd":@A,"rs":@B,"nu":20,"nv":5})",
      R"({"type":"plastic","reflectance":@A,"eta":1.5,"alpha":0.2})",
      R"({"type":"plastic","reflectance":@B,"eta":1.5})",
      R"({"type":"conductor","fresnel":"schlick","f0":@B})",
      R"({"type":"roughconductor","fresnel":"schlick","f0":@A,"alpha":0.25})",
      R"({"type":"blend","weight":0.4,"bsdfs":[{"type":"diffuse","reflectance":@A},{"type":"phong","kd":0,"ks":@B,"exponent":30}]})",
  };
  auto fill = [](std::string t, const std::string& a, const std::string& b) {
    for (auto [key, v] : {std::pair{std::string("@A"), a}, std::pair{std::string("@B"), b}})
      for (size_t at; (at = t.find(key)) != std::string::npos;) t.replace(at, 2, v);
    return t;
  };
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return std::string(buf);
  };
  SpectralScratch scratch;
  for (const auto& t : templates) {
    const auto m = parse_material_with_spectra(fill(t, A, B));
    for (double lambda : {380.0, 470.0, 530.0, 610.0, 720.0}) {
      const double a = diffuse_rho(da, lambda), b = diffuse_rho(db, lambda);
      const BxDF grey = parse_material(fill(t, num(a), num(b)));
      SampledWavelengths w = at(lambda);
      const SpectralBxDF s = spectral(m, w, scratch);
      for (double to : {0.0, 35.0, 80.0}) {
        for (double ti : {5.0, 35.0, 60.0, 88.0}) {
          const Vec3 wo = dir_deg(to, 0), wi = dir_deg(ti, 160);
          const double e = grey.f(wo, wi)[0];
          EXPECT_NEAR(s.f(wo, wi)[0], e, 1e-4 * std::max(1.0, e)) << t << " λ=" << w[0] << " θo=" << to << " θi=" << ti;
        }
        // A delta-only model has no f: compare its sampled weight. (Other models may choose
        // lobes by the mean over the wavelengths, so their samples legitimately differ.)
        if (!is_delta_only(grey.flags())) continue;
        const auto q = s.sample(dir_deg(to, 0), 0.4f, 0.3f, 0.6f);
        const auto r = grey.sample(dir_deg(to, 0), 0.4f, 0.3f, 0.6f);
        ASSERT_EQ(bool(q), bool(r)) << t;
        if (q) {
          EXPECT_NEAR(q->weight[0], r->weight[0], 1e-4 * std::max(1.0f, r->weight[0])) << t << " λ=" << w[0];
        }
      }
    }
  }
}

// --- 5. Dielectrics: named glass and dispersion -----------------------------------------

TEST(SpectralMaterial, NamedGlassUsesSellmeierAtTheHeroAndTerminatesTheOthers) {
  // BK7's table (data/glasses/BK7.csv, 22 nm rows) interpolated linearly is within
  // h²/8 max|n''| ≈ 9e-5 of the formula over 360–830 nm.
  SpectralScratch scratch;
  for (const char* material_json : {R"({"type":"dielectric","eta":"BK7"})", R"({"type":"roughdielectric","alpha":0.2,"eta":"BK7"})",
                           R"({"type":"dielectric","eta":{"sellmeier":{"B":[1.03961212,0.231792344,1.01046945],"C":[0.00600069867,0.0200179144,103.560653]}}})"}) {
    const auto m = parse_material_with_spectra(material_json);
    for (double lambda : {360.0, 404.7, 486.1, 587.6, 656.3, 706.5, 829.9}) {
      SampledWavelengths w = at(lambda);
      const Float hero_pdf = w.pdf(0);
      const SpectralBxDF s = spectral(m, w, scratch);
      EXPECT_TRUE(w.secondary_terminated()) << material_json;
      EXPECT_FLOAT_EQ(w.pdf(0), hero_pdf / 4) << material_json;
      EXPECT_NEAR(s.relative_eta(), bk7_sellmeier(w[0]), 1.5e-4) << material_json << " λ=" << w[0];
    }
  }
  // A plastic's coat keeps its index at 550 nm (spectral_material.h): no termination.
  {
    const auto m = parse_material_with_spectra(R"({"type":"plastic","reflectance":0.5,"eta":"BK7"})");
    SampledWavelengths w = at(420);
    spectral(m, w, scratch);
    EXPECT_FALSE(w.secondary_terminated());
  }
  // Published: N-BK7 n_d (587.56 nm) = 1.51680 (SCHOTT data sheet).
  EXPECT_NEAR(bk7_sellmeier(587.5618), 1.51680, 1e-5);
  // A constant index: nothing dropped, the same index at every wavelength.
  for (const char* material_json : {R"({"type":"dielectric","eta":1.5})", R"({"type":"roughdielectric","alpha":0.2,"eta":1.33})"}) {
    const auto m = parse_material_with_spectra(material_json);
    SampledWavelengths w = at(420);
    const SampledSpectrum pdf = w.pdf();
    const SpectralBxDF s = spectral(m, w, scratch);
    EXPECT_FALSE(w.secondary_terminated()) << material_json;
    for (int j = 0; j < 4; ++j) EXPECT_EQ(w.pdf(j), pdf[j]) << material_json;
    EXPECT_FLOAT_EQ(s.relative_eta(), m.bxdf.relative_eta()) << material_json;
  }
}

// --- 5. Blends convert both parts ---------------------------------------------------------

TEST(SpectralMaterial, BlendsConvertBothParts) {
  // Two spectrum-given reflectances, piecewise linear: the blend is (1 − w) ρ0/π + w ρ1/π.
  const auto m = parse_material_with_spectra(R"({"type":"blend","weight":0.3,"bsdfs":[
      {"type":"diffuse","reflectance":{"spectrum":[[360,0.1],[830,0.9]]}},
      {"type":"diffuse","reflectance":{"spectrum":[[360,1],[600,0.2],[830,0.5]]}}]})");
  auto rho0 = [](double l) { return 0.1 + 0.8 * (l - 360) / 470; };
  auto rho1 = [](double l) { return l <= 600 ? 1 - 0.8 * (l - 360) / 240 : 0.2 + 0.3 * (l - 600) / 230; };
  SpectralScratch scratch;
  for (double lambda : {360.0, 420.0, 555.5, 600.0, 777.0}) {
    SampledWavelengths w = at(lambda);
    const SampledSpectrum f = spectral(m, w, scratch).f(dir_deg(10, 0), dir_deg(50, 180));
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(f[j] * kPiD, 0.7 * rho0(w[j]) + 0.3 * rho1(w[j]), 1e-5) << "λ=" << w[j];
  }
  // A blend with a dispersive part terminates, and its dielectric part has n(λ_hero).
  const auto d = parse_material_with_spectra(
      R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse","reflectance":0.5},{"type":"dielectric","eta":"BK7"}]})");
  SampledWavelengths w = at(480);
  const SpectralBxDF s = spectral(d, w, scratch);
  EXPECT_TRUE(w.secondary_terminated());
  EXPECT_NEAR(s.relative_eta(), bk7_sellmeier(w[0]), 1.5e-4);
  // A blend of two blends (nested parts use the scratch storage).
  const auto nested = parse_material_with_spectra(R"({"type":"blend","weight":0.5,"bsdfs":[
      {"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse","reflectance":{"spectrum":[[360,0.1],[830,0.9]]}},{"type":"diffuse","reflectance":0}]},
      {"type":"blend","weight":1,"bsdfs":[{"type":"diffuse","reflectance":0},{"type":"diffuse","reflectance":{"spectrum":[[360,1],[600,0.2],[830,0.5]]}}]}]})");
  for (double lambda : {400.0, 650.0}) {
    SampledWavelengths wl = at(lambda);
    const SampledSpectrum f = spectral(nested, wl, scratch).f(dir_deg(10, 0), dir_deg(50, 180));
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(f[j] * kPiD, 0.25 * rho0(wl[j]) + 0.5 * rho1(wl[j]), 1e-5) << "nested, λ=" << wl[j];
  }
}

// --- 5. Textured colours are upsampled from the texture's RGB value -------------------

TEST(SpectralMaterial, TexturedColoursAreUpsampledFromTheirRgbValue) {
  // A material whose reflectance is a spectrum; a texture replaces it by an RGB value.
  const auto m = parse_material_with_spectra(R"({"type":"diffuse","reflectance":{"spectrum":[[360,0.1],[830,0.9]]}})");
  const std::array<ParamValue, 1> grey{ParamValue{MaterialParam::Reflectance, Color(0.37f)}};
  MaterialWithSpectra t{with_params(m.bxdf, grey), m.spectra};
  const TexturedColours bit = TexturedColours(1) << unsigned(MaterialParam::Reflectance);
  for (double lambda : {380.0, 500.0, 700.0}) {
    EXPECT_NEAR(diffuse_rho(t, lambda, bit), 0.37, 1e-6) << "textured grey at " << lambda;
    // Without the bit the material's own spectrum is used.
    EXPECT_NEAR(diffuse_rho(t, lambda, 0), 0.1 + 0.8 * (at(lambda)[0] - 360) / 470, 1e-5) << lambda;
  }
  // A coloured texel: its spectrum reduces to the texel's colour.
  const std::array<ParamValue, 1> colour{ParamValue{MaterialParam::Reflectance, Color(0.7f, 0.2f, 0.4f)}};
  MaterialWithSpectra c{with_params(m.bxdf, colour), m.spectra};
  const auto back = srgb_under_d65([&](double l) { return diffuse_rho(c, l, bit); });
  EXPECT_NEAR(back[0], 0.7, 2e-3);
  EXPECT_NEAR(back[1], 0.2, 2e-3);
  EXPECT_NEAR(back[2], 0.4, 2e-3);
  // A textured conductor index: eta and k linear between (450, b), (550, g), (650, r)
  // (spectral_material.h), so at 500 nm n = (0.5 + 1.4)/2, k = (2.5 + 1.8)/2.
  const auto au = parse_material_with_spectra(R"({"type":"conductor","material":"Au"})");
  const std::array<ParamValue, 2> index{ParamValue{MaterialParam::Eta, Color(0.2f, 0.5f, 1.4f)},
                                        ParamValue{MaterialParam::K, Color(3.0f, 2.5f, 1.8f)}};
  MaterialWithSpectra ti{with_params(au.bxdf, index), au.spectra};
  const TexturedColours bits = (TexturedColours(1) << unsigned(MaterialParam::Eta)) | (TexturedColours(1) << unsigned(MaterialParam::K));
  const std::pair<double, std::pair<double, double>> expected[] = {
      {400, {1.4, 1.8}}, {500, {0.95, 2.15}}, {600, {0.35, 2.75}}, {700, {0.2, 3.0}}};
  SpectralScratch scratch;
  for (const auto& [lambda, nk] : expected) {
    SampledWavelengths w = at(lambda);
    const auto s = spectral(ti, w, scratch, bits).sample(dir_deg(0, 0), 0.5f, 0.5f, 0.5f);
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->weight[0], normal_incidence_reflectance(nk.first, nk.second), 1e-4) << lambda;
  }
}

// --- 4. Gold -------------------------------------------------------------------------------

// Gold's normal-incidence reflectance F0(n(λ), k(λ)) from data/metals/Au.csv, reduced to
// linear sRGB under D65 by this file's quadrature, against gonio's spectral albedo of
// {"type":"conductor","material":"Au"} at wo = N (to_spectral at every quadrature node,
// reduced by the same quadrature), and the RGB mode's albedo within 2 % of it.
TEST(SpectralMaterial, GoldSpectralAlbedoMatchesTheMeasuredSpectrum) {
  const auto nk = read_data("metals/Au.csv");
  const auto au = parse_material_with_spectra(R"({"type":"conductor","material":"Au"})");
  const auto rough = parse_material_with_spectra(R"({"type":"roughconductor","alpha":0.3,"material":"Au"})");
  SpectralScratch scratch;
  double worst = 0;
  auto gonio_albedo = [&](double l) {
    SampledWavelengths w = at(l);
    const auto a = spectral(au, w, scratch).exact_albedo(dir_deg(0, 0), TransportMode::Radiance);
    EXPECT_TRUE(a);
    const double expect = normal_incidence_reflectance(lerp_rows(nk, w[0], 1), lerp_rows(nk, w[0], 2));
    worst = std::max(worst, std::abs(double(a->reflectance[0]) - expect));
    // The sampled reflection at normal incidence carries the same weight.
    const auto s = spectral(au, w, scratch).sample(dir_deg(0, 0), 0.5f, 0.5f, 0.5f);
    EXPECT_TRUE(s && std::abs(double(s->weight[0]) - double(a->reflectance[0])) < 1e-6) << l;
    return double(a->reflectance[0]);
  };
  const auto spectral_rgb = srgb_under_d65(gonio_albedo);
  const auto measured_rgb =
      srgb_under_d65([&](double l) { return normal_incidence_reflectance(lerp_rows(nk, l, 1), lerp_rows(nk, l, 2)); });
  EXPECT_LT(worst, 1e-4) << "gonio's F0(λ) against the CSV interpolated linearly in n and k";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(spectral_rgb[size_t(c)], measured_rgb[size_t(c)], 5e-4) << "channel " << c;
  // Gold's red is outside the sRGB gamut (> 1 before a clamp); RGB mode's F0 is the colour
  // clamped to [0, 1] (docs/spectral.md, "Named metals in RGB mode"), so compare after the same clamp.
  EXPECT_GT(spectral_rgb[0], 1.0);
  const auto rgb = au.bxdf.exact_albedo(dir_deg(0, 0), TransportMode::Radiance);
  ASSERT_TRUE(rgb);
  for (int c = 0; c < 3; ++c) {
    const double target = std::clamp(spectral_rgb[size_t(c)], 0.0, 1.0);
    EXPECT_NEAR(rgb->reflectance[c] / target, 1.0, 0.02) << "channel " << c;
  }
  // The rough conductor uses the same spectra: its f at wo = wi = N is
  // D(N) G F0(λ) / (4 cos θo cos θi) (Walter et al. 2007, eq. 20), so the ratio of two
  // wavelengths is the ratio of their F0.
  for (double l : {450.0, 650.0}) {
    SampledWavelengths w = at(l), w2 = at(550);
    const double a = spectral(rough, w, scratch).f(dir_deg(0, 0), dir_deg(0, 0))[0];
    const double b = spectral(rough, w2, scratch).f(dir_deg(0, 0), dir_deg(0, 0))[0];
    const double ea = normal_incidence_reflectance(lerp_rows(nk, w[0], 1), lerp_rows(nk, w[0], 2));
    const double eb = normal_incidence_reflectance(lerp_rows(nk, w2[0], 1), lerp_rows(nk, w2[0], 2));
    EXPECT_NEAR(a / b, ea / eb, 1e-4) << l;
  }
}

// --- 6. Finite everywhere ------------------------------------------------------------------

TEST(SpectralMaterial, FiniteAtTheEndsOfTheRangeAtGrazingAndBelowTheHorizon) {
  std::vector<std::string> all = coloured_materials();
  for (const auto& [name, material_json] : grey_materials(0.5)) all.push_back(material_json);
  // Directions: normal, grazing (cos θ = 1e-7 and exactly 0), below the horizon, straight
  // down, and a general one.
  const Vec3 dirs[] = {{0, 0, 1}, {0.9999999f, 0, 1e-7f}, {1, 0, 0}, {0, 1, 0}, {0.6f, 0, -0.8f},
                       {0, 0, -1}, {0.5f, 0.5f, 0.70710678f}, {-0.2f, 0.1f, -1e-7f}, dir_deg(89.9, 33)};
  // λ_0 at 360 and ≈ 830 nm (the largest the visible sampler gives), and between.
  std::vector<SampledWavelengths> ws = {SampledWavelengths::sample_uniform(0),
                                        SampledWavelengths::sample_visible(kOneMinusEpsilon),
                                        SampledWavelengths::sample_visible(0), at(555)};
  EXPECT_EQ(ws[0][0], 360.0f);
  EXPECT_NEAR(ws[1][0], 830.0, 0.5);
  SpectralScratch scratch;
  auto finite = [](const SampledSpectrum& s) {
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(s[j]) || s[j] < 0) return false;
    return true;
  };
  for (const auto& material_json : all) {
    const auto m = parse_material_with_spectra(material_json);
    for (const auto& w0 : ws) {
      SampledWavelengths w = w0;
      const SpectralBxDF s = spectral(m, w, scratch);
      for (const Vec3& wo : dirs) {
        for (const Vec3& wi : dirs) {
          for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
            EXPECT_TRUE(finite(s.f(wo, wi, mode))) << material_json << " λ0=" << w[0];
            const Float p = s.pdf(wo, wi, mode);
            EXPECT_TRUE(std::isfinite(p) && p >= 0) << material_json << " λ0=" << w[0];
          }
        }
        for (float ul : {0.0f, 0.3f, 0.7f, kOneMinusEpsilon}) {
          for (float u1 : {0.0f, 0.5f, kOneMinusEpsilon}) {
            const auto smp = s.sample(wo, ul, u1, 0.25f);
            if (!smp) continue;
            EXPECT_TRUE(finite(smp->weight) && std::isfinite(smp->pdf) && smp->pdf >= 0) << material_json << " λ0=" << w[0];
            EXPECT_TRUE(std::isfinite(smp->wi.x) && std::isfinite(smp->wi.y) && std::isfinite(smp->wi.z)) << material_json;
            // A non-delta sample is consistent with pdf() and f() (contract.h): weight =
            // f |cos θi| / pdf, checked where the numbers are well conditioned.
            if (smp->delta || !(smp->pdf > 1e-3f) || std::abs(wo.z) < 1e-3f || std::abs(smp->wi.z) < 1e-3f) continue;
            EXPECT_NEAR(s.pdf(wo, smp->wi), smp->pdf, 1e-3 * smp->pdf) << material_json << " λ0=" << w[0];
            const SampledSpectrum f = s.f(wo, smp->wi);
            for (int j = 0; j < 4; ++j)
              EXPECT_NEAR(smp->weight[j], f[j] * std::abs(smp->wi.z) / smp->pdf, 1e-3 * std::max(1.0f, smp->weight[j]))
                  << material_json << " λ=" << w[j];
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace gonio
