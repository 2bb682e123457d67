#pragma once
// Microfacet normal distributions — GGX (Trowbridge–Reitz) and Beckmann, anisotropic
// with alpha_x along S and alpha_y along T — with the Smith masking function Λ, the
// height-correlated masking–shadowing G2 = 1 / (1 + Λ(wo) + Λ(wi)) (Heitz 2014, eq. 99;
// SPEC §1), the distribution of visible normals and its sampling.
//
// All directions in the local shading frame; microfacet normals wm have wm.z > 0.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gonio/math/select.h"
#include "gonio/math/special.h"
#include "gonio/math/vec3.h"

namespace gonio {

enum class MicrofacetType : std::uint8_t { GGX, Beckmann };

struct MicrofacetDistribution {
  MicrofacetType type = MicrofacetType::GGX;
  Float alpha_x = 0.1f, alpha_y = 0.1f;

  // Below this roughness the models switch to their smooth (delta) counterparts: the
  // lobe is then narrower than float precision can sample and evaluate faithfully.
  static constexpr Float kSmoothAlpha = 1e-3f;
  bool effectively_smooth() const { return std::max(alpha_x, alpha_y) < kSmoothAlpha; }
  bool is_isotropic() const { return alpha_x == alpha_y; }

  // The hot functions below take the distribution type as an optional template argument
  // (kRuntime: read `type`), so that a model can instantiate its sampler once per type and
  // the GGX code carries no Beckmann branch.
  static constexpr int kRuntime = -1;
  template <int kType>
  bool is_ggx() const {
    if constexpr (kType == kRuntime) return type == MicrofacetType::GGX;
    else return kType == static_cast<int>(MicrofacetType::GGX);
  }

  // D(wm), normalised so that ∫ D(wm) cos θm dωm = 1.
  //   GGX (Walter et al. 2007, eq. 33; anisotropic form Heitz 2014, eq. 85):
  //     1 / (π αx αy cos⁴θm (1 + tan²θm (cos²φm/αx² + sin²φm/αy²))²)
  //   written with cos⁴θ (1 + e)² = (cos²θ + x²/αx² + y²/αy²)² to stay finite at grazing.
  //   Beckmann (Walter et al. 2007, eq. 25; Heitz 2014, eq. 84):
  //     exp(−tan²θm (cos²φm/αx² + sin²φm/αy²)) / (π αx αy cos⁴θm)
  Float D(const Vec3& wm) const {
    const Float cos2 = wm.z * wm.z;
    if (!(wm.z > 0)) return 0;
    const Float sx = wm.x / alpha_x, sy = wm.y / alpha_y;
    if (type == MicrofacetType::GGX) {
      const Float d = cos2 + sx * sx + sy * sy;
      return 1 / (kPi * alpha_x * alpha_y * d * d);
    }
    const Float e = (sx * sx + sy * sy) / cos2;
    if (e > Float(80)) return 0;  // exp(−80) ≈ 2e-35: zero in every sum
    return std::exp(-e) / (kPi * alpha_x * alpha_y * cos2 * cos2);
  }

  // D(h/|h|) for an unnormalised h with h.z > 0 and h2 = |h|²: what the models use for a
  // half vector (no normalisation on the way to D). With q = h.z² + (h.x/αx)² + (h.y/αy)²
  // and r = |h|²/q (bounded by the roughness, so nothing overflows where D itself does
  // not), the forms above become
  //   GGX:      r² / (π αx αy),
  //   Beckmann: exp(−(q − h.z²)/h.z²) (|h|²/h.z²)² / (π αx αy).
  template <int kType = kRuntime>
  [[gnu::always_inline]] Float D_unnormalized(const Vec3& h, Float h2) const {
    if (!(h.z > 0)) return 0;
    const Float sx = h.x / alpha_x, sy = h.y / alpha_y;
    const Float hz2 = h.z * h.z;
    const Float pi_axy = kPi * alpha_x * alpha_y;
    if (is_ggx<kType>()) {
      const Float r = h2 / (hz2 + sx * sx + sy * sy);
      return r * (r * (1 / pi_axy));  // 1/(π αx αy) does not wait for r
    }
    const Float e = (sx * sx + sy * sy) / hz2;
    if (e > Float(80)) return 0;  // as in D
    const Float c2 = h2 / hz2;    // 1/cos²θm
    return std::exp(-e) * (c2 * c2) / pi_axy;
  }

  // Smith Λ(w) (Heitz 2014, eqs. 72 and 86), with a = 1 / (α₀ tan θ), α₀ the roughness
  // along w's azimuth: α₀² tan²θ = (x² αx² + y² αy²) / z².
  //   GGX:      Λ = (−1 + sqrt(1 + 1/a²)) / 2
  //   Beckmann: Λ = (erf(a) − 1)/2 + exp(−a²) / (2 a sqrt(π))
  // Grazing directions (z = 0) are fully masked: a large finite Λ. Where 1/a² = t/cos²θ
  // leaves float range (|cos θ| below ~1e-19: cos² is denormal or 0), Λ takes its
  // asymptote, (1/a)/2 (GGX) or (1/a)/(2√π) (Beckmann), capped at 1e30: the ratio would
  // otherwise be ∞ and Λ ∞/∞ = NaN.
  Float Lambda(const Vec3& w) const {
    const Float cos2 = w.z * w.z;
    const Float t = (w.x * alpha_x) * (w.x * alpha_x) + (w.y * alpha_y) * (w.y * alpha_y);
    if (!(t > 0)) return 0;
    const Float a2t2 = t / cos2;  // = 1/a²
    if (!(a2t2 < Float(1e30))) {
      const Float inv_a = std::sqrt(t) / std::abs(w.z);  // ∞ for w.z = 0
      const Float asymptote = type == MicrofacetType::GGX ? inv_a / 2 : inv_a * Float(0.28209479177387814347);
      return std::min(asymptote, Float(1e30));
    }
    if (type == MicrofacetType::GGX) {
      // (sqrt(1 + x) − 1)/2 = x / (2 (sqrt(1 + x) + 1)), free of cancellation for small x
      return a2t2 / (2 * (std::sqrt(1 + a2t2) + 1));
    }
    const Float a = 1 / std::sqrt(a2t2);
    if (a > Float(7)) return 0;  // both terms below 1e-23
    return (-std::erfc(a) + std::exp(-a * a) / (a * Float(1.7724538509055160273))) / 2;
  }

  Float G1(const Vec3& w) const { return 1 / (1 + Lambda(w)); }

  // T(w) = |cos θ| (1 + 2 Λ(w)), the form of Smith's Λ the hot paths use: with it
  //   |cos θ| (1 + Λ(w)) = (T(w) + |cos θ|)/2,
  //   G2(wo, wi) = 2 |cos θo| |cos θi| / (|cos θi| T(wo) + |cos θo| T(wi)),
  //   G2/G1(wo)  = |cos θi| (T(wo) + |cos θo|) / (|cos θi| T(wo) + |cos θo| T(wi)),
  // sums of positive terms without a division per direction. For GGX (Heitz 2014,
  // eq. 86: 1 + 2Λ = sqrt(1 + α₀² tan²θ)) T is the length of the stretched direction
  // (αx x, αy y, z), which sample_visible computes anyway.
  template <int kType = kRuntime>
  [[gnu::always_inline]] Float smith_t(const Vec3& w) const {
    if (is_ggx<kType>()) {
      const Float sx = w.x * alpha_x, sy = w.y * alpha_y;
      return std::sqrt(sx * sx + sy * sy + w.z * w.z);
    }
    return std::abs(w.z) * (1 + 2 * Lambda(w));
  }
  // Height-correlated masking–shadowing (Heitz 2014, eq. 99).
  Float G2(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + Lambda(wo) + Lambda(wi)); }

  // Distribution of normals visible from w (Heitz & d'Eon 2014, eq. 2):
  // D_w(wm) = G1(w) max(0, w·wm) D(wm) / cos θw. For w below the surface (seen from
  // inside a dielectric) it is the distribution visible from −w, which sample_visible
  // draws from: the same normals, facing the other way.
  Float D_visible(const Vec3& w, const Vec3& wm) const {
    const Float cos_w = std::abs(w.z);
    if (cos_w == 0) return 0;
    const Float facing = std::copysign(Float(1), w.z) * dot(w, wm);
    return facing > 0 ? G1(w) / cos_w * D(wm) * facing : Float(0);
  }

  // A visible normal, unnormalised: the samplers need wm only through m/|m|², which saves
  // them a sqrt and a division on their critical path. 16 bytes, so that it is returned in
  // registers even from the out-of-line Beckmann sampler.
  struct VisibleNormal {
    Vec3 m;    // ∝ wm, m.z > 0
    Float m2;  // |m|²
    Vec3 wm() const { return m * (1 / std::sqrt(m2)); }
  };

  // Samples a normal from D_w for w on the upper side (w.z > 0).
  Vec3 sample_visible(const Vec3& w, Float u1, Float u2) const { return sample_visible_terms(w, u1, u2).wm(); }

  // GGX inline (the hot path, a few dozen instructions); Beckmann out of line.
  template <int kType = kRuntime>
  [[gnu::always_inline]] VisibleNormal sample_visible_terms(const Vec3& w, Float u1, Float u2) const {
    if (!is_ggx<kType>()) return sample_visible_beckmann(w, u1, u2);
    // Stretch w into the configuration of a unit-roughness distribution (both are
    // stretch-invariant; Heitz & d'Eon 2014, §4), sample there, unstretch the normal.
    // Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps": the visible
    // normals of the unit GGX are ws + a uniform direction (√(1 − z²) cos φ, √(1 − z²) sin φ, z)
    // on the cap z ≥ −ws.z, ws the unit stretched direction. Everything below is that,
    // scaled by L = |(αx x, αy y, z)| = T(w) (the normal's direction does not change), so
    // that ws = (αx x, αy y, z)/L needs no division: z' = L z, s' = L √(1 − z²), and
    // h.z = L (z + ws.z) is formed directly (> 0 for u2 < 1).
    const Float sx = alpha_x * w.x, sy = alpha_y * w.y;
    const Float len = std::sqrt(sx * sx + sy * sy + w.z * w.z);  // = smith_t(w)
    const SinCos ph = sincos_2pi(u1);
    const Float hz = (1 - u2) * (len + w.z);
    const Float z = hz - w.z;
    const Float s = std::sqrt(std::max(Float(0), (len - z) * (len + z)));
    const Vec3 m{alpha_x * (s * ph.cos + sx), alpha_y * (s * ph.sin + sy), hz};
    const Float m2 = length_squared(m);
    if (!(m.z > 0 && m2 > 0)) [[unlikely]] return {{0, 0, 1}, 1};  // degenerate (w = 0, u2 = 1): the macro normal
    return {m, m2};
  }

  // Classic sampling of wm ∝ D(wm) cos θm (Walter et al. 2007, eqs. 28, 35), kept for
  // comparison with visible-normal sampling; density pdf_classic().
  Vec3 sample_classic(Float u1, Float u2) const {
    // Slopes of the unit distribution, then stretched: r² = u/(1−u) (GGX) or −ln(1−u).
    const Float u = std::min(u1, kOneMinusEpsilon);
    const Float r = type == MicrofacetType::GGX ? std::sqrt(u / (1 - u)) : std::sqrt(-std::log(1 - u));
    const Float ph = 2 * kPi * u2;
    const Vec3 wm = normalize(Vec3{-alpha_x * r * std::cos(ph), -alpha_y * r * std::sin(ph), 1});
    return wm;
  }
  Float pdf_classic(const Vec3& wm) const { return D(wm) * std::max(Float(0), wm.z); }

 private:
  [[gnu::noinline]] VisibleNormal sample_visible_beckmann(const Vec3& w, Float u1, Float u2) const {
    const Vec3 ws = normalize(Vec3{alpha_x * w.x, alpha_y * w.y, w.z});  // stretched, as for GGX
    const Vec3 h = sample_beckmann_visible_standard(ws, u1, u2);
    const Vec3 m{alpha_x * h.x, alpha_y * h.y, h.z};
    const Float m2 = length_squared(m);
    if (!(m.z > 0 && m2 > 0)) return {{0, 0, 1}, 1};
    return {m, m2};
  }

  // Visible normal of the unit Beckmann distribution seen from ws (ws.z > 0), as an
  // unnormalised normal (−x̃, −ỹ, 1) from visible slopes (Heitz & d'Eon 2014, §5). With
  // ws rotated to azimuth 0 and c = cot θ, slope x̃ has density ∝ (c − x̃) exp(−x̃²) on
  // x̃ < c, whose CDF is [c √π/2 (1 + erf x̃) + exp(−x̃²)/2] / [c √π/2 (1 + erf c) +
  // exp(−c²)/2]; it is inverted by Newton's method safeguarded with bisection. ỹ is
  // independent, with density exp(−ỹ²)/√π: ỹ = erf⁻¹(2u − 1).
  static Vec3 sample_beckmann_visible_standard(const Vec3& ws, Float u1, Float u2) {
    const double sin_t = std::sqrt(std::max(0.0, double(ws.x) * ws.x + double(ws.y) * ws.y));
    // Beyond c = 1e8 the weight (c − x̃) is constant over the Gaussian to 1e-7.
    const double c = sin_t > 0 ? std::min(double(ws.z) / sin_t, 1e8) : 1e8;
    const double sqrt_pi_2 = 0.88622692545275801365;
    const double erf_c = std::erf(c);
    const double u = std::clamp(double(u1), 1e-12, 1 - 1e-12);
    const double target = u * (c * sqrt_pi_2 * (1 + erf_c) + 0.5 * std::exp(-c * c));
    double lo = -8, hi = c;
    // Start from a fitted inverse of the CDF in the erf domain, erf x̃ ≈ erf c −
    // (1 + erf c)(1 − u)^p(θ), p(θ) = 1 − 0.876 θ + 0.4265 θ² − 0.0594 θ³ (the initial
    // guess of BeckmannSample11 in pbrt-v3, src/core/microfacet.cpp, which inverts the
    // same CDF in the erf domain; Pharr, Jakob & Humphreys 2016). At normal
    // incidence it is erf⁻¹(2u − 1), the exact answer; at θ = 85° it takes 2.7 CDF
    // evaluations per sample instead of 6.5. Float precision is enough for a start.
    const Float theta = std::atan2(Float(sin_t), ws.z);
    const Float p = 1 + theta * (Float(-0.876) + theta * (Float(0.4265) - Float(0.0594) * theta));
    const double b = erf_c - (1 + erf_c) * double(std::pow(Float(1 - u), p));
    double x = std::clamp(double(erf_inv(Float(b))), lo, hi);
    for (int it = 0; it < 50; ++it) {
      const double ex = std::exp(-x * x);
      const double g = c * sqrt_pi_2 * (1 + std::erf(x)) + 0.5 * ex - target;
      if (std::abs(g) <= 2e-7 * target) break;  // beyond float precision of the slope
      if (g > 0) hi = x;
      else lo = x;
      // Newton steps that leave the bracket are replaced by bisection.
      const double dg = (c - x) * ex;
      double next = dg > 0 ? x - g / dg : 0.5 * (lo + hi);
      const bool newton = next > lo && next < hi;
      if (!newton) next = 0.5 * (lo + hi);
      const double step = std::abs(next - x);
      x = next;
      if (hi - lo < 1e-7 * std::max(1.0, std::abs(x))) break;
      // Newton converges quadratically: after a step this small the error is of order
      // step², far below float precision, and one more evaluation would only confirm it.
      if (newton && step < 1e-4 * std::max(1.0, std::abs(x))) break;
    }
    const double y = erf_inv(Float(2 * double(u2) - 1));
    // Rotate the slopes back to ws's azimuth.
    const double cp = sin_t > 0 ? ws.x / sin_t : 1, sp = sin_t > 0 ? ws.y / sin_t : 0;
    return {Float(-(cp * x - sp * y)), Float(-(sp * x + cp * y)), 1};
  }
};

}  // namespace gonio
