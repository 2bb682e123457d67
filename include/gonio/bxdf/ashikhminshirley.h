#pragma once
// Anisotropic Phong BRDF of Ashikhmin & Shirley 2000, "An Anisotropic Phong BRDF Model":
//   specular (eq. 4): ρs = sqrt((nu+1)(nv+1))/(8π) · (n·h)^((nu hx² + nv hy²)/(1 − hz²))
//                          / ((h·k) max(cos θi, cos θo)) · F(h·k),  F Schlick with Rs
//   diffuse (eq. 5):  ρd = 28 Rd/(23π) (1 − Rs) (1 − (1 − cos θi/2)⁵)(1 − (1 − cos θo/2)⁵)
// with k = wo (h·wo = h·wi). Reciprocal. The half vector is sampled by their eq. 9,
// density sqrt((nu+1)(nv+1))/(2π) (n·h)^(nu cos²φ + nv sin²φ), then reflected
// (pdf(wi) = p(h)/(4 k·h)); the diffuse term cosine-weighted.
//
// Numerics (issue 9): h·k is written |wo + wi|/2 (exact for unit vectors, h = wo + wi
// normalised) in f and pdf alike, so their ratio survives the digits wo + wi loses at
// grazing. The lobe is chosen with probability at least 1/5 (diffuse_probability): its
// Schlick factor reaches 1 at grazing even when Rs = 0, and a lobe never sampled gave
// weights of 3e4.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/diffuse_glossy.h"
#include "gonio/fresnel.h"

namespace gonio {

template <typename C>
struct AshikhminShirleyBxDFT : diffuse_glossy::Model<AshikhminShirleyBxDFT<C>, C> {
  using color_type = C;
  static constexpr std::string_view kName = "ashikhminshirley";
  C rd{0.5f}, rs{0.05f};
  Float nu = 100, nv = 100;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection | BxDFFlags::GlossyReflection; }
  bool is_isotropic() const { return nu == nv; }

  // Exponent of n·h for a unit half vector: nu cos²φh + nv sin²φh.
  Float exponent(const Vec3& h) const {
    const Float t = h.x * h.x + h.y * h.y;
    return t > 0 ? (nu * h.x * h.x + nv * h.y * h.y) / t : (nu + nv) / 2;
  }
  C f_upper(const Vec3& wo, const Vec3& wi) const {
    const Vec3 sum = wo + wi;
    const Float len = length(sum);
    const Vec3 h = sum / len;
    // h·wo = h·wi = |wo + wi|/2: symmetric in wi and wo, and the same value as in pdf.
    const Float hk = len / 2;
    const Float a = 1 - wi.z / 2, b = 1 - wo.z / 2;
    const Float a5 = a * a * a * a * a, b5 = b * b * b * b * b;
    C value = rd * (Float(28) / (23 * kPi)) * (C(1.f) - rs) * ((1 - a5) * (1 - b5));
    if (len > 0 && h.z > 0) {
      const C F = fresnel_schlick(rs, hk);  // their eq. 5, Schlick's F at h·k
      const Float lobe = std::sqrt((nu + 1) * (nv + 1)) / (8 * kPi) * std::pow(h.z, exponent(h)) /
                         (hk * std::max(wi.z, wo.z));
      value += F * lobe;
    }
    return value;
  }
  Vec3 sample_lobe(const Vec3& wo, Float u1, Float u2) const {
    // Eq. 9: φ = atan(sqrt((nu+1)/(nv+1)) tan(π u/2)) in the first quadrant, mapped to
    // the four quadrants by 4 u1; cos θh = (1 − u2)^(1/(nu cos²φ + nv sin²φ + 1)).
    const Float q = 4 * u1;
    const int quadrant = std::min(3, int(q));
    const Float u = q - Float(quadrant);
    Float ph = std::atan(std::sqrt((nu + 1) / (nv + 1)) * std::tan(kPiOver2 * u));
    if (quadrant == 1) ph = kPi - ph;
    else if (quadrant == 2) ph = kPi + ph;
    else if (quadrant == 3) ph = 2 * kPi - ph;
    const Float cp = std::cos(ph), sp = std::sin(ph);
    // sin² = 1 − c² through expm1, exact for narrow lobes.
    const Float lu = std::log(std::max(1 - u2, Float(1e-30))) / (nu * cp * cp + nv * sp * sp + 1);
    const Float c = std::exp(lu);
    const Float s = std::sqrt(std::max(Float(0), -std::expm1(2 * lu)));
    return reflect(wo, Vec3{s * cp, s * sp, c});
  }
  Float lobe_pdf(const Vec3& wo, const Vec3& wi) const {
    const Vec3 sum = wo + wi;
    const Float len = length(sum);
    if (!(len > 0) || !(sum.z > 0)) return 0;
    const Vec3 h = sum / len;
    return std::sqrt((nu + 1) * (nv + 1)) * kInv2Pi * std::pow(h.z, exponent(h)) / (2 * len);
  }
  // The diffuse term's share by its reflectance Rd (1 − Rs) against Rs, the lobe's
  // share kept at least 1/5 (see the note at the top).
  Float diffuse_probability() const {
    return std::min(Float(0.8), diffuse_glossy::diffuse_share(rd * (C(1.f) - rs), rs));
  }

};

using AshikhminShirleyBxDF = AshikhminShirleyBxDFT<Color>;

}  // namespace gonio
