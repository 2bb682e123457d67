#pragma once
// Smooth conductor: perfect specular reflection (lecture eq. 23) weighted by the Fresnel
// reflectance of a metal with complex index eta + i k, exact or by Schlick's
// approximation (lecture eq. 28), or by Hoffman's F82-tint generalisation of it
// (fresnel_f82, fresnel.h). Reflects on whichever side wo lies (SPEC §1).

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/fresnel.h"
#include "gonio/hemispherical_average.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

enum class FresnelModel : std::uint8_t { Exact, Schlick, F82 };

// Channel-wise conductor Fresnel, shared by the smooth conductor and (later) the rough one.
template <typename C>
struct ConductorFresnelT {
  using color_type = C;
  FresnelModel model = FresnelModel::Exact;
  C eta{1.0f};  // real part of the relative index
  C k{0.0f};    // extinction coefficient
  C f0{1.0f};   // reflectance at normal incidence, used by Schlick and F82
  C f82{1.0f};  // F82: the tint at μ = 1/7, in [0, 1] (1 = Schlick)
  // F82: its coefficient a = fresnel_f82_a(f0, f82) per channel, a function of the
  // material alone, computed once by prepare(): whoever sets f0 or f82 calls it.
  C f82_a{0.0f};
  // A thin film on the metal (thin_film.h; inactive: the bare metal), read over the complex
  // index (eta, k): the exact model's own, or an F82-tint curve's effective one
  // (f82_effective_index.h, openpbr). Where it covers film.coverage = w of the surface,
  // F = (1 − w) F_bare + w R_film, F_bare this model's own (F82-tint's for openpbr).
  ThinFilmT<C> film{};

  void prepare() { f82_a = fresnel_f82_a(f0, f82); }

  C operator()(Float cos_i) const { return (*this)(cos_i, cos_i * cos_i); }
  // The same with cos²θi given as well (callers that have it before cos θi: the exact
  // formula needs cos θi only after two square roots of its own).
  C operator()(Float cos_i, Float cos2_i) const {
    const Float c = std::abs(cos_i);
    if (film.active()) {
      const C r = film.film_reflectance(std::min(c, Float(1)), eta, k);
      return film.coverage < 1 ? bare(c, cos2_i) * (1 - film.coverage) + r * film.coverage : r;
    }
    return bare(c, cos2_i);
  }
  // The bare metal's reflectance at c = |cos θi|.
  C bare(Float c, Float cos2_i) const {
    if (model == FresnelModel::Schlick) return fresnel_schlick(f0, c);
    if (model == FresnelModel::F82) return fresnel_f82_from_a(f0, f82_a, c);
#if defined(__GNUC__)
    if constexpr (C::size() <= 4) return exact_simd(c, std::min(cos2_i, Float(1)));
#endif
    (void)cos2_i;
    return map(eta, k, [c](Float n, Float kk) { return fresnel_conductor(c, n, kk); });
  }

#if defined(__GNUC__)
  // fresnel_conductor_core (fresnel.h) for all channels at once, in a GCC/Clang vector of
  // 4 floats (SSE sqrtps/divps on x86-64): one channel's latency instead of three. Unused
  // lanes repeat channel 0, so they never divide 0 by 0.
  C exact_simd(Float c, Float c2) const {
    using V = Float __attribute__((vector_size(16)));
    V n, kk;
    for (int i = 0; i < 4; ++i) {
      n[i] = eta[i < C::size() ? i : 0];
      kk[i] = k[i < C::size() ? i : 0];
    }
    const V zero{};
    V rs, rp;
    fresnel_conductor_core<V>(zero + std::min(c, Float(1)), zero + (1 - c2), n, kk, rs, rp);
    const V r = (rs + rp) / 2;
    C out;
    for (int i = 0; i < C::size(); ++i) out[i] = r[i];
    return out;
  }
#endif

  // The Mueller matrix of the reflection in the s/p basis (polarization/interface.h), per
  // channel; fresnel_factor() sets its M00 to operator()'s value. Schlick's approximation
  // has no phase: it is taken as a non-polarizing reflector, diag(1, 1, −1, −1) (the Jones
  // matrix diag(−1, 1) of a perfect mirror in this basis) scaled by F; so is F82-tint,
  // Schlick's generalisation (Hoffman 2023), which has no phase either.
  MuellerT<C> mueller(Float cos_i) const {
    const Float c = std::min(std::abs(cos_i), Float(1));
    if (film.active()) {
      const MuellerT<C> r = film.film_mueller(c, eta, k, true, false);
      return film.coverage < 1 ? bare_mueller(c) * (1 - film.coverage) + r * film.coverage : r;
    }
    return bare_mueller(c);
  }
  MuellerT<C> bare_mueller(Float c) const {
    MuellerT<C> m;
    for (int ch = 0; ch < C::size(); ++ch) {
      MuellerT<Float> one;
      if (model == FresnelModel::Schlick || model == FresnelModel::F82) {
        one(0, 0) = one(1, 1) = 1;
        one(2, 2) = one(3, 3) = -1;
      } else {
        one = mueller_reflection(fresnel_conductor_amplitudes(c, eta[ch], k[ch]));
      }
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) m(i, j)[ch] = one(i, j);
    }
    return m;
  }
};

using ConductorFresnel = ConductorFresnelT<Color>;

// F_avg = 2 ∫ F(μ) μ dμ per channel (Kulla & Conty 2017; Simpson's rule, 64 panels by
// default: F is smooth in μ; openpbr's spectral film, made per shading point, takes 16).
// F82-tint without a film has its closed form (fresnel_f82_average; SPEC §2).
template <typename C>
C conductor_average_fresnel(const ConductorFresnelT<C>& fr, int panels = 64) {
  if (fr.model == FresnelModel::F82 && !fr.film.active()) return fresnel_f82_average(fr.f0, fr.f82);
  const auto avg = cosine_weighted_average(
      [&](double mu) {
        const C f = fr(Float(mu));
        std::array<double, size_t(C::size())> v{};
        for (int i = 0; i < C::size(); ++i) v[size_t(i)] = f[i];
        return v;
      },
      panels);
  C out;
  for (int i = 0; i < C::size(); ++i) out[i] = Float(avg[size_t(i)]);
  return out;
}

template <typename C>
struct ConductorBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "conductor";
  ConductorFresnelT<Unpolarized<C>> fresnel;

  static constexpr BxDFFlags flags() { return BxDFFlags::SpecularReflection; }
  C f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float, Float, Float,
                                   TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    const Vec3 wi{-wo.x, -wo.y, wo.z};
    return BSDFSampleT<C>{wi, fresnel_factor<C>(fresnel(wo.z), [&] { return fresnel.mueller(wo.z); }, wo, wi), 1,
                          true, Lobe::Reflection, 1};
  }

  // Unpolarized only: a Mueller matrix's albedo is its M00, the unpolarized model's. A
  // member template, so that the library's explicit instances for Mueller matrices
  // (polarization/instances.h) leave it out (clang 14 ignores a plain member's requires).
  template <typename U = C>
    requires(!kPolarized<U>)
  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    return {wo.z != 0 ? fresnel(wo.z) : C{}, C{}};
  }
};

using ConductorBxDF = ConductorBxDFT<Color>;

}  // namespace gonio
