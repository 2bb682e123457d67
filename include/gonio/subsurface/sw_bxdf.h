#pragma once
// The directional term of the separable BSSRDF (pbrt-v3 §11.4.1, eq. 11.7):
//   Sw(ωi) = (1 − Fr(η, cos θi)) / (c π),   c = 1 − 2 FM1,
// FM1 = ∫0^1 Fr(μ) μ dμ the first Fresnel moment (d'Eon & Irving 2011, "A quantized-
// diffusion model for rendering translucent materials", §5) of light arriving from the
// outside onto relative index η, so that ∫ Sw cos θ dω = 1 over the hemisphere: the
// profile Sp already holds the power that leaves, and Sw only distributes it in direction.
//
// As a small BxDF-like value type (f, pdf, sample, eval, flags of bxdf/contract.h) for the
// exit point of a path: next-event estimation evaluates it, the next direction is sampled
// from it (cosine-weighted). It is one-sided by construction: f(wo, wi) = Sw(wi) for wi on
// wo's side and does not depend on wo otherwise — the reciprocal factor 1 − Fr(cos θo)
// belongs to the entry point. So it is not reciprocal and does not join the BxDF variant.

#include <cmath>
#include <optional>

#include "gonio/bxdf/contract.h"
#include "gonio/fresnel.h"
#include "gonio/math/warp.h"

namespace gonio {

// ∫0^1 Fr(μ, eta) μ^k dμ for light arriving at cos θ = μ onto relative index eta
// (n beyond / n of incidence; eta < 1 is light from inside a denser medium, total
// internal reflection included), by Gauss–Legendre quadrature split at the critical
// angle, with gonio's one dielectric Fresnel (fresnel.h). d'Eon & Irving 2011 fit these
// moments by polynomials; here they are integrated to ~1e-7.
double fresnel_moment(int k, double eta);

template <typename C>
struct SwBxDFT {
  using color_type = C;
  Float eta = 1.33f;      // n_inside / n_outside of the boundary (SPEC §1)
  Float inv_c_pi = kInvPi;  // 1 / (c π)

  SwBxDFT() = default;
  explicit SwBxDFT(Float eta_) : eta(eta_) {
    const double c = 1 - 2 * fresnel_moment(1, eta_);
    inv_c_pi = static_cast<Float>(1 / (c * kPiD));
  }

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  // Sw at |cos θ| = c (light crossing the boundary outward at that angle).
  Float value(Float cos_theta) const {
    const Float c = std::min(std::abs(cos_theta), Float(1));
    return (1 - fresnel_dielectric(c, eta)) * inv_c_pi;
  }

  C f(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return C(wo.z * wi.z > 0 ? value(wi.z) : Float(0));
  }

  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return wo.z * wi.z > 0 ? std::abs(wi.z) * kInvPi : Float(0);
  }

  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return {f(wo, wi, mode), pdf(wo, wi, mode)};
  }

  // Cosine-weighted on wo's side; weight = Sw cos θ / (cos θ / π) = (1 − Fr) / c.
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float /*u_lobe*/, Float u1, Float u2,
                                       TransportMode = TransportMode::Radiance) const {
    Vec3 wi = square_to_cosine_hemisphere(u1, u2);
    if (!(std::abs(wo.z) * wi.z > 0)) return std::nullopt;
    const Float pdf = wi.z * kInvPi;
    const Float weight = value(wi.z) * kPi;
    wi.z = std::copysign(wi.z, wo.z);
    return BSDFSampleT<C>{wi, C(weight), pdf, false, Lobe::Reflection, 1};
  }
};
using SwBxDF = SwBxDFT<Color>;

}  // namespace gonio
