#pragma once
// The machinery shared by the classic two-lobe models (Phong, Blinn–Phong, Ward,
// Ashikhmin–Shirley): a diffuse lobe sampled cosine-weighted and a glossy lobe with
// its own sampling, chosen with a fixed probability; the density is the mixture and
// the weight f |cos θi| / pdf. Models supply, for wo and wi on the upper side:
//   Color f_upper(wo, wi); Vec3 sample_lobe(wo, u1, u2); Float lobe_pdf(wo, wi);
//   Float diffuse_probability().
// Reflection is two-sided (SPEC §1): wo below the surface mirrors both directions.
// Directions within 1e-7 of the tangent plane scatter nothing: the glossy lobes divide
// by powers of cosines there, and the lost sliver of the diffuse lobe is negligible.

#include <cmath>
#include <optional>

#include "gonio/bxdf/contract.h"
#include "gonio/math/warp.h"

namespace gonio::diffuse_glossy {

inline constexpr Float kGrazing = 1e-7f;

inline bool usable(const Vec3& wo, const Vec3& wi) {
  return (wo.z > 0) == (wi.z > 0) && std::abs(wo.z) >= kGrazing && std::abs(wi.z) >= kGrazing;
}

template <typename M>
typename M::color_type f(const M& m, Vec3 wo, Vec3 wi) {
  if (!usable(wo, wi)) return {};
  if (wo.z < 0) {
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  return m.f_upper(wo, wi);
}

template <typename M>
Float pdf(const M& m, Vec3 wo, Vec3 wi) {
  if (!usable(wo, wi)) return 0;
  if (wo.z < 0) {
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  const Float pd = m.diffuse_probability();
  return pd * wi.z * kInvPi + (1 - pd) * m.lobe_pdf(wo, wi);
}

template <typename M>
std::optional<BSDFSampleT<typename M::color_type>> sample(const M& m, Vec3 wo, Float u_lobe, Float u1, Float u2) {
  if (std::abs(wo.z) < kGrazing) return std::nullopt;
  const bool flip = wo.z < 0;
  if (flip) wo.z = -wo.z;
  const Float pd = m.diffuse_probability();
  Vec3 wi = u_lobe < pd ? square_to_cosine_hemisphere(u1, u2) : m.sample_lobe(wo, u1, u2);
  if (!(wi.z >= kGrazing)) return std::nullopt;
  const Float p = pd * wi.z * kInvPi + (1 - pd) * m.lobe_pdf(wo, wi);
  if (!(p > 0)) return std::nullopt;
  const auto value = m.f_upper(wo, wi) * (wi.z / p);
  if (flip) wi.z = -wi.z;
  return BSDFSampleT<typename M::color_type>{wi, value, p, false, Lobe::Reflection, 1};
}

// The contract's f, pdf and sample for a model M that supplies the pieces above
// (curiously recurring template: no virtual call).
template <typename M, typename C>
struct Model {
  C f(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return diffuse_glossy::f(self(), wo, wi);
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode = TransportMode::Radiance) const {
    return diffuse_glossy::pdf(self(), wo, wi);
  }
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode = TransportMode::Radiance) const {
    return diffuse_glossy::sample(self(), wo, u_lobe, u1, u2);
  }

 private:
  const M& self() const { return static_cast<const M&>(*this); }
};

// Probability of the diffuse lobe from the lobes' average reflectances.
template <typename C>
Float diffuse_share(const C& kd, const C& ks) {
  const Float d = kd.average(), s = ks.average();
  return d + s > 0 ? d / (d + s) : Float(1);
}

}  // namespace gonio::diffuse_glossy
