#pragma once
// Energy compensation for the rough dielectric (Kulla & Conty 2017, "Revisiting
// Physically Based Shading at Imageworks", the dielectric case; design and derivation in
// docs/design/dielectric-multiscatter.md). Light that single scattering loses,
// 1 − E±(μo), is returned by a reciprocal lobe split between reflection and
// transmission. In importance mode, with "+" outside and "−" inside:
//   reflection on side s:  r_s (1 − E_s(μo)) (1 − E_s(μi)) / (π (1 − Ē_s))
//   transmission s → s':   t_s (1 − E_s(μo)) (1 − E_s'(μi)) / (π (1 − Ē_s'))
// with t₊ = (1 − F̄₊) x, t₋ = (1 − F̄₋)(1 − x), r = 1 − t, F̄ the cosine-weighted
// average Fresnel reflectance, 1 − F̄₋ = (1 − F̄₊)/η² and x = (1 − Ē₋)/((1 − Ē₊) + (1 − Ē₋)),
// the split for which t₊ (1 − Ē₊) = η² t₋ (1 − Ē₋): the lobe is then reciprocal in the
// sense of SPEC §1, and each side's lobes integrate to exactly 1 − E(μo).

#include <algorithm>
#include <cmath>

#include "gonio/bxdf/contract.h"
#include "gonio/math/warp.h"
#include "gonio/microfacet.h"

namespace gonio {

// E(μ) of the single-scattering rough dielectric (importance mode, R + T) for wo on the
// side of index n_wo, crossing to n_far: e = n_far / n_wo (any e > 0), and its mean.
Float dielectric_microfacet_albedo(MicrofacetType type, Float alpha, Float e, Float mu);
Float dielectric_microfacet_average_albedo(MicrofacetType type, Float alpha, Float e);
// F̄(η) = 2 ∫ F(μ) μ dμ for light arriving from the side of relative index η.
Float average_dielectric_fresnel(Float eta);

struct DielectricMultiscatterLobe {
  MicrofacetType type = MicrofacetType::GGX;
  Float alpha = 0.1f;
  Float eta = 1.5f;          // n_inside / n_outside
  Float fbar_out = 0;        // F̄ seen from outside
  Float e_avg_out = 1, e_avg_in = 1;
  Float r_out = 1, t_out = 0, r_in = 1, t_in = 0;

  static DielectricMultiscatterLobe make(const MicrofacetDistribution& d, Float eta) {
    return remake(d, eta, average_dielectric_fresnel(eta));
  }
  // With F̄ already known (a textured roughness changes α, not η).
  static DielectricMultiscatterLobe remake(const MicrofacetDistribution& d, Float eta, Float fbar_out) {
    DielectricMultiscatterLobe m;
    m.type = d.type;
    // Isotropic roughness only (material_from_json rejects anisotropic multiscatter):
    // the tables are for isotropic surfaces, and near total internal reflection the loss
    // of an anisotropic one is not bounded by that of any single isotropic α, so no
    // stand-in roughness keeps the total below 1 in every direction.
    m.alpha = std::sqrt(d.alpha_x * d.alpha_y);
    m.eta = eta;
    m.fbar_out = fbar_out;
    m.e_avg_out = dielectric_microfacet_average_albedo(m.type, m.alpha, eta);
    m.e_avg_in = dielectric_microfacet_average_albedo(m.type, m.alpha, 1 / eta);
    const Float miss_out = std::max(Float(0), 1 - m.e_avg_out), miss_in = std::max(Float(0), 1 - m.e_avg_in);
    const Float x = miss_out + miss_in > 0 ? miss_in / (miss_out + miss_in) : Float(0.5);
    m.t_out = (1 - fbar_out) * x;
    m.t_in = (1 - fbar_out) / (eta * eta) * (1 - x);
    m.r_out = 1 - m.t_out;
    m.r_in = 1 - m.t_in;
    return m;
  }

  Float E(bool outside, Float mu) const {
    return dielectric_microfacet_albedo(type, alpha, outside ? eta : 1 / eta, mu);
  }
  Float miss_avg(bool outside) const { return std::max(Float(1e-6), 1 - (outside ? e_avg_out : e_avg_in)); }

  // f in importance mode for wo, wi on the given sides, from |cos θo|, |cos θi|.
  Float f_importance(bool wo_outside, bool wi_outside, Float cos_o, Float cos_i) const {
    const Float split = wo_outside == wi_outside ? (wo_outside ? r_out : r_in) : (wo_outside ? t_out : t_in);
    return split * (1 - E(wo_outside, cos_o)) * (1 - E(wi_outside, cos_i)) / (kPi * miss_avg(wi_outside));
  }
  // Probability of sampling this lobe: the share 1 − E(μo) of the energy it carries.
  Float probability(bool wo_outside, Float cos_o) const {
    return std::clamp(1 - E(wo_outside, cos_o), Float(0), Float(0.9));
  }
  // Density of its sampling (cosine-weighted on the chosen side), without `probability`.
  Float pdf(bool wo_outside, bool wi_outside, Float cos_i) const {
    const Float side = wo_outside == wi_outside ? (wo_outside ? r_out : r_in) : (wo_outside ? t_out : t_in);
    return side * cos_i * kInvPi;
  }
};

}  // namespace gonio
