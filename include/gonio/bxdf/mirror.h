#pragma once
// Perfect specular reflection with a constant reflectance, lecture §5.2, eq. 23:
// f = ρ δ(cos θi − cos θr) δ(φi − φr ± π) / cos θi — a delta lobe, so f and pdf are 0
// and sample() returns the mirror direction with weight ρ.

#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"

namespace gonio {

struct MirrorBxDF {
  static constexpr std::string_view kName = "mirror";
  Color reflectance{1.0f};

  static constexpr BxDFFlags flags() { return BxDFFlags::SpecularReflection; }
  Color f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  std::optional<BSDFSample> sample(const Vec3& wo, Float, Float, Float,
                                   TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    return BSDFSample{{-wo.x, -wo.y, wo.z}, reflectance, 1, true, Lobe::Reflection, 1};
  }

  DirectionalAlbedo albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? reflectance : Color{}, Color{}};
  }
};

}  // namespace gonio
