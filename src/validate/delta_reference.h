#pragma once
// What a model's delta lobes must return, computed by the validator itself (internal to
// the property "consistency"). The mean weight of the delta samples of each lobe is the
// lobe's reflectance: for a smooth dielectric F and (1 − F)(n_wo/n_wi)² (radiance) or
// 1 − F (importance), for a thin sheet 2r/(1 + r) per polarization and 1 minus that,
// for a smooth conductor its Fresnel reflectance (exact, Schlick or F82-tint), for a mirror its
// reflectance. These come from fresnel_reference.h and the model's declared parameters
// (index, complex index, F0, F82 tint, reflectance, blend weight) — never from the model's
// sample() or albedo(), which are what is being checked; comparing the sampler with the
// model's own albedo() was circular, as both shared the (n_wo/n_wi)² code.

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "fresnel_reference.h"
#include "gonio/bxdf.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/piecewise_linear.h"
#include "gonio/spectrum/spectrum_to_rgb.h"

namespace gonio::validation {

struct DeltaReference {
  std::array<double, kColorChannels> reflection{}, transmission{};
};

// A thin film's RGB reflectance for light from the outside at cos θ1 = c: the
// characteristic-matrix reflectance (fresnel_reference.h) at every nanometre of the CIE
// tables, on the substrate's declared (n, k) there (kept with the film's table), reduced
// to linear sRGB as `gonio spectrum` reduces a reflectance (spectrum_to_rgb).
inline std::array<double, kColorChannels> film_reference(double c, const ThinFilmT<Color>& film) {
  std::array<double, kColorChannels> out{};
  out.fill(1);
  if (!film.table || c < 0) return out;
  std::vector<std::pair<double, double>> points;
  const auto& sub = film.table->substrate;
  for (size_t l = 0; l < sub.size(); ++l) {
    const double lambda = double(spectral_data::kCieFirstNm) + double(l);
    points.emplace_back(lambda, reference_film_reflectance(c, film.eta, film.thickness, sub[l].first, sub[l].second, lambda));
  }
  const Color rgb = spectrum_to_rgb(Spectrum(PiecewiseLinearSpectrum::from_points(points, "film")), SpectrumUse::kReflectance);
  for (int i = 0; i < kColorChannels; ++i) out[size_t(i)] = rgb[i];
  return out;
}

// cos θ outside for light inside a substrate of relative index eta at |cos θ| = c, by
// Snell's law in angle form; −1 beyond the critical angle.
inline double reference_outside_cos(double c, double eta) {
  const double s = eta * std::sin(std::acos(std::min(1.0, std::abs(c))));
  return s < 1 ? std::cos(std::asin(s)) : -1;
}

// A smooth dielectric interface with relative index eta = n_inside / n_outside, seen from
// wo. e = n(far side) / n(wo's side); (n_wo/n_wi)² = 1/e² in radiance mode.
inline DeltaReference dielectric_reference(const Vec3& wo, double eta, TransportMode mode,
                                           const ThinFilmT<Color>* film = nullptr) {
  DeltaReference r;
  if (wo.z == 0) return r;
  const double e = wo.z > 0 ? eta : 1 / eta;
  if (film && film->active()) {  // the film-covered interface: R per channel, 1 − R through
    // From outside onto eta < 1 beyond asin eta, the bare substrate reflects totally: so
    // does the lossless stack (R = 1).
    const double c1 = wo.z > 0 ? (std::sin(std::acos(std::min(1.0, double(wo.z)))) >= eta ? -1 : double(wo.z))
                               : reference_outside_cos(wo.z, eta);
    r.reflection = film_reference(c1, *film);
    // Where the film covers a share w < 1 (openpbr's thin_film_weight), the rest is bare.
    const double w = std::clamp(double(film->coverage), 0.0, 1.0);
    const double bare = reference_fresnel_dielectric(wo.z, e);
    const double scale = mode == TransportMode::Radiance ? 1 / (e * e) : 1;
    for (size_t c = 0; c < r.reflection.size(); ++c) {
      r.reflection[c] = (1 - w) * bare + w * r.reflection[c];
      r.transmission[c] = (1 - r.reflection[c]) * scale;
    }
    return r;
  }
  const double F = reference_fresnel_dielectric(wo.z, e);
  const double scale = mode == TransportMode::Radiance ? 1 / (e * e) : 1;
  r.reflection.fill(F);
  r.transmission.fill((1 - F) * scale);
  return r;
}

// A thin sheet: R of the sheet reflected, 1 − R straight through, in either mode (the
// medium is the same on both sides) and from either side.
inline DeltaReference thin_sheet_reference(const Vec3& wo, double eta, const ThinFilmT<Color>* film = nullptr) {
  DeltaReference r;
  if (wo.z == 0) return r;
  if (film && film->active()) {  // the soap bubble: the film between two outside media
    r.reflection = film_reference(std::abs(wo.z), *film);
    for (size_t c = 0; c < r.reflection.size(); ++c) r.transmission[c] = 1 - r.reflection[c];
    return r;
  }
  const double R = reference_thin_sheet(wo.z, eta);
  r.reflection.fill(R);
  r.transmission.fill(1 - R);
  return r;
}

inline DeltaReference conductor_reference(const Vec3& wo, const ConductorFresnel& fr) {
  DeltaReference r;
  if (wo.z == 0) return r;
  if (fr.film.active()) {
    r.reflection = film_reference(std::abs(wo.z), fr.film);
    return r;
  }
  for (int c = 0; c < kColorChannels; ++c)
    r.reflection[size_t(c)] = fr.model == FresnelModel::Schlick ? reference_fresnel_schlick(wo.z, fr.f0[c])
                              : fr.model == FresnelModel::F82   ? reference_fresnel_f82(wo.z, fr.f0[c], fr.f82[c])
                                                                : reference_fresnel_conductor(wo.z, fr.eta[c], fr.k[c]);
  return r;
}


// openpbr (issue 35): its delta lobes summed per side, from the declared parameters and
// the validator's own Fresnel (fresnel_reference.h): the pass-through 1 − α; under the
// layers seen from wo (α (1 − F E_fuzz) lerp(1, T_coat^(2/μt) (1 − E_coat), C) Δ, with
// E_fuzz the fuzz's fitted albedo, a smooth coat's E its Fresnel and a rough one's its
// tables, Δ = lerp(1, (1 − K)/(1 − E_b K), C δ)) the smooth coat's F, a smooth metal's
// ξ F82 (or its film's), a smooth specular layer's tinted F (or its film's), and the glass's (tinted
// reflection F from outside, (1 − F) times the mode's scaling through the layers at the
// outside direction, bare from inside, where it is the only lobe) or the thin sheet's.
inline DeltaReference openpbr_reference(const OpenPbrBxDF& m, const Vec3& wo, TransportMode mode) {
  DeltaReference r;
  if (wo.z == 0) return r;
  const OpenPbrParams<Color>& p = m.params;
  const double alpha = std::clamp(double(p.geometry_opacity), 0.0, 1.0);
  r.transmission.fill(1 - alpha);
  if (!(alpha > 0)) return r;
  const double mu = std::min(1.0, std::abs(double(wo.z)));
  const Vec3 up{wo.x, wo.y, Float(mu)};
  // The indices and smoothness, written out again from SPEC-OPB (not read from the model):
  // the TIR fix, the modulated index of eq. `modulated_ior` (F0 scaled by ξ), the base's
  // index through the coat (eq. `specular_ior_ratio_with_tir_fix`), the roughening of the
  // base by the coat ("Roughening") and the anisotropic α of eq. `openpbr-anisotropy-formula`.
  const auto tir = [](double e) { return e < 1 ? 1 / e : e; };
  const auto modulated = [](double eta, double xi) {
    const double f0 = (eta - 1) * (eta - 1) / ((eta + 1) * (eta + 1));
    const double s = std::sqrt(std::clamp(xi * f0, 0.0, 0.99999)) * (eta >= 1 ? 1 : -1);
    return (1 + s) / (1 - s);
  };
  const auto largest_alpha = [](double roughness, double aniso) {
    const double b = 1 - std::clamp(aniso, 0.0, 1.0);
    return roughness * roughness * std::sqrt(2 / (1 + b * b));
  };
  const double smooth_alpha = double(MicrofacetDistribution::kSmoothAlpha);
  const double eta_c = tir(double(p.coat_ior));
  const bool coat_smooth = largest_alpha(p.coat_roughness, p.coat_roughness_anisotropy) < smooth_alpha;
  // A rough coat's E(w) and Ē are its albedo tables' (coat_albedo.h, whose own tests
  // compare them with a quadrature of the microfacet lobe): the one input taken from the model.
  const auto coat_e = [&](const Vec3& w) {
    if (eta_c == 1) return 0.0;
    return coat_smooth ? reference_fresnel_dielectric(std::min(1.0, double(w.z)), eta_c) : double(m.coat_E(w));
  };
  // Ē of the coat (smooth: 2∫F μ dμ by the midpoint rule), K, E_b, Δ (SPEC-OPB "Darkening").
  double ebar = 0;
  if (eta_c != 1) {
    if (coat_smooth) {
      for (int i = 0; i < 4096; ++i) {
        const double x = (i + 0.5) / 4096;
        ebar += 2 * reference_fresnel_dielectric(x, eta_c) * x / 4096;
      }
    } else {
      ebar = m.coat_avg;
    }
  }
  const double K = 1 - (1 - ebar) / (eta_c * eta_c);
  const double C = p.coat_weight, M = p.base_metalness, T = p.transmission_weight, S = p.subsurface_weight;
  const double xi_m = std::clamp(double(p.specular_weight), 0.0, 1.0);
  // The film covers thin_film_weight of the specular layer, the metal and the glass; its
  // reflectance is the validator's own Airy sum over each one's substrate table (the metal's
  // the F82 curve's effective index, the glass's its index).
  const double film_w = p.thin_film_thickness > 0 ? std::clamp(double(p.thin_film_weight), 0.0, 1.0) : 0.0;
  const auto metal_f = [&](double x, int c) {
    const double f = reference_fresnel_f82(x, std::clamp(double(p.base_color[c] * p.base_weight), 0.0, 1.0),
                                           std::clamp(double(p.specular_color[c]), 0.0, 1.0));
    return film_w > 0 ? (1 - film_w) * f + film_w * film_reference(x, m.metal.fresnel.film)[size_t(c)] : f;
  };
  const auto layer = [&](const Vec3& w, double mu_o, double mu_i, int c) {
    const double efz = p.fuzz_weight * double(sheen_albedo(w.z, std::max(p.fuzz_roughness, Float(0.01))));
    const double ec = C > 0 ? coat_e(w) : 0.0;
    const double tc = std::sqrt(std::max(0.0, double(p.coat_color[c])));
    const auto mut = [&](double x) { return std::sqrt(std::max(1e-12, 1 - (1 - x * x) / (eta_c * eta_c))); };
    const double a = tc >= 1 ? 1.0 : std::pow(tc, 1 / mut(mu_o) + (mu_i > 0 ? 1 / mut(mu_i) : 0.0));
    const double rho = std::clamp(double(p.base_color[c] * p.base_weight), 0.0, 1.0);
    const double eb = ((1 - S) * rho + S * std::clamp(double(p.subsurface_color[c]), 0.0, 1.0)) * (1 - T) + T;
    const double e_b = eb * (1 - M) + (M > 0 ? metal_f(1, c) : 0.0) * xi_m * M;
    const double delta = (1 - K) / std::max(1e-6, 1 - e_b * K);
    const double dark = 1 + (delta - 1) * C * std::clamp(double(p.coat_darkening), 0.0, 1.0);
    return alpha * (1 - efz) * (1 - C * (1 - a * (1 - ec))) * dark;
  };
  const double rb = p.specular_roughness, rc = p.coat_roughness;
  const double rough = rb + (std::pow(std::min(1.0, std::pow(rb, 4) + 2 * std::pow(rc, 4)), 0.25) - rb) * C;
  const double alpha_spec = largest_alpha(rough, p.specular_roughness_anisotropy);
  const bool spec_smooth = alpha_spec < smooth_alpha;
  const double eta_spec =
      tir(modulated(double(p.specular_ior) + (tir(double(p.specular_ior / p.coat_ior)) - double(p.specular_ior)) * C,
                    double(p.specular_weight)));
  const double eta_glass = modulated(double(p.specular_ior), double(p.specular_weight));
  const bool glass_smooth = spec_smooth || alpha_spec * std::abs(eta_glass - 1) < smooth_alpha;
  const bool outside = wo.z > 0;
  // From inside a transmitting shape (wo below, not thin-walled) light meets the glass's
  // bare interface only: the layers and the opaque parts are outside it.
  const bool bare_inside = !outside && T > 0 && M < 1 && !p.geometry_thin_walled;
  for (int c = 0; c < kColorChannels; ++c) {
    double refl = 0;
    // The layers and the opaque parts (two-sided: mirrored for wo below).
    if (!bare_inside && C > 0 && coat_smooth && eta_c != 1)
      refl += alpha * (1 - p.fuzz_weight * double(sheen_albedo(up.z, std::max(p.fuzz_roughness, Float(0.01))))) * C *
              reference_fresnel_dielectric(mu, eta_c);
    const double base = layer(up, mu, mu, c);
    if (spec_smooth && !bare_inside) {
      if (M > 0) refl += base * M * xi_m * metal_f(mu, c);
      if (T < 1 && (eta_spec != 1 || film_w > 0)) {
        double F = reference_fresnel_dielectric(mu, eta_spec);
        if (film_w > 0) F = (1 - film_w) * F + film_w * film_reference(mu, m.film)[size_t(c)];
        refl += base * (1 - M) * (1 - T) * p.specular_color[c] * F;
      }
    }
    double trans = 0;
    const double tint = p.transmission_depth > 0 ? 1.0 : std::clamp(double(p.transmission_color[c]), 0.0, 1.0);
    if (T > 0 && M < 1) {
      if (p.geometry_thin_walled) {
        // (A rough sheet has no delta lobe: openpbr.h, rough_sheet.)
        if (spec_smooth) {
          const auto sheet = thin_sheet_reference(up, eta_spec);
          double R = sheet.reflection[size_t(c)], Tr = sheet.transmission[size_t(c)];
          if (film_w > 0) {
            const auto bubble = thin_sheet_reference(up, eta_spec, &m.film);
            R = (1 - film_w) * R + film_w * bubble.reflection[size_t(c)];
            Tr = (1 - film_w) * Tr + film_w * bubble.transmission[size_t(c)];
          }
          refl += base * (1 - M) * T * p.specular_color[c] * R;
          trans += base * (1 - M) * T * tint * Tr;
        }
      } else if (glass_smooth) {
        ThinFilmT<Color> glass_film = m.glass.film;  // its table: the glass's substrate
        glass_film.coverage = Float(film_w);
        const DeltaReference g = dielectric_reference(wo, eta_glass, mode, film_w > 0 ? &glass_film : nullptr);
        if (outside) {
          refl += base * (1 - M) * T * p.specular_color[c] * g.reflection[size_t(c)];
          trans += layer(up, mu, 0, c) * (1 - M) * T * tint * g.transmission[size_t(c)];
        } else {
          refl += alpha * (1 - M) * T * g.reflection[size_t(c)];
          // Out through the layers at the refracted outside direction.
          // Snell from inside: sin θ_out = η sin θ_in (η = n_inside / n_outside).
          const double e = eta_glass, st2 = e * e * (1 - mu * mu);
          if (st2 < 1) {
            const double mo = std::sqrt(1 - st2);
            const Vec3 w_out{Float(-wo.x * e), Float(-wo.y * e), Float(mo)};
            trans += layer(w_out, mo, 0, c) * (1 - M) * T * tint * g.transmission[size_t(c)];
          }
        }
      }
    }
    r.reflection[size_t(c)] = refl;
    r.transmission[size_t(c)] += trans;
  }
  return r;
}

// The expected delta-lobe reflectances of `bxdf` at wo, or none when the validator does
// not know what the model's delta lobe is (a user model with a specular reflection lobe
// and no specular transmission). Models without delta lobes expect 0: a delta sample
// from them is an error. A user model with a specular transmission lobe is taken to be
// a smooth dielectric interface of its declared relative_eta() — the one thing a delta
// refraction can be under SPEC §1.
inline std::optional<DeltaReference> delta_reference(const BxDF& bxdf, const Vec3& wo, TransportMode mode) {
  return std::visit(
      [&](const auto& m) -> std::optional<DeltaReference> {
        using M = std::decay_t<decltype(m)>;
        DeltaReference r;
        if constexpr (std::is_same_v<M, MirrorBxDF>) {
          if (wo.z != 0)
            for (int c = 0; c < kColorChannels; ++c) r.reflection[size_t(c)] = m.reflectance[c];
          return r;
        } else if constexpr (std::is_same_v<M, ConductorBxDF>) {
          return conductor_reference(wo, m.fresnel);
        } else if constexpr (std::is_same_v<M, DielectricBxDF>) {
          return dielectric_reference(wo, m.eta, mode, &m.film);
        } else if constexpr (std::is_same_v<M, ThinDielectricBxDF>) {
          return thin_sheet_reference(wo, m.eta, &m.film);
        } else if constexpr (std::is_same_v<M, RoughConductorBxDF>) {
          return m.distribution.effectively_smooth() ? conductor_reference(wo, m.fresnel) : r;
        } else if constexpr (std::is_same_v<M, RoughDielectricBxDF>) {
          return m.specular() ? dielectric_reference(wo, m.eta, mode, &m.film) : r;
        } else if constexpr (std::is_same_v<M, PlasticBxDF>) {
          // The smooth coat's mirror reflection: F from outside the coat, on wo's side.
          if (m.smooth() && wo.z != 0) r.reflection.fill(reference_fresnel_dielectric(wo.z, m.eta));
          return r;
        } else if constexpr (std::is_same_v<M, BlendBxDF>) {
          const auto a = delta_reference((*m.parts)[0], wo, mode), b = delta_reference((*m.parts)[1], wo, mode);
          if (!a || !b) return std::nullopt;
          const double w = m.weight;
          for (size_t c = 0; c < size_t(kColorChannels); ++c) {
            r.reflection[c] = (1 - w) * a->reflection[c] + w * b->reflection[c];
            r.transmission[c] = (1 - w) * a->transmission[c] + w * b->transmission[c];
          }
          return r;
        } else if constexpr (std::is_same_v<M, LayeredBxDF>) {
          // A smooth top's specular chain, summed in closed form: light reflected by the
          // top (F: the dielectric's, under its film when it has one, or the thin sheet's
          // 2r/(1 + r), each per channel from the references above), or refracted in
          // (a sheet does not bend it), attenuated by e^{−τ/μ'} each way, reflected by the
          // bottom's delta lobe (R_b, the validator's own reference at the inner
          // direction) and bounced between bottom and top (F from inside equals F from
          // outside at Snell's pair of angles, for a lossless film too; the radiance
          // scalings in and out cancel):
          //   R = F + (1 − F)² T R_b / (1 − F T R_b),  T = e^{−2τ/μ'};
          // through a bottom that transmits T_b (its own reference, with the mode's
          // scaling), t_in e^{−τ/μ'} T_b / (1 − F T R_b), t_in the top's transmission.
          // A rough top has no delta lobe. A stack that reflects only is two-sided.
          if (wo.z == 0) return r;
          const bool through = is_transmissive(m.bottom->flags());
          const auto top_reference = [&](const Vec3& w) {
            return m.thin_top ? thin_sheet_reference(w, m.top.eta, &m.top.film)
                              : dielectric_reference(w, m.top.eta, mode, &m.top.film);
          };
          const double eta = m.thin_top ? 1.0 : double(m.top.eta);
          if (through && wo.z < 0) {
            // Seen from below: the bottom's own R0 and T0 (into the medium, at cos θ_v by
            // the bottom's index), then the chain between the top (F from inside, t_out
            // out) and the bottom (R_b, and T_b back out below):
            //   T = T0 e^{−τ/μ_v} t_out / (1 − F T R_b),  R = R0 + T0 T F T_b / (1 − F T R_b).
            const auto b0 = delta_reference(*m.bottom, wo, mode);
            if (!b0) return std::nullopt;
            r.reflection = b0->reflection;
            const double eb = double(m.bottom->relative_eta()), mu = std::abs(double(wo.z));
            const double sv2 = eb * eb * (1 - mu * mu);
            if (!m.top.specular() || !(sv2 < 1)) return r;
            const double mu_v = std::sqrt(1 - sv2), sin_v = std::sqrt(sv2);
            const auto t = top_reference(Vec3{Float(sin_v), 0, Float(-mu_v)});
            const auto b1 = delta_reference(*m.bottom, Vec3{Float(sin_v), 0, Float(mu_v)}, mode);
            if (!b1) return std::nullopt;
            const double T1 = m.thickness > 0 ? std::exp(-double(m.thickness) / mu_v) : 1.0;
            for (size_t c = 0; c < size_t(kColorChannels); ++c) {
              const double loop = 1 - t.reflection[c] * T1 * T1 * b1->reflection[c];
              r.transmission[c] = b0->transmission[c] * T1 * t.transmission[c] / loop;
              r.reflection[c] += b0->transmission[c] * T1 * T1 * t.reflection[c] * b1->transmission[c] / loop;
            }
            return r;
          }
          if (!m.top.specular()) return r;
          const double mu = std::abs(double(wo.z));
          const Vec3 up{wo.x, wo.y, Float(mu)};
          const DeltaReference top = top_reference(up);
          const std::array<double, kColorChannels>& F = top.reflection;
          const double s2 = (1 - mu * mu) / (eta * eta);
          if (!(s2 < 1)) {  // total internal reflection from outside (η < 1)
            r.reflection = F;
            return r;
          }
          const double mu_in = m.thin_top ? mu : std::sqrt(1 - s2);
          const Vec3 inner{Float(wo.x / eta), Float(wo.y / eta), Float(mu_in)};
          const auto b = delta_reference(*m.bottom, inner, mode);
          if (!b) return std::nullopt;
          const double T1 = m.thickness > 0 ? std::exp(-double(m.thickness) / mu_in) : 1.0, T = T1 * T1;
          for (size_t c = 0; c < size_t(kColorChannels); ++c) {
            const double rb = b->reflection[c], f = F[c];
            r.reflection[c] = f + (1 - f) * (1 - f) * T * rb / (1 - f * T * rb);
            if (through) r.transmission[c] = top.transmission[c] * T1 * b->transmission[c] / (1 - f * T * rb);
          }
          return r;
        } else if constexpr (std::is_same_v<M, OpenPbrBxDF>) {
          return openpbr_reference(m, wo, mode);
        } else if constexpr (std::is_same_v<M, GltfPbrBxDF>) {
          // gltf_pbr's one delta lobe: the pass-through of alpha coverage a (glTF 2.0 §3.9.4),
          // 1 − a from alpha, alpha_mode and alpha_cutoff as the specification reads them.
          const GltfPbrParams<Color>& p = m.params;
          const double a = std::clamp(double(p.alpha), 0.0, 1.0);
          const double cover = p.alpha_mode < 0.5 ? 1.0 : p.alpha_mode < 1.5 ? (a >= double(p.alpha_cutoff) ? 1.0 : 0.0) : a;
          r.transmission.fill(1 - cover);
          return r;
        } else if constexpr (std::is_same_v<M, UserBxDF>) {
          const BxDFFlags f = m.flags();
          if (has(f, BxDFFlags::Specular) && has(f, BxDFFlags::Transmission) && !has(f, BxDFFlags::Glossy | BxDFFlags::Diffuse))
            return dielectric_reference(wo, m.relative_eta(), mode);
          if (has(f, BxDFFlags::Specular)) return std::nullopt;
          return r;
        } else {
          return r;  // no delta lobe
        }
      },
      bxdf.models());
}

}  // namespace gonio::validation
