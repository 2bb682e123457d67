#pragma once
// Perfect specular reflection with a constant reflectance, lecture §5.2, eq. 23:
// f = ρ δ(cos θi − cos θr) δ(φi − φr ± π) / cos θi — a delta lobe, so f and pdf are 0
// and sample() returns the mirror direction with weight ρ.

#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"

namespace gonio {

template <typename C>
struct MirrorBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "mirror";
  C reflectance{1.0f};

  static constexpr BxDFFlags flags() { return BxDFFlags::SpecularReflection; }
  C f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float, Float, Float,
                                   TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    return BSDFSampleT<C>{{-wo.x, -wo.y, wo.z}, reflectance, 1, true, Lobe::Reflection, 1};
  }

  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? reflectance : C{}, C{}};
  }
};

using MirrorBxDF = MirrorBxDFT<Color>;

}  // namespace gonio
