#pragma once
// The hair fibre BSDF of Chiang, Bitterli, Tappan & Burley 2016, "A Practical and
// Controllable Hair and Fur Model for Production Path Tracing" (Computer Graphics Forum
// 35(2)), built on Marschner et al. 2003 and d'Eon et al. 2011, in pbrt-v4's frame
// (HairBxDF, src/pbrt/bxdfs.h/.cpp): the fibre runs along +x; for a direction w,
// sin θ = w.x and φ = atan2(w.z, w.y). SPEC §2 fixes what f is for a fibre:
//
//   f(wo, wi) = S(wo, wi) / |wi.z|,   S = Σ_{p=0..2} M_p(θi; θo_p) A_p N_p(φi − φo) + M_3 A_3 / (2π),
//
// p = 0 (R), 1 (TT), 2 (TRT), 3 (the residual of all longer paths, not tilted, uniform in
// azimuth), so that f |cos θi| = S, whose integral over the whole sphere is the fibre's
// albedo (no refraction scaling).
//  * M_p: d'Eon et al. 2011 eq. 7, the azimuthal integral of a spherical Gaussian (a
//    von Mises–Fisher lobe of concentration 1/v about the mirror cone):
//      M_p = exp(−sin θi sin θo_p / v) I0(cos θi cos θo_p / v) / (2 v sinh(1/v)),
//    taken in the log form log I0(a) − b − 1/v − log v − log(1 − e^(−2/v)), finite for every
//    variance (log I0 by Abramowitz & Stegun 9.8.1/9.8.2: |relative error| < 2e-7).
//  * the cuticle tilt α: θo_p = θo − 2α (R), θo + α (TT), θo + 4α (TRT), as pbrt-v4's
//    HairBxDF::f (Marschner 2003 §4.1 with 3α for TRT; MaterialX's GLSL tilts θi with the
//    opposite overall sign); cos θo_p is taken in absolute value.
//  * A_p: Fresnel f = F(cos θo cos γo, η) (Chiang eq. 3 / pbrt-v4), transmittance
//    T = exp(−σa 2 cos γt / cos θt): A0 = f, A1 = (1 − f)² T, A2 = A1 T f,
//    A3 = A2 T f / (1 − T f) (Chiang eq. 6, the geometric series of the residual).
//  * N_p: the trimmed logistic of Chiang §4.2 (eqs. 11–13): N_p(φ) = l_t(φ − Φ(p, h); s),
//    Φ = 2 p γt − 2 γo + p π, l(x; s) = e^(−|x|/s)/(s (1 + e^(−|x|/s))²) normalised over
//    [−π, π] by tanh(π/(2s)).
//  * roughness (Chiang eqs. 7–8): v = (0.726 βm + 0.812 βm² + 3.7 βm²⁰)²,
//    s = √(π/8) (0.265 βn + 1.194 βn² + 5.372 βn²²); one βm gives v_TT = v/4 and
//    v_TRT = 4 v (Marschner's widths β/2 and 2β); the residual takes TRT's v.
//  * the offset h across the fibre: fixed, or (unset) averaged over h by the
//    kGaussPoints-point Gauss–Legendre rule (½ Σ w_k S(h_k)); eval, sample and pdf all use
//    the same rule, so the sampler's density is exactly pdf().
// Sampling (Chiang §4.3, d'Eon et al. 2013): an offset h_k with probability w_k/2 (from
// u2, which is then rescaled), a lobe p ∝ tint_p A_p (from u_lobe, rescaled), θi from M_p
// exactly (d'Eon 2013 §3: cos of the angle from the mirror cone's axis by inverting the
// vMF's CDF, 1 + v log(u + (1 − u) e^(−2/v)), about a uniform azimuth), Δφ from the trimmed
// logistic exactly; the returned pdf is the full mixture, the weight f |cos θi| / pdf.
// Not reciprocal (A_p and the tilt depend on ωo only): kReciprocal = false. Importance
// mode is the adjoint f_imp(wo, wi) = f(wi, wo) (SPEC §1), sampled with radiance mode's
// density. Not isotropic about z: its isotropy is about the fibre's axis.

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/fresnel.h"
#include "gonio/math/constants.h"

namespace gonio {

namespace hair {

// The Gauss–Legendre rule over h in [−1, 1] (nodes ±x, weights w; Σ w = 2).
inline constexpr int kGaussPoints = 8;
inline constexpr std::array<double, 4> kGaussX = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                                  0.9602898564975363};
inline constexpr std::array<double, 4> kGaussW = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                                  0.1012285362903763};
inline Float gauss_node(int k) { return Float(k < 4 ? -kGaussX[size_t(3 - k)] : kGaussX[size_t(k - 4)]); }
// w_k / 2: the probability of node k (they sum to 1).
inline Float gauss_prob(int k) { return Float(0.5 * (k < 4 ? kGaussW[size_t(3 - k)] : kGaussW[size_t(k - 4)])); }

// Chiang et al. 2016 eq. 7: longitudinal roughness β_m in (0, 1] to the variance v.
inline Float variance_from_beta_m(Float b) {
  const Float b2 = b * b, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
  const Float x = Float(0.726) * b + Float(0.812) * b2 + Float(3.7) * b16 * b4;
  return x * x;
}
// Chiang et al. 2016 eq. 8: azimuthal roughness β_n in (0, 1] to the logistic scale s.
inline constexpr Float kSqrtPiOver8 = Float(0.62665706865775012);
inline Float scale_from_beta_n(Float b) {
  const Float b2 = b * b, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
  return kSqrtPiOver8 * (Float(0.265) * b + Float(1.194) * b2 + Float(5.372) * b16 * b4 * b2);
}
// Chiang et al. 2016 eq. 9: the absorption giving a fibre of roughness β_n the colour c
// (each channel in (0, 1]).
inline Float sigma_a_from_color(Float c, Float bn) {
  const Float b2 = bn * bn, b3 = b2 * bn, b4 = b2 * b2, b5 = b4 * bn;
  const Float d = Float(5.969) - Float(0.215) * bn + Float(2.532) * b2 - Float(10.73) * b3 + Float(5.574) * b4 +
                  Float(0.245) * b5;
  const Float l = std::log(std::clamp(c, Float(1e-4), Float(1))) / d;
  return l * l;
}
// d'Eon et al. 2011 (§6, as pbrt-v4's HairBxDF::SigmaAFromConcentration): the
// absorption per unit concentration of eumelanin and pheomelanin, RGB.
inline constexpr Float kEumelanin[3] = {0.419f, 0.697f, 1.37f};
inline constexpr Float kPheomelanin[3] = {0.187f, 0.4f, 1.05f};

// log I0(x), x ≥ 0: Abramowitz & Stegun 9.8.1 (x ≤ 3.75) and 9.8.2 (x > 3.75, where
// I0(x) = e^x / √x · P(3.75/x)).
inline Float log_i0(Float x) {
  if (x <= Float(3.75)) {
    const Float t = x * (1 / Float(3.75)), t2 = t * t;
    const Float p =
        1 + t2 * (Float(3.5156229) +
                  t2 * (Float(3.0899424) +
                        t2 * (Float(1.2067492) + t2 * (Float(0.2659732) + t2 * (Float(0.0360768) + t2 * Float(0.0045813))))));
    return std::log(p);
  }
  const Float t = Float(3.75) / x;
  const Float p =
      Float(0.39894228) +
      t * (Float(0.01328592) +
           t * (Float(0.00225319) +
                t * (Float(-0.00157565) +
                     t * (Float(0.00916281) +
                          t * (Float(-0.02057706) +
                               t * (Float(0.02635537) + t * (Float(-0.01647633) + t * Float(0.00392377))))))));
  return x - Float(0.5) * std::log(x) + std::log(p);
}

// d'Eon et al. 2011 eq. 7 in log form (see the header comment). sin_o/cos_o: the tilted
// outgoing angle of the lobe (cos_o ≥ 0).
inline Float longitudinal(Float sin_i, Float cos_i, Float sin_o, Float cos_o, Float v, Float log_norm) {
  const Float inv_v = 1 / v;
  const Float a = std::max(Float(0), cos_i * cos_o * inv_v), b = sin_i * sin_o * inv_v;
  return std::exp(log_i0(a) - b - inv_v + log_norm);
}
inline Float longitudinal(Float sin_i, Float cos_i, Float sin_o, Float cos_o, Float v) {
  return longitudinal(sin_i, cos_i, sin_o, cos_o, v, -std::log(v) - std::log(-std::expm1(-2 / v)));
}

// The trimmed logistic of Chiang §4.2 on [−π, π]; inv_trim = 1/tanh(π/(2s)).
inline Float trimmed_logistic(Float x, Float s, Float inv_trim) {
  const Float e = std::exp(-std::abs(x) / s);
  return e * inv_trim / (s * (1 + e) * (1 + e));
}
inline Float trimmed_logistic(Float x, Float s) { return trimmed_logistic(x, s, 1 / std::tanh(kPi / (2 * s))); }
// x in [−π, π] by inverting its CDF (pbrt-v4 SampleTrimmedLogistic's closed form).
inline Float sample_trimmed_logistic(Float u, Float s) {
  const Float c0 = 1 / (1 + std::exp(kPi / s));  // CDF(−π) of the untrimmed logistic
  const Float k = std::tanh(kPi / (2 * s));      // CDF(π) − CDF(−π)
  const Float y = u * k + c0;
  const Float x = s * std::log(y / std::max(1 - y, Float(1e-30)));
  return std::clamp(x, -kPi, kPi);
}
// φ − Φ wrapped into [−π, π].
inline Float wrap_angle(Float x) {
  constexpr Float two_pi = 2 * kPi;
  x -= two_pi * std::round(x * kInv2Pi);
  return std::clamp(x, -kPi, kPi);
}
inline Float azimuthal(Float dphi, int p, Float s, Float gamma_o, Float gamma_t, Float inv_trim) {
  const Float phi_p = 2 * Float(p) * gamma_t - 2 * gamma_o + Float(p) * kPi;  // Φ(p, h)
  return trimmed_logistic(wrap_angle(dphi - phi_p), s, inv_trim);
}
inline Float azimuthal(Float dphi, int p, Float s, Float gamma_o, Float gamma_t) {
  return azimuthal(dphi, p, s, gamma_o, gamma_t, 1 / std::tanh(kPi / (2 * s)));
}

}  // namespace hair

template <typename C>
struct HairBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "hair";
  static constexpr bool kReciprocal = false;
  static constexpr std::string_view kNonReciprocalReason =
      "a fibre's attenuation A_p and cuticle tilt follow wo only (Chiang et al. 2016; pbrt-v4 skips its own "
      "reciprocity test for HairBxDF), so f(wo, wi) |cos wi| != f(wi, wo) |cos wo|";
  static constexpr int kLobes = 4;  // R, TT, TRT, residual

  C sigma_a{0.0f};                        // absorption per unit radius
  Float eta = Float(1.55);
  Float h = 0;
  bool average_h = true;                  // h unset: the Gauss–Legendre average
  std::array<Float, kLobes> v{};          // longitudinal variances
  std::array<Float, 3> s{};               // logistic scales (the residual is uniform)
  std::array<C, 3> tint{C(1.0f), C(1.0f), C(1.0f)};
  std::array<Float, 3> sin_tilt{}, cos_tilt{};  // the shifts −2α, +α, +4α
  // Derived by prepare() from v and s: −log v − log(1 − e^(−2/v)) (M_p's normalisation)
  // and 1/tanh(π/(2s)) (the trimmed logistic's).
  std::array<Float, kLobes> log_norm{};
  std::array<Float, 3> inv_trim{};

  void prepare() {
    for (size_t p = 0; p < kLobes; ++p) log_norm[p] = -std::log(v[p]) - std::log(-std::expm1(-2 / v[p]));
    for (size_t p = 0; p < 3; ++p) inv_trim[p] = 1 / std::tanh(kPi / (2 * s[p]));
  }

  // Chiang's defaults: β_m = β_n = 0.3, α = 2°.
  HairBxDFT() {
    set_roughness({Float(0.3), Float(0.3), Float(0.3)}, {Float(0.3), Float(0.3), Float(0.3)});
    v[1] = v[0] / 4;
    v[2] = v[3] = 4 * v[0];
    prepare();
    set_alpha(Float(2) * kPi / 180);
  }

  // The model from the paper's parameters: β_m, β_n per lobe (R, TT, TRT) and α in
  // radians (sets v, s and the tilts).
  void set_roughness(const std::array<Float, 3>& beta_m, const std::array<Float, 3>& beta_n) {
    for (size_t p = 0; p < 3; ++p) {
      v[p] = hair::variance_from_beta_m(beta_m[p]);
      s[p] = hair::scale_from_beta_n(beta_n[p]);
    }
    v[3] = v[2];
    prepare();
  }
  void set_alpha(Float alpha) {
    const Float shifts[3] = {-2 * alpha, alpha, 4 * alpha};
    for (size_t p = 0; p < 3; ++p) {
      sin_tilt[p] = std::sin(shifts[p]);
      cos_tilt[p] = std::cos(shifts[p]);
    }
  }

  static constexpr BxDFFlags flags() { return BxDFFlags::GlossyReflection | BxDFFlags::GlossyTransmission; }
  static constexpr bool is_isotropic() { return false; }
  // A fibre: `check` reports isotropy about z as not applicable and tests over the sphere.
  static constexpr bool is_fibre() { return true; }

  // What depends on wo only.
  struct Outgoing {
    Float sin_o, cos_o, phi_o;
    Float sin_p[kLobes], cos_p[kLobes];  // the tilted θo of each lobe
  };
  Outgoing outgoing(const Vec3& wo) const {
    Outgoing o;
    o.sin_o = std::clamp(wo.x, Float(-1), Float(1));
    o.cos_o = std::sqrt(std::max(Float(0), 1 - o.sin_o * o.sin_o));
    o.phi_o = std::atan2(wo.z, wo.y);
    for (size_t p = 0; p < 3; ++p) {
      // sin(θo + δ), |cos(θo + δ)|
      o.sin_p[p] = o.sin_o * cos_tilt[p] + o.cos_o * sin_tilt[p];
      o.cos_p[p] = std::abs(o.cos_o * cos_tilt[p] - o.sin_o * sin_tilt[p]);
    }
    o.sin_p[3] = o.sin_o;
    o.cos_p[3] = o.cos_o;
    return o;
  }
  // What depends on wo and h: the angles inside and the attenuations.
  struct AtOffset {
    Float gamma_o, gamma_t;
    C ap[kLobes];
    Float lobe_pdf[kLobes];  // ∝ the average of tint_p A_p
  };
  AtOffset at_offset(const Outgoing& o, Float hh) const {
    AtOffset a;
    hh = std::clamp(hh, Float(-1), Float(1));
    a.gamma_o = std::asin(hh);
    const Float cos_gamma_o = std::sqrt(std::max(Float(0), 1 - hh * hh));
    // Bravais' index in the normal plane, η′ = √(η² − sin²θo)/cos θo: sin γt = h/η′
    // (written without dividing by cos θo).
    const Float sin_t = o.sin_o / eta, cos_t = std::sqrt(std::max(Float(1e-12), 1 - sin_t * sin_t));
    const Float sin_gamma_t =
        std::clamp(hh * o.cos_o / std::sqrt(std::max(Float(1e-12), eta * eta - o.sin_o * o.sin_o)), Float(-1), Float(1));
    const Float cos_gamma_t = std::sqrt(std::max(Float(0), 1 - sin_gamma_t * sin_gamma_t));
    a.gamma_t = std::asin(sin_gamma_t);
    const C T = map(sigma_a, [&](Float sa) { return std::exp(-sa * (2 * cos_gamma_t / cos_t)); });
    const Float f = fresnel_dielectric(o.cos_o * cos_gamma_o, eta);
    a.ap[0] = C(f);
    a.ap[1] = T * ((1 - f) * (1 - f));
    a.ap[2] = a.ap[1] * T * f;
    a.ap[3] = map(a.ap[2] * T * f, T, [&](Float num, Float t) {
      const Float d = 1 - t * f;
      return d > 0 ? num / d : Float(0);
    });
    Float sum = 0;
    for (size_t p = 0; p < kLobes; ++p) {
      a.lobe_pdf[p] = std::max(Float(0), (a.ap[p] * tint[std::min(p, size_t(2))]).average());
      sum += a.lobe_pdf[p];
    }
    for (size_t p = 0; p < kLobes; ++p) a.lobe_pdf[p] = sum > 0 ? a.lobe_pdf[p] / sum : Float(0);
    return a;
  }

  int offsets() const { return average_h ? hair::kGaussPoints : 1; }
  Float offset(int k) const { return average_h ? hair::gauss_node(k) : h; }
  Float offset_prob(int k) const { return average_h ? hair::gauss_prob(k) : Float(1); }

  // S(wo, wi) and the sampling density of wi (radiance mode), together.
  BSDFEvalT<C> scatter(const Vec3& wo, const Vec3& wi) const { return scatter(outgoing(wo), wi, -1, nullptr); }
  // The same from wo's terms, with those of offset node `known_k` already at hand (sample()).
  BSDFEvalT<C> scatter(const Outgoing& o, const Vec3& wi, int known_k, const AtOffset* known) const {
    const Float sin_i = std::clamp(wi.x, Float(-1), Float(1));
    const Float cos_i = std::sqrt(std::max(Float(0), 1 - sin_i * sin_i));
    const Float dphi = std::atan2(wi.z, wi.y) - o.phi_o;
    Float mp[kLobes];
    for (size_t p = 0; p < kLobes; ++p)
      mp[p] = hair::longitudinal(sin_i, cos_i, o.sin_p[p], o.cos_p[p], v[p], log_norm[p]);
    C sum(0.0f);
    Float pdf = 0;
    AtOffset computed{};
    for (int k = 0; k < offsets(); ++k) {
      if (k != known_k) computed = at_offset(o, offset(k));
      const AtOffset& a = k == known_k ? *known : computed;
      C sk(0.0f);
      Float pk = 0;
      for (int p = 0; p < 3; ++p) {
        const Float mn = mp[p] * hair::azimuthal(dphi, p, s[size_t(p)], a.gamma_o, a.gamma_t, inv_trim[size_t(p)]);
        sk += a.ap[p] * tint[size_t(p)] * mn;
        pk += a.lobe_pdf[p] * mn;
      }
      const Float mn3 = mp[3] * kInv2Pi;
      sk += a.ap[3] * tint[2] * mn3;
      pk += a.lobe_pdf[3] * mn3;
      sum += sk * offset_prob(k);
      pdf += pk * offset_prob(k);
    }
    return {sum, pdf};
  }

  // 1/|z| for f = S/|z|: 0 in the tangent plane (contract.h), and |z| taken as at least
  // kMinCos so that f stays finite as z → 0 (S is bounded; f |cos| = S holds for |z| ≥ kMinCos).
  static constexpr Float kMinCos = Float(1e-7);
  static Float inv_cos(Float z) { return z != 0 ? 1 / std::max(std::abs(z), kMinCos) : Float(0); }

  // Importance mode (light arriving along wo): the adjoint of the scattering kernel S,
  // f_imp(wo, wi) |cos θi| = S(wi, wo) (a fibre's |cos| is no geometric factor, so the
  // surfaces' rule f_imp(wo, wi) = f(wi, wo) of SPEC §1 would leave a factor |wo.z|/|wi.z|).
  // Sampled by an even mixture of radiance mode's sampler at wo and the uniform sphere
  // (S(wi, wo) as a function of wi is not what the sampler draws; the uniform half bounds
  // the weights by 8π S).
  static constexpr Float kImportanceUniform = Float(0.5);
  Float importance_pdf(Float radiance_pdf) const {
    return (1 - kImportanceUniform) * radiance_pdf + kImportanceUniform * kInv4Pi;
  }

  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (mode == TransportMode::Radiance) {
      BSDFEvalT<C> e = scatter(wo, wi);
      e.f *= inv_cos(wi.z);
      return e;
    }
    return {scatter(wi, wo).f * inv_cos(wi.z), importance_pdf(scatter(wo, wi).pdf)};
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (mode == TransportMode::Radiance) return scatter(wo, wi).f * inv_cos(wi.z);
    return scatter(wi, wo).f * inv_cos(wi.z);
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    const Float p = scatter(wo, wi).pdf;
    return mode == TransportMode::Radiance ? p : importance_pdf(p);
  }

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    if (mode == TransportMode::Importance) {
      if (u_lobe < kImportanceUniform) {
        // The uniform sphere: z = 1 − 2 u1, φ = 2π u2.
        const Float z = 1 - 2 * u1, r = std::sqrt(std::max(Float(0), 1 - z * z)), ph = 2 * kPi * u2;
        return finish_sample(wo, Vec3{r * std::cos(ph), r * std::sin(ph), z}, mode, nullptr, -1, nullptr);
      }
      u_lobe = std::min((u_lobe - kImportanceUniform) / (1 - kImportanceUniform), kOneMinusEpsilon);
    }
    const Outgoing o = outgoing(wo);
    // The offset from u2, which is then rescaled to [0, 1).
    int k = 0;
    if (average_h) {
      Float c = 0;
      for (; k < hair::kGaussPoints - 1; ++k) {
        const Float pk = offset_prob(k);
        if (u2 < c + pk) break;
        c += pk;
      }
      u2 = std::min((u2 - c) / offset_prob(k), kOneMinusEpsilon);
    }
    const AtOffset a = at_offset(o, offset(k));
    // The lobe from u_lobe, rescaled likewise.
    int p = 0;
    {
      Float c = 0;
      for (; p < kLobes - 1; ++p) {
        if (u_lobe < c + a.lobe_pdf[p]) break;
        c += a.lobe_pdf[p];
      }
      if (!(a.lobe_pdf[p] > 0)) return std::nullopt;
      u_lobe = std::clamp((u_lobe - c) / a.lobe_pdf[p], Float(0), kOneMinusEpsilon);
    }
    // θi from M_p (d'Eon et al. 2013): the cosine of the angle to the lobe's axis.
    const Float vp = v[size_t(p)];
    const Float cos_c =
        std::max(Float(-1), 1 + vp * std::log(std::max(u1 + (1 - u1) * std::exp(-2 / vp), Float(1e-35))));
    const Float sin_c = std::sqrt(std::max(Float(0), 1 - cos_c * cos_c));
    const Float sin_i = std::clamp(-cos_c * o.sin_p[p] + sin_c * std::cos(2 * kPi * u2) * o.cos_p[p], Float(-1), Float(1));
    const Float cos_i = std::sqrt(std::max(Float(0), 1 - sin_i * sin_i));
    // Δφ from N_p.
    const Float phi_p = 2 * Float(p) * a.gamma_t - 2 * a.gamma_o + Float(p) * kPi;
    const Float dphi = p < 3 ? phi_p + hair::sample_trimmed_logistic(u_lobe, s[size_t(p)]) : 2 * kPi * u_lobe;
    const Float phi_i = o.phi_o + dphi;
    return finish_sample(wo, Vec3{sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i)}, mode, &o, k, &a);
  }
  // f and pdf at the sampled wi: radiance mode reuses wo's terms and those of the node drawn.
  std::optional<BSDFSampleT<C>> finish_sample(const Vec3& wo, const Vec3& wi, TransportMode mode, const Outgoing* o,
                                              int k, const AtOffset* a) const {
    if (wi.z == 0) return std::nullopt;
    BSDFEvalT<C> e;
    if (mode == TransportMode::Radiance && o) {
      e = scatter(*o, wi, k, a);
      e.f *= inv_cos(wi.z);
    } else {
      e = eval(wo, wi, mode);
    }
    // A direction of density below 1e-30 (the far tail of a narrow lobe, drawn only at
    // u = 0 or 1 exactly) is dropped: its weight would overflow.
    if (!(e.pdf > Float(1e-30))) return std::nullopt;
    BSDFSampleT<C> r;
    r.wi = wi;
    r.pdf = e.pdf;
    r.weight = e.f * (std::abs(wi.z) / e.pdf);
    if (!r.weight.is_finite()) return std::nullopt;
    r.lobe = wi.z * wo.z > 0 ? Lobe::Reflection : Lobe::Transmission;
    return r;
  }
};
using HairBxDF = HairBxDFT<Color>;

}  // namespace gonio
