#pragma once
// The adversarial sweep (docs/robustness.md): every model type at extreme parameters,
// evaluated and sampled at extreme directions in both transport modes. Shared by the
// tool gonio_adversarial (≥ 10⁸ calls) and the unit test AdversarialSweep (a reduced run).
//
// What counts as a failure, per call:
//   value     f, pdf, a sample's weight or pdf is NaN, ±Inf or negative; a sampled wi is
//             not finite or not unit length (|‖wi‖ − 1| > 1e-5)
//   agree     a non-delta sample disagrees with eval at its own direction: f(wo, wi) = 0
//             or pdf(wo, wi) = 0 while the sample carries weight, or pdf(wo, wi) differs
//             from the sample's pdf by more than 1e-3 relative
//   weight    a sample weight above 10 × the model's albedo bound (1 for reflection; the
//             radiance scaling 1/η² of a refraction included): the variance disasters of
//             issue 9 (Ward at grazing, weights of 1e16). Radiance mode only for a model
//             that is not reciprocal (its adjoint's albedo is not bounded by 1).
// Directions: |cos θ| log-uniform in [1e-45, 1e-2], ±0, denormals, exactly ±1, ordinary
// values; φ random or on an axis; wi independent, = wo, = −wo, or wo's mirror image;
// lengths off by up to ±4 ulp (unit within float rounding, as the contract allows).
// Random numbers u: 0, 1 − ulp, 1/2, or uniform.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "gonio/material.h"
#include "gonio/rng.h"

namespace gonio::adversarial {

// Materials at extreme parameters: roughness at and around the smooth threshold 1e-3,
// anisotropy 1e-4 against 1, indices 1, 1 + 1e-6, 1e-4, 1e4, exponents 0 and 1e6,
// kd + ks = 1, reflectances 0 and 1.
inline std::vector<std::string> extreme_materials() {
  std::vector<std::string> v = {
      R"({"type":"diffuse","reflectance":0})",
      R"({"type":"diffuse","reflectance":1})",
      R"({"type":"diffuse","reflectance":[0,0.5,1]})",
      R"({"type":"mirror","reflectance":0})",
      R"({"type":"mirror","reflectance":1})",
      R"({"type":"conductor","material":"Au"})",
      R"({"type":"conductor","eta":0.0001,"k":0})",
      R"({"type":"conductor","eta":10000,"k":10000})",
      R"({"type":"conductor","eta":1,"k":0})",
      R"({"type":"conductor","fresnel":"schlick","f0":0})",
      R"({"type":"conductor","fresnel":"schlick","f0":1})",
      R"({"type":"orennayar","reflectance":1,"sigma":0})",
      R"({"type":"orennayar","reflectance":1,"sigma":89.99})",
      R"({"type":"orennayar","reflectance":1,"sigma":30,"model":"full"})",
      R"({"type":"orennayar","reflectance":1,"sigma":89.99,"model":"full"})",
      R"({"type":"sheen","roughness":1e-30})",
      R"({"type":"sheen","roughness":0.00999})",
      R"({"type":"sheen","roughness":0.05})",
      R"({"type":"sheen","color":[0,0.5,1],"roughness":1})",
      R"({"type":"eon","reflectance":1,"roughness":0})",
      R"({"type":"eon","reflectance":1,"roughness":1e-7})",
      R"({"type":"eon","reflectance":1,"roughness":1})",
      R"({"type":"eon","reflectance":0,"roughness":1})",
      R"({"type":"eon","reflectance":[1,0.5,0],"roughness":0.5})",
      // openpbr (issue 35): every parameter group at its extremes.
      R"({"type":"openpbr"})",
      R"({"type":"openpbr","base_color":1,"base_diffuse_roughness":1,"specular_roughness":0,"specular_ior":3,"specular_weight":2})",
      R"({"type":"openpbr","specular_ior":0.0001,"specular_roughness":1,"specular_roughness_anisotropy":1,"specular_rotation":0.3})",
      R"({"type":"openpbr","specular_ior":1,"base_diffuse_roughness":1,"base_color":0})",
      R"({"type":"openpbr","base_metalness":1,"base_color":1,"specular_color":0,"specular_roughness":0.0001})",
      R"({"type":"openpbr","coat_weight":1,"coat_roughness":1,"coat_roughness_anisotropy":1,"coat_color":0,"coat_ior":10000,"coat_darkening":1})",
      R"({"type":"openpbr","coat_weight":1,"coat_roughness":0,"coat_ior":0.0001,"fuzz_weight":1,"fuzz_roughness":0,"fuzz_color":1})",
      R"({"type":"openpbr","transmission_weight":1,"specular_roughness":1,"specular_ior":10000,"transmission_color":0})",
      R"({"type":"openpbr","transmission_weight":1,"specular_roughness":0.001,"specular_ior":0.0001,"coat_weight":1})",
      R"({"type":"openpbr","geometry_thin_walled":true,"transmission_weight":0.5,"subsurface_weight":1,"subsurface_scatter_anisotropy":-1,"thin_film_weight":1,"thin_film_thickness":10,"thin_film_ior":10000})",
      R"({"type":"openpbr","geometry_opacity":0,"fuzz_weight":1})",
      R"({"type":"openpbr","geometry_opacity":0.0001,"base_metalness":0.5,"transmission_weight":0.5,"subsurface_weight":0.5,"coat_weight":0.5,"fuzz_weight":0.5})",
      R"({"type":"conductor","fresnel":"f82","f0":0,"f82":0})",
      R"({"type":"conductor","fresnel":"f82","f0":1,"f82":1})",
      R"({"type":"conductor","fresnel":"f82","f0":[1,0.5,0],"f82":[0,0.5,1]})",
      R"({"type":"blend","weight":0,"bsdfs":[{"type":"diffuse"},{"type":"mirror"}]})",
      R"({"type":"blend","weight":1,"bsdfs":[{"type":"diffuse"},{"type":"mirror"}]})",
      R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"dielectric","eta":1.5},{"type":"roughdielectric","alpha":0.3,"eta":1.5}]})",
      R"({"type":"blend","weight":0.3,"bsdfs":[{"type":"ward","kd":0,"ks":1,"alpha":0.0001},{"type":"phong","kd":0,"ks":1,"exponent":1000000}]})",
      R"({"type":"layered","top":{"type":"dielectric","eta":10000},"bottom":{"type":"diffuse","reflectance":1},"thickness":0})",
      R"({"type":"layered","top":{"type":"roughdielectric","alpha":0.001,"eta":0.0001},"bottom":{"type":"mirror"},"thickness":10000,"albedo":1,"g":0.9,"max_depth":1})",
      R"({"type":"layered","top":{"type":"roughdielectric","alpha":10,"eta":1},"bottom":{"type":"conductor","eta":10000,"k":10000},"thickness":0.01,"albedo":0,"g":-0.5})",
      R"({"type":"layered","top":{"type":"thindielectric","eta":0.0001},"bottom":{"type":"diffuse","reflectance":1},"thickness":10000,"albedo":1,"g":-0.9})",
      R"({"type":"layered","top":{"type":"thindielectric","eta":10000,"thin_film":{"thickness":10000,"eta":10000}},"bottom":{"type":"mirror"},"thickness":0.001,"albedo":0.5})",
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5,"thin_film":{"thickness":300,"eta":1.38}},"bottom":{"type":"eon","reflectance":0.5},"thickness":0})",
      // Transmitting bottoms: a slab with a medium, extreme indices and roughness, two sheets.
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"dielectric","eta":1.2},"thickness":0.2,"albedo":0.5})",
      R"({"type":"layered","top":{"type":"dielectric","eta":10000},"bottom":{"type":"roughdielectric","alpha":1,"eta":0.0001},"thickness":0})",
      R"({"type":"layered","top":{"type":"thindielectric","eta":1.5},"bottom":{"type":"thindielectric","eta":10000},"thickness":10000,"albedo":0.5,"g":0.9})",
  };
  for (const char* eta : {"1", "1.000001", "0.0001", "10000", "1.5", "0.6667"}) {
    v.push_back(std::string(R"({"type":"dielectric","eta":)") + eta + "}");
    v.push_back(std::string(R"({"type":"thindielectric","eta":)") + eta + "}");
    // A film is refused on eta < 0.1 (material.cpp, make_dielectric_film).
    for (const char* film : {R"({"thickness":0,"eta":1.38})", R"({"thickness":10000,"eta":10000})", R"({"thickness":350,"eta":1})"}) {
      if (std::string_view(eta) == "0.0001") break;
      v.push_back(std::string(R"({"type":"dielectric","eta":)") + eta + R"(,"thin_film":)" + film + "}");
      v.push_back(std::string(R"({"type":"roughdielectric","alpha":0.3,"eta":)") + eta + R"(,"thin_film":)" + film + "}");
    }
    for (const char* alpha : {"0.0001", "0.000999", "0.001", "0.00101", "0.3", "1", "10"})
      for (const char* dist : {"ggx", "beckmann"})
        v.push_back(std::string(R"({"type":"roughdielectric","distribution":")") + dist + R"(","eta":)" + eta +
                    R"(,"alpha":)" + alpha + "}");
    // Compensation is refused outside its tables' index range [0.25, 4].
    if (std::string_view(eta) != "0.0001" && std::string_view(eta) != "10000")
      v.push_back(std::string(R"({"type":"roughdielectric","multiscatter":true,"eta":)") + eta + R"(,"alpha":0.5})");
  }
  for (const char* alpha : {"0.0001", "0.000999", "0.001", "0.00101", "0.3", "1", "10", "[0.0001,1]", "[1,0.0001]"})
    for (const char* dist : {"ggx", "beckmann"}) {
      v.push_back(std::string(R"({"type":"roughconductor","material":"Cu","distribution":")") + dist +
                  R"(","alpha":)" + alpha + "}");
      if (alpha[0] != '[') {  // compensation is refused for anisotropic alpha
        v.push_back(std::string(R"({"type":"roughconductor","fresnel":"schlick","f0":1,"multiscatter":true,"distribution":")") +
                    dist + R"(","alpha":)" + alpha + "}");
        v.push_back(std::string(R"({"type":"roughconductor","fresnel":"f82","f0":[1,0.5,0],"f82":[0,0.5,1],"multiscatter":true,"distribution":")") +
                    dist + R"(","alpha":)" + alpha + "}");
      }
    }
  for (const char* eta : {"1", "1.000001", "1.5", "10000"}) {
    v.push_back(std::string(R"({"type":"plastic","reflectance":1,"eta":)") + eta + "}");
    for (const char* alpha : {"0.0001", "0.001", "0.2", "1"})
      v.push_back(std::string(R"({"type":"plastic","reflectance":1,"eta":)") + eta + R"(,"alpha":)" + alpha + "}");
  }
  for (const char* type : {"phong", "blinnphong"})
    for (const char* kdks : {R"("kd":0,"ks":1)", R"("kd":1,"ks":0)", R"("kd":0.5,"ks":0.5)", R"("kd":0,"ks":0)"})
      for (const char* n : {"0", "1", "1000", "1000000"})
        v.push_back(std::string(R"({"type":")") + type + R"(",)" + kdks + R"(,"exponent":)" + n + "}");
  for (const char* kdks : {R"("kd":0,"ks":1)", R"("kd":0.5,"ks":0.5)", R"("kd":1,"ks":0)"})
    for (const char* alpha : {"0.0001", "0.001", "0.2", "1", "[0.0001,1]", "[1,0.0001]", "1e-30"})
      v.push_back(std::string(R"({"type":"ward",)") + kdks + R"(,"alpha":)" + alpha + "}");
  for (const char* rdrs : {R"("rd":0,"rs":1)", R"("rd":1,"rs":0)", R"("rd":1,"rs":1)"})
    for (const char* nunv : {R"("nu":1e-6,"nv":1e-6)", R"("nu":1,"nv":1)", R"("nu":1000000,"nv":1000000)",
                             R"("nu":1e-6,"nv":1000000)", R"("nu":1000000,"nv":1e-6)"})
      v.push_back(std::string(R"({"type":"ashikhminshirley",)") + rdrs + "," + nunv + "}");
  return v;
}

struct Tally {
  std::uint64_t calls = 0;
  std::uint64_t value = 0, agree = 0, weight = 0;
  double max_weight = 0;
  std::string first_failure;  // the first failing call, for the report
  std::uint64_t failures() const { return value + agree + weight; }
};

namespace detail {

inline Float log_uniform_cos(Pcg32& rng) {
  // |cos θ| = 10^x, x uniform in [−45, −2]; below 1.4e-45 a float is 0.
  return Float(std::pow(10.0, -45 + 43 * rng.next_double()));
}

inline Float special_cos(Pcg32& rng) {
  static constexpr Float kSpecial[] = {0.f, 1.f, 0x1p-149f, 0x1p-140f, 0x1p-127f, 0x1p-126f, 1e-38f, 1e-30f, 1e-22f,
                                       1e-20f, 1e-19f, 1e-12f, 9.99e-8f, 1e-7f, 1.0001e-7f, 1e-6f, 1e-4f,
                                       0x1.fffffep-1f, 0.5f};
  return kSpecial[rng.next_u32() % (sizeof kSpecial / sizeof kSpecial[0])];
}

// A direction with the given |cos θ|: sin θ from double so that cos θ ≈ 1 keeps its digits.
inline Vec3 direction(Pcg32& rng, Float c) {
  const double s = std::sqrt(std::max(0.0, 1 - double(c) * c));
  double ph;
  switch (rng.next_u32() % 4) {
    case 0: ph = 0; break;
    case 1: ph = 0.5 * 3.14159265358979323846; break;
    default: ph = 2 * 3.14159265358979323846 * rng.next_double();
  }
  Vec3 w{Float(s * std::cos(ph)), Float(s * std::sin(ph)), c};
  if (rng.next_u32() & 1) w.z = -w.z;  // also turns +0 into −0
  if (rng.next_u32() % 4 == 0) {       // off unit length by up to ±4 ulp
    const int k = int(rng.next_u32() % 9) - 4;
    const Float scale = 1 + Float(k) * std::numeric_limits<Float>::epsilon();
    w = Vec3{w.x * scale, w.y * scale, w.z * scale};
  }
  return w;
}

inline Vec3 random_direction(Pcg32& rng) {
  switch (rng.next_u32() % 4) {
    case 0: return direction(rng, log_uniform_cos(rng));
    case 1: return direction(rng, special_cos(rng));
    default: return direction(rng, rng.next_float());
  }
}

inline Float random_u(Pcg32& rng) {
  switch (rng.next_u32() % 5) {
    case 0: return 0;
    case 1: return kOneMinusEpsilon;
    case 2: return 0.5f;
    default: return rng.next_float();
  }
}

inline bool good(double v) { return std::isfinite(v) && v >= 0; }
inline bool good(const Color& c) {
  for (int i = 0; i < Color::size(); ++i)
    if (!good(c[i])) return false;
  return true;
}
inline double max_channel(const Color& c) {
  double m = 0;
  for (int i = 0; i < Color::size(); ++i) m = std::max(m, double(c[i]));
  return m;
}

inline std::string describe(const char* what, const Vec3& wo, const Vec3& wi, Float u0, Float u1, Float u2,
                            TransportMode mode, double value) {
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s = %.9g at wo (%.9g %.9g %.9g) wi (%.9g %.9g %.9g) u (%.9g %.9g %.9g) %s", what,
                value, wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, u0, u1, u2,
                mode == TransportMode::Radiance ? "radiance" : "importance");
  return buf;
}

}  // namespace detail

// `pairs` (wo, wi, u) draws, each in both transport modes: 10 calls per draw.
inline Tally sweep(const BxDF& m, std::uint64_t pairs, std::uint64_t seed) {
  using namespace detail;
  Tally t;
  Pcg32 rng(seed, 0x5eed);
  auto note = [&](std::uint64_t& counter, const std::string& what) {
    if (counter++ == 0 && t.first_failure.empty()) t.first_failure = what;
  };
  for (std::uint64_t n = 0; n < pairs; ++n) {
    const Vec3 wo = random_direction(rng);
    Vec3 wi;
    switch (rng.next_u32() % 6) {
      case 0: wi = wo; break;
      case 1: wi = Vec3{-wo.x, -wo.y, -wo.z}; break;
      case 2: wi = Vec3{-wo.x, -wo.y, wo.z}; break;
      default: wi = random_direction(rng);
    }
    const Float u0 = random_u(rng), u1 = random_u(rng), u2 = random_u(rng);
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      const Color f = m.f(wo, wi, mode);
      const Float pdf = m.pdf(wo, wi, mode);
      t.calls += 2;
      if (!good(f)) note(t.value, describe("f", wo, wi, u0, u1, u2, mode, f[0] + f[1] + f[2]));
      if (!good(pdf)) note(t.value, describe("pdf", wo, wi, u0, u1, u2, mode, pdf));
      const auto s = m.sample(wo, u0, u1, u2, mode);
      ++t.calls;
      if (!s) continue;
      const double len = std::sqrt(double(s->wi.x) * s->wi.x + double(s->wi.y) * s->wi.y + double(s->wi.z) * s->wi.z);
      if (!good(s->weight)) note(t.value, describe("sample weight", wo, s->wi, u0, u1, u2, mode, s->weight[0]));
      if (!good(s->pdf)) note(t.value, describe("sample pdf", wo, s->wi, u0, u1, u2, mode, s->pdf));
      if (!(std::abs(len - 1) <= 1e-5)) note(t.value, describe("sample |wi|", wo, s->wi, u0, u1, u2, mode, len));
      const double w = max_channel(s->weight);
      if (std::isfinite(w)) t.max_weight = std::max(t.max_weight, w);
      const double scale = mode == TransportMode::Radiance && s->lobe == Lobe::Transmission && s->eta > 0
                               ? std::max(1.0, 1 / (double(s->eta) * s->eta))
                               : 1.0;
      // A non-reciprocal model's importance mode (its adjoint) has no albedo bound of 1:
      // the LTC sheen's reaches 4.4 for light at grazing incidence (docs/testing.md), and
      // its weights are held to `value` and `agree` only.
      const bool bounded = mode == TransportMode::Radiance || m.nonreciprocal_reason().empty();
      if (bounded && w > 10 * scale) note(t.weight, describe("sample weight", wo, s->wi, u0, u1, u2, mode, w));
      if (s->delta) continue;
      const Color fs = m.f(wo, s->wi, mode);
      const Float ps = m.pdf(wo, s->wi, mode);
      t.calls += 2;
      if (!good(fs)) note(t.value, describe("f(sampled)", wo, s->wi, u0, u1, u2, mode, fs[0]));
      if (!good(ps)) note(t.value, describe("pdf(sampled)", wo, s->wi, u0, u1, u2, mode, ps));
      if (w > 0 && !(max_channel(fs) > 0))
        note(t.agree, describe("f(sampled wi) = 0 for weight", wo, s->wi, u0, u1, u2, mode, w));
      else if (!(ps > 0) || !(std::abs(ps - s->pdf) <= 1e-3 * std::max(ps, s->pdf)))
        note(t.agree, describe("pdf(sampled wi) vs sample pdf", wo, s->wi, u0, u1, u2, mode, double(ps) - s->pdf));
    }
  }
  return t;
}

}  // namespace gonio::adversarial
