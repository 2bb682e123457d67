// Spectral mode's models from the parsed materials (spectral_material.h).

#include "gonio/spectral_material.h"

#include <type_traits>
#include <variant>

#include "gonio/bxdf/openpbr_dispersion.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/spectrum_to_rgb.h"

namespace gonio {

std::array<SpectralBxDF, 2>* SpectralScratch::next_parts() {
  // Pointers handed out earlier must stay valid while the model is in use, so the storage
  // never moves: it is made once, for the most blends one material can hold (a tree of
  // kMaxBlendDepth levels has 2^8 − 1 blends).
  if (parts_.empty()) parts_.resize(size_t(1) << kMaxBlendDepth);
  if (used_ == parts_.size()) return nullptr;
  return &parts_[used_++];
}

SampledSpectrum upsample_colour(MaterialParam param, const Color& rgb, const SampledWavelengths& w) noexcept {
  if (param == MaterialParam::Eta || param == MaterialParam::K) {
    // Linear between (450, b), (550, g), (650, r), constant outside.
    SampledSpectrum s;
    for (int j = 0; j < SampledSpectrum::size(); ++j) {
      const Float l = w[j];
      if (l <= kRgbIndexWavelengths[2]) s[j] = rgb[2];
      else if (l >= kRgbIndexWavelengths[0]) s[j] = rgb[0];
      else if (l <= kRgbIndexWavelengths[1]) {
        const Float t = (l - kRgbIndexWavelengths[2]) / (kRgbIndexWavelengths[1] - kRgbIndexWavelengths[2]);
        s[j] = rgb[2] + t * (rgb[1] - rgb[2]);
      } else {
        const Float t = (l - kRgbIndexWavelengths[1]) / (kRgbIndexWavelengths[0] - kRgbIndexWavelengths[1]);
        s[j] = rgb[1] + t * (rgb[0] - rgb[1]);
      }
    }
    return s;
  }
  return rgb_to_sigmoid_polynomial(rgb[0], rgb[1], rgb[2]).eval(w);
}

namespace {

using MP = MaterialParam;
using SS = SampledSpectrum;

struct Converter {
  const MaterialSpectra& spectra;
  SampledWavelengths& w;
  SpectralScratch& scratch;
  TexturedColours textured;

  SS colour(MP p, const Color& rgb) const {
    const auto& s = spectra.colour[size_t(p)];
    if (s && !(textured >> unsigned(p) & 1u)) return s->eval(w);
    return upsample_colour(p, rgb, w);
  }
  // The index at the hero wavelength; the others are dropped when it varies (dispersion).
  Float index(Float rgb_eta) const {
    if (!spectra.index || !spectra.dispersive) return rgb_eta;
    w.terminate_secondary();
    return spectra.index->eval(w[0]);
  }

  // The film at the path's wavelengths: exact per wavelength (bxdf/thin_film.h).
  ThinFilmT<SS> film(const ThinFilmT<Color>& f) const {
    ThinFilmT<SS> s;
    s.thickness = f.thickness;
    s.eta = f.eta;
    for (int j = 0; j < SS::size(); ++j) s.lambda[j] = w[j];
    return s;
  }

  ConductorFresnelT<SS> fresnel(const ConductorFresnel& f) const {
    ConductorFresnelT<SS> s;
    s.film = film(f.film);
    s.model = f.model;
    s.eta = colour(MP::Eta, f.eta);
    s.k = colour(MP::K, f.k);
    s.f0 = spectra.colour[size_t(MP::F0)] ? colour(MP::F0, f.f0)
                                           : map(s.eta, s.k, [](Float n, Float k) { return fresnel_f0(n, k); });
    // F82-tint's tint has no recorded spectrum: its RGB (a spectrum reduced to RGB at
    // parse time) upsampled as a reflectance.
    if (f.model == FresnelModel::F82) s.f82 = upsample_colour(MP::Reflectance, f.f82, w);
    s.prepare();
    return s;
  }

  SpectralBxDF operator()(const DiffuseBxDF& m) const { return DiffuseBxDFT<SS>{colour(MP::Reflectance, m.reflectance)}; }
  SpectralBxDF operator()(const MirrorBxDF& m) const { return MirrorBxDFT<SS>{colour(MP::Reflectance, m.reflectance)}; }
  SpectralBxDF operator()(const ConductorBxDF& m) const { return ConductorBxDFT<SS>{fresnel(m.fresnel)}; }
  SpectralBxDF operator()(const DielectricBxDF& m) const { return DielectricBxDFT<SS>{index(m.eta), film(m.film)}; }
  SpectralBxDF operator()(const ThinDielectricBxDF& m) const {
    return ThinDielectricBxDFT<SS>{m.film.active() ? m.eta : index(m.eta), film(m.film)};
  }
  SpectralBxDF operator()(const RoughConductorBxDF& m) const {
    RoughConductorBxDFT<SS> s;
    s.distribution = m.distribution;
    s.fresnel = fresnel(m.fresnel);
    if (m.multiscatter) {
      SS f_avg;
      if (spectra.f_avg && !(textured & ((1u << unsigned(MP::Eta)) | (1u << unsigned(MP::K)) | (1u << unsigned(MP::F0)))))
        f_avg = spectra.f_avg->eval(w);
      else
        f_avg = conductor_average_fresnel(s.fresnel);  // a textured index: per shading point
      s.multiscatter = MultiscatterLobeT<SS>::make(m.distribution, f_avg);
    }
    return s;
  }
  SpectralBxDF operator()(const RoughDielectricBxDF& m) const {
    RoughDielectricBxDFT<SS> s;
    s.distribution = m.distribution;
    s.eta = index(m.eta);
    s.film = film(m.film);
    if (m.multiscatter)
      s.multiscatter = s.eta == m.eta || !spectra.f_avg
                           ? *m.multiscatter
                           : DielectricMultiscatterLobe::remake(m.distribution, s.eta, spectra.f_avg->eval(w[0]));
    return s;
  }
  // A fibre: sigma_a (like an index: linear between the channels' wavelengths, as its
  // RGB coefficients are values at them) and the tints upsampled as reflectances.
  SpectralBxDF operator()(const HairBxDF& m) const {
    HairBxDFT<SS> s;
    s.sigma_a = upsample_colour(MP::Eta, m.sigma_a, w);
    s.eta = m.eta;
    s.h = m.h;
    s.average_h = m.average_h;
    s.v = m.v;
    s.s = m.s;
    for (size_t i = 0; i < 3; ++i) s.tint[i] = upsample_colour(MP::Reflectance, m.tint[i], w);
    s.sin_tilt = m.sin_tilt;
    s.cos_tilt = m.cos_tilt;
    s.log_norm = m.log_norm;
    s.inv_trim = m.inv_trim;
    return s;
  }
  SpectralBxDF operator()(const SheenBxDF& m) const {
    return SheenBxDFT<SS>{colour(MP::SheenColor, m.color), m.roughness};
  }
  SpectralBxDF operator()(const CharlieSheenBxDF& m) const {
    return CharlieSheenBxDFT<SS>{colour(MP::SheenColor, m.color), m.roughness};
  }
  SpectralBxDF operator()(const OrenNayarBxDF& m) const {
    OrenNayarBxDFT<SS> s;
    s.reflectance = colour(MP::Reflectance, m.reflectance);
    s.sigma = m.sigma;
    s.full = m.full;
    return s;
  }
  SpectralBxDF operator()(const EonBxDF& m) const {
    return EonBxDFT<SS>::make(colour(MP::Reflectance, m.reflectance), m.roughness);
  }
  template <typename M>
    requires std::is_same_v<M, PhongBxDF> || std::is_same_v<M, BlinnPhongBxDF>
  SpectralBxDF operator()(const M& m) const {
    using T = std::conditional_t<std::is_same_v<M, PhongBxDF>, PhongBxDFT<SS>, BlinnPhongBxDFT<SS>>;
    T s;
    s.kd = colour(MP::Kd, m.kd);
    s.ks = colour(MP::Ks, m.ks);
    s.exponent = m.exponent;
    return s;
  }
  SpectralBxDF operator()(const WardBxDF& m) const {
    WardBxDFT<SS> s;
    s.kd = colour(MP::Kd, m.kd);
    s.ks = colour(MP::Ks, m.ks);
    s.alpha_x = m.alpha_x;
    s.alpha_y = m.alpha_y;
    return s;
  }
  SpectralBxDF operator()(const AshikhminShirleyBxDF& m) const {
    AshikhminShirleyBxDFT<SS> s;
    s.rd = colour(MP::Rd, m.rd);
    s.rs = colour(MP::Rs, m.rs);
    s.nu = m.nu;
    s.nv = m.nv;
    return s;
  }
  SpectralBxDF operator()(const PlasticBxDF& m) const {
    return PlasticBxDFT<SS>::make(static_cast<const PlasticCoat&>(m), colour(MP::Reflectance, m.reflectance));
  }
  SpectralBxDF operator()(const MeasuredBxDF& m) const {
    MeasuredBxDFT<SS> s;
    s.data = m.data;  // the parsed material's table outlives the spectral model
    s.wavelengths = w;
    return s;
  }
  SpectralBxDF operator()(const RglBxDF& m) const {
    RglBxDFT<SS> s;
    s.data = m.data;  // the parsed material's table outlives the spectral model
    s.wavelengths = w;
    return s;
  }
  SpectralBxDF operator()(const BlendBxDF& m) const {
    std::array<SpectralBxDF, 2>* parts = scratch.next_parts();
    if (!parts || spectra.parts.size() != 2) return DiffuseBxDFT<SS>{SS(0)};
    for (size_t i = 0; i < 2; ++i)
      (*parts)[i] = Converter{spectra.parts[i], w, scratch, 0}.convert((*m.parts)[i]);
    BlendBxDFT<SS> s;
    s.weight = m.weight;
    s.parts = parts;
    return s;
  }
  // The top at the path's wavelengths (its index at the hero wavelength when dispersive),
  // the bottom in one scratch slot (a layered material counts as one level of nesting).
  SpectralBxDF operator()(const LayeredBxDF& m) const {
    std::array<SpectralBxDF, 2>* parts = scratch.next_parts();
    if (!parts || spectra.parts.size() != 2) return DiffuseBxDFT<SS>{SS(0)};
    (*parts)[0] = Converter{spectra.parts[1], w, scratch, 0}.convert(*m.bottom);
    const SpectralBxDF top = Converter{spectra.parts[0], w, scratch, 0}(m.top);
    LayeredBxDFT<SS> s;
    s.top = std::get<RoughDielectricBxDFT<SS>>(top.models());
    s.thin_top = m.thin_top;
    s.bottom = &(*parts)[0];
    s.thickness = m.thickness;
    s.albedo = colour(MP::Reflectance, m.albedo);
    s.g = m.g;
    s.max_depth = m.max_depth;
    s.samples = m.samples;
    return s;
  }
  // openpbr: its colours upsampled at the path's wavelengths (a spectrum given for one was
  // reduced to RGB at parse time; a textured one is the texture's RGB at this point, which
  // with_params put in `params`), the model made again for them, the film exact per
  // wavelength.
  SpectralBxDF operator()(const OpenPbrBxDF& m) const {
    const auto up = [&](const Color& c) { return upsample_colour(MP::Reflectance, c, w); };
    const OpenPbrParams<Color>& p = m.params;
    OpenPbrParams<SS> s;
    for (size_t i = 0; i < kOpenPbrFieldCount; ++i) {
      const auto& from = kOpenPbrFields<Color>[i];
      const auto& to = kOpenPbrFields<SS>[i];
      if (from.number) s.*to.number = p.*from.number;
      else s.*to.colour = up(p.*from.colour);
    }
    s.geometry_thin_walled = p.geometry_thin_walled;
    s.reciprocal_layering = p.reciprocal_layering;
    // Dispersion (openpbr_dispersion.h): the interface's index at the hero wavelength, and
    // the path goes on with the hero only (as a dispersive dielectric does, above). The
    // quadratures kept from the RGB model are η_d's.
    if (const auto eta = openpbr::dispersed_ior(p, w[0])) {
      s.specular_ior = *eta;
      w.terminate_secondary();
    }
    const openpbr::Solved solved = m.solved();
    return OpenPbrBxDFT<SS>::make(s, film(m.film), &solved);
  }
  // gltf_pbr: its colours upsampled at the path's wavelengths (as openpbr's). Dispersion
  // (KHR_materials_dispersion: η(λ) = η_d + (η_d − 1)/V (523655/λ² − 1.5168), V = 20 /
  // dispersion, the formula of openpbr_dispersion.h): where the material refracts, the
  // index at the hero wavelength, and the path goes on with the hero only.
  SpectralBxDF operator()(const GltfPbrBxDF& m) const {
    const GltfPbrParams<Color>& p = m.params;
    GltfPbrParams<SS> s;
    for (size_t i = 0; i < kGltfPbrFieldCount; ++i) {
      const auto& from = kGltfPbrFields<Color>[i];
      const auto& to = kGltfPbrFields<SS>[i];
      if (from.number) s.*to.number = p.*from.number;
      else s.*to.colour = upsample_colour(MP::Reflectance, p.*from.colour, w);
    }
    if (m.volume() && p.dispersion > 0) {
      s.ior = std::max(Float(1), openpbr::cauchy_index(p.ior, 20 / p.dispersion, w[0]));
      w.terminate_secondary();
    }
    return GltfPbrBxDFT<SS>::make(s);
  }
  // A MaterialX node (pbr_node.h): its inputs in one scratch slot, its factor upsampled
  // as a reflectance, the throughput table shared with the RGB model.
  SpectralBxDF operator()(const PbrNodeBxDF& m) const {
    std::array<SpectralBxDF, 2>* parts = scratch.next_parts();
    if (!parts || spectra.parts.size() != 2) return DiffuseBxDFT<SS>{SS(0)};
    const size_t n = m.op == PbrOp::Scale ? 1 : 2;
    for (size_t i = 0; i < n; ++i) (*parts)[i] = Converter{spectra.parts[i], w, scratch, 0}.convert((*m.parts)[i]);
    PbrNodeBxDFT<SS> s;
    s.op = m.op;
    s.through = m.through;
    s.scale = m.scale == Color(1) ? SS(1) : upsample_colour(MP::Reflectance, m.scale, w);
    s.weight = m.weight;
    s.albedo_table = m.albedo_table;
    s.parts = parts;
    return s;
  }
  SpectralBxDF operator()(const UserBxDF&) const { return DiffuseBxDFT<SS>{SS(0)}; }

  SpectralBxDF convert(const BxDF& rgb) const {
    return std::visit([this](const auto& m) { return (*this)(m); }, rgb.models());
  }
};

}  // namespace

SpectralBxDF to_spectral(const BxDF& rgb, const MaterialSpectra& spectra, SampledWavelengths& w,
                         SpectralScratch& scratch, TexturedColours textured) noexcept {
  return Converter{spectra, w, scratch, textured}.convert(rgb);
}

}  // namespace gonio
