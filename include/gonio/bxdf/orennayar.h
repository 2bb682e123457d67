#pragma once
// Oren & Nayar 1994, "Generalization of Lambert's Reflectance Model": rough diffuse
// surfaces of V-cavities with a Gaussian distribution of facet slopes (σ in radians).
//   qualitative model (their eq. 30; gonio's default, as in most renderers):
//     f = ρ/π (A + B max(0, cos(φi − φo)) sin α tan β),
//     A = 1 − 0.5 σ²/(σ² + 0.33), B = 0.45 σ²/(σ² + 0.09), α = max(θi, θo), β = min(θi, θo)
//   full model (their eqs. 26–29, with the interreflection term L2):
//     f = ρ/π [C1 + cos Δφ C2 tan β + (1 − |cos Δφ|) C3 tan((α + β)/2)]
//         + 0.17 ρ²/π σ²/(σ² + 0.13) [1 − cos Δφ (2β/π)²]
//     C1 = A, C2 = 0.45 σ²/(σ²+0.09) (sin α if cos Δφ ≥ 0, else sin α − (2β/π)³),
//     C3 = 0.125 σ²/(σ²+0.09) (4αβ/π²)²
// Both are symmetric in wi and wo (reciprocal). The full model's L1 is clamped at 0 (its
// fitted C2 term goes negative at grazing angles). Two-sided.
// tan β grows without bound as both directions graze, so, like the glossy models, the
// model scatters nothing within 1e-7 of the tangent plane (diffuse_glossy::usable): f
// stays finite (a denormal cos θo gave tan β = ∞ and NaN, issue 9).
// Sampling: f itself is unbounded there (its albedo is not), so cosine sampling alone
// gave weights π f ≈ B ρ sin α tan β of 10³–10⁷ at grazing wo. A share q of uniform
// hemisphere samples bounds them: f cos θi ≤ ρ/π (A + B + ...) since tan β cos θi ≤ sin θi
// (β = θi) or ≤ 1 (β = θo < θi), and likewise tan((α + β)/2) cos θi ≤ 2, so
// weight ≤ 2π f cos θi / q stays a few times ρ. σ = 0 is Lambert: q = 0, cosine only.

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/diffuse_glossy.h"
#include "gonio/math/warp.h"

namespace gonio {

template <typename C>
struct OrenNayarBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "orennayar";
  C reflectance{0.5f};
  Float sigma = 0;  // radians
  bool full = false;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  C f(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!diffuse_glossy::usable(wo, wi)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Float s2 = sigma * sigma;
    const Float A = 1 - Float(0.5) * s2 / (s2 + Float(0.33));
    const Float Bc = Float(0.45) * s2 / (s2 + Float(0.09));
    // sin and cos of the polar angles, and cos(φi − φo) from the tangential parts.
    const Float sin_i = std::sqrt(std::max(Float(0), 1 - wi.z * wi.z));
    const Float sin_o = std::sqrt(std::max(Float(0), 1 - wo.z * wo.z));
    const Float tp = wi.x * wo.x + wi.y * wo.y;
    const Float denom = sin_i * sin_o;
    const Float cos_dphi = denom > Float(1e-12) ? std::clamp(tp / denom, Float(-1), Float(1)) : Float(0);
    // α = max(θi, θo) has the larger sine; β = min has the smaller tangent.
    const bool i_larger = wi.z < wo.z;  // θi > θo
    const Float sin_alpha = i_larger ? sin_i : sin_o;
    const Float tan_beta = i_larger ? sin_o / wo.z : sin_i / wi.z;
    if (!full) {
      return reflectance * (kInvPi * (A + Bc * std::max(Float(0), cos_dphi) * sin_alpha * tan_beta));
    }
    // Clamped: a unit vector's z may round to just above 1 (acos would give NaN).
    const Float alpha = std::acos(std::min({wi.z, wo.z, Float(1)}));
    const Float beta = std::acos(std::min(std::max(wi.z, wo.z), Float(1)));
    const Float b2 = 2 * beta * kInvPi;
    const Float C2 = cos_dphi >= 0 ? Bc * sin_alpha : Bc * (sin_alpha - b2 * b2 * b2);
    const Float t = 4 * alpha * beta * kInvPi * kInvPi;
    const Float C3 = Float(0.125) * s2 / (s2 + Float(0.09)) * t * t;
    // tan((α + β)/2) = (sin α + sin β)/(cos α + cos β): no tangent of an angle that float
    // rounding can push past π/2 (where tan turns negative).
    const Float sin_beta = i_larger ? sin_o : sin_i;
    const Float tan_half_sum = (sin_alpha + sin_beta) / (wi.z + wo.z);
    // The fitted C2 term can drive L1 below 0 towards grazing with cos Δφ < 0 (tan β
    // grows without bound); a BRDF is never negative, so it is clamped (symmetrically in
    // wi and wo, which keeps reciprocity).
    const Float L1 = std::max(Float(0), A + cos_dphi * C2 * tan_beta + (1 - std::abs(cos_dphi)) * C3 * tan_half_sum);
    const Float L2 = Float(0.17) * s2 / (s2 + Float(0.13)) * (1 - cos_dphi * b2 * b2);
    return reflectance * (kInvPi * L1) + reflectance * reflectance * (kInvPi * L2);
  }

  // Probability of a uniform hemisphere sample (the rest are cosine-weighted).
  Float uniform_share() const { return sigma > 0 ? Float(0.25) : Float(0); }
  Float mixture_pdf(Float cos_i) const {
    const Float q = uniform_share();
    return (1 - q) * cos_i * kInvPi + q * kInv2Pi;
  }

  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return diffuse_glossy::usable(wo, wi) ? mixture_pdf(std::abs(wi.z)) : Float(0);
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    Vec3 wi = u_lobe < uniform_share() ? square_to_uniform_hemisphere(u1, u2) : square_to_cosine_hemisphere(u1, u2);
    if (std::abs(wo.z) < diffuse_glossy::kGrazing || wi.z < diffuse_glossy::kGrazing) return std::nullopt;
    const Float cos_i = wi.z, p = mixture_pdf(cos_i);
    wi.z = std::copysign(wi.z, wo.z);
    return BSDFSampleT<C>{wi, f(wo, wi, mode) * (cos_i / p), p, false, Lobe::Reflection, 1};
  }
};

using OrenNayarBxDF = OrenNayarBxDFT<Color>;

}  // namespace gonio
