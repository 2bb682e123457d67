#pragma once
// Energy-conserving modified Phong (Lafortune & Willems 1994, "Using the Modified Phong
// Reflectance Model for Physically Based Rendering"):
//   f = kd/π + ks (n + 2)/(2π) cosⁿ α,  α the angle between wi and the mirror direction
// of wo. Reciprocal; albedo ≤ kd + ks ≤ 1. The glossy lobe is sampled around the mirror
// direction with density (n + 1)/(2π) cosⁿ α (their §4).

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/diffuse_glossy.h"
#include "gonio/math/frame.h"

namespace gonio {

template <typename C>
struct PhongBxDFT : diffuse_glossy::Model<PhongBxDFT<C>, C> {
  using color_type = C;
  static constexpr std::string_view kName = "phong";
  C kd{0.5f}, ks{0.2f};
  Float exponent = 20;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }

  Float cos_alpha(const Vec3& wo, const Vec3& wi) const {
    return std::max(Float(0), -wo.x * wi.x - wo.y * wi.y + wo.z * wi.z);  // wi · mirror(wo)
  }
  C f_upper(const Vec3& wo, const Vec3& wi) const {
    const Float lobe = (exponent + 2) * kInv2Pi * std::pow(cos_alpha(wo, wi), exponent);
    return kd * kInvPi + ks * lobe;
  }
  Vec3 sample_lobe(const Vec3& wo, Float u1, Float u2) const {
    // cos = u^(1/(n+1)); sin² = 1 − u^(2/(n+1)) through expm1, exact for narrow lobes.
    const Float lu = std::log(std::max(u1, Float(1e-30)));
    const Float c = std::exp(lu / (exponent + 1));
    const Float s = std::sqrt(std::max(Float(0), -std::expm1(2 * lu / (exponent + 1))));
    const Float ph = 2 * kPi * u2;
    const Frame fr = Frame::from_normal(Vec3{-wo.x, -wo.y, wo.z});
    return fr.to_world({s * std::cos(ph), s * std::sin(ph), c});
  }
  Float lobe_pdf(const Vec3& wo, const Vec3& wi) const {
    return (exponent + 1) * kInv2Pi * std::pow(cos_alpha(wo, wi), exponent);
  }
  Float diffuse_probability() const { return diffuse_glossy::diffuse_share(kd, ks); }

};

using PhongBxDF = PhongBxDFT<Color>;

}  // namespace gonio
