#pragma once
// Smooth dielectric interface: specular reflection with probability F and refraction by
// Snell's law with probability 1 − F (lecture §5.2–5.4), total internal reflection when
// sin²θt ≥ 1, and the radiance scaling (n_wo / n_wi)² of lecture eq. 27 in radiance mode
// only (Veach 1997, §5.2). eta = n_inside / n_outside; for wo.z < 0 the roles swap.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/fresnel.h"

namespace gonio {

struct DielectricBxDF {
  static constexpr std::string_view kName = "dielectric";
  Float eta = 1.5f;  // n_inside / n_outside

  static constexpr BxDFFlags flags() {
    return BxDFFlags::SpecularReflection | BxDFFlags::SpecularTransmission;
  }
  Float relative_eta() const { return eta; }
  Color f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  // u_lobe < F chooses reflection; each lobe's weight is its share divided by its
  // probability: 1 for reflection, (n_wo/n_wi)² (radiance) or 1 (importance) for refraction.
  std::optional<BSDFSample> sample(const Vec3& wo, Float u_lobe, Float, Float,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    // Inlined fresnel_dielectric + refract, sharing cos θt between them.
    Float e = eta, cos_o = wo.z;
    if (cos_o < 0) {
      e = 1 / e;
      cos_o = -cos_o;
    }
    const Float sin2_t = std::max(Float(0), 1 - cos_o * cos_o) / (e * e);
    Float r = 1, cos_t = 0;
    if (sin2_t < 1) {
      cos_t = std::sqrt(1 - sin2_t);
      const Float rs = (cos_o - e * cos_t) / (cos_o + e * cos_t);
      const Float rp = (e * cos_o - cos_t) / (e * cos_o + cos_t);
      r = (rs * rs + rp * rp) / 2;
    }
    if (u_lobe < r)
      return BSDFSample{{-wo.x, -wo.y, wo.z}, Color(1.0f), r, true, Lobe::Reflection, 1};
    // Refraction (lecture §5.3), written in the local frame: wt = −wo/η + (cos θo/η − cos θt) n,
    // with n the normal on wo's side.
    const Float inv_eta = 1 / e;
    const Float nz = wo.z > 0 ? Float(1) : Float(-1);
    // Normalised because 1 − cos²θo loses digits near normal incidence, which a large η
    // would magnify into a visibly non-unit vector; the TIR decision stays a function
    // of cos θo alone, so it is invariant under rotation about N.
    const Vec3 wi = normalize(Vec3{-wo.x * inv_eta, -wo.y * inv_eta, -nz * cos_t});
    return BSDFSample{wi, Color(transmission_scale(e, mode)), 1 - r, true,
                      Lobe::Transmission, e};
  }

  DirectionalAlbedo albedo(const Vec3& wo, TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return {};
    const Float r = fresnel_dielectric(wo.z, eta);
    const Float eta_crossed = wo.z > 0 ? eta : 1 / eta;
    return {Color(r), Color((1 - r) * transmission_scale(eta_crossed, mode))};
  }
};

}  // namespace gonio
