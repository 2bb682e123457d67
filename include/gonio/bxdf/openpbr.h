#pragma once
// OpenPBR Surface 1.1 (Academy Software Foundation, "OpenPBR Surface specification",
// v1.1, 2024-06-28; cited as SPEC-OPB with its section names) as one BSDF built from
// gonio's own lobes (issue 35, docs/openpbr.md). The slab tree of SPEC-OPB "Model",
// reduced to a mixture of lobes as its "Reduction to a mixture of lobes" does:
//
//   f = lerp(δ_passthrough, f_surface, geometry_opacity)                 (opacity)
//   f_surface = F f_fuzz + (1 − F E_fuzz(v)) f_coated                     (fuzz)
//   f_coated  = C f_coat + lerp(1, A_coat (1 − E_coat(v)), C) Δ f_base   (coat)
//   f_base    = M ξ f_metal + (1 − M) f_dielectric
//   f_dielectric = (1 − T) [f_spec + N_s (1 − E_s(wo))(1 − E_s(wi)) f_diffuse] + T f_glass
//
// v is the view direction (wo in radiance mode, wi in importance mode: the adjoint).
//
// Layering, per layer (the issue asks for the reciprocal albedo scaling
// f_top + f_below (1 − E_top(wo))(1 − E_top(wi))/(1 − Ē_top) where it is allowed):
//  * specular over diffuse (glossy-diffuse): the RECIPROCAL form. SPEC-OPB "Glossy-diffuse"
//    allows it there ("f_dielectric + N (1 − E(ωi))(1 − E(ωo)) f_diffuse", N a normalisation
//    "such that eq. glossy_diffuse_albedo_constraint is satisfied", left to the
//    implementation for a rough base). For a Lambertian base N = 1/(1 − Ē_s) makes a base of
//    albedo C reflect exactly C (1 − E_s(wo)). For EON (base_diffuse_roughness > 0) that
//    constant left up to 1.6 % at grazing (EON is not Lambert's shape), so N is taken
//    separable, N = b(μo) b(μi) (still reciprocal), with b solved once per material so that
//    the white base reflects 1 − E_s(μo) at 64 cosines: b_i Σ_j k(μi, μj)(1 − E_s(μj)) b_j μj/64
//    = 1, k the azimuthal integral of the albedo-1 EON lobe (closed form, diffuse_kernel),
//    by the symmetric scaling iteration b ← b / sqrt(b K b) (a matrix balancing). With the
//    specular layer's E_s the isotropic one of its mean roughness. Below the specular layer sits the EON lobe
//    (eon.h) of albedo lerp(base_weight·base_color, subsurface_color, S): the subsurface is
//    a BSDF here (a diffuse-like lobe of albedo subsurface_color; the BSSRDF is the
//    renderer's, not stage 1's).
//  * coat over base and fuzz over coated base: the VIEW-DEPENDENT form of SPEC-OPB eqs.
//    `coat_layering_formula_with_albedo_scaling` and `fuzz-layering-approx`. The reciprocal
//    form over a specular base gains energy: a white mirror under a coat of Ē would reflect
//    E(wo) + (1 − E(wo))²/(1 − Ē) at normal incidence, 1.049 for coat_ior 1.6. The fuzz lobe
//    itself is not reciprocal (sheen.h). So a material with coat_weight or fuzz_weight > 0
//    is not reciprocal (nonreciprocal_reason()); the rest is.
//  * metal: F82-tint (Kutz et al. 2021, SPEC-OPB "Metal") with specular_color as the tint at
//    82° and Kulla–Conty's multiple-scattering lobe (roughconductor.h, multiscatter.h; for an
//    anisotropic roughness from the distribution's own E(μ, φ), anisotropic_albedo.h), times
//    ξ = min(specular_weight, 1) once.
//  * glass (transmission_weight): the rough dielectric of roughdielectric.h with its
//    Kulla–Conty compensation (R + T conserves energy), transmission_color a constant tint
//    on the refraction when transmission_depth is 0 (SPEC-OPB "Translucent base"; with a
//    depth the interior is the renderer's medium). Thin-walled: the thin sheet
//    (thindielectric.h; rough: rough_sheet below) and the thin-walled
//    subsurface ½ S (1 ∓ g) of an albedo-1 EON lobe reflected and transmitted (SPEC-OPB
//    "Thin-walled case").
// Coat: absorption A_coat = coat_color^((1/μt_o + 1/μt_i)/2) (SPEC-OPB "View-dependent
// absorption", coat_color = T² at normal incidence), darkening Δ = lerp(1, (1 − K)/(1 − E_b K),
// C·coat_darkening), K = 1 − (1 − Ē_coat)/η_c² (SPEC-OPB "Darkening": the interfaced-Lambertian
// result; with Ē of the coat's own lobe it is exactly plastic.h's internal-reflection series),
// roughening r' = lerp(r, min(1, r⁴ + 2 r_c⁴)^¼, C) of the base (SPEC-OPB "Roughening"), and
// the base's index seen through the coat η_s = lerp(n_b, tirfix(n_b / n_c), C) (SPEC-OPB eq.
// `specular_ior_ratio_with_tir_fix`). specular_weight ξ modulates that index (SPEC-OPB eqs.
// `unmodulated_fresnel`, `modulated_ior`): F_s = ((1 − η)/(1 + η))², ε = sgn(η − 1)
// sqrt(min(ξ F_s, 0.99999)), η' = (1 + ε)/(1 − ε). An index below 1 reflects as its inverse
// (the same TIR fix; the coat tables are for η ≥ 1). Thin film (Belcour & Barla 2017,
// thin_film.h) on the dielectric reflection lobe, on the metal (over the F82 curve's
// effective complex index, f82_effective_index.h) and on the glass, covering
// thin_film_weight of each.
//
// Polarized mode (C = MuellerT<colour>): the specular, coat, metal and glass lobes polarize
// (fresnel_factor); the diffuse, subsurface and fuzz lobes depolarize, and the layer
// factors (transmission through coat and fuzz) are taken as non-polarizing attenuations.
//
// No allocation, no virtual call: the model is a value; everything that depends on the
// material alone is made once by make() (per shading point in spectral mode).

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/openpbr_params.h"
#include "gonio/bxdf/eon.h"
#include "gonio/bxdf/f82_effective_index.h"
#include "gonio/bxdf/roughconductor.h"
#include "gonio/bxdf/roughdielectric.h"
#include "gonio/bxdf/sheen.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/bxdf/thindielectric.h"
#include "gonio/coat_albedo.h"
#include "gonio/dielectric_multiscatter.h"
#include "gonio/fresnel.h"
#include "gonio/microfacet.h"
#include "gonio/multiscatter.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

namespace openpbr {

// SPEC-OPB "Microfacet model", eq. `openpbr-anisotropy-formula`: α_t = r² sqrt(2/(1 + (1 − a)²)),
// α_b = (1 − a) α_t, along the tangent (x) and bitangent (y).
inline MicrofacetDistribution distribution(Float r, Float a) {
  MicrofacetDistribution d;
  d.type = MicrofacetType::GGX;
  const Float b = 1 - std::clamp(a, Float(0), Float(1));
  // Floored at 1e-4 (still "smooth" below MicrofacetDistribution::kSmoothAlpha): anisotropy 1
  // gives α_b = 0, on which D and Λ would divide by zero.
  const Float at = r * r * std::sqrt(2 / (1 + b * b));
  d.alpha_x = std::max(at, Float(1e-4));
  d.alpha_y = std::max(b * at, Float(1e-4));
  return d;
}

// SPEC-OPB eq. `modulated_ior`: the index whose normal-incidence Fresnel is ξ F_s.
inline Float modulated_ior(Float eta, Float xi) {
  const Float fs = (1 - eta) * (1 - eta) / ((1 + eta) * (1 + eta));
  const Float s = std::sqrt(std::clamp(xi * fs, Float(0), Float(0.99999)));
  const Float eps = eta >= 1 ? s : -s;
  return (1 + eps) / (1 - eps);
}

// The TIR fix (SPEC-OPB eq. `specular_ior_ratio_with_tir_fix`): an index below 1 reflects as its inverse.
inline Float tirfix(Float eta) { return eta < 1 ? 1 / eta : eta; }

// The specular layer's reflecting index: the base's index seen through the coat,
// η_s = lerp(n_b, tirfix(n_b / n_c), C) (SPEC-OPB eq. `specular_ior_ratio_with_tir_fix`),
// modulated by specular_weight (eq. `modulated_ior`), as an index ≥ 1.
inline Float specular_layer_eta(Float specular_ior, Float coat_ior, Float coat_weight, Float specular_weight) {
  const Float eta_s = specular_ior + (tirfix(specular_ior / coat_ior) - specular_ior) * coat_weight;
  return tirfix(modulated_ior(eta_s, specular_weight));
}

// A turn about the normal by the fraction `turn` (cos, sin), and directions into/out of it.
struct Rotation {
  Float c = 1, s = 0;
  static Rotation of(Float turn) {
    if (turn == 0) return {};
    const double a = 2 * kPiD * double(turn);
    return {Float(std::cos(a)), Float(std::sin(a))};
  }
  bool identity() const { return c == 1 && s == 0; }
  // Into the lobe's frame (its tangent turned by the angle).
  Vec3 in(const Vec3& w) const { return {c * w.x + s * w.y, -s * w.x + c * w.y, w.z}; }
  Vec3 out(const Vec3& w) const { return {c * w.x - s * w.y, s * w.x + c * w.y, w.z}; }
};

// The single-scattering microfacet reflection of wo, wi (upper side, lobe frame), per unit
// Fresnel: f/F = D G2 / (4 cos θo cos θi) (Walter et al. 2007, eq. 20), its visible-normal
// density D / (4 cos θo (1 + Λo)) and the facet cosine |wo + wi|/2 (the forms of plastic.h).
struct Glossy {
  Float f_per_f = 0, pdf = 0, cos_h = 1;
  bool valid = false;
};
inline Glossy glossy(const MicrofacetDistribution& d, const Vec3& wo, const Vec3& wi) {
  Glossy g;
  if (wo.z < Float(1e-7) || wi.z < Float(1e-7)) return g;
  const Vec3 h = wo + wi;
  const Float h2 = length_squared(h);
  if (!(h2 > 0)) return g;
  const Float D = d.D_unnormalized(h, h2);
  const Float to = d.smith_t(wo), ti = d.smith_t(wi);
  g.f_per_f = D / (2 * (wi.z * to + wo.z * ti));
  g.pdf = D / (2 * (to + wo.z));
  g.cos_h = std::min(std::sqrt(h2) / 2, Float(1));
  g.valid = true;
  return g;
}

// What make() solves by quadrature at kNormNodes cosines μ_j = (j + ½)/kNormNodes, which the
// spectral and polarized forms of a model take from its RGB form (made from the same
// parameters) instead of solving again: a view of that model's tables (nothing is copied
// until make() takes what it needs; spectral mode makes a model per shading point).
constexpr int kNormNodes = 64;
// The film tables hold one more node, at a cosine this close to grazing: the film changes
// the rough lobe's albedo fastest there (issue 56: from the first node, μ = 1/128, to
// θ = 89.95° the change grew by 0.009 at a 10 µm film of index 10⁴, and the diffuse under it
// took that as its own: albedo 1.0055).
constexpr int kFilmNodes = kNormNodes + 1;
constexpr Float kFilmGrazingMu = Float(1e-5);
// Also the averages that make() integrates (2048 panels each, some 13 µs): the coat's and
// the bare specular layer's Ē, and the glass's compensation lobe.
struct Solved {
  const std::array<Float, kNormNodes>* diff_b = nullptr;
  const std::array<Float, kFilmNodes>* film_dE = nullptr;
  const std::array<Color, kFilmNodes>* film_dE_rgb = nullptr;  // per RGB channel, with a film
  const std::array<Color, kNormNodes>* diff_b_rgb = nullptr;
  const Float* coat_avg = nullptr;
  const Float* spec_avg_bare = nullptr;
  const std::optional<DielectricMultiscatterLobe>* glass_ms = nullptr;
};

// A table at the nodes μ_j = (j + ½)/kNormNodes read at μ, linearly (clamped at the ends).
template <typename T>
T at_nodes(const std::array<T, kNormNodes>& table, Float mu) {
  const Float x = std::clamp(mu * kNormNodes - Float(0.5), Float(0), Float(kNormNodes - 1));
  const int i = std::min(int(x), kNormNodes - 2);
  const Float t = x - Float(i);
  return table[size_t(i)] * (1 - t) + table[size_t(i + 1)] * t;
}
// A film table (nodes μ_j, then kFilmGrazingMu) read at μ: below the first node, linearly
// between the grazing node and it.
template <typename T>
T at_film_nodes(const std::array<T, kFilmNodes>& table, Float mu) {
  constexpr Float first = Float(0.5) / kNormNodes;
  if (mu >= first) {
    const Float x = std::min(mu * kNormNodes - Float(0.5), Float(kNormNodes - 1));
    const int i = std::min(int(x), kNormNodes - 2);
    const Float t = x - Float(i);
    return table[size_t(i)] * (1 - t) + table[size_t(i + 1)] * t;
  }
  const Float t = std::clamp((mu - kFilmGrazingMu) / (first - kFilmGrazingMu), Float(0), Float(1));
  return table[size_t(kNormNodes)] * (1 - t) + table[0] * t;
}

enum Component : int { kPass, kFuzz, kCoat, kMetal, kSpec, kDiffuse, kDiffuseT, kGlass, kLobes };

// The film over the metal and over the glass with RGB mode's tables of its reflectance
// there (made at parse time, src/material.cpp); an inactive one is the specular layer's
// film read at the channels' wavelengths.
template <typename U>
struct SubstrateFilms {
  ThinFilmT<U> metal, glass;
};
// Below this index the film's table does not resolve a glass (material.cpp's
// kThinFilmMinSubstrateEta): such a glass is bare.
inline constexpr Float kMinFilmGlassEta = Float(0.1);

}  // namespace openpbr

template <typename C>
struct OpenPbrBxDFT {
  using color_type = C;
  using U = Unpolarized<C>;
  static constexpr std::string_view kName = "openpbr";

  OpenPbrParams<U> params;  // as given (what the model was made from)

  // What make() derives.
  Float opacity = 1, fuzz = 0, coat = 0, metal_w = 0, trans = 0, sss = 0;
  bool thin = false;
  bool reciprocal_layering = false;  // params.reciprocal_layering (layer_through)
  Float fuzz_avg = 0;                // fuzz · cosine-weighted mean of sheen_albedo (reciprocal layering)
  BxDFFlags flags_ = BxDFFlags::DiffuseReflection;
  // Fuzz (sheen.h), white for the layer's albedo, tinted for its lobe.
  SheenBxDFT<U> sheen{};
  // Coat.
  MicrofacetDistribution coat_dist{};
  openpbr::Rotation coat_rot{};
  Float coat_eta = Float(1.6);  // tirfix(coat_ior)
  CoatAlbedo coat_albedo{};
  Float coat_avg = 0;          // Ē_coat
  U coat_trans{Float(1)};       // sqrt(coat_color): the one-way transmittance at normal incidence
  U coat_log_trans{Float(0)};   // its logarithm (≥ −10⁴), so that T^k is one exp per channel
  U darkening{Float(1)};        // lerp(1, Δ, C δ)
  // Metal.
  RoughConductorBxDFT<C> metal{};
  Float metal_xi = 1;           // min(specular_weight, 1)
  U f82_avg_est{Float(1)};
  // Dielectric specular layer (reflection lobe of the opaque base).
  MicrofacetDistribution spec_dist{};
  openpbr::Rotation spec_rot{};
  Float spec_eta = Float(1.5);  // the reflecting index (≥ 1)
  CoatAlbedo spec_albedo{};
  Float spec_avg = 0;            // Ē_s
  Float spec_norm = 1;           // 1/(1 − Ē_s)
  Float film_w = 0;
  ThinFilmT<U> film{};
  // Diffuse (EON): single- and multiple-scattering colours of the mixture (eon.h).
  EonBxDFT<U> eon{};             // its sampling and pdf
  U diff_rho{}, diff_rho_ms{};   // reflection
  U difft_rho{}, difft_rho_ms{}; // thin-walled transmission
  Float eon_a = 1, eon_ms = 0;
  // The separable normalisation b(μ) of the diffuse under the specular layer (top of the
  // file), at μ_j = (j + ½)/kNormNodes; unused (b = 1/sqrt(1 − Ē_s)) at roughness 0.
  static constexpr int kNormNodes = openpbr::kNormNodes;
  std::array<Float, kNormNodes> diff_b{};
  // A thin film's change of the rough specular lobe's albedo at the same cosines (unused
  // without a film or for a smooth layer, whose film albedo is exact: solve_film_albedo()).
  std::array<Float, openpbr::kFilmNodes> film_dE{};
  U film_norm_ratio{Float(1)};  // (1 − Ē_s)/(1 − Ē_c) per channel with a film (make())
  std::array<Color, openpbr::kFilmNodes> film_dE_rgb{};
  std::array<Color, kNormNodes> diff_b_rgb{};
  Float spec_avg_bare = 0;       // Ē_s without the film
  openpbr::Solved solved() const {
    return {&diff_b,    &film_dE,       &film_dE_rgb,      &diff_b_rgb,
            &coat_avg,  &spec_avg_bare, &glass.multiscatter};
  }
  // Glass.
  RoughDielectricBxDFT<C> glass{};
  ThinDielectricBxDFT<C> sheet{};
  ThinDielectricBxDFT<C> sheet_film{};
  // A thin-walled glass whose specular layer is rough (SPEC-OPB "Thin-walled": the sheet's
  // reflection lobe and its undeflected transmission, roughened): at each microfacet h the
  // sheet reflects R_sheet(wo·h) (thindielectric.h, the film's Airy sum over film_w of
  // it) and transmits 1 − R_sheet, the transmitted light leaving along the reflection
  // mirrored through the surface: the lobe D G2 / (4 μo μi) of the specular layer's
  // roughness centred on −wo instead of on the mirror direction. The two lobes share their
  // facets, so at each h R + T = 1, and the pair is reciprocal (D, G2 and wo·h are symmetric
  // under the mirror). The width of the transmitted lobe is the reflection's (Kulla &
  // Conty 2017 roughen it by the index; gonio keeps one roughness, documented).
  bool rough_sheet = false;
  U trans_tint{Float(1)};

  // `solved`: the quadratures of a model made from the same parameters (the spectral
  // and polarized forms copy the RGB model's instead of solving again).
  // `films`: the same film over the metal and the glass (openpbr::SubstrateFilms).
  static OpenPbrBxDFT make(const OpenPbrParams<U>& p, ThinFilmT<U> film_on_spec = {},
                           const openpbr::Solved* solved = nullptr, openpbr::SubstrateFilms<U> films = {}) {
    using namespace openpbr;
    OpenPbrBxDFT m;
    m.params = p;
    m.opacity = std::clamp(p.geometry_opacity, Float(0), Float(1));
    m.fuzz = p.fuzz_weight;
    m.coat = p.coat_weight;
    m.metal_w = p.base_metalness;
    m.trans = p.transmission_weight;
    m.sss = p.subsurface_weight;
    m.thin = p.geometry_thin_walled;
    m.reciprocal_layering = p.reciprocal_layering;
    // Fuzz: fuzz_roughness 0 is the sheen fits' smallest roughness (sheen.h).
    m.sheen.color = p.fuzz_color;
    m.sheen.roughness = sheen_fit::clamp_roughness(p.fuzz_roughness);
    if (m.reciprocal_layering && m.fuzz > 0) {
      // F Ē_fuzz = F 2 ∫ R(μ) μ dμ, by the midpoint rule at the normalisation's nodes.
      double avg = 0;
      for (int j = 0; j < kNormNodes; ++j) {
        const Float mu = (Float(j) + Float(0.5)) / kNormNodes;
        avg += 2.0 * double(sheen_albedo(mu, m.sheen.roughness)) * double(mu) / kNormNodes;
      }
      m.fuzz_avg = m.fuzz * Float(avg);
    }
    // Coat.
    m.coat_dist = distribution(p.coat_roughness, p.coat_roughness_anisotropy);
    m.coat_rot = Rotation::of(p.coat_rotation);
    m.coat_eta = tirfix(p.coat_ior);
    m.coat_albedo = CoatAlbedo::make(MicrofacetType::GGX, m.coat_eta);
    if (!m.coat_dist.effectively_smooth()) m.coat_albedo.prepare_roughness(m.coat_dist.alpha_x);
    // Ē_coat only under a coat (its darkening and lobe scale by coat_weight).
    if (!(m.coat > 0)) m.coat_avg = 0;
    else if (solved) m.coat_avg = *solved->coat_avg;
    else
      m.coat_avg = m.coat_eta == 1 ? Float(0)
                   : m.coat_dist.effectively_smooth() ? average_dielectric_fresnel(m.coat_eta)
                                                      : m.coat_albedo.average(m.coat_dist);
    m.coat_trans = map(p.coat_color, [](Float c) { return std::sqrt(std::max(c, Float(0))); });
    m.coat_log_trans = map(m.coat_trans, [](Float t) {
      return t >= 1 ? Float(0) : t > 0 ? std::max(std::log(t), Float(-1e4)) : Float(-1e4);
    });
    // The base's roughness, roughened by the coat (SPEC-OPB "Roughening").
    const Float rb = p.specular_roughness, rc = p.coat_roughness;
    const Float rough = rb + (std::pow(std::min(Float(1), rb * rb * rb * rb + 2 * rc * rc * rc * rc), Float(0.25)) - rb) * m.coat;
    m.spec_eta = specular_layer_eta(p.specular_ior, p.coat_ior, m.coat, p.specular_weight);
    m.spec_dist = distribution(rough, p.specular_roughness_anisotropy);
    m.spec_rot = Rotation::of(p.specular_rotation);
    m.spec_albedo = CoatAlbedo::make(MicrofacetType::GGX, m.spec_eta);
    if (!m.spec_dist.effectively_smooth()) m.spec_albedo.prepare_roughness(m.spec_dist.alpha_x);
    m.film_w = film_on_spec.active() ? p.thin_film_weight : Float(0);
    m.film = film_on_spec;
    if (solved) m.spec_avg_bare = *solved->spec_avg_bare;
    else
      m.spec_avg_bare = m.spec_eta == 1 ? Float(0)
                        : m.spec_dist.effectively_smooth() ? average_dielectric_fresnel(m.spec_eta)
                                                           : m.spec_albedo.average(m.spec_dist);
    m.spec_avg = m.spec_avg_bare;
    // Ē_s must be the cosine-weighted mean of the E_s(μ) that eval uses, film included, or
    // the diffuse under a film gains (an anti-reflection film) or loses energy: the film's
    // change of E_s, 2 ∫ (E_film(μ) − E(μ)) μ dμ, added by the midpoint rule.
    if (m.film_w > 0 && !m.spec_dist.effectively_smooth()) {
      if (solved) {
        m.film_dE = *solved->film_dE;
        if constexpr (std::is_same_v<U, Color>) m.film_dE_rgb = *solved->film_dE_rgb;
      } else {
        m.solve_film_albedo();
      }
    }
    U channel_change(Float(0));
    // Only a diffuse under the specular layer reads Ē_s (its normalisation).
    if (m.film_w > 0 && (1 - m.metal_w) * (1 - m.trans) > 0) {
      double change = 0;
      for (int j = 0; j < kNormNodes; ++j) {
        const Float mu = (Float(j) + Float(0.5)) / kNormNodes, e = m.spec_E_iso_bare(mu);
        change += 2.0 * double(m.with_film(mu, e) - e) * double(mu) / kNormNodes;
      }
      // The channels' deviation: RGB mode reads tables; spectral mode sums Airy per
      // wavelength at each node, per shading point, so it takes 16 nodes (gonio_bench_spectrum's
      // to_spectral_model/openpbr_base_film: 27.0 µs per model with 64 nodes, 8.4 with 16).
      const int dev_nodes = std::is_same_v<U, Color> ? kNormNodes : 16;
      for (int j = 0; j < dev_nodes; ++j) {
        const Float mu = (Float(j) + Float(0.5)) / Float(dev_nodes);
        channel_change += m.film_deviation(mu) * (2 * mu / Float(dev_nodes));
      }
      m.spec_avg = std::clamp(m.spec_avg + Float(change), Float(0), Float(1));
    }
    m.spec_norm = 1 / std::max(Float(1e-6), 1 - m.spec_avg);
    // Per channel the film's Ē_c = Ē_s + its channel's deviation; the diffuse's normalisation
    // is scaled by (1 − Ē_s)/(1 − Ē_c), which makes it exact per channel for a Lambertian base.
    m.film_norm_ratio = map(channel_change, [&](Float d) {
      return (1 - m.spec_avg) / std::max(Float(1e-6), 1 - std::clamp(m.spec_avg + d, Float(0), Float(1)));
    });
    // Metal: F82-tint, F0 = base_weight base_color, tint specular_color (SPEC-OPB "Metal").
    m.metal.distribution = m.spec_dist;
    m.metal.fresnel.model = FresnelModel::F82;
    m.metal.fresnel.f0 = map(p.base_color * p.base_weight, [](Float v) { return std::clamp(v, Float(0), Float(1)); });
    m.metal.fresnel.f82 = map(p.specular_color, [](Float v) { return std::clamp(v, Float(0), Float(1)); });
    m.metal.fresnel.prepare();
    // The film on the metal (SPEC-OPB "Thin-film iridescence": on the base substrate, metal
    // or dielectric), over the F82 curve's effective complex index (f82_effective_index.h),
    // covering thin_film_weight of it; Kulla–Conty's F_avg is then that of the mixture.
    const auto substrate_film = [&](const ThinFilmT<U>& given) {
      ThinFilmT<U> f = given;
      if (!f.active()) {
        f = film_on_spec;
        f.table.reset();  // film_on_spec's is over the specular layer's index
      }
      f.coverage = std::clamp(p.thin_film_weight, Float(0), Float(1));
      return f;
    };
    if (m.metal_w > 0 && film_on_spec.active() && p.thin_film_weight > 0) {
      m.metal.fresnel.film = substrate_film(films.metal);
      f82_effective_index(m.metal.fresnel.f0, m.metal.fresnel.f82, m.metal.fresnel.eta, m.metal.fresnel.k);
      // RGB mode reads the film's table; spectral mode sums Airy per wavelength, per shading
      // point: 16 panels (gonio_bench_spectrum's to_spectral_model/openpbr_metal_film: 9.0 µs
      // per model; 52 µs with 64 panels and the Ē_s loop above, which it now skips).
      m.f82_avg_est = conductor_average_fresnel(m.metal.fresnel, std::is_same_v<U, Color> ? 64 : 16);
    } else {
      m.f82_avg_est = fresnel_f82_average(m.metal.fresnel.f0, m.metal.fresnel.f82);
    }
    // Anisotropic roughness too (multiscatter.h: E(μ, φ) from the process's tables on a
    // grid of (αx, αy), anisotropic_albedo.h, so a textured roughness tabulates nothing per
    // shading point). Made whatever the metalness.
    if (!m.spec_dist.effectively_smooth())
      m.metal.multiscatter = MultiscatterLobeT<U>::make(m.spec_dist, m.f82_avg_est);
    m.metal_xi = std::clamp(p.specular_weight, Float(0), Float(1));
    // Diffuse: EON of roughness base_diffuse_roughness (eon.h), mixed with the subsurface's.
    const Float r = p.base_diffuse_roughness;
    m.eon = EonBxDFT<U>::make(U(1), r);
    const U rho_d = map(p.base_color * p.base_weight, [](Float v) { return std::clamp(v, Float(0), Float(1)); });
    const U rho_s = map(p.subsurface_color, [](Float v) { return std::clamp(v, Float(0), Float(1)); });
    const eon::Constants<U> kd(rho_d, r), ks(rho_s, r);
    m.eon_a = kd.a;
    m.eon_ms = kd.ms;
    if (!m.thin) {
      m.diff_rho = rho_d * (1 - m.sss) + rho_s * m.sss;
      m.diff_rho_ms = kd.rho_ms * (1 - m.sss) + ks.rho_ms * m.sss;
    } else {
      // SPEC-OPB "Thin-walled case": ½ S (1 − g) reflected, ½ S (1 + g) transmitted, each an
      // albedo-1 lobe (ρ = ρ_ms = 1 for EON).
      const Float g = std::clamp(p.subsurface_scatter_anisotropy, Float(-1), Float(1));
      const U half_r = rho_s * (Float(0.5) * (1 - g)), half_t = rho_s * (Float(0.5) * (1 + g));
      m.diff_rho = rho_d * (1 - m.sss) + half_r * m.sss;
      m.diff_rho_ms = kd.rho_ms * (1 - m.sss) + half_r * m.sss;
      m.difft_rho = half_t * m.sss;
      m.difft_rho_ms = half_t * m.sss;
    }
    if (solved) {
      m.diff_b = *solved->diff_b;
      if constexpr (std::is_same_v<U, Color>)
        if (m.film_w > 0) m.diff_b_rgb = *solved->diff_b_rgb;
    }
    else if (r > 0) m.solve_diffuse_norm();
    // Glass.
    m.glass.distribution = m.spec_dist;
    m.glass.eta = modulated_ior(p.specular_ior, p.specular_weight);
    // The glass's compensation only where there is a glass (transmission_weight > 0, not
    // thin-walled); `solved`'s when it has one (its inputs, the distribution and the
    // index, are the same there).
    if (m.trans > 0 && !m.thin && !m.glass.specular() && m.glass.distribution.is_isotropic() &&
        m.glass.eta >= Float(0.25) && m.glass.eta <= Float(4))
      m.glass.multiscatter = solved && *solved->glass_ms ? *solved->glass_ms
                                                         : DielectricMultiscatterLobe::make(m.glass.distribution, m.glass.eta);
    // The film on the glass (SPEC-OPB "Thin-film iridescence": on the dielectric base "the
    // thin-film should also generate color fringes in the transmission lobe"): the rough
    // dielectric's own film (roughdielectric.h: R_film at each facet, 1 − R_film through it)
    // over thin_film_weight of the surface; its Kulla–Conty lobe stays the bare interface's.
    if (m.trans > 0 && !m.thin && film_on_spec.active() && p.thin_film_weight > 0 && m.glass.eta >= kMinFilmGlassEta)
      m.glass.film = substrate_film(films.glass);
    m.sheet.eta = m.spec_eta;
    m.rough_sheet = m.thin && !m.spec_dist.effectively_smooth();
    m.sheet_film.eta = m.spec_eta;
    m.sheet_film.film = film_on_spec;
    if (m.film_w > 0) m.sheet_film.film.eta = film_on_spec.eta;
    m.trans_tint = p.transmission_depth > 0 ? U(1) : map(p.transmission_color, [](Float v) { return std::clamp(v, Float(0), Float(1)); });
    // Darkening (SPEC-OPB "Darkening"): Δ = (1 − K)/(1 − E_b K), K = 1 − (1 − Ē_coat)/η_c²,
    // E_b the base's albedo blended by the mix weights (a translucent base returns no
    // internally reflected light: E_b = 1 there, no darkening).
    {
      const Float K = 1 - (1 - m.coat_avg) / (m.coat_eta * m.coat_eta);
      const U eb_diel = (rho_d * (1 - m.sss) + rho_s * m.sss) * (1 - m.trans) + U(m.trans);
      const U eb = eb_diel * (1 - m.metal_w) + m.metal.fresnel(Float(1)) * (m.metal_xi * m.metal_w);
      const U delta = map(eb, [K](Float e) { return (1 - K) / std::max(Float(1e-6), 1 - e * K); });
      const Float t = m.coat * std::clamp(p.coat_darkening, Float(0), Float(1));
      m.darkening = U(1) + (delta - U(1)) * t;
    }
    // Flags.
    BxDFFlags f = BxDFFlags::None;
    const bool spec_smooth = m.spec_dist.effectively_smooth();
    if (m.fuzz > 0) f = f | BxDFFlags::GlossyReflection;
    if (m.coat > 0) f = f | (m.coat_dist.effectively_smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection);
    if (m.metal_w > 0 || ((1 - m.metal_w) * (1 - m.trans) > 0 && m.spec_on()))
      f = f | (spec_smooth ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection);
    if ((1 - m.metal_w) * (1 - m.trans) > 0) f = f | BxDFFlags::DiffuseReflection;
    if (m.thin && m.sss > 0 && (1 - m.metal_w) * (1 - m.trans) > 0) f = f | BxDFFlags::DiffuseTransmission;
    if (m.trans > 0 && m.metal_w < 1)
      f = f | (m.rough_sheet ? BxDFFlags::GlossyReflection | BxDFFlags::GlossyTransmission
                             : (m.thin ? m.sheet.flags() : m.glass.flags()));
    if (m.opacity < 1) f = f | BxDFFlags::SpecularTransmission;
    if (m.opacity <= 0) f = BxDFFlags::SpecularTransmission;
    m.flags_ = f;
    return m;
  }

  BxDFFlags flags() const { return flags_; }
  // The emitted radiance leaving the surface at cosine mu (> 0) of the outward normal,
  // emission_luminance × emission_color in gonio's radiance units (no factor 683). SPEC-OPB
  // "Emission": the emitting layer lies under the coat and the fuzz, which absorb and
  // reflect part of it on its way out — the same one-way transmission through fuzz and coat
  // (layer albedos 1 − F E_fuzz(μ), coat absorption T^(1/μt), 1 − E_coat(μ)) as the light a
  // transmitting base sends out (through_layers), without the coat's darkening, which is
  // light reflected back into the base; and of the whole, the opacity α. The layers' albedos
  // are taken at azimuth 0 (exact for an isotropic coat).
  U emission(Float mu) const {
    const Float m = std::clamp(mu, Float(0), Float(1));
    if (!(m > 0) || !(params.emission_luminance > 0)) return U(0);
    const Layers l = layers({std::sqrt(std::max(Float(0), 1 - m * m)), 0, m});
    U s = U(opacity * (1 - l.e_fz));
    if (coat > 0) s = s * ((U(1) - coat_transmittance(1 / coat_mu_t(m)) * (1 - l.e_c)) * (-coat) + U(1));
    return s * params.emission_color * params.emission_luminance;
  }
  Float relative_eta() const { return trans > 0 && !thin && metal_w < 1 && opacity > 0 ? glass.eta : Float(1); }
  bool is_isotropic() const {
    return spec_dist.is_isotropic() && (coat <= 0 || coat_dist.is_isotropic());
  }
  std::string_view nonreciprocal_reason() const {
    if (opacity > 0 && fuzz > 0)
      return "openpbr: the fuzz (LTC sheen, Zeltner et al. 2022) follows wo only, and the layers under it are scaled "
             "by 1 - E_fuzz(wo) (OpenPBR's view-dependent albedo scaling)";
    if (opacity > 0 && coat > 0 && !reciprocal_layering)
      return "openpbr: the base under the coat is scaled by 1 - E_coat(wo) (OpenPBR's view-dependent albedo scaling; "
             "the reciprocal form gains energy over a specular base, docs/openpbr.md)";
    return {};
  }

  // ∫ f_EON(μo, μi, φ) dφ over the azimuth for ρ = 1 (eon.h): with s = sin θo sin θi cos φ,
  // t = max(μo, μi) where s > 0 (|φ| < π/2) else 1, ∫ s/t dφ = 2 sin θo sin θi (1/max − 1),
  // and the multiple-scattering term does not depend on φ.
  Float diffuse_kernel(Float mo, Float mi, Float co, Float ci) const {
    const Float r = params.base_diffuse_roughness;
    const Float so = std::sqrt(std::max(Float(0), 1 - mo * mo)), si = std::sqrt(std::max(Float(0), 1 - mi * mi));
    return 2 * eon_a + 2 * eon_a * r * kInvPi * so * si * (1 / std::max(mo, mi) - 1) + 2 * kPi * eon_ms * co * ci;
  }
  // b(μ) of the separable normalisation (top of the file), solved by matrix balancing.
  // With a film in RGB, one b per channel (diff_b_rgb) for each channel's E_s; diff_b for
  // their mean.
  void solve_diffuse_norm() {
    std::array<Float, kNormNodes> e{};
    const Float a_iso = iso_alpha();
    for (int j = 0; j < kNormNodes; ++j) {
      const Float m = (Float(j) + Float(0.5)) / kNormNodes;
      e[size_t(j)] = film_w > 0 ? with_film(m, spec_E_iso_bare(m, a_iso)) : spec_E_iso_bare(m, a_iso);
    }
    diff_b = balance(e);
    if constexpr (std::is_same_v<U, Color>) {
      if (!(film_w > 0)) return;
      for (int ch = 0; ch < 3; ++ch) {
        std::array<Float, kNormNodes> ec{};
        for (int j = 0; j < kNormNodes; ++j) {
          const Float m = (Float(j) + Float(0.5)) / kNormNodes;
          ec[size_t(j)] = std::clamp(e[size_t(j)] + film_deviation(m)[ch], Float(0), Float(1));
        }
        const auto b = balance(ec);
        for (int j = 0; j < kNormNodes; ++j) diff_b_rgb[size_t(j)][ch] = b[size_t(j)];
      }
    }
  }
  // b_i Σ_j k(μi, μj)(1 − e_j) b_j μj/n = 1 for the specular layer's albedos e_j at the nodes.
  std::array<Float, kNormNodes> balance(const std::array<Float, kNormNodes>& e) const {
    constexpr int n = kNormNodes;
    std::array<Float, n> mu{}, c{};
    for (int j = 0; j < n; ++j) {
      mu[size_t(j)] = (Float(j) + Float(0.5)) / n;
      c[size_t(j)] = eon::one_minus_g(mu[size_t(j)]);
    }
    std::array<std::array<Float, n>, n> k{};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        k[size_t(i)][size_t(j)] = diffuse_kernel(mu[size_t(i)], mu[size_t(j)], c[size_t(i)], c[size_t(j)]) *
                                  (1 - e[size_t(j)]) * mu[size_t(j)] / n;
    std::array<Float, n> b{};
    b.fill(std::sqrt(spec_norm));
    for (int it = 0; it < 200; ++it) {
      std::array<Float, n> next{};
      for (int i = 0; i < n; ++i) {
        Float kb = 0;
        for (int j = 0; j < n; ++j) kb += k[size_t(i)][size_t(j)] * b[size_t(j)];
        const Float v = b[size_t(i)] * kb;
        next[size_t(i)] = v > Float(1e-12) ? std::min(b[size_t(i)] / std::sqrt(v), Float(1e6)) : b[size_t(i)];
      }
      b = next;
    }
    return b;
  }
  // N(μo, μi) of the diffuse under the specular layer.
  Float diffuse_norm(Float mo, Float mi) const {
    if (!(params.base_diffuse_roughness > 0)) return spec_norm;
    return openpbr::at_nodes(diff_b, std::min(mo, Float(1))) * openpbr::at_nodes(diff_b, std::min(mi, Float(1)));
  }

  // --- per-direction quantities -----------------------------------------------------

  // The layers' albedos seen from w (upper side): F E_fuzz(w) and E_coat(w); and for the
  // view direction (view_layers), the specular layer's E_s(w), which both the lobe
  // probabilities and the diffuse's scaling need (one table lookup, not two).
  struct Layers {
    Float e_fz = 0, e_c = 0;
    Float e_s = 0;
  };
  Layers layers(const Vec3& w) const {
    Layers l;
    if (fuzz > 0) l.e_fz = fuzz * sheen_albedo(w.z, sheen.roughness);
    if (coat > 0) l.e_c = coat_E(w);
    return l;
  }
  Layers view_layers(const Vec3& w) const {
    Layers l = layers(w);
    l.e_s = spec_E(w);
    return l;
  }
  Float coat_E(const Vec3& w) const {
    if (coat_eta == 1) return 0;
    if (coat_dist.effectively_smooth()) return fresnel_dielectric(std::min(w.z, Float(1)), coat_eta);
    return coat_albedo.E(coat_dist, coat_rot.in(w));
  }
  // Whether the opaque base has a specular reflection lobe: an interface of index ≠ 1, or
  // a film (which reflects even on an index-1 interface, specular_weight 0).
  bool spec_on() const { return spec_eta != 1 || film_w > 0; }
  Float spec_E(const Vec3& w) const {
    if (!spec_on()) return 0;
    const Float mu = std::min(w.z, Float(1));
    const Float e = spec_eta == 1                      ? Float(0)
                    : spec_dist.effectively_smooth() ? fresnel_dielectric(mu, spec_eta)
                                                     : spec_albedo.E(spec_dist, spec_rot.in(w));
    return film_w > 0 ? with_film(mu, e) : e;
  }
  // E_s per channel, which the diffuse's scaling uses (a coloured film must not let a
  // channel gain): the channel average spec_E plus the film's deviation from its average
  // at μ, w (R_c(μ) − R̄(μ)) (exact for a smooth layer, (1 − w) F + w R_c; for a rough one
  // the deviation of the lobe's albedo is taken as the film's at the macro-surface cosine).
  U spec_E_channels(const Vec3& w) const { return spec_E_channels(w, spec_E(w)); }
  U spec_E_channels(const Vec3& w, Float e) const {
    if (!(film_w > 0)) return U(e);
    return map(U(e) + film_deviation(std::min(w.z, Float(1))), [](Float v) { return std::clamp(v, Float(0), Float(1)); });
  }
  // Each channel's film albedo less the channels' mean, at μ: smooth, w (R_c(μ) − R̄(μ))
  // exactly; rough, in RGB, w (ΔE_c(μ) − mean ΔE(μ)) from solve_film_albedo's table; rough in
  // spectral mode (whose channels are the path's wavelengths, not the table's), the smooth
  // form at the macro-surface cosine (an approximation, docs/openpbr.md).
  U film_deviation(Float mu) const {
    if (!(film_w > 0)) return U(0);
    if constexpr (std::is_same_v<U, Color>) {
      if (!spec_dist.effectively_smooth()) {
        const Color d = openpbr::at_film_nodes(film_dE_rgb, mu);
        return (d - Color(d.average())) * film_w;
      }
    }
    const U R = film.reflectance(mu, U(spec_eta), U(0));
    return (R - U(R.average())) * film_w;
  }
  // The diffuse's albedo scaling (1 − E_s(wo))(1 − E_s(wi)) N(μo, μi) (top of the file),
  // es_o = spec_E(wo).
  U diffuse_scale(const Vec3& wo, const Vec3& wi, Float es_o) const {
    const Float n = diffuse_norm(wo.z, wi.z);
    if (!(film_w > 0)) return U((1 - es_o) * (1 - spec_E(wi)) * n);
    const U through = (U(1) - spec_E_channels(wo, es_o)) * (U(1) - spec_E_channels(wi));
    if constexpr (std::is_same_v<U, Color>) {
      // An EON base: each channel's own b (solve_diffuse_norm).
      if (params.base_diffuse_roughness > 0)
        return through * openpbr::at_nodes(diff_b_rgb, std::min(wo.z, Float(1))) *
               openpbr::at_nodes(diff_b_rgb, std::min(wi.z, Float(1)));
    }
    return through * film_norm_ratio * n;
  }
  // The isotropic roughness standing for an anisotropic pair in μ-only quadratures.
  Float iso_alpha() const {
    return std::sqrt((spec_dist.alpha_x * spec_dist.alpha_x + spec_dist.alpha_y * spec_dist.alpha_y) / 2);
  }
  // The bare interface's albedo at μ (no film), of the isotropic roughness iso_alpha().
  Float spec_E_iso_bare(Float mu, std::optional<Float> a_iso = std::nullopt) const {
    if (spec_eta == 1) return 0;
    if (spec_dist.effectively_smooth()) return fresnel_dielectric(mu, spec_eta);
    return spec_albedo.E(a_iso ? *a_iso : iso_alpha(), mu);
  }
  // The albedo at μ of the specular layer whose bare albedo is e, with the film over film_w
  // of it (channel average: the layers below see one albedo). Smooth: exactly
  // (1 − w) F + w R_film. Rough: e + w ΔE(μ), ΔE solved at make() (solve_film_albedo).
  Float with_film(Float mu, Float e) const {
    if (spec_dist.effectively_smooth()) {
      const Float R = film.reflectance(mu, U(spec_eta), U(0)).average();
      return std::clamp(e * (1 - film_w) + R * film_w, Float(0), Float(1));
    }
    return std::clamp(e + film_w * openpbr::at_film_nodes(film_dE, mu), Float(0), Float(1));
  }
  // ΔE(μ) = ∫ D G2 / (4 μo μi) (R_film(h·wo) − F(h·wo)) μi dωi at the nodes μ_j: the film's
  // change of the rough lobe's albedo (Walter et al. 2007 eq. 20 with the film's Fresnel),
  // by visible-normal sampling (Heitz 2018), whose weight for this integrand is
  // G2/G1(wo) (R_film − F), on a 16 × 16 stratified grid, for the isotropic iso_alpha().
  void solve_film_albedo() {
    MicrofacetDistribution d = spec_dist;
    d.alpha_x = d.alpha_y = iso_alpha();
    constexpr int kGrid = 16;
    for (int j = 0; j < openpbr::kFilmNodes; ++j) {
      const Float mu = j < kNormNodes ? (Float(j) + Float(0.5)) / kNormNodes : openpbr::kFilmGrazingMu;
      const Vec3 wo{std::sqrt(1 - mu * mu), 0, mu};
      const Float g1 = d.G1(wo);
      U acc(Float(0));
      for (int a = 0; a < kGrid; ++a)
        for (int b = 0; b < kGrid; ++b) {
          const Vec3 h = d.sample_visible(wo, (Float(a) + Float(0.5)) / kGrid, (Float(b) + Float(0.5)) / kGrid);
          const Vec3 wi = reflect(wo, h);
          if (!(wi.z > 0)) continue;
          const Float c = std::clamp(dot(wo, h), Float(0), Float(1));
          acc += (film.reflectance(c, U(spec_eta), U(0)) - U(fresnel_dielectric(c, spec_eta))) * (d.G2(wo, wi) / g1);
        }
      acc = acc * (Float(1) / (kGrid * kGrid));
      film_dE[size_t(j)] = acc.average();
      if constexpr (std::is_same_v<U, Color>) film_dE_rgb[size_t(j)] = acc;
    }
  }
  // The cosine refracted into the coat (SPEC-OPB "View-dependent absorption").
  Float coat_mu_t(Float mu) const {
    return std::sqrt(std::max(Float(1e-12), 1 - (1 - mu * mu) / (coat_eta * coat_eta)));
  }
  // T^k per channel, T = sqrt(coat_color) (k ≥ 1: the path length in units of the thickness).
  U coat_transmittance(Float k) const {
    return map(coat_log_trans, [k](Float l) { return l >= 0 ? Float(1) : std::exp(k * l); });
  }
  // coat_color^((1/μt_o + 1/μt_i)/2) = T^(1/μt_o + 1/μt_i), T = sqrt(coat_color).
  U coat_absorption(Float mu_o, Float mu_i) const {
    const Float k = 1 / coat_mu_t(mu_o) + 1 / coat_mu_t(mu_i);
    return coat_transmittance(k);
  }
  // What reaches the base and comes back, seen from v: α (1 − F E_fz(v)) lerp(1, A (1 − E_c(v)), C) Δ.
  U base_scale(const Layers& v, Float mu_o, Float mu_i) const {
    return base_scale(v, v, mu_o, mu_i, false);
  }
  // The same for the pair wo, wi with their layers lo, li: with reciprocal_layering each layer
  // lets through layer_through(...) instead of 1 − E(v) (a lobe of the base that is diffuse
  // or not: `diffuse`); else, as above, of the view direction (lo in radiance mode, li in
  // importance mode: the caller passes it as both).
  U base_scale(const Layers& lo, const Layers& li, Float mu_o, Float mu_i, bool diffuse) const {
    U s = U(opacity * layer_through(lo.e_fz, li.e_fz, fuzz_avg, diffuse));
    if (coat > 0) {
      const U through = coat_absorption(mu_o, mu_i) * layer_through(lo.e_c, li.e_c, coat_avg, diffuse);
      s = s * ((U(1) - through) * (-coat) + U(1)) * darkening;
    }
    return s;
  }
  // The fraction of what lies below a layer of albedos e_o = E(ωo), e_i = E(ωi) (and mean
  // Ē = e_avg) that it lets out. View-dependent (OpenPBR 1.1 eqs.
  // `coat_layering_formula_with_albedo_scaling`, `fuzz-layering-approx`): 1 − e_o (the caller
  // passes the view's albedo as both). reciprocal_layering, symmetric in ωo ↔ ωi (gonio's
  // extension, docs/openpbr.md), per kind of lobe below: for the diffuse,
  // (1 − e_o)(1 − e_i)/(1 − Ē), exact for a Lambertian base (2 ∫ (1 − E(μ)) μ dμ = 1 − Ē);
  // for the specular and glossy lobes, min(1 − e_o, 1 − e_i): exact for a mirror base
  // (μi = μo), and the largest factor symmetric in ωo ↔ ωi that never exceeds the view
  // form's 1 − e_o, so that the view's albedo, which that form conserves, cannot grow.
  // (The product over (1 − Ē) gains 5 % over a mirror at normal incidence; the geometric
  // mean sqrt((1 − e_o)(1 − e_i)) 10 % over a rough white metal at 85°.)
  Float layer_through(Float e_o, Float e_i, Float e_avg, bool diffuse) const {
    if (!reciprocal_layering) return 1 - e_o;
    if (!diffuse) return std::min(1 - e_o, 1 - e_i);
    return std::max(Float(0), (1 - e_o) * (1 - e_i)) / std::max(Float(1e-6), 1 - e_avg);
  }

  // The specular layer's Fresnel (with the film over thin_film_weight of it).
  U spec_fresnel(Float c) const {
    const Float F = fresnel_dielectric(c, spec_eta);
    if (!(film_w > 0)) return U(F);
    return U(F * (1 - film_w)) + film.reflectance(c, U(spec_eta), U(0)) * film_w;
  }

  // The lobes' selection probabilities for wo (upper side; l = view_layers(wo)): their
  // albedo estimates. In importance mode the layers' scaling follows wi (the adjoint of the view-dependent
  // form), which sampling does not know: the base's share is then not reduced by wo's
  // layers (else a grazing wo, where the coat reflects nearly everything, would draw the
  // base almost never while wi's scaling lets it through: unbounded weights).
  std::array<Float, openpbr::kLobes> probabilities(const Vec3& wo, const Layers& l,
                                                   TransportMode mode = TransportMode::Radiance,
                                                   bool inside = false) const {
    using namespace openpbr;
    std::array<Float, kLobes> p{};
    const Float mu = std::min(wo.z, Float(1));
    p[kPass] = 1 - opacity;
    p[kFuzz] = opacity * l.e_fz * std::max(sheen.color.average(), Float(0.05));
    if (coat > 0 && coat_eta != 1) p[kCoat] = opacity * (1 - l.e_fz) * coat * std::max(l.e_c, Float(0.02));
    const bool radiance = mode == TransportMode::Radiance;
    const Float base = opacity * (radiance ? (1 - l.e_fz) * (1 - coat * l.e_c) : Float(1)) *
                       std::max(darkening.average(), Float(0.05));
    if (metal_w > 0)
      p[kMetal] = base * metal_w * std::max(metal_xi * fresnel_f82(metal.fresnel.f0, metal.fresnel.f82, mu).average(), Float(0.05));
    const Float diel = base * (1 - metal_w);
    const Float es = l.e_s;
    if (trans < 1) {
      if (spec_on()) p[kSpec] = diel * (1 - trans) * std::max(es, Float(0.02)) * std::max(params.specular_color.average(), Float(0.1));
      p[kDiffuse] = diel * (1 - trans) * (1 - es) * std::max(diff_rho.average(), Float(0.05));
      if (thin && sss > 0) p[kDiffuseT] = diel * (1 - trans) * (1 - es) * std::max(difft_rho.average(), Float(0.05));
    }
    // From inside (wo.z < 0 before the mirroring, non-thin) the glass is bare: its share is
    // not reduced by the outside layers' albedo at wo.
    if (trans > 0) p[kGlass] = (inside && !thin ? opacity * (1 - metal_w) : diel) * trans;
    // And it is all there is from inside a transmitting shape: fuzz, coat and the opaque
    // base lie outside the interface (bare_inside).
    if (inside && bare_inside_any()) p[kFuzz] = p[kCoat] = p[kMetal] = p[kSpec] = p[kDiffuse] = p[kDiffuseT] = 0;
    Float sum = 0;
    for (Float v : p) sum += v;
    if (!(sum > 0)) {
      p = {};
      p[opacity < 1 ? kPass : kDiffuse] = 1;
      return p;
    }
    for (Float& v : p) v /= sum;
    return p;
  }

  // Whether a wo below the surface is inside a medium: the glass refracts into the shape
  // (transmission, not thin-walled, some dielectric share).
  bool bare_inside_any() const { return trans > 0 && !thin && metal_w < 1; }

  // --- evaluation -------------------------------------------------------------------

  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0 || wi.z == 0 || opacity <= 0) return {};
    const Vec3 wo_u{wo.x, wo.y, std::abs(wo.z)};
    const Layers lo = view_layers(wo_u);
    return eval_given(wo, wi, mode, lo, probabilities(wo_u, lo, mode, wo.z < 0));
  }
  // eval with wo's layers (view_layers of the upper-side wo) and lobe probabilities
  // already known (sample() has them).
  BSDFEvalT<C> eval_given(const Vec3& wo, const Vec3& wi, TransportMode mode, const Layers& lo,
                          const std::array<Float, openpbr::kLobes>& p) const {
    using namespace openpbr;
    if (wo.z == 0 || wi.z == 0 || opacity <= 0) return {};
    const bool reflection = (wo.z > 0) == (wi.z > 0);
    const Float s = wo.z > 0 ? 1 : -1;  // mirror the pair to wo's side up
    const Vec3 wo_u{wo.x, wo.y, s * wo.z}, wi_u{wi.x, wi.y, s * wi.z};
    C f{};
    Float pdf = 0;
    const bool radiance = mode == TransportMode::Radiance;
    // Light inside a transmitting shape (wo below, not thin-walled) meets the glass's bare
    // interface only: the other lobes are on the outside, and mirroring them to wo's side
    // reflected it back (a coated glass returned up to twice the light at grazing).
    if (reflection && wo.z < 0 && bare_inside_any()) {
      const BSDFEvalT<C> e = glass.eval(spec_rot.in(wo), spec_rot.in(wi), mode);
      return {e.f * ((1 - metal_w) * opacity * trans), p[kGlass] * e.pdf};
    }
    if (reflection) {
      // wi's layers, only where read: importance mode or reciprocal_layering (a hot path).
      const Layers li = !radiance || reciprocal_layering ? layers(wi_u) : lo;
      // The view direction's layers (reciprocal_layering reads both, lo and li).
      const Layers& lv = radiance || reciprocal_layering ? lo : li;
      const Layers& lw = reciprocal_layering ? li : lv;
      // Fuzz.
      if (fuzz > 0 && p[kFuzz] > 0) {
        // lo.e_fz = fuzz R(μo): the lobe's albedo is known.
        const BSDFEvalT<U> e = sheen.eval_upper(wo_u, wi_u, mode, lo.e_fz / fuzz);
        f += C(e.f * (opacity * fuzz));
        pdf += p[kFuzz] * e.pdf;
      }
      // Coat (rough; the smooth one is a delta).
      if (coat > 0 && coat_eta != 1 && !coat_dist.effectively_smooth()) {
        const Glossy g = glossy(coat_dist, coat_rot.in(wo_u), coat_rot.in(wi_u));
        if (g.valid) {
          const Float F = fresnel_dielectric(g.cos_h, coat_eta);
          f += fresnel_factor<C>(
              F * g.f_per_f * (opacity * layer_through(lv.e_fz, lw.e_fz, fuzz_avg, false) * coat),
              [&] { return broadcast<U>(dielectric_reflection_mueller(g.cos_h, coat_eta)); }, wo, wi);
          pdf += p[kCoat] * g.pdf;
        }
      }
      const U base = base_scale(lv, lw, wo_u.z, wi_u.z, false);
      // Metal.
      if (metal_w > 0) {
        const BSDFEvalT<C> e = metal.eval(spec_rot.in(wo), spec_rot.in(wi), mode);
        f += e.f * (base * (metal_w * metal_xi));
        pdf += p[kMetal] * e.pdf;
      }
      const Float diel = (1 - metal_w);
      if (diel > 0 && trans < 1) {
        const Float w = diel * (1 - trans);
        // Specular reflection (rough; the smooth one is a delta).
        if (spec_on() && !spec_dist.effectively_smooth()) {
          const Glossy g = glossy(spec_dist, spec_rot.in(wo_u), spec_rot.in(wi_u));
          if (g.valid) {
            f += fresnel_factor<C>(
                spec_fresnel(g.cos_h) * params.specular_color * base * (g.f_per_f * w),
                [&] { return broadcast<U>(dielectric_reflection_mueller(g.cos_h, spec_eta)); }, wo, wi);
            pdf += p[kSpec] * g.pdf;
          }
        }
        // Diffuse under it, reciprocal albedo scaling.
        const U base_d = reciprocal_layering ? base_scale(lv, lw, wo_u.z, wi_u.z, true) : base;
        f += C(eon_f(wo_u, wi_u, diff_rho, diff_rho_ms) * base_d * diffuse_scale(wo_u, wi_u, lo.e_s) * w);
        pdf += p[kDiffuse] * eon.pdf(wo_u, wi_u);
      }
      // The rough thin-walled sheet's reflection (rough_sheet).
      if (diel > 0 && trans > 0 && rough_sheet) {
        const Glossy g = glossy(spec_dist, spec_rot.in(wo_u), spec_rot.in(wi_u));
        if (g.valid) {
          const SheetShares r = sheet_shares(g.cos_h);
          f += fresnel_factor<C>(r.reflect * params.specular_color * base * (g.f_per_f * diel * trans),
                                 [&] { return sheet_mueller(g.cos_h, true); }, wo, wi);
          pdf += p[kGlass] * g.pdf * r.p_reflect;
        }
      }
      // Glass, reflection: from outside under the layers, tinted; from inside bare.
      if (diel > 0 && trans > 0 && !thin) {
        const BSDFEvalT<C> e = glass.eval(spec_rot.in(wo), spec_rot.in(wi), mode);
        if (wo.z > 0) f += e.f * (params.specular_color * base * (diel * trans));
        else f += e.f * (opacity * diel * trans);
        pdf += p[kGlass] * e.pdf;
      }
      return {f, pdf};
    }
    // Transmission.
    const Float diel = 1 - metal_w;
    if (!(diel > 0)) return {};
    if (!thin && trans > 0) {
      const BSDFEvalT<C> e = glass.eval(spec_rot.in(wo), spec_rot.in(wi), mode);
      const Vec3 w_out = wo.z > 0 ? wo : wi;
      const Layers l = w_out.z == wo_u.z ? lo : layers(w_out);
      f += e.f * (through_layers(l, w_out.z) * trans_tint * (diel * trans));
      pdf += p[kGlass] * e.pdf;
    }
    if (rough_sheet && trans > 0) {
      // The rough sheet's transmission: its reflection lobe at wi mirrored to wo's side.
      const Vec3 wm{wi_u.x, wi_u.y, -wi_u.z};
      const Glossy g = glossy(spec_dist, spec_rot.in(wo_u), spec_rot.in(wm));
      if (g.valid) {
        const Layers lm = !radiance || reciprocal_layering ? layers(wm) : lo;
        const Layers& lv = radiance || reciprocal_layering ? lo : lm;
        const SheetShares r = sheet_shares(g.cos_h);
        f += fresnel_factor<C>(r.transmit * base_scale(lv, reciprocal_layering ? lm : lv, wo_u.z, wm.z, false) * trans_tint *
                                   (g.f_per_f * diel * trans),
                               [&] { return sheet_mueller(g.cos_h, false); }, wo, wi);
        pdf += p[kGlass] * g.pdf * (1 - r.p_reflect);
      }
    }
    if (thin && sss > 0 && trans < 1) {
      // The thin-walled subsurface's transmission, mirrored to wo's side.
      const Vec3 wm{wi_u.x, wi_u.y, -wi_u.z};
      const Layers lm = !radiance || reciprocal_layering ? layers(wm) : lo;
      const Layers& lv = radiance || reciprocal_layering ? lo : lm;
      f += C(eon_f(wo_u, wm, difft_rho, difft_rho_ms) * base_scale(lv, reciprocal_layering ? lm : lv, wo_u.z, wm.z, true) *
             diffuse_scale(wo_u, wm, lo.e_s) *
             (diel * (1 - trans)));
      pdf += p[kDiffuseT] * eon.pdf(wo_u, wm);
    }
    return {f, pdf};
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const { return eval(wo, wi, mode).f; }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).pdf;
  }

  // Transmission through fuzz and coat once, at the outside direction w (upper side).
  U through_layers(const Layers& l, Float mu) const {
    U s = U(opacity * (1 - l.e_fz));
    if (coat > 0) {
      const Float k = 1 / coat_mu_t(std::min(mu, Float(1)));
      const U a = coat_transmittance(k);
      s = s * ((U(1) - a * (1 - l.e_c)) * (-coat) + U(1)) * darkening;
    }
    return s;
  }

  // EON (eon.h) for a single-scattering colour rho and a multiple-scattering one rho_ms:
  // f = rho A/π (1 + r s/t) + rho_ms r A (c1 − G_o/π)(c1 − G_i/π)/(π (c1 − c2)).
  U eon_f(const Vec3& wo, const Vec3& wi, const U& rho, const U& rho_ms) const {
    if (!diffuse_glossy::usable(wo, wi)) return U(0);
    const Float r = params.base_diffuse_roughness;
    if (r <= 0) return rho * kInvPi;
    const Float s = std::max(Float(-1), dot(wi, wo) - wi.z * wo.z);
    const eon::FonTerms t = eon::fon_terms(wo.z, wi.z, s);
    return rho * (kInvPi * eon_a * (1 + r * t.s_over_t)) + rho_ms * (eon_ms * t.c_o * t.c_i);
  }

  // --- sampling ---------------------------------------------------------------------

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                       TransportMode mode = TransportMode::Radiance) const {
    using namespace openpbr;
    if (wo.z == 0) return std::nullopt;
    const Float s = wo.z > 0 ? 1 : -1;
    const Vec3 wo_u{wo.x, wo.y, s * wo.z};
    const Layers lo = view_layers(wo_u);
    const auto p = probabilities(wo_u, lo, mode, wo.z < 0);
    int k = 0;
    Float acc = 0;
    for (; k < kLobes - 1; ++k) {
      if (u_lobe < acc + p[size_t(k)]) break;
      acc += p[size_t(k)];
    }
    // Rounding can leave u_lobe past the last nonzero share: step back to it, and its start.
    while (k > 0 && !(p[size_t(k)] > 0)) acc = std::max(Float(0), acc - p[size_t(--k)]);
    const Float pk = p[size_t(k)];
    if (!(pk > 0)) return std::nullopt;
    const Float u = std::clamp((u_lobe - acc) / pk, Float(0), kOneMinusEpsilon);
    const auto up = [&](const Vec3& w) { return Vec3{w.x, w.y, s * w.z}; };  // upper ↔ actual
    Vec3 wi_u;
    switch (k) {
      case kPass: {
        const Vec3 wi = -wo;
        return BSDFSampleT<C>{wi, identity(U(Float(1))) * ((1 - opacity) / pk), pk, true, Lobe::Transmission, 1};
      }
      case kFuzz: {
        const auto sm = sheen.sample(wo_u, u, u1, u2, mode);
        if (!sm) return std::nullopt;
        wi_u = sm->wi;
        break;
      }
      case kCoat: {
        if (coat_dist.effectively_smooth()) {
          const Float F = fresnel_dielectric(std::min(wo_u.z, Float(1)), coat_eta);
          const Vec3 wi{-wo.x, -wo.y, wo.z};
          const C w = fresnel_factor<C>(F * (opacity * (1 - lo.e_fz) * coat / pk),
                                        [&] { return broadcast<U>(dielectric_reflection_mueller(std::min(wo_u.z, Float(1)), coat_eta)); },
                                        wo, wi);
          return BSDFSampleT<C>{wi, w, pk, true, Lobe::Reflection, 1};
        }
        const Vec3 wl = coat_rot.in(wo_u);
        wi_u = coat_rot.out(reflect(wl, coat_dist.sample_visible(wl, u1, u2)));
        break;
      }
      case kMetal: {
        const auto sm = metal.sample(spec_rot.in(wo), u, u1, u2, mode);
        if (!sm) return std::nullopt;
        const Vec3 wi = spec_rot.out(sm->wi);
        if (sm->delta) {
          const U base = base_scale(lo, wo_u.z, wo_u.z);
          return BSDFSampleT<C>{wi, sm->weight * (base * (metal_w * metal_xi / pk)), pk * sm->pdf, true, Lobe::Reflection, 1};
        }
        wi_u = up(wi);
        break;
      }
      case kSpec: {
        if (spec_dist.effectively_smooth()) {
          const Float c = std::min(wo_u.z, Float(1));
          const Vec3 wi{-wo.x, -wo.y, wo.z};
          const U base = base_scale(lo, wo_u.z, wo_u.z);
          const U v = spec_fresnel(c) * params.specular_color * base * ((1 - metal_w) * (1 - trans) / pk);
          const C w = fresnel_factor<C>(v, [&] { return broadcast<U>(dielectric_reflection_mueller(c, spec_eta)); }, wo, wi);
          return BSDFSampleT<C>{wi, w, pk, true, Lobe::Reflection, 1};
        }
        const Vec3 wl = spec_rot.in(wo_u);
        wi_u = spec_rot.out(reflect(wl, spec_dist.sample_visible(wl, u1, u2)));
        break;
      }
      case kDiffuse:
      case kDiffuseT: {
        const auto d = eon.sample_direction_upper(wo_u, u, u1, u2);
        if (!d) return std::nullopt;
        wi_u = *d;
        if (k == kDiffuseT) wi_u.z = -wi_u.z;
        break;
      }
      case kGlass:
      default: {
        if (rough_sheet) {
          // A facet of the visible normals, then its reflection or (mirrored) transmission
          // with the sheet's reflectance there as the probability.
          const Vec3 wl = spec_rot.in(wo_u);
          const Vec3 h = spec_dist.sample_visible(wl, u1, u2);
          const Vec3 wr = spec_rot.out(reflect(wl, h));
          if (!(wr.z > 0)) return std::nullopt;
          const bool refl = u < sheet_shares(std::clamp(dot(wl, h), Float(0), Float(1))).p_reflect;
          wi_u = refl ? wr : Vec3{wr.x, wr.y, -wr.z};
          break;
        }
        if (thin) return sample_sheet(wo, wo_u, lo, u, pk);
        const auto sm = glass.sample(spec_rot.in(wo), u, u1, u2, mode);
        if (!sm) return std::nullopt;
        const Vec3 wi = spec_rot.out(sm->wi);
        if (sm->delta) {
          U scale;
          if (sm->lobe == Lobe::Reflection)
            scale = wo.z > 0 ? params.specular_color * base_scale(lo, wo_u.z, wo_u.z) : U(opacity);
          else
            scale = through_layers(wo.z > 0 ? lo : layers(Vec3{wi.x, wi.y, wi.z}), wo.z > 0 ? wo.z : wi.z) * trans_tint;
          return BSDFSampleT<C>{wi, sm->weight * (scale * ((1 - metal_w) * trans / pk)), pk * sm->pdf, true, sm->lobe, sm->eta};
        }
        wi_u = up(wi);
        break;
      }
    }
    // A reflection lobe's direction below the horizon (or the diffuse transmission's above)
    // is no sample: eval's density has no share of it on the other side.
    if (k != kGlass && (k == kDiffuseT ? !(wi_u.z < 0) : !(wi_u.z > 0))) return std::nullopt;
    const Vec3 wi = up(wi_u);
    if (wi.z == 0) return std::nullopt;
    const BSDFEvalT<C> e = eval_given(wo, wi, mode, lo, p);
    if (!(e.pdf > 0)) return std::nullopt;
    const bool transmit = (wi.z > 0) != (wo.z > 0);
    const Float eta = transmit && !thin ? (wo.z > 0 ? glass.eta : 1 / glass.eta) : Float(1);
    return BSDFSampleT<C>{wi, e.f * (std::abs(wi.z) / e.pdf), e.pdf, false, transmit ? Lobe::Transmission : Lobe::Reflection, eta};
  }

 private:
  // The rough sheet's reflectance and transmittance per channel at the facet cosine c, and
  // the reflection's probability (their channel average): the bare sheet's, and the
  // film's Airy sum over film_w of it (the mixture sample_sheet draws for a smooth one).
  struct SheetShares {
    U reflect, transmit;
    Float p_reflect;
  };
  SheetShares sheet_shares(Float c) const {
    U r(sheet_terms(c).r());
    if (film_w > 0 && sheet_film.film.active())
      r = r * (1 - film_w) + sheet_film.film.reflectance(std::min(c, Float(1)), U(1), U(0)) * film_w;
    return {r, U(1) - r, std::clamp(r.average(), Float(0), Float(1))};
  }
  ThinSheetTerms<Float> sheet_terms(Float c) const { return thin_sheet_terms(c, sheet.eta); }
  // Its Mueller shape (polarized mode): the bare sheet's, mixed with the film's.
  MuellerT<U> sheet_mueller(Float c, bool reflection) const {
    const Float cc = std::min(c, Float(1));
    MuellerT<U> m = broadcast<U>(thin_sheet_mueller(sheet_terms(cc), reflection, cc, sheet.eta));
    if (film_w > 0 && sheet_film.film.active()) {
      m *= (1 - film_w);
      m += sheet_film.film.mueller(cc, U(1), U(0), reflection, false) * film_w;
    }
    return m;
  }

  // A non-polarizing pass-through of value v (identity Mueller matrix in polarized mode).
  static C identity(const U& v) {
    if constexpr (kPolarized<C>) {
      C m;
      for (int i = 0; i < 4; ++i) m(i, i) = v;
      return m;
    } else {
      return C(v);
    }
  }

  // The thin-walled translucent base: the smooth sheet (and the soap-bubble film over
  // thin_film_weight of it), under the layers seen from wo.
  std::optional<BSDFSampleT<C>> sample_sheet(const Vec3& wo, const Vec3& wo_u, const Layers& lo, Float u, Float pk) const {
    Float pf = 1;
    bool with_film = false;
    if (film_w > 0 && film.active()) {
      with_film = u < film_w;
      pf = with_film ? film_w : 1 - film_w;
      u = std::clamp(with_film ? u / film_w : (u - film_w) / (1 - film_w), Float(0), kOneMinusEpsilon);
    }
    const auto sm = (with_film ? sheet_film : sheet).sample(wo, u, 0, 0);
    if (!sm) return std::nullopt;
    const U base = base_scale(lo, wo_u.z, wo_u.z);
    const U scale = sm->lobe == Lobe::Reflection ? params.specular_color * base : base * trans_tint;
    // The film's share of the choice is the mix weight: the weight is unchanged by it.
    return BSDFSampleT<C>{sm->wi, sm->weight * (scale * ((1 - metal_w) * trans / pk)), pk * pf * sm->pdf, true, sm->lobe, 1};
  }
};

using OpenPbrBxDF = OpenPbrBxDFT<Color>;

}  // namespace gonio
