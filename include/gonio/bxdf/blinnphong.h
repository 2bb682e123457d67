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

template <typename C>
struct BlinnPhongBxDFT : diffuse_glossy::Model<BlinnPhongBxDFT<C>, C> {
  using color_type = C;
  static constexpr std::string_view kName = "blinnphong";
  C kd{0.5f}, ks{0.2f};
  Float exponent = 20;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }

  Float normalization() const {
    return (exponent + 2) * (exponent + 4) / (8 * kPi * (std::exp2(-exponent / 2) + exponent));
  }
  C f_upper(const Vec3& wo, const Vec3& wi) const {
    const Vec3 h = wo + wi;
    const Float cos_h = std::max(Float(0), h.z / length(h));
    return kd * kInvPi + ks * (normalization() * std::pow(cos_h, exponent));
  }
  Vec3 sample_lobe(const Vec3& wo, Float u1, Float u2) const {
    // cos = u^(1/(n+1)); sin² = 1 − u^(2/(n+1)) through expm1, exact for narrow lobes.
    const Float lu = std::log(std::max(u1, Float(1e-30)));
    const Float c = std::exp(lu / (exponent + 1));
    const Float s = std::sqrt(std::max(Float(0), -std::expm1(2 * lu / (exponent + 1))));
    const Float ph = 2 * kPi * u2;
    return reflect(wo, Vec3{s * std::cos(ph), s * std::sin(ph), c});
  }
  // wo·ĥ is written |h|/2 (exact for unit wo, wi: h = wo + wi = 2 (wo·ĥ) ĥ), not
  // dot(wo, ĥ): where wo + wi loses digits (grazing, wi ≈ mirror of wo) the two disagree
  // and weights reached 6e4 for n = 1e6 (issue 9).
  Float lobe_pdf(const Vec3& wo, const Vec3& wi) const {
    const Vec3 h = wo + wi;
    const Float len = length(h);
    if (!(h.z > 0) || !(len > 0)) return 0;
    return (exponent + 1) * kInv2Pi * std::pow(h.z / len, exponent) / (2 * len);
  }
  Float diffuse_probability() const { return diffuse_glossy::diffuse_share(kd, ks); }

};

using BlinnPhongBxDF = BlinnPhongBxDFT<Color>;

}  // namespace gonio
