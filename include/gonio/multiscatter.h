#pragma once
// Energy compensation for multiple scattering between microfacets (Kulla & Conty 2017,
// "Revisiting Physically Based Shading at Imageworks", §"Energy compensation"): a
// reciprocal lobe added to the single-scattering BRDF,
//   f_ms(wo, wi) = F_ms (1 − E(μo)) (1 − E(μi)) / (π (1 − E_avg)),
// where E(μ) is the directional albedo of the single-scattering microfacet BRDF with
// F = 1, E_avg = 2 ∫ E(μ) μ dμ its cosine-weighted average, and
// F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg)) the colour of the light that escapes
// after bouncing (F_avg = 2 ∫ F(μ) μ dμ). With F = 1 the added lobe returns exactly the
// energy 1 − E(μo) the single-scattering lobe loses, for every wo.
//
// The lobe is importance-sampled by its own shape, μi ∝ (1 − E(μi)) μi (tabulated CDFs,
// AlbedoComplementSampler), so that its weight is F_ms (1 − E(μo)) whatever wi is.
//
// E(μ, α) and E_avg(α) come from tables that gonio computes itself at build time
// (tools/make_albedo_tables.cpp). They are indexed by the isotropic roughness, and α > 1
// uses the α = 1 entries. Anisotropic roughness: E(ωo) depends on ωo's azimuth too and on
// no single isotropic α (with sqrt(αx αy) standing in, a white furnace at α = [0.05, 1]
// kept 0.60 at normal incidence), so the lobe reads E(μ, φ) of the distribution itself,
// from tables on a grid of (αx, αy) made once per process (anisotropic_albedo.h); its μi is then drawn from the
// isotropic tables at α = max(αx, αy), whose loss 1 − E is at least the anisotropic one's
// nearly everywhere, so that the weight stays bounded, and lobe_pdf is that density.

#include <algorithm>
#include <cmath>
#include <memory>

#include "gonio/bxdf/anisotropic_albedo.h"
#include "gonio/color.h"
#include "gonio/math/warp.h"
#include "gonio/microfacet.h"

namespace gonio {

// Directional albedo E(μ) of the F = 1 single-scattering microfacet BRDF (one bilinear
// lookup) and its cosine-weighted average E_avg (one linear lookup).
Float microfacet_albedo(MicrofacetType type, Float alpha, Float mu);
Float microfacet_average_albedo(MicrofacetType type, Float alpha);

// Sampling μ with density ∝ (1 − E(μ)) μ, E as microfacet_albedo interpolates it. The
// interpolant is linear in the roughness between two table rows, so the density is the
// mixture of the two rows' densities with weights (1 − t) L₀ and t L₁ (L the rows' losses
// 1 − E_avg): prepared once per roughness, drawn per sample.
struct AlbedoComplementSampler {
  MicrofacetType type = MicrofacetType::GGX;
  int row = 0;          // the lower row; the upper one is row + 1
  Float p_row = 1;      // probability of drawing from the lower row
  Float loss = 0;       // (1 − t) L₀ + t L₁ = 2 ∫ (1 − E) μ dμ
  static AlbedoComplementSampler make(MicrofacetType type, Float alpha);
  // μ in [0, 1] from one uniform number.
  Float sample(Float u) const;
};

template <typename C>
struct MultiscatterLobeT {
  using color_type = C;
  MicrofacetType type = MicrofacetType::GGX;
  Float alpha = 0.1f;
  Float e_avg = 1;
  C f_ms;             // F_ms times 1/(π (1 − E_avg))
  Float energy_ratio = 0; // avg(F_ms) / avg(F_avg): sets how often the lobe is sampled
  C f_avg;            // the F_avg it was made with, to remake it for another roughness
  AlbedoComplementSampler sampler;  // draws μi ∝ (1 − E(μi)) μi
  Float inv_pi_loss = 0;  // 1 / (π (1 − E_avg)) of the sampler's normalisation (0: no lobe)
  // Anisotropic roughness: E(μ, φ) of the distribution (then `alpha` is the sampler's).
  AnisotropicAlbedoBlend aniso;

  // `f_avg`: the cosine-weighted average Fresnel reflectance 2 ∫ F(μ) μ dμ. No allocation
  // (an anisotropic distribution's tables are the process's, anisotropic_albedo.h).
  static MultiscatterLobeT<C> make(const MicrofacetDistribution& d, const C& f_avg) {
    MultiscatterLobeT<C> m;
    m.type = d.type;
    if (d.is_isotropic()) {
      m.alpha = d.alpha_x;
      m.e_avg = microfacet_average_albedo(m.type, m.alpha);
    } else {
      m.aniso = AnisotropicAlbedoBlend::at(d);
      m.alpha = std::max(d.alpha_x, d.alpha_y);
      m.e_avg = m.aniso.average();
    }
    m.f_avg = f_avg;
    const Float e = m.e_avg;
    // The lobe vanishes for a perfectly smooth (E_avg = 1) or black surface.
    const Float denom = kPi * std::max(Float(1e-6), 1 - e);
    const C fms = map(f_avg, [&](Float fa) { return fa * fa * e / (1 - fa * (1 - e)); });
    m.f_ms = fms / denom;
    m.energy_ratio = f_avg.average() > 0 ? fms.average() / f_avg.average() : Float(0);
    m.sampler = AlbedoComplementSampler::make(m.type, m.alpha);
    m.inv_pi_loss = m.sampler.loss > 0 ? 1 / (kPi * m.sampler.loss) : Float(0);
    return m;
  }

  // E(ω) in the distribution's frame.
  Float E(const Vec3& w) const { return aniso.active() ? aniso.E(w) : microfacet_albedo(type, alpha, std::abs(w.z)); }

  // The lobe from E(μo) and E(μi).
  C f(Float e_o, Float e_i) const { return f_ms * ((1 - e_o) * (1 - e_i)); }

  // Probability of sampling this lobe rather than the single-scattering one: its share
  // of the expected energy, F_ms (1 − E(μo)) against F_avg E(μo).
  Float probability(Float e_o) const {
    if (!(inv_pi_loss > 0)) return 0;
    const Float ms = energy_ratio * (1 - e_o);
    return ms + e_o > 0 ? std::clamp(ms / (ms + e_o), Float(0), Float(0.9)) : Float(0);
  }
  // Density of sample() per solid angle: (1 − E(μi)) μi / (π (1 − E_avg)), normalised
  // since 2π ∫ (1 − E) μ dμ = π (1 − E_avg). With it the lobe's weight is
  // f_ms cos θi / pdf = F_ms (1 − E(μo)) (1 − E_avg)/(1 − E_avg) — bounded, where cosine
  // sampling gave (1 − E(μi))/(1 − E_avg), 10⁴ for a near-smooth surface at grazing μi.
  // (Anisotropic: of the sampler's isotropic E at `alpha`, not the lobe's e_i.)
  Float lobe_pdf(Float cos_i, Float e_i) const {
    const Float e = aniso.active() ? microfacet_albedo(type, alpha, cos_i) : e_i;
    return std::max(Float(0), 1 - e) * cos_i * inv_pi_loss;
  }
  Float mix_pdf(Float e_o, Float pdf_single, Float cos_i, Float e_i) const {
    const Float p = probability(e_o);
    return (1 - p) * pdf_single + p * lobe_pdf(cos_i, e_i);
  }
  // wi ∝ (1 − E(μi)) μi: μi from the tables, φ uniform.
  Vec3 sample(Float u1, Float u2) const {
    const Float mu = sampler.sample(u1);
    const Float s = std::sqrt(std::max(Float(0), (1 - mu) * (1 + mu)));
    const Float ph = 2 * kPi * u2;
    return {s * std::cos(ph), s * std::sin(ph), mu};
  }
};

using MultiscatterLobe = MultiscatterLobeT<Color>;

}  // namespace gonio
