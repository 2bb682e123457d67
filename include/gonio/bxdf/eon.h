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
#include "gonio/fresnel.h"
#include "gonio/math/fast_acos.h"
#include "gonio/math/fast_atan.h"
#include "gonio/math/warp.h"

namespace gonio {

namespace eon {

inline constexpr Float kC1 = Float(0.5 - 2.0 / (3.0 * 3.14159265358979323846));
inline constexpr Float kC2 = Float(2.0 / 3.0 - 28.0 / (15.0 * 3.14159265358979323846));

// A_F = 1/(1 + c1 r) (§2).
inline Float a_fon(Float r) { return 1 / (1 + kC1 * r); }

// The FON terms of f for μo, μi (cosines, clamped to [0, 1]) and s = wi·wo − μo μi (§2, §3):
// 1 − E_F = r A_F (c1 − G/π) for both directions (see above) and Fujii's s/t. The same
// formulas as written, evaluated for both directions at once in a 4-lane vector (SSE on
// x86-64): one sqrtps gives sin θ and √(1 − μ) of both, θ = acos μ is a polynomial times
// √(1 − μ) (math/fast_acos.h; its polynomial runs alongside the square root), and both
// 1/(1 + sin θ) come from one division, 1/((1 + sin θo)(1 + sin θi)) times the other factor.
// f is a chain of dependent operations: square roots and divisions were most of its time.
struct FonTerms {
  Float c_o, c_i;  // c1 − G(μ)/π ≥ 0 for μo, μi
  Float s_over_t;  // s/t, t = max(μo, μi) if s > 0, else 1
};
inline FonTerms fon_terms(Float mu_o, Float mu_i, Float s) {
  using V = Float4;  // gonio/math/fast_atan.h
  using detail::splat;
  const V zero{}, one = splat<V>(1);
  V mu{mu_o, mu_i, mu_o, mu_i};
  mu = mu < zero ? zero : (mu > one ? one : mu);
  // lanes 0, 1: 1 − μ²; lanes 2, 3: 1 − μ.
  V rad = one - mu * V{mu[0], mu[1], 1, 1};
  rad = rad > zero ? rad : zero;
  const V root = lane_sqrt(rad);
  const V si{root[0], root[1], root[0], root[1]};         // sin θ
  const V sqrt_one_minus{root[2], root[3], root[2], root[3]};  // √(1 − μ)
  // θ = acos μ (A&S 4.4.46, |error| ≤ 2e-8 rad: below float resolution).
  const V theta = sqrt_one_minus * detail::acos_poly(mu);
  const Float t = s > 0 ? std::max(mu[0], mu[1]) : Float(1);
  const Float s_over_t = s / t;
  const Float inv = 1 / ((1 + si[0]) * (1 + si[1]));
  // tan θ (1 − sin³θ) = sin θ μ (1 + sin θ + sin²θ)/(1 + sin θ), without dividing by μ.
  const V other_plus_one{1 + si[1], 1 + si[0], 1 + si[1], 1 + si[0]};
  const V tan_term = si * mu * (one + si + si * si) * (other_plus_one * inv);
  const V g = si * (theta - si * mu) + splat<V>(Float(2.0 / 3.0)) * (tan_term - si);
  const V c = splat<V>(kC1) - g * splat<V>(kInvPi);
  return {std::max(Float(0), c[0]), std::max(Float(0), c[1]), s_over_t};
}

// c1 − G(μ)/π ≥ 0, so that 1 − E_F(μ) = r A_F (c1 − G(μ)/π) (§3, E_F exact; see above).
inline Float one_minus_g(Float mu) { return fon_terms(mu, mu, 0).c_o; }

// E_F(μ), the FON lobe's exact directional albedo at ρ = 1 (§3).
inline Float albedo_fon(Float mu, Float r) {
  const Float a = a_fon(r);
  return 1 - r * a * one_minus_g(mu);
}
// Ē_F = A_F (1 + c2 r) (§3).
inline Float average_albedo_fon(Float r) { return a_fon(r) * (1 + kC2 * r); }

// What f needs of the material alone (ρ, r), computed once when the material is made
// (EonBxDFT::prepare) instead of at each evaluation: A_F, the factor r A_F/(π (c1 − c2))
// of f_ms, ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F)) (§3; a division per channel) and r^0.1 of
// the uniform share (§4). `rho` and `r` record the parameters they belong to, so that a
// model whose fields were set without prepare() still evaluates correctly (slower).
template <typename C>
struct Constants {
  C rho{Float(-1)};
  Float r = -1;
  Float a = 1, ms = 0, r_pow = 0;
  C rho_ms{};

  Constants() = default;
  Constants(const C& reflectance, Float roughness) : rho(reflectance), r(roughness) {
    a = a_fon(r);
    ms = kInvPi * r * a / (kC1 - kC2);
    r_pow = r > 0 ? std::pow(r, Float(0.1)) : Float(0);
    const Float avg = average_albedo_fon(r);
    rho_ms = rho * rho * avg / (C(1) - rho * (1 - avg));
  }
  bool matches(const C& reflectance, Float roughness) const {
    if (roughness != r) return false;
    for (int i = 0; i < C::size(); ++i)
      if (reflectance[i] != rho[i]) return false;
    return true;
  }
};

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
inline Float uniform_share_from_power(Float mu, Float r_pow) {
  return r_pow * (Float(0.162925) + mu * (Float(-0.372058) + (Float(0.538233) - Float(0.290822) * mu) * mu));
}
inline Float uniform_share(Float mu, Float r) {
  if (r <= 0) return 0;
  return uniform_share_from_power(mu, std::pow(r, Float(0.1)));
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
  // The material's constants (eon::Constants): prepare() fills them, and whoever sets
  // reflectance or roughness calls it again (the parser, textured parameters, the spectral
  // conversion); if it was not called, they are computed at each evaluation instead.
  eon::Constants<C> constants_{};

  static EonBxDFT make(const C& rho, Float r) {
    EonBxDFT m;
    m.reflectance = rho;
    m.roughness = r;
    m.prepare();
    return m;
  }
  void prepare() { constants_ = eon::Constants<C>(reflectance, roughness); }
  eon::Constants<C> constants() const {
    return constants_.matches(reflectance, roughness) ? constants_ : eon::Constants<C>(reflectance, roughness);
  }

  static constexpr BxDFFlags flags() { return BxDFFlags::DiffuseReflection; }

  // ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F)) (§3).
  C rho_ms() const { return constants().rho_ms; }

  C f(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!diffuse_glossy::usable(wo, wi)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    // At r = 0, A_F = 1 and f_ms = 0: Lambert.
    if (roughness <= 0) return reflectance * kInvPi;
    if (!constants_.matches(reflectance, roughness)) return f_upper(wo, wi, eon::Constants<C>(reflectance, roughness));
    return f_upper(wo, wi, constants_);
  }

  Float pdf(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!diffuse_glossy::usable(wo, wi)) return 0;
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    return mixture_pdf(wo, wi, uniform_share(wo.z));
  }

  std::optional<BSDFSampleT<C>> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < diffuse_glossy::kGrazing) return std::nullopt;
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    const Float pu = uniform_share(wo.z);
    const std::optional<Vec3> d = sample_direction_upper(wo, pu, u_lobe, u1, u2);
    if (!d) return std::nullopt;
    Vec3 wi = *d;
    const Float p = mixture_pdf(wo, wi, pu);
    if (!(p > 0)) return std::nullopt;
    const C weight = f(wo, wi, mode) * (wi.z / p);
    if (flip) wi.z = -wi.z;
    return BSDFSampleT<C>{wi, weight, p, false, Lobe::Reflection, 1};
  }

  // The sampled direction alone, for wo on the upper side (openpbr evaluates its whole
  // mixture there, so the lobe's own weight would be thrown away).
  std::optional<Vec3> sample_direction_upper(const Vec3& wo, Float u_lobe, Float u1, Float u2) const {
    if (!(wo.z >= diffuse_glossy::kGrazing)) return std::nullopt;
    return sample_direction_upper(wo, uniform_share(wo.z), u_lobe, u1, u2);
  }

  // The closed form of the whole model's directional albedo ("E_EON", §3).
  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (std::abs(wo.z) < diffuse_glossy::kGrazing) return {C{}, C{}};
    const eon::Constants<C> k = constants();
    const Float one_minus_e = roughness * k.a * eon::one_minus_g(std::abs(wo.z));
    return {reflectance * (1 - one_minus_e) + k.rho_ms * one_minus_e, C{}};
  }

 private:
  // f for wo, wi on the upper side, r > 0.
  C f_upper(const Vec3& wo, const Vec3& wi, const eon::Constants<C>& k) const {
    // s = sin θi sin θo cos Δφ ≥ −1; rounding took it below −1 (f < 0) for opposite
    // grazing directions.
    const Float s = std::max(Float(-1), dot(wi, wo) - wi.z * wo.z);
    const eon::FonTerms t = eon::fon_terms(wo.z, wi.z, s);
    // f_ss + f_ms, f_ms = ρ_ms/π r A_F (c1 − G_o/π)(c1 − G_i/π)/(c1 − c2) (see above).
    return reflectance * (kInvPi * k.a * (1 + roughness * t.s_over_t)) + k.rho_ms * (k.ms * t.c_o * t.c_i);
  }
  // P_u of §4 for wo at cos θo = mu (0 at r = 0).
  Float uniform_share(Float mu) const {
    if (roughness <= 0) return 0;
    return eon::uniform_share_from_power(mu, constants_.r == roughness ? constants_.r_pow : std::pow(roughness, Float(0.1)));
  }
  // The mixture's direction for wo on the upper side, pu = uniform_share(wo.z).
  std::optional<Vec3> sample_direction_upper(const Vec3& wo, Float pu, Float u_lobe, Float u1, Float u2) const {
    Vec3 wi;
    if (roughness <= 0) {
      wi = square_to_cosine_hemisphere(u1, u2);  // the CLTC at roughness 0 (mixture_pdf)
    } else if (u_lobe < pu) {
      wi = square_to_uniform_hemisphere(u1, u2);
    } else {
      const eon::Frame frame(wo);
      wi = normalize(frame.to_world(eon::cltc_sample(eon::ltc_terms(wo.z, roughness), u1, u2)));
    }
    if (!(wi.z >= diffuse_glossy::kGrazing)) return std::nullopt;
    return wi;
  }
  // wo and wi on the upper side; pu = uniform_share(wo.z).
  Float mixture_pdf(const Vec3& wo, const Vec3& wi, Float pu) const {
    // At roughness 0 the LTC is the identity and nothing is clipped (a = c = 1, b = d = 0):
    // the cosine density, without the LTC's terms (openpbr's default base is there).
    if (roughness <= 0) return wi.z * kInvPi;
    const eon::Frame frame(wo);
    const Float pc = eon::cltc_pdf(eon::ltc_terms(wo.z, roughness), frame.to_local(wi));
    return pu * kInv2Pi + (1 - pu) * pc;
  }
};

using EonBxDF = EonBxDFT<Color>;

}  // namespace gonio
