#pragma once
// Blinn–Phong with the normalisation SPEC §2 fixes:
//   f = kd/π + ks N(n) cosⁿ θh,  N(n) = (n + 2)(n + 4) / (8π (2^(−n/2) + n)),
// θh the angle of the half vector (Blinn 1977). This N is the exact normalisation of the
// lobe's albedo at normal incidence, so that the albedo never exceeds ks (derivation by
// integrating cosⁿ θh cos θi over the hemisphere; e.g. Giesen 2009). The lobe is
// sampled through the half vector, density (n + 1)/(2π) cosⁿ θh / (4 wo·h).

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/diffuse_glossy.h"
#include "gonio/fresnel.h"

namespace gonio {

struct BlinnPhongBxDF : diffuse_glossy::Model<BlinnPhongBxDF> {
  static constexpr std::string_view kName = "blinnphong";
  Color kd{0.5f}, ks{0.2f};
  Float exponent = 20;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }

  Float normalization() const {
    return (exponent + 2) * (exponent + 4) / (8 * kPi * (std::exp2(-exponent / 2) + exponent));
  }
  Color f_upper(const Vec3& wo, const Vec3& wi) const {
    const Vec3 h = normalize(wo + wi);
    return kd * kInvPi + ks * (normalization() * std::pow(std::max(Float(0), h.z), exponent));
  }
  Vec3 sample_lobe(const Vec3& wo, Float u1, Float u2) const {
    // cos = u^(1/(n+1)); sin² = 1 − u^(2/(n+1)) through expm1, exact for narrow lobes.
    const Float lu = std::log(std::max(u1, Float(1e-30)));
    const Float c = std::exp(lu / (exponent + 1));
    const Float s = std::sqrt(std::max(Float(0), -std::expm1(2 * lu / (exponent + 1))));
    const Float ph = 2 * kPi * u2;
    return reflect(wo, Vec3{s * std::cos(ph), s * std::sin(ph), c});
  }
  Float lobe_pdf(const Vec3& wo, const Vec3& wi) const {
    const Vec3 h = normalize(wo + wi);
    const Float oh = dot(wo, h);
    if (!(oh > 0) || !(h.z > 0)) return 0;
    return (exponent + 1) * kInv2Pi * std::pow(h.z, exponent) / (4 * oh);
  }
  Float diffuse_probability() const { return diffuse_glossy::diffuse_share(kd, ks); }

};

}  // namespace gonio
