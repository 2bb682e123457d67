#pragma once
// Sheen (fuzz) lobe: Zeltner, Burley & Chiang 2022, "Practical Multiple-Scattering Sheen
// Using Linearly Transformed Cosines" (SIGGRAPH 2022 Talks), the fuzz of OpenPBR Surface
// 1.1 and the "zeltner" mode of MaterialX's sheen_bsdf. A volumetric layer of fibres
// normal to the surface (SGGX fibre phase function, single and multiple scattering) is
// fitted, per view cosine μo and roughness r, by a linearly transformed cosine (their
// §2 and eq. 1, after Heitz et al. 2016):
//
//   f(wo, wi) μi = color · R(μo, r) · D_o(wi),
//   D_o(w) = D_cos(w′/|w′|) |det M⁻¹| / |w′|³,  w′ = M⁻¹ w,  D_cos(w) = max(0, w.z)/π,
//   M⁻¹ = [[a, 0, b], [0, a, 0], [0, 0, 1]] in the frame whose x axis is wo's tangential
//   direction (their eq. 2: only a and b are fitted).
//
// With |det M⁻¹| = a² and (w′/|w′|).z = w.z/|w′|:  D_o(w) = a² w.z / (π |w′|⁴).
// a, b and R are the rational and Gaussian fits of the paper's 32 × 32 tables
// (ltc_table_sheen_volume) published by MaterialX 1.39
// (libraries/pbrlib/genglsl/lib/mx_microfacet_sheen.glsl, used by OpenPBR's reference
// shader); see sheen_fit below. Two corrections the fits need to be a BRDF: R's offset
// term dips below 0 (to −2.1e-5) for r in (0.041, 0.132), so R is clamped at 0; and the
// fits are only meant for r ≥ 0.01 (MaterialX clamps there too; below it R's Gaussian
// peak narrows without bound and R exceeds 1 for r < 1e-13), so the lobe of r < 0.01 is
// that of 0.01.
//
// Properties (tests/unit/test_sheen.cpp proves each):
//  * M⁻¹ keeps the z component, so D_o lies wholly above the horizon and integrates to
//    1 there: the directional albedo in radiance mode is exactly color · R(μo, r), with
//    no table and no loss below the horizon (sheen_albedo).
//  * Sampling is exact: a cosine sample w′, w = M w′ normalised, pdf = D_o(w), and the
//    weight is color · R(μo, r) for every sample (radiance mode).
//  * Not reciprocal (R and the transform follow wo only): kReciprocal = false, and the
//    validator reports `reciprocity` as not applicable. Importance mode is its adjoint,
//    f_imp(wo, wi) = f(wi, wo) (SPEC §1), whose albedo (light arriving along wo) is not
//    bounded by 1 at grazing incidence (docs/testing.md measures it); it is sampled by
//    an even mixture of the LTC around wo and a cosine lobe, which bounds its weights.
// The lobe is two-sided (wo below the surface mirrors the frame), as the other BRDFs.

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/math/warp.h"

namespace gonio {

namespace sheen_fit {

// The fits hold for roughness in [0.01, 1] (see above).
inline constexpr Float kMinRoughness = Float(0.01);
inline Float clamp_roughness(Float r) { return std::clamp(r, kMinRoughness, Float(1)); }

// a(μ, r): the rational fit of M⁻¹'s diagonal entry (MaterialX, zeltner_sheen_ltc_aInv).
inline Float ltc_a(Float mu, Float r) {
  return (Float(2.58126) * mu + Float(0.813703) * r) * r /
         (1 + Float(0.310327) * mu * mu + Float(2.60994) * mu * r);
}
// b(μ, r): the rational fit of M⁻¹'s off-diagonal entry (zeltner_sheen_ltc_bInv); ≤ 0.
inline Float ltc_b(Float mu, Float r) {
  return std::sqrt(std::max(Float(0), 1 - mu)) * (r - 1) * r * r * r /
         (Float(0.0000254053) + Float(1.71228) * mu - Float(1.71506) * mu * r + Float(1.34174) * r * r);
}
// R(μ, r): the fitted directional albedo of the fibre layer, a Gaussian in μ plus an
// offset (zeltner_sheen_dir_albedo), clamped at 0 (the offset's dip).
inline Float albedo(Float mu, Float r) {
  const Float s = r * (Float(0.0206607) + Float(1.58491) * r) / (Float(0.0379424) + r * (Float(1.32227) + r));
  const Float m = r * (Float(-0.193854) + r * (Float(-1.14885) + r * (Float(1.7932) - Float(0.95943) * r * r))) /
                  (Float(0.046391) + r);
  const Float o = r * (Float(0.000654023) + (Float(-0.0207818) + Float(0.119681) * r) * r) /
                  (Float(1.26264) + r * (Float(-1.92021) + r));
  const Float t = (mu - m) / s;
  return std::max(Float(0), std::exp(Float(-0.5) * t * t) / (s * Float(2.5066282746310002)) + o);
}

// The LTC of view direction wo (wo.z > 0) at a fitted roughness.
struct Ltc {
  Float a, b;
  Float cx, cy;  // wo's tangential direction (the frame's x axis)

  static Ltc of(const Vec3& wo, Float r) {
    const Float mu = std::min(wo.z, Float(1));
    const Float t2 = wo.x * wo.x + wo.y * wo.y;
    Ltc l{ltc_a(mu, r), ltc_b(mu, r), 1, 0};
    if (t2 > Float(1e-30)) {
      const Float inv = 1 / std::sqrt(t2);
      l.cx = wo.x * inv;
      l.cy = wo.y * inv;
    }
    return l;
  }
  // a² / (π |M⁻¹ w|⁴) = D_o(w) / w.z: finite as w.z → 0 (|M⁻¹ w| ≥ a/1.02 for unit w).
  Float density_over_cos(const Vec3& w) const {
    const Float lx = w.x * cx + w.y * cy, ly = w.y * cx - w.x * cy;
    const Float px = a * lx + b * w.z, py = a * ly;
    const Float l2 = px * px + py * py + w.z * w.z;
    return a * a * kInvPi / (l2 * l2);
  }
  // w = M w′ (normalised) for a cosine-distributed w′, back in the local frame.
  Vec3 transform(const Vec3& wp) const {
    const Float x = (wp.x - b * wp.z) / a, y = wp.y / a;
    const Vec3 w = normalize(Vec3{x, y, wp.z});
    return {cx * w.x - cy * w.y, cy * w.x + cx * w.y, w.z};
  }
};

}  // namespace sheen_fit

// The directional albedo of the lobe with a white colour for view cosine μ (radiance
// mode): exactly R(μ, r), since D_o integrates to 1 above the horizon. The layers under
// a sheen are scaled by 1 − color · sheen_albedo(μ, r) (OpenPBR's fuzz layering).
inline Float sheen_albedo(Float mu, Float roughness) {
  return sheen_fit::albedo(std::clamp(std::abs(mu), Float(0), Float(1)), sheen_fit::clamp_roughness(roughness));
}
// Its cosine-weighted hemispherical average 2 ∫ R(μ, r) μ dμ (the E_avg of an energy-
// preserving layering), tabulated at r = i / (kSheenAverageSize − 1) at build time by
// tools/make_sheen_table.cpp and interpolated linearly in r (src/sheen.cpp).
inline constexpr int kSheenAverageSize = 100;
Float sheen_average_albedo(Float roughness);
namespace tables {
extern const float kSheenAverageAlbedo[kSheenAverageSize];
}

template <typename C>
struct SheenBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "sheen";
  static constexpr bool kReciprocal = false;
  static constexpr std::string_view kNonReciprocalReason =
      "the LTC sheen fits f(wo, wi) cos(wi) per view direction wo (Zeltner et al. 2022): its albedo R and "
      "transform follow wo only, so f(wo, wi) != f(wi, wo)";
  C color{1.0f};
  Float roughness = 0.5f;

  static constexpr BxDFFlags flags() { return BxDFFlags::GlossyReflection; }

  // Radiance mode, wo.z > 0 and wi.z > 0: color R(μo) D_o(wi) / μi.
  C f_up(const Vec3& wo, const Vec3& wi) const {
    const Float r = sheen_fit::clamp_roughness(roughness);
    const auto l = sheen_fit::Ltc::of(wo, r);
    return color * (sheen_fit::albedo(std::min(wo.z, Float(1)), r) * l.density_over_cos(wi));
  }

  C f(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    return mode == TransportMode::Radiance ? f_up(wo, wi) : f_up(wi, wo);
  }

  // Radiance mode samples the LTC alone; importance mode an even mixture of it and a
  // cosine lobe (its integrand follows wi's LTC, which the one around wo can miss).
  Float pdf(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return 0;
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Float d = sheen_fit::Ltc::of(wo, sheen_fit::clamp_roughness(roughness)).density_over_cos(wi) * wi.z;
    return mode == TransportMode::Radiance ? d : Float(0.5) * (d + wi.z * kInvPi);
  }

  // f and pdf in one pass (one LTC of wo), for wo and wi on the upper side. r_o is R(μo, r)
  // when the caller already has it (openpbr's fuzz layer scales the layers below by it).
  BSDFEvalT<C> eval_upper(const Vec3& wo, const Vec3& wi, TransportMode mode, std::optional<Float> r_o = {}) const {
    if (!(wo.z > 0 && wi.z > 0)) return {};
    const Float r = sheen_fit::clamp_roughness(roughness);
    const Float d = sheen_fit::Ltc::of(wo, r).density_over_cos(wi);
    if (mode == TransportMode::Radiance) {
      const Float R = r_o ? *r_o : sheen_fit::albedo(std::min(wo.z, Float(1)), r);
      return {color * (R * d), d * wi.z};
    }
    return {f_up(wi, wo), Float(0.5) * (d * wi.z + wi.z * kInvPi)};
  }
  BSDFEvalT<C> eval(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    return eval_upper(wo, wi, mode);
  }

  std::optional<BSDFSampleT<C>> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    const Float r = sheen_fit::clamp_roughness(roughness);
    const auto l = sheen_fit::Ltc::of(wo, r);
    const Vec3 wp = square_to_cosine_hemisphere(u1, u2);
    const bool cosine = mode == TransportMode::Importance && u_lobe < Float(0.5);
    Vec3 wi = cosine ? wp : l.transform(wp);
    // No direction for a grazing wo, nor at the rim, nor where f's side test underflows.
    if (!(wo.z * wi.z > 0)) return std::nullopt;
    const Float d = l.density_over_cos(wi) * wi.z;
    C weight;
    Float p = d;
    if (mode == TransportMode::Radiance) {
      if (!(d > 0)) return std::nullopt;
      weight = color * sheen_fit::albedo(std::min(wo.z, Float(1)), r);  // f μi / D_o = color R
    } else {
      p = Float(0.5) * (d + wi.z * kInvPi);
      weight = f_up(wi, wo) * (wi.z / p);
    }
    if (flip) wi.z = -wi.z;
    return BSDFSampleT<C>{wi, weight, p, false, Lobe::Reflection, 1};
  }

  // Exact in radiance mode (color R(μo)); importance mode has no closed form.
  std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& wo, TransportMode mode = TransportMode::Radiance) const {
    if (mode != TransportMode::Radiance) return std::nullopt;
    if (wo.z == 0) return DirectionalAlbedoT<C>{C{}, C{}};
    return DirectionalAlbedoT<C>{color * sheen_albedo(wo.z, roughness), C{}};
  }
};

using SheenBxDF = SheenBxDFT<Color>;

}  // namespace gonio
