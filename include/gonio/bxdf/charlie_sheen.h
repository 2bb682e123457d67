#pragma once
// The "Charlie" sheen of Estevez & Kulla (Production Friendly Microfacet Sheen BRDF,
// SIGGRAPH 2017; Conty & Kulla 2017), MaterialX's sheen_bsdf in mode "conty_kulla"
// (MaterialX PBR spec, "Conty-Kulla Sheen Equations"; genglsl
// mx_imageworks_sheen_brdf):
//   D(θh) = (2 + 1/r) sin(θh)^(1/r) / (2π),     f = c D / (4 (μi + μo − μi μo)),
// r floored at 0.005 as MaterialX does; no Fresnel, no masking (the "smoother
// denominator" replaces both). D is normalised (∫ D cos θh dω = 1). f is symmetric in
// its two directions, so the lobe is reciprocal; it is two-sided (mirrored below).
// Sampling: an even mixture of uniform and cosine-weighted hemisphere sampling, whose
// pdf is bounded below by 1/(4π), so a weight is at most π c D_max = c (2 + 1/r)/2.

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/charlie_distribution.h"
#include "gonio/bxdf/contract.h"
#include "gonio/math/constants.h"
#include "gonio/math/warp.h"

namespace gonio {

template <typename C>
struct CharlieSheenBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "charlie_sheen";
  C color{1};
  Float roughness = 0.3f;

  static constexpr BxDFFlags flags() { return BxDFFlags::GlossyReflection; }

  // D(θh) from cos θh.
  Float d(Float cos_h) const { return charlie_d(cos_h, std::max(roughness, Float(0.005))); }
  C f(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return C(0);
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Vec3 h = wo + wi;
    const Float len = std::sqrt(dot(h, h));
    if (!(len > 0)) return C(0);
    const Float mi = std::min(wi.z, Float(1)), mo = std::min(wo.z, Float(1));
    return color * (d(h.z / len) / (4 * (mi + mo - mi * mo)));
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return 0;
    return Float(0.5) * (kInvPi * Float(0.5) + std::abs(wi.z) * kInvPi);
  }
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return {f(wo, wi, mode), pdf(wo, wi, mode)};
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    Vec3 wi;
    if (u_lobe < Float(0.5)) {
      const Float z = u1, s = std::sqrt(std::max(Float(0), 1 - z * z)), phi = 2 * kPi * u2;
      wi = Vec3(s * std::cos(phi), s * std::sin(phi), z);
    } else {
      wi = square_to_cosine_hemisphere(u1, u2);
    }
    if (!(wi.z > 0)) return std::nullopt;
    if (wo.z < 0) wi.z = -wi.z;
    const BSDFEvalT<C> e = eval(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    BSDFSampleT<C> s;
    s.wi = wi;
    s.pdf = e.pdf;
    s.weight = e.f * (std::abs(wi.z) / e.pdf);
    return s;
  }
};
using CharlieSheenBxDF = CharlieSheenBxDFT<Color>;

}  // namespace gonio
