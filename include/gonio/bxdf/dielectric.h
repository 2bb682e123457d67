#pragma once
// Smooth dielectric interface: specular reflection with probability F and refraction by
// Snell's law with probability 1 − F (lecture §5.2–5.4), total internal reflection when
// sin²θt ≥ 1, and the radiance scaling (n_wo / n_wi)² of lecture eq. 27 in radiance mode
// only (Veach 1997, §5.2). eta = n_inside / n_outside; for wo.z < 0 the roles swap.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/fresnel.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

template <typename C>
struct DielectricBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "dielectric";
  Float eta = 1.5f;  // n_inside / n_outside
  // A thin film on the outside face (thin_film.h; inactive: the bare interface).
  ThinFilmT<Unpolarized<C>> film{};

  static constexpr BxDFFlags flags() {
    return BxDFFlags::SpecularReflection | BxDFFlags::SpecularTransmission;
  }
  Float relative_eta() const { return eta; }
  C f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  // u_lobe < F chooses reflection; each lobe's weight is its share divided by its
  // probability: 1 for reflection, (n_wo/n_wi)² (radiance) or 1 (importance) for
  // refraction.
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float, Float,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    if (film.active()) return sample_film(wo, u_lobe, mode);
    const bool inside = wo.z < 0;
    const Float inv = 1 / eta;
    const Float e = inside ? inv : eta;  // n(far side) / n(wo's side)
    const Float inv_e = inside ? eta : inv;
    const Float cos_o = std::abs(wo.z);
    // Fresnel (fresnel.h), 1 under total internal reflection.
    const Float r = fresnel_dielectric_oriented(cos_o, cos_o * cos_o, e, inv_e);
    const bool reflect = u_lobe < r;
    const Vec3 wi = scattered(wo, inv_e, reflect);
    const Float weight = reflect ? Float(1) : transmission_scale(e, mode);
    const C w = fresnel_factor<C>(
        weight,
        [&] {
          return broadcast<Unpolarized<C>>(reflect ? dielectric_reflection_mueller(cos_o, e)
                                                   : dielectric_transmission_mueller(cos_o, e));
        },
        wo, wi);
    return BSDFSampleT<C>{wi, w, reflect ? r : 1 - r, true,
                      reflect ? Lobe::Reflection : Lobe::Transmission, reflect ? Float(1) : e};
  }

  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return {};
    const Float eta_crossed = wo.z > 0 ? eta : 1 / eta;
    if (film.active()) {
      using U = Unpolarized<C>;
      const U r = film_reflectance(wo);
      return {C(r), C((U(1) - r) * transmission_scale(eta_crossed, mode))};
    }
    const Float r = fresnel_dielectric(wo.z, eta);
    return {C(r), C((1 - r) * transmission_scale(eta_crossed, mode))};
  }

  // The reflected or refracted direction (inv_e = n(wo's side) / n(far side)).
  // Refraction (lecture §5.3) in the local frame: wt = −wo/η + (cos θo/η − cos θt) n, n on
  // wo's side. Its z is taken from the tangential part, sqrt(1 − |wt_xy|²), rather than
  // from cos θt: 1 − cos²θo loses digits near normal incidence, which a large η
  // magnifies into a visibly non-unit vector. The decision for total internal
  // reflection stays with the caller, a function of cos θo alone.
  [[gnu::always_inline]] static Vec3 scattered(const Vec3& wo, Float inv_e, bool reflect) {
    if (reflect) return {-wo.x, -wo.y, wo.z};
    Float tx = -wo.x * inv_e, ty = -wo.y * inv_e;
    const Float t2 = tx * tx + ty * ty;
    if (t2 > 1) {  // rounding at the edge of total internal reflection
      const Float sc = 1 / std::sqrt(t2);
      tx *= sc;
      ty *= sc;
    }
    const Float tz = std::sqrt(std::max(Float(0), 1 - tx * tx - ty * ty));
    return {tx, ty, std::copysign(tz, -wo.z)};
  }

 private:
  // The film-covered interface's reflectance per channel for light along wo (from inside:
  // at the corresponding outside angle; 1 beyond the critical angle).
  Unpolarized<C> film_reflectance(const Vec3& wo) const {
    using U = Unpolarized<C>;
    const Float c1 = film_read_cos(std::abs(wo.z), eta, wo.z < 0);
    return c1 < 0 ? U(1) : film.reflectance(c1, U(eta), U(0));
  }

  // With a film the reflectance is a colour: the lobe is chosen with the probability of its
  // channel average, and each channel's weight is its share over that probability.
  std::optional<BSDFSampleT<C>> sample_film(const Vec3& wo, Float u_lobe, TransportMode mode) const {
    using U = Unpolarized<C>;
    const bool inside = wo.z < 0;
    const Float e = inside ? 1 / eta : eta, inv_e = inside ? eta : 1 / eta;
    const Float c = std::min(std::abs(wo.z), Float(1));
    const Float c1 = film_read_cos(c, eta, inside);
    const bool tir = c1 < 0;
    const U r = tir ? U(1) : film.reflectance(c1, U(eta), U(0));
    const Float p = tir ? Float(1) : std::clamp(r.average(), Float(0), Float(1));
    const bool reflect = u_lobe < p;
    const Vec3 wi = scattered(wo, inv_e, reflect);
    const U value = reflect ? r / p : (U(1) - r) * (transmission_scale(e, mode) / (1 - p));
    const C w = fresnel_factor<C>(
        value,
        [&] {
          if (tir) return broadcast<U>(dielectric_reflection_mueller(c, e));
          return film.mueller(c1, U(eta), U(0), reflect, reflect && inside);
        },
        wo, wi);
    return BSDFSampleT<C>{wi, w, reflect ? p : 1 - p, true, reflect ? Lobe::Reflection : Lobe::Transmission,
                          reflect ? Float(1) : e};
  }
};

using DielectricBxDF = DielectricBxDFT<Color>;

}  // namespace gonio
