#pragma once
// Ideal diffuse (Lambertian) reflection, lecture §5.1: f = ρ/π, so that ρ_dh = ρ (eq. 19).

#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/math/select.h"
#include "gonio/math/warp.h"

namespace gonio {

template <typename C>
struct DiffuseBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "diffuse";
  C reflectance{0.5f};

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  // Branch-free: which side wi lies on is data, and a mispredicted branch costs more
  // than the model (docs/benchmarks.md).
  C f(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return reflectance * keep_if(wo.z * wi.z > 0, kInvPi);
  }

  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return keep_if(wo.z * wi.z > 0, std::abs(wi.z) * kInvPi);
  }

  // Cosine-weighted hemisphere on wo's side; weight = (ρ/π) cos θ / (cos θ/π) = ρ.
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float /*u_lobe*/, Float u1, Float u2,
                                   TransportMode = TransportMode::Radiance) const {
    Vec3 wi = square_to_cosine_hemisphere(u1, u2);
    // No direction for a grazing wo, nor at the rim of the disk (zero density), nor where
    // f's side test wo.z · wi.z > 0 underflows (a denormal wo.z): a sample must evaluate
    // to what it carries (issue 9), and the test stays one multiply in f and pdf.
    if (!(std::abs(wo.z) * wi.z > 0)) return std::nullopt;
    const Float pdf = wi.z * kInvPi;
    wi.z = std::copysign(wi.z, wo.z);
    return BSDFSampleT<C>{wi, reflectance, pdf, false, Lobe::Reflection, 1};
  }

  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? reflectance : C{}, C{}};
  }
};

using DiffuseBxDF = DiffuseBxDFT<Color>;

}  // namespace gonio
