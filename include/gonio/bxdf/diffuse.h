#pragma once
// Ideal diffuse (Lambertian) reflection, lecture §5.1: f = ρ/π, so that ρ_dh = ρ (eq. 19).

#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/math/warp.h"

namespace gonio {

struct DiffuseBxDF {
  static constexpr std::string_view kName = "diffuse";
  Color reflectance{0.5f};

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  Color f(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return wo.z * wi.z > 0 ? reflectance * kInvPi : Color{};
  }

  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return wo.z * wi.z > 0 ? std::abs(wi.z) * kInvPi : Float(0);
  }

  // Cosine-weighted hemisphere on wo's side; weight = (ρ/π) cos θ / (cos θ/π) = ρ.
  std::optional<BSDFSample> sample(const Vec3& wo, Float /*u_lobe*/, Float u1, Float u2,
                                   TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    Vec3 wi = square_to_cosine_hemisphere(u1, u2);
    if (wi.z == 0) return std::nullopt;  // boundary of the disk: zero density
    if (wo.z < 0) wi.z = -wi.z;
    return BSDFSample{wi, reflectance, std::abs(wi.z) * kInvPi, false, Lobe::Reflection, 1};
  }

  DirectionalAlbedo albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? reflectance : Color{}, Color{}};
  }
};

}  // namespace gonio
