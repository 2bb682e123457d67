#pragma once
// EON, the energy-preserving Oren–Nayar of Portsmouth, Kutz & Hill, "EON: A practical
// energy-preserving rough diffuse BRDF", JCGT 14(1), 2025 (arXiv 2410.18026 v3; OpenPBR's
// base diffuse). ρ = reflectance (the single-scattering albedo), r = roughness in [0, 1].
// (The stored copy of the paper we could read shows its listings but not its equation
// numbers, so formulas are cited by section and by the name they carry in the listings.)
//
//  single scattering, §2 (Fujii's "FON" form of the qualitative Oren–Nayar model):
//    f_ss = ρ/π A_F (1 + r s/t),   s = wi·wo − μi μo,   t = max(μi, μo) if s > 0 else 1,
//    A_F = 1/(1 + c1 r),  B_F = r A_F,  c1 = 1/2 − 2/(3π)
//  its exact directional albedo at ρ = 1, §3 ("E_FON_exact"), θ = acos μ:
//    E_F(μ) = A_F + (B_F/π) G(μ),
//    G = sin θ (θ − sin θ cos θ) + (2/3)(tan θ (1 − sin³θ) − sin θ)
//  and its cosine-weighted average, §3: Ē_F = 2∫E_F μ dμ = A_F (1 + c2 r), c2 = 2/3 − 28/(15π)
//  multiple scattering, §3 (the analytic energy compensation):
//    f_ms = ρ_ms/π (1 − E_F(μo)) (1 − E_F(μi)) / (1 − Ē_F),
//    ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F))
//  directional albedo of the whole model ("E_EON"): ρ E_F(μo) + ρ_ms (1 − E_F(μo)): with
//    ρ = 1, exactly 1 at every angle and roughness (the white furnace).
// Numerics (same formulas, rearranged): 1 − A_F = c1 r A_F, so 1 − E_F = r A_F (c1 − G/π)
// and 1 − Ē_F = r A_F (c1 − c2) carry no cancellation, and f_ms = ρ_ms/π r A_F
// (c1 − G_o/π)(c1 − G_i/π)/(c1 − c2) is exactly 0 at r = 0 (the listing's clamps to 1e-7
// left ρ_ms 10⁻⁷/π there: the model is exactly Lambert at r = 0). tan θ (1 − sin³θ) is
// sin θ μ (1 + sin θ + sin²θ)/(1 + sin θ) (1 − sin θ = μ²/(1 + sin θ)): no 0/0 at μ = 0,
// where G = π/2 − 2/3 and E_F = 1.
//
// Sampling, §4: "clipped linearly transformed cosine" (CLTC) sampling, mixed with uniform
// hemisphere sampling. In the frame of wo (x along wo's tangential part), a cosine
// distribution restricted to the directions wh whose image M wh lies above the horizon
// (the fraction s = (1 + 1/√(1 + d²))/2 of it) is mapped by the paper's fitted
// M = [[a, 0, b], [0, c, 0], [d, 0, 1]] (coefficients "ltc_terms": rational fits in μo
// and r); density D(wi) = |M|² (adj M wi)_z / (π s |adj M wi|⁴). A share
// P_u = r^0.1 (0.162925 − 0.372058 μ + 0.538233 μ² − 0.290822 μ³) of samples is uniform
// over the hemisphere; pdf = P_u/(2π) + (1 − P_u) D. The clipped region is generalised
// to the sign of d: the fit makes d ≤ 0 except within 5e-4 of μo = 1, where it is
// +3.5e-3 r; the listing's map assumes d ≤ 0. At r = 0, M = I and P_u = 0: cosine
// sampling, as for Lambert.
// f grows without bound as both directions graze (s/t ~ 1/μ), like Oren–Nayar's tan β;
// f cos θi ≤ ρ/π A_F (1 + r) + f_ms stays bounded, and the uniform share bounds the
// sample weights. Directions within 1e-7 of the tangent plane scatter nothing
// (diffuse_glossy::usable), as for the other diffuse models. Two-sided (SPEC §1).

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/diffuse_glossy.h"
#include "gonio/math/fast_atan.h"
#include "gonio/math/warp.h"

namespace gonio {

namespace eon {

inline constexpr Float kC1 = Float(0.5 - 2.0 / (3.0 * 3.14159265358979323846));
inline constexpr Float kC2 = Float(2.0 / 3.0 - 28.0 / (15.0 * 3.14159265358979323846));

// A_F = 1/(1 + c1 r) (§2).
inline Float a_fon(Float r) { return 1 / (1 + kC1 * r); }

// c1 − G(μ)/π ≥ 0, so that 1 − E_F(μ) = r A_F (c1 − G(μ)/π) (§3, E_F exact; see above).
inline Float one_minus_g(Float mu) {
  mu = std::clamp(mu, Float(0), Float(1));
  const Float si = std::sqrt(std::max(Float(0), 1 - mu * mu));
  // tan θ (1 − sin³θ) without dividing by μ.
  const Float tan_term = si * mu * (1 + si + si * si) / (1 + si);
  // θ = acos μ = atan2(sin θ, μ), by the project's polynomial atan2 (|error| ≤ 2e-8 rad,
  // below float resolution; math/fast_atan.h): libm's acos was most of f's time.
  const Float theta = fast_atan2(si, mu);
  const Float g = si * (theta - si * mu) + Float(2.0 / 3.0) * (tan_term - si);
  return std::max(Float(0), kC1 - g * kInvPi);
}

// E_F(μ), the FON lobe's exact directional albedo at ρ = 1 (§3).
inline Float albedo_fon(Float mu, Float r) {
  const Float a = a_fon(r);
  return 1 - r * a * one_minus_g(mu);
}
// Ē_F = A_F (1 + c2 r) (§3).
inline Float average_albedo_fon(Float r) { return a_fon(r) * (1 + kC2 * r); }

// The paper's fitted LTC matrix M for wo at cos θo = mu (§4, "ltc_terms").
struct Ltc {
  Float a, b, c, d;
};
inline Ltc ltc_terms(Float mu, Float r) {
  Ltc m;
  m.a = 1 + r * (Float(0.303392) + (Float(-0.518982) + Float(0.111709) * mu) * mu +
                 (Float(-0.276266) + Float(0.335918) * mu) * r);
  m.b = r * (Float(-1.16407) + Float(1.15859) * mu + (Float(0.150815) - Float(0.150105) * mu) * r) /
        (mu * mu * mu - Float(1.43545));
  m.c = 1 + (Float(0.20013) + (Float(-0.506373) + Float(0.261777) * mu) * mu) * r;
  m.d = ((Float(0.540852) + (Float(-1.01625) + Float(0.475392) * mu) * mu) * r) /
        (Float(-1.0743) + mu * (Float(0.0725628) + mu));
  return m;
}

// Share of uniform hemisphere samples (§4).
inline Float uniform_share(Float mu, Float r) {
  if (r <= 0) return 0;
  return std::pow(r, Float(0.1)) *
         (Float(0.162925) + mu * (Float(-0.372058) + (Float(0.538233) - Float(0.290822) * mu) * mu));
}

// The LTC frame of wo (upper side): x along wo's tangential part, z the normal.
struct Frame {
  Float cx = 1, cy = 0;  // unit x axis (cx, cy, 0); y axis (−cy, cx, 0)
  explicit Frame(const Vec3& wo) {
    const Float l2 = wo.x * wo.x + wo.y * wo.y;
    if (l2 > 0) {
      const Float inv = 1 / std::sqrt(l2);
      cx = wo.x * inv;
      cy = wo.y * inv;
    }
  }
  Vec3 to_local(const Vec3& w) const { return {cx * w.x + cy * w.y, -cy * w.x + cx * w.y, w.z}; }
  Vec3 to_world(const Vec3& v) const { return {cx * v.x - cy * v.y, cy * v.x + cx * v.y, v.z}; }
};

// Fraction s of the cosine lobe kept by the clipping (§4).
inline Float clipped_fraction(Float d) { return Float(0.5) * (1 + 1 / std::sqrt(d * d + 1)); }

// CLTC density of wi (upper side, unit) for wo at cos θo = mu (§4).
inline Float cltc_pdf(const Ltc& m, const Vec3& wi_ltc) {
  const Float det = m.c * (m.a - m.b * m.d);
  const Vec3 v{m.c * (wi_ltc.x - m.b * wi_ltc.z), (m.a - m.b * m.d) * wi_ltc.y, m.c * (m.a * wi_ltc.z - m.d * wi_ltc.x)};
  if (!(v.z > 0)) return 0;
  const Float l2 = length_squared(v);
  const Float q = det / l2;
  return q * q * v.z * kInvPi / clipped_fraction(m.d);
}

// A CLTC sample in the LTC frame (not normalised).
inline Vec3 cltc_sample(const Ltc& m, Float u1, Float u2) {
  const Float rad = std::sqrt(u1), phi = 2 * kPi * u2;
  Float x = rad * std::cos(phi);
  const Float y = rad * std::sin(phi);
  // The disk's chord at y mapped linearly onto its part whose image lies above the
  // horizon: x' from −√(1 − y²) to vz √(1 − y²) (d ≤ 0), or mirrored (d > 0).
  const Float s = clipped_fraction(m.d);
  const Float chord = std::sqrt(std::max(Float(0), 1 - y * y));
  x = (1 - s) * chord + s * x;
  if (m.d <= 0) x = -x;
  const Vec3 wh{x, y, std::sqrt(std::max(Float(0), 1 - x * x - y * y))};
  return {m.a * wh.x + m.b * wh.z, m.c * wh.y, m.d * wh.x + wh.z};
}

}  // namespace eon

template <typename C>
struct EonBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "eon";
  C reflectance{0.8f};
  Float roughness = 0;

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  // ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F)) (§3).
  C rho_ms() const {
    const Float avg = eon::average_albedo_fon(roughness);
    return reflectance * reflectance * avg / (C(1) - reflectance * (1 - avg));
  }

  C f(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!diffuse_glossy::usable(wo, wi)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Float r = roughness, a = eon::a_fon(r);
    // s = sin θi sin θo cos Δφ ≥ −1; rounding took it below −1 (f < 0) for opposite
    // grazing directions.
    const Float s = std::max(Float(-1), dot(wi, wo) - wi.z * wo.z);
    const Float s_over_t = s > 0 ? s / std::max(wi.z, wo.z) : s;
    const C f_ss = reflectance * (kInvPi * a * (1 + r * s_over_t));
    if (r <= 0) return f_ss;
    const Float ms = kInvPi * r * a * eon::one_minus_g(wo.z) * eon::one_minus_g(wi.z) / (eon::kC1 - eon::kC2);
    return f_ss + rho_ms() * ms;
  }

  Float pdf(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!diffuse_glossy::usable(wo, wi)) return 0;
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    return mixture_pdf(wo, wi);
  }

  std::optional<BSDFSampleT<C>> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < diffuse_glossy::kGrazing) return std::nullopt;
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    Vec3 wi;
    if (u_lobe < eon::uniform_share(wo.z, roughness)) {
      wi = square_to_uniform_hemisphere(u1, u2);
    } else {
      const eon::Frame frame(wo);
      wi = normalize(frame.to_world(eon::cltc_sample(eon::ltc_terms(wo.z, roughness), u1, u2)));
    }
    if (!(wi.z >= diffuse_glossy::kGrazing)) return std::nullopt;
    const Float p = mixture_pdf(wo, wi);
    if (!(p > 0)) return std::nullopt;
    const C weight = f(wo, wi, mode) * (wi.z / p);
    if (flip) wi.z = -wi.z;
    return BSDFSampleT<C>{wi, weight, p, false, Lobe::Reflection, 1};
  }

  // The closed form of the whole model's directional albedo ("E_EON", §3).
  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < diffuse_glossy::kGrazing) return {C{}, C{}};
    const Float e = eon::albedo_fon(std::abs(wo.z), roughness);
    const Float one_minus_e = roughness * eon::a_fon(roughness) * eon::one_minus_g(std::abs(wo.z));
    return {reflectance * e + rho_ms() * one_minus_e, C{}};
  }

 private:
  // wo and wi on the upper side.
  Float mixture_pdf(const Vec3& wo, const Vec3& wi) const {
    const Float pu = eon::uniform_share(wo.z, roughness);
    const eon::Frame frame(wo);
    const Float pc = eon::cltc_pdf(eon::ltc_terms(wo.z, roughness), frame.to_local(wi));
    return pu * kInv2Pi + (1 - pu) * pc;
  }
};

using EonBxDF = EonBxDFT<Color>;

}  // namespace gonio
