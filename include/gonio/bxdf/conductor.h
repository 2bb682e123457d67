#pragma once
// Smooth conductor: perfect specular reflection (lecture eq. 23) weighted by the Fresnel
// reflectance of a metal with complex index eta + i k, exact or by Schlick's
// approximation (lecture eq. 28). Reflects on whichever side wo lies (SPEC §1).

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/fresnel.h"

namespace gonio {

enum class FresnelModel : std::uint8_t { Exact, Schlick };

// Channel-wise conductor Fresnel, shared by the smooth conductor and (later) the rough one.
struct ConductorFresnel {
  FresnelModel model = FresnelModel::Exact;
  Color eta{1.0f};  // real part of the relative index
  Color k{0.0f};    // extinction coefficient
  Color f0{1.0f};   // reflectance at normal incidence, used by Schlick

  Color operator()(Float cos_i) const {
    const Float c = std::abs(cos_i);
    if (model == FresnelModel::Schlick) {
      const Float m = std::min(Float(1), 1 - c);
      const Float m5 = (m * m) * (m * m) * m;
      return f0 + (Color(1.0f) - f0) * m5;
    }
    return map(eta, k, [c](Float n, Float kk) { return fresnel_conductor(c, n, kk); });
  }
};

struct ConductorBxDF {
  static constexpr std::string_view kName = "conductor";
  ConductorFresnel fresnel;

  static constexpr BxDFFlags flags() { return BxDFFlags::SpecularReflection; }
  Color f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  std::optional<BSDFSample> sample(const Vec3& wo, Float, Float, Float,
                                   TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    return BSDFSample{{-wo.x, -wo.y, wo.z}, fresnel(wo.z), 1, true, Lobe::Reflection, 1};
  }

  DirectionalAlbedo albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? fresnel(wo.z) : Color{}, Color{}};
  }
};

}  // namespace gonio
