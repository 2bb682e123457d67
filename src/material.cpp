// Material descriptions (SPEC §2) → BxDF, with errors that name the field.

#include "gonio/material.h"

#include <filesystem>
#include <functional>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <array>
#include <iterator>
#include <type_traits>
#include <variant>
#include <memory>
#include <map>
#include <set>
#include <stdexcept>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gonio/hemispherical_average.h"
#include "gonio/io/materialx.h"
#include "gonio/json_text.h"
#include "gonio/material_types.h"
#include "gonio/metals.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/metal_spectra.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/spectrum/spectrum_json.h"
#include "gonio/spectrum/spectrum_to_rgb.h"
#include "gonio/subsurface/albedo_inversion.h"
#include "gonio/subsurface/named_media.h"
#include "gonio/subsurface/subsurface.h"

namespace gonio {
namespace {

using nlohmann::json;

// A parameter that must be positive must stay positive, and normal, as a float: 1e-320
// passes "> 0" as a double but becomes 0 (or a denormal, whose reciprocal overflows).
bool positive_float(double v) { return static_cast<float>(v) >= FLT_MIN; }
constexpr const char* kTooSmallForFloat = " (too small for a float: it would round to 0 or a denormal)";

// Error messages show values as json_excerpt does (json_text.h).
std::string show(const json& v) { return json_excerpt(v); }

// Reads the parameters of one material as its entry in the registry (material_types.h)
// declares them: defaults, ranges and choices come from there, and any key the entry
// does not list, or that the type did not read, is reported as unknown with the list of
// the keys it takes.
class Params {
 public:
  Params(const json& obj, std::string prefix, const MaterialTypeSpec& type, MaterialSpectra& spectra,
         const std::string& base_dir)
      : obj_(obj), prefix_(std::move(prefix)), type_(type), spectra_(spectra), base_dir_(base_dir) {}
  const std::string& base_dir() const { return base_dir_; }

  // Where the spectra of the parameters read are recorded (spectral_material.h).
  MaterialSpectra& spectra() { return spectra_; }

  [[noreturn]] void fail(const std::string& msg) const { throw InputError(prefix_ + msg); }

  // The registry's entry for `key`; reading a key the registry does not declare is a
  // programming error (the reference would not show it).
  const ParamSpec& spec(const char* key) const {
    const ParamSpec* s = find_param(type_, key);
    if (!s) throw std::logic_error("material registry: " + std::string(type_.name) + " does not declare '" + key + "'");
    return *s;
  }

  // Whether the description gives `key` (a default does not count).
  bool has(const char* key) {
    spec(key);
    if (!obj_.contains(key)) return false;
    used_.insert(key);
    return true;
  }

  // The value given, else the registry's default; a missing parameter without one is an error.
  const json& value(const char* key) {
    const ParamSpec& s = spec(key);
    if (obj_.contains(key)) {
      used_.insert(key);
      return obj_.at(key);
    }
    if (s.default_json.empty()) {
      std::string hint;
      if (s.kind == ParamKind::Roughness) hint = " (a number, or [alpha_x, alpha_y])";
      else if (s.kind == ParamKind::Materials) hint = " (an array of 2 materials)";
      else if (s.kind == ParamKind::Material) hint = " (a material)";
      else if (s.range.present) hint = " (" + range_text(s.range, s.unit) + ")";
      fail(std::string("missing parameter '") + key + "'" + hint);
    }
    auto [it, inserted] = defaults_.try_emplace(key);
    if (inserted) it->second = json::parse(s.default_json);
    return it->second;
  }

  // A number within the registry's range.
  double number(const char* key) {
    const json& v = value(key);
    if (!v.is_number()) fail(std::string(key) + " must be a number, got " + show(v));
    const double d = finite(key, v);
    check_range(key, d);
    return d;
  }

  // A colour: a number (grey) or [r, g, b], each channel within the registry's range
  // (checked on the value as written, so the message shows it even when it does not fit
  // in a float).
  Color color(const char* key) {
    const json& v = value(key);
    Color c;
    const std::string k(key);
    const bool index = k == "eta" || k == "k";
    // A subsurface medium's coefficients (1/unit) and mean free path are not
    // reflectances: a spectrum gives its values at the channels' wavelengths, as an index
    // does. They have no slot among the textured parameters, so nothing is recorded.
    const bool coefficient = k == "sigma_s" || k == "sigma_a" || k == "mfp";
    std::optional<Spectrum> unrecorded;
    std::optional<Spectrum>& recorded =
        is_colour_param(key) ? spectra_.colour[size_t(colour_param(key))] : unrecorded;
    if (v.is_number() || v.is_array()) {
      if (v.is_number()) {
        c = Color(static_cast<Float>(checked(key, v)));
      } else if (v.size() == static_cast<size_t>(Color::size())) {
        for (int i = 0; i < Color::size(); ++i) {
          const json& e = v[static_cast<size_t>(i)];
          if (!e.is_number()) fail(std::string(key) + " must be a number or [r, g, b], got " + show(v));
          c[i] = static_cast<Float>(checked(key, e));
        }
      } else {
        fail(std::string(key) + " must be a number, [r, g, b] or a spectrum, got " + show(v));
      }
      recorded = rgb_as_spectrum(c, index);
    } else if (v.is_object()) {
      // A spectrum (SPEC §2), reduced to RGB: a conductor's n and k by their values at the
      // channels' wavelengths, any other colour as a reflectance under D65.
      const SpectrumUse use = index || coefficient ? SpectrumUse::kIndex : SpectrumUse::kReflectance;
      Spectrum sp = spectrum(key, use);
      c = spectrum_to_rgb(sp, use);
      for (int i = 0; i < Color::size(); ++i) check_range(key, c[i]);
      recorded = std::move(sp);
    } else {
      fail(std::string(key) + " must be a number, [r, g, b] or a spectrum, got " + show(v));
    }
    return c;
  }

  // A dielectric's index: a number, or (SPEC §2) a named glass, {"sellmeier": ...} or
  // {"spectrum": ...}, which RGB mode reads at the green channel's wavelength.
  double index(const char* key) {
    const json& v = value(key);
    if (v.is_number()) {
      const double d = number(key);
      spectra_.index = ConstantSpectrum{Float(d)};
      spectra_.dispersive = false;
      return d;
    }
    if (!v.is_string() && !v.is_object())
      fail(std::string(key) + " must be a number, a glass name, {\"sellmeier\": ...} or a spectrum, got " + show(v));
    Spectrum sp = spectrum(key, SpectrumUse::kIndex);
    const double d = sp.eval(kRgbIndexWavelengths[1]);
    check_range(key, d);
    // Spectral mode reads it at each wavelength: it must stay in range over the visible.
    const ParamSpec& ps = spec(key);
    for (Float l = kLambdaMin; l <= kLambdaMax; l += 5) {
      const double n = sp.eval(l);
      if (ps.range.present && !(std::isfinite(n) && ps.range.contains(n)))
        fail(std::string(key) + " must be " + range_requirement(ps.range, ps.unit) + " over 360-830 nm, got " +
             format_number(n) + " at " + format_number(l) + " nm");
    }
    spectra_.index = std::move(sp);
    spectra_.dispersive = true;
    return d;
  }

  bool boolean(const char* key) {
    const json& v = value(key);
    if (!v.is_boolean()) fail(std::string(key) + " must be true or false, got " + show(v));
    return v.get<bool>();
  }

  // A roughness: a number (isotropic) or [alpha_x, alpha_y], each within the range.
  std::pair<double, double> roughness(const char* key) {
    const json& v = value(key);
    double a = 0, b = 0;
    if (v.is_number()) {
      a = b = finite(key, v);
    } else if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
      a = finite(key, v[0]);
      b = finite(key, v[1]);
    } else {
      fail(std::string(key) + " must be a number or [alpha_x, alpha_y], got " + show(v));
    }
    check_range(key, a);
    check_range(key, b);
    return {a, b};
  }

  // A fibre's per-lobe value: a number (one for every lobe) or [R, TT, TRT], each in range.
  // `single` tells which form was given.
  std::array<double, 3> lobes(const char* key, bool* single = nullptr) {
    const json& v = value(key);
    std::array<double, 3> r{};
    if (v.is_number()) {
      r.fill(finite(key, v));
      if (single) *single = true;
    } else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number()) {
      for (size_t i = 0; i < 3; ++i) r[i] = finite(key, v[i]);
      if (single) *single = false;
    } else {
      fail(std::string(key) + " must be a number or [R, TT, TRT], got " + show(v));
    }
    for (double x : r) check_range(key, x);
    return r;
  }
  // [a, b] (MaterialX's vector2), each in range.
  std::array<double, 2> pair(const char* key) {
    const json& v = value(key);
    if (!(v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()))
      fail(std::string(key) + " must be [a, b] (two numbers), got " + show(v));
    const std::array<double, 2> r{finite(key, v[0]), finite(key, v[1])};
    for (double x : r) check_range(key, x);
    return r;
  }

  const json& raw(const char* key) { return value(key); }

  std::string string(const char* key) {
    const json& v = value(key);
    if (!v.is_string()) fail(std::string(key) + " must be a string, got " + show(v));
    return v.get<std::string>();
  }

  // One of the registry's choices for `key`.
  std::string choice(const char* key) {
    const std::string got = string(key);
    const std::string_view choices = spec(key).choices;
    std::string list;
    size_t start = 0;
    while (start <= choices.size()) {
      const size_t bar = std::min(choices.find('|', start), choices.size());
      const std::string_view c = choices.substr(start, bar - start);
      if (c == got) return got;
      const bool last = bar == choices.size();
      if (!list.empty()) list.append(last ? " or " : ", ");
      list.append("\"").append(c).append("\"");
      start = bar + 1;
    }
    fail(std::string(key) + " must be " + list + ", got \"" + got + "\"");
  }

  // Before the type reads anything: a misspelt key is named as such, not reported as the
  // required parameter it was meant to be ("alpah" → unknown 'alpah', not missing 'alpha').
  void reject_undeclared() const {
    for (const auto& [key, value] : obj_.items())
      if (key != "type" && !find_param(type_, key))
        fail("unknown parameter '" + key + "'; " + std::string(type_.name) + " takes " + param_names(type_));
  }
  // After it: a declared key the type did not read (one that another key excludes).
  void reject_unknown() const {
    for (const auto& [key, value] : obj_.items()) {
      if (key == "type") continue;
      if (!find_param(type_, key) || !used_.count(key))
        fail("unknown parameter '" + key + "'; " + std::string(type_.name) + " takes " + param_names(type_));
    }
  }

 private:
  static bool is_colour_param(const char* key) {
    for (int i = 0; i < kColourParams; ++i)
      if (material_param_info(MaterialParam(i)).key == key) return true;
    return false;
  }
  static MaterialParam colour_param(const char* key) {
    for (int i = 0; i < kColourParams; ++i)
      if (material_param_info(MaterialParam(i)).key == key) return MaterialParam(i);
    throw std::logic_error(std::string("material: '") + key + "' is not a colour parameter");
  }
  // An RGB value as the spectrum spectral mode uses: a reflectance-like colour upsampled
  // (Jakob & Hanika 2019), an index linear between the channels' wavelengths.
  static std::optional<Spectrum> rgb_as_spectrum(const Color& c, bool index) {
    if (c[0] == c[1] && c[1] == c[2]) return Spectrum(ConstantSpectrum{c[0]});
    if (index)
      return Spectrum(PiecewiseLinearSpectrum::from_points(
          {{kRgbIndexWavelengths[2], c[2]}, {kRgbIndexWavelengths[1], c[1]}, {kRgbIndexWavelengths[0], c[0]}}, "index"));
    for (int i = 0; i < 3; ++i)
      if (!(c[i] >= 0 && c[i] <= 1)) return std::nullopt;  // upsampled (clamped) per shading point
    return Spectrum(RgbAlbedoSpectrum(c[0], c[1], c[2]));
  }
  // parse_spectrum's errors start with the field; they get this material's prefix.
  Spectrum spectrum(const char* key, SpectrumUse use) {
    try {
      return parse_spectrum(value(key), key, use, base_dir_);
    } catch (const InputError& e) {
      // A spectrum file's own errors name the file, not the field: add it.
      const std::string what = e.what(), field = std::string(key) + ": ";
      fail(what.rfind(field, 0) == 0 ? what : field + what);
    }
  }
  double finite(const char* key, const json& v) const {
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(std::string(key) + " must be finite, got " + show(v));
    return d;
  }
  double checked(const char* key, const json& v) const {
    const double d = finite(key, v);
    check_range(key, d);
    return d;
  }
  void check_range(const char* key, double d) const {
    const ParamSpec& s = spec(key);
    if (!s.range.present) return;
    if (!s.range.contains(d))
      fail(std::string(key) + " must be " + range_requirement(s.range, s.unit, d) + ", got " + format_number(d));
    // An open lower end at 0 means "positive", which must survive the cast to float.
    if (s.range.lo_open && s.range.lo == 0 && !positive_float(d))
      fail(std::string(key) + " must be > 0, got " + format_number(d) + kTooSmallForFloat);
  }

  const json& obj_;
  std::string prefix_;
  const MaterialTypeSpec& type_;
  std::set<std::string> used_;
  std::map<std::string, json> defaults_;
  MaterialSpectra& spectra_;
  const std::string& base_dir_;  // where a spectrum's relative CSV path is resolved
};

BxDF make_diffuse(Params& p) {
  DiffuseBxDF m;
  m.reflectance = p.color("reflectance");
  return m;
}

BxDF make_mirror(Params& p) {
  MirrorBxDF m;
  m.reflectance = p.color("reflectance");
  return m;
}

// F0 of the index, for Schlick: ((n−1)² + k²) / ((n+1)² + k²).
void set_f0_from_index(ConductorFresnel& fr) {
  if (fr.model == FresnelModel::F82) return;  // F82-tint has no index: its f0 is given
  fr.f0 = map(fr.eta, fr.k, [](Float n, Float k) { return fresnel_f0(n, k); });
}

ConductorFresnel make_conductor_fresnel(Params& p) {
  ConductorFresnel fr;
  const std::string fresnel = p.choice("fresnel");
  fr.model = fresnel == "schlick" ? FresnelModel::Schlick : fresnel == "f82" ? FresnelModel::F82 : FresnelModel::Exact;
  const bool has_material = p.has("material");
  const bool has_eta = p.has("eta");
  const bool has_k = p.has("k");
  const bool has_f0 = p.has("f0");
  // F82-tint (SPEC §2): f0 and f82, never the index.
  if (p.has("f82") && fr.model != FresnelModel::F82) p.fail("f82 needs \"fresnel\": \"f82\"");
  if (fr.model == FresnelModel::F82) {
    if (has_material || has_eta || has_k) p.fail("fresnel \"f82\" takes f0 (and f82), not the index (material or eta/k)");
    if (!has_f0) p.fail("missing parameter: fresnel \"f82\" needs f0");
    fr.f0 = p.color("f0");
    fr.f82 = p.color("f82");
    fr.prepare();
    return fr;
  }
  if (has_material && (has_eta || has_k))
    p.fail("give either material or eta/k, not both");
  if (has_f0 && fr.model != FresnelModel::Schlick)
    p.fail("f0 needs \"fresnel\": \"schlick\" or \"f82\"");
  if (has_f0 && (has_material || has_eta || has_k))
    p.fail("give either f0 or the index (material or eta/k), not both");
  if (has_k && !has_eta) p.fail("k needs eta");
  if (!has_material && !has_eta && !has_f0)
    p.fail(fr.model == FresnelModel::Schlick ? "missing parameter: give material, eta (+ k) or f0"
                                             : "missing parameter: give material or eta (+ k)");
  if (has_f0) {
    fr.f0 = p.color("f0");
    return fr;
  }
  if (has_material) {
    const std::string name = p.string("material");
    const auto metal = named_metal(name);
    if (!metal) {
      std::string known;
      for (auto n : named_metal_names()) known += (known.empty() ? "" : ", ") + std::string(n);
      p.fail("unknown material \"" + name + "\" (known: " + known + ")");
    }
    fr.eta = metal->eta;
    fr.k = metal->k;
    const auto spectra = named_metal_spectra(name);
    if (!spectra) throw std::logic_error("named metal " + name + " has no spectrum table");
    p.spectra().colour[size_t(MaterialParam::Eta)] = spectra->eta;
    p.spectra().colour[size_t(MaterialParam::K)] = spectra->k;
  } else {
    fr.eta = p.color("eta");
    fr.k = p.color("k");
  }
  set_f0_from_index(fr);
  return fr;
}

// thin_film (issue 34; SPEC §2): {"thickness": nm, "eta": n}, each field in its range and
// named in the error; with a thickness > 0 the RGB table of the film on the substrate
// whose (n, k) at λ nm is `substrate(λ)` (bxdf/thin_film.h).
constexpr double kThinFilmMaxThickness = 1e4, kThinFilmMinEta = 1, kThinFilmMaxEta = 1e4;
ThinFilmT<Color> make_thin_film(Params& p, const std::function<std::pair<double, double>(double)>& substrate) {
  ThinFilmT<Color> film;
  film.lambda = thin_film_rgb_lambda();
  if (!p.has("thin_film")) return film;
  const json& v = p.raw("thin_film");
  if (!v.is_object()) p.fail("thin_film must be an object {\"thickness\": nm, \"eta\": n}, got " + show(v));
  for (const auto& [key, value] : v.items())
    if (key != "thickness" && key != "eta") p.fail("thin_film: unknown field '" + key + "'; it takes thickness, eta");
  const auto field = [&](const char* key, double lo, double hi, const char* unit) {
    if (!v.contains(key)) p.fail(std::string("thin_film: missing field '") + key + "'");
    const json& f = v.at(key);
    if (!f.is_number() || !std::isfinite(f.get<double>()))
      p.fail(std::string("thin_film.") + key + " must be a number, got " + show(f));
    const double d = f.get<double>();
    if (!(d >= lo && d <= hi))
      p.fail(std::string("thin_film.") + key + " must be in [" + format_number(lo) + ", " + format_number(hi) + "]" +
             unit + ", got " + format_number(d));
    return d;
  };
  const double thickness = field("thickness", 0, kThinFilmMaxThickness, " nm");
  const double eta = field("eta", kThinFilmMinEta, kThinFilmMaxEta, "");
  film.thickness = Float(thickness);
  film.eta = Float(eta);
  if (film.active()) film.table = make_thin_film_rgb_table(film.thickness, film.eta, substrate);
  return film;
}

// A dielectric substrate's (n, 0) at λ, from the index read by Params::index.
std::function<std::pair<double, double>(double)> dielectric_substrate(Params& p, Float rgb_eta) {
  if (!p.spectra().index) return [rgb_eta](double) { return std::pair<double, double>(rgb_eta, 0); };
  const Spectrum sp = *p.spectra().index;
  return [sp](double l) { return std::pair<double, double>(sp.eval(Float(l)), 0); };
}

// A dielectric's film. Below η = 0.1 the substrate's critical angle seen from outside is
// within 0.5 % of grazing and, from inside, the film is read at an outside cosine within
// 10⁻² of 1 where R changes by the whole of 1 − F: the float cosine and the RGB table no
// longer resolve it (the validator measured 2 % at η = 0.01), so such a film is refused.
constexpr double kThinFilmMinSubstrateEta = 0.1;
ThinFilmT<Color> make_dielectric_film(Params& p, double eta) {
  ThinFilmT<Color> film = make_thin_film(p, dielectric_substrate(p, Float(eta)));
  if (film.active() && eta < kThinFilmMinSubstrateEta)
    p.fail("thin_film needs eta >= " + format_number(kThinFilmMinSubstrateEta) + " (a substrate index the film's table "
           "resolves), got " + format_number(eta));
  return film;
}

// A conductor's film, on the index recorded for it (its n and k spectra).
void add_conductor_film(Params& p, ConductorFresnel& fr) {
  const auto& eta_sp = p.spectra().colour[size_t(MaterialParam::Eta)];
  const auto& k_sp = p.spectra().colour[size_t(MaterialParam::K)];
  const Color eta = fr.eta, k = fr.k;
  fr.film = make_thin_film(p, [&](double l) {
    // An index given as RGB without a recorded spectrum: the green channel's.
    const double n = eta_sp ? eta_sp->eval(Float(l)) : eta[1];
    const double kk = k_sp ? k_sp->eval(Float(l)) : k[1];
    return std::pair<double, double>(n, kk);
  });
  if (fr.film.active() && fr.model != FresnelModel::Exact)
    p.fail(std::string("thin_film needs the conductor's complex index (fresnel \"exact\"), not fresnel \"") +
           (fr.model == FresnelModel::F82 ? "f82" : "schlick") + "\"");
}

BxDF make_conductor(Params& p) {
  ConductorBxDF m{make_conductor_fresnel(p)};
  add_conductor_film(p, m.fresnel);
  return m;
}

// alpha (number or [alpha_x, alpha_y]) and distribution.
MicrofacetDistribution make_distribution(Params& p) {
  MicrofacetDistribution d;
  d.type = p.choice("distribution") == "beckmann" ? MicrofacetType::Beckmann : MicrofacetType::GGX;
  const auto [ax, ay] = p.roughness("alpha");
  d.alpha_x = static_cast<Float>(ax);
  d.alpha_y = static_cast<Float>(ay);
  return d;
}

// Spectral mode's F_avg(λ) of a multiple-scattering rough conductor, tabulated every 5 nm
// from the index (or f0) spectra recorded for it.
Spectrum tabulate_average_fresnel(FresnelModel model, const MaterialSpectra& s) {
  const auto at = [&](MaterialParam p, Float lambda, Float fallback) {
    const auto& sp = s.colour[size_t(p)];
    return sp ? sp->eval(lambda) : fallback;
  };
  std::vector<std::pair<double, double>> points;
  for (Float l = kLambdaMin; l <= kLambdaMax; l += 5) {
    ConductorFresnelT<BasicColor<1>> fr;
    fr.model = model;
    fr.eta = BasicColor<1>(at(MaterialParam::Eta, l, 1));
    fr.k = BasicColor<1>(at(MaterialParam::K, l, 0));
    fr.f0 = BasicColor<1>(s.colour[size_t(MaterialParam::F0)] ? at(MaterialParam::F0, l, 1)
                                                               : fresnel_f0(fr.eta[0], fr.k[0]));
    points.emplace_back(l, conductor_average_fresnel(fr)[0]);
  }
  return PiecewiseLinearSpectrum::from_points(points, "F_avg");
}

BxDF make_roughconductor(Params& p) {
  RoughConductorBxDF m;
  m.distribution = make_distribution(p);
  m.fresnel = make_conductor_fresnel(p);
  add_conductor_film(p, m.fresnel);
  if (p.boolean("multiscatter")) {
    if (m.fresnel.film.active()) p.fail("thin_film does not combine with multiscatter (its tables are of the bare metal)");
    // An anisotropic alpha: the lobe tabulates the distribution's own E(μ, φ) (multiscatter.h).
    if (!m.distribution.effectively_smooth())
      m.multiscatter = MultiscatterLobe::make(m.distribution, conductor_average_fresnel(m.fresnel));
    // F82's average is a closed form (conductor_average_fresnel): spectral mode takes it
    // per wavelength, no table.
    if (m.multiscatter && m.fresnel.model != FresnelModel::F82)
      p.spectra().f_avg = tabulate_average_fresnel(m.fresnel.model, p.spectra());
  }
  return m;
}

BxDF make_roughdielectric(Params& p) {
  RoughDielectricBxDF m;
  m.distribution = make_distribution(p);
  const double eta = p.index("eta");
  m.eta = Float(eta);
  m.film = make_dielectric_film(p, eta);
  if (p.boolean("multiscatter")) {
    if (m.film.active()) p.fail("thin_film does not combine with multiscatter (its tables are of the bare interface)");
    if (!m.distribution.is_isotropic())
      p.fail("multiscatter needs an isotropic alpha (a number), got [alpha_x, alpha_y]");
    // The albedo tables cover η' in [1, 4] on either side (docs/design/dielectric-multiscatter.md);
    // extrapolated beyond, the lobe went negative at η = 10⁻⁴.
    if (m.eta < 0.25f || m.eta > 4)
      p.fail("multiscatter needs eta in [0.25, 4] (the range of its albedo tables), got " + format_number(m.eta));
    if (!m.specular()) m.multiscatter = DielectricMultiscatterLobe::make(m.distribution, m.eta);
    // A dispersive index: spectral mode remakes the lobe at the hero wavelength, with
    // F̄(λ) tabulated here (2048 panels per wavelength would cost microseconds per
    // shading point); the index must stay within the tables at every wavelength.
    if (m.multiscatter && p.spectra().dispersive) {
      std::vector<std::pair<double, double>> points;
      for (Float l = kLambdaMin; l <= kLambdaMax; l += 5) {
        const Float n = p.spectra().index->eval(l);
        if (!(n >= 0.25f && n <= 4))
          p.fail("multiscatter needs eta in [0.25, 4] (the range of its albedo tables) over 360-830 nm, got " +
                 format_number(n) + " at " + format_number(l) + " nm");
        points.emplace_back(l, average_dielectric_fresnel(n));
      }
      p.spectra().f_avg = PiecewiseLinearSpectrum::from_points(points, "F_avg");
    }
  }
  return m;
}

BxDF make_dielectric(Params& p) {
  DielectricBxDF m;
  const double eta = p.index("eta");
  m.eta = Float(eta);
  m.film = make_dielectric_film(p, eta);
  return m;
}

BxDF make_thindielectric(Params& p) {
  ThinDielectricBxDF m;
  m.eta = Float(p.index("eta"));
  m.film = make_thin_film(p, [](double) { return std::pair<double, double>(1, 0); });  // the soap bubble
  return m;
}

// kd + ks ≤ 1 per channel, the energy bound of the two-lobe models (SPEC §2).
void check_sum_at_most_one(Params& p, const char* a, const Color& ca, const char* b, const Color& cb) {
  for (int i = 0; i < Color::size(); ++i)
    if (ca[i] + cb[i] > 1 + 1e-6)
      p.fail(std::string(a) + " + " + b + " must be <= 1 per channel, got " + format_number(ca[i] + cb[i]));
}

// Oren–Nayar's σ is given in degrees and kept in radians.
Float sigma_radians(double degrees) { return Float(degrees * kPiD / 180); }

BxDF make_orennayar(Params& p) {
  OrenNayarBxDF m;
  m.reflectance = p.color("reflectance");
  m.sigma = sigma_radians(p.number("sigma"));
  m.full = p.choice("model") == "full";
  return m;
}

BxDF make_sheen(Params& p) {
  SheenBxDF m;
  m.color = p.color("color");
  m.roughness = Float(p.number("roughness"));
  return m;
}

// The hair fibre (bxdf/hair.h; SPEC §2): absorption from sigma_a, a colour (Chiang eq. 9)
// or melanin concentrations (d'Eon et al. 2011), roughness per lobe, tilt in degrees.
BxDF make_hair(Params& p) {
  HairBxDF m;
  bool single_m = true, single_n = true;
  const auto bm = p.lobes("beta_m", &single_m), bn = p.lobes("beta_n", &single_n);
  (void)single_n;
  m.set_roughness({Float(bm[0]), Float(bm[1]), Float(bm[2])}, {Float(bn[0]), Float(bn[1]), Float(bn[2])});
  if (single_m) {
    // Chiang §4.1 after Marschner: TT and TRT have half and twice R's width.
    m.v[1] = m.v[0] / 4;
    m.v[2] = m.v[3] = 4 * m.v[0];
    m.prepare();
  }
  m.set_alpha(Float(p.number("alpha") * kPiD / 180));
  m.eta = Float(p.number("eta"));
  m.tint = {p.color("tint_R"), p.color("tint_TT"), p.color("tint_TRT")};
  if (p.has("h")) {
    m.h = Float(p.number("h"));
    m.average_h = false;
  }
  const bool has_sigma = p.has("sigma_a"), has_color = p.has("color");
  const bool has_melanin = p.has("eumelanin") || p.has("pheomelanin");
  if (int(has_sigma) + int(has_color) + int(has_melanin) > 1)
    p.fail("give one of sigma_a, color, or eumelanin/pheomelanin");
  if (has_sigma) {
    m.sigma_a = p.color("sigma_a");
  } else if (has_color) {
    const Color c = p.color("color");
    m.sigma_a = map(c, [&](Float x) { return hair::sigma_a_from_color(x, Float(bn[0])); });
  } else {
    const double ce = has_melanin ? (p.has("eumelanin") ? p.number("eumelanin") : 0) : 1.3;
    const double cp = p.has("pheomelanin") ? p.number("pheomelanin") : 0;
    for (int c = 0; c < 3; ++c)
      m.sigma_a[c] = Float(ce * hair::kEumelanin[c] + cp * hair::kPheomelanin[c]);
  }
  return m;
}

// MaterialX's chiang_hair_bsdf (SPEC §2): (v, s) per lobe as chiang_hair_roughness gives
// them (the logistic's scale is s sqrt(pi/8), MaterialX's mx_hair_trimmed_logistic),
// clamped to [0.001, 1] as MaterialX's genglsl does; alpha = (cuticle_angle − 0.5) pi.
BxDF make_chiang_hair(Params& p) {
  HairBxDF m;
  const char* keys[3] = {"roughness_R", "roughness_TT", "roughness_TRT"};
  for (size_t i = 0; i < 3; ++i) {
    const auto vs = p.pair(keys[i]);
    m.v[i] = Float(std::clamp(vs[0], 0.001, 1.0));
    m.s[i] = Float(std::clamp(vs[1], 0.001, 1.0)) * hair::kSqrtPiOver8;
  }
  m.v[3] = m.v[2];
  m.prepare();
  m.set_alpha(Float((p.number("cuticle_angle") - 0.5) * kPiD));
  m.eta = Float(p.number("ior"));
  m.tint = {p.color("tint_R"), p.color("tint_TT"), p.color("tint_TRT")};
  m.sigma_a = p.color("absorption_coefficient");
  if (p.has("h")) {
    m.h = Float(p.number("h"));
    m.average_h = false;
  }
  return m;
}

BxDF make_eon(Params& p) {
  return EonBxDF::make(p.color("reflectance"), Float(p.number("roughness")));
}

template <typename M>
BxDF make_phong_like(Params& p) {
  M m;
  m.kd = p.color("kd");
  m.ks = p.color("ks");
  check_sum_at_most_one(p, "kd", m.kd, "ks", m.ks);
  m.exponent = Float(p.number("exponent"));
  return m;
}

BxDF make_ward(Params& p) {
  WardBxDF m;
  m.kd = p.color("kd");
  m.ks = p.color("ks");
  check_sum_at_most_one(p, "kd", m.kd, "ks", m.ks);
  const auto [ax, ay] = p.roughness("alpha");
  m.alpha_x = Float(ax);
  m.alpha_y = Float(ay);
  return m;
}

BxDF make_ashikhminshirley(Params& p) {
  AshikhminShirleyBxDF m;
  m.rd = p.color("rd");
  m.rs = p.color("rs");
  m.nu = Float(p.number("nu"));
  m.nv = Float(p.number("nv"));
  return m;
}

BxDF make_plastic(Params& p) {
  const Color reflectance = p.color("reflectance");
  const Float eta = Float(p.index("eta"));
  std::optional<MicrofacetDistribution> coat;
  if (p.has("alpha")) coat = make_distribution(p);
  else if (p.has("distribution")) p.fail("distribution needs alpha (a rough coat)");
  // The coat's albedo tables E_coat(μ, α, η) are for isotropic roughness; an anisotropic
  // coat looked up at its projected roughness gained 2.8 % at 89.9° (docs/microfacet.md).
  if (coat && !coat->is_isotropic())
    p.fail("a rough coat needs an isotropic alpha (a number), got [alpha_x, alpha_y]");
  return PlasticBxDF::make(reflectance, eta, coat);
}

// The table is read once per file (load_measured); a relative path is the scene's or the
// working directory's.
BxDF make_measured(Params& p) {
  const std::string file = p.string("file");
  if (file.empty()) p.fail("file must name a MERL table, got \"\"");
  std::filesystem::path path(file);
  if (path.is_relative() && !p.base_dir().empty()) path = std::filesystem::path(p.base_dir()) / path;
  try {
    return MeasuredBxDF::make(load_measured(path.string()));
  } catch (const InputError& e) {
    p.fail(e.what());
  }
}

// An RGL .bsdf file (SPEC §2 `rgl`, issue 59): read once per file (load_rgl), a relative
// path as `measured`'s.
BxDF make_rgl(Params& p) {
  const std::string file = p.string("file");
  if (file.empty()) p.fail("file must name an RGL .bsdf file, got \"\"");
  std::filesystem::path path(file);
  if (path.is_relative() && !p.base_dir().empty()) path = std::filesystem::path(p.base_dir()) / path;
  try {
    return RglBxDF::make(load_rgl(path.string()));
  } catch (const InputError& e) {
    p.fail(e.what());
  }
}

// --- subsurface (SPEC §2, issue 14) --------------------------------------------------

// The key of the albedo table: what A(ϖ) depends on besides ϖ (hexadecimal floats, exact).
std::string albedo_table_key(const BxDF& boundary, Float eta, Float g) {
  char buf[160];
  Float ax = 0, ay = 0;
  int dist = -1;
  int ms = 0;
  if (const auto* r = std::get_if<RoughDielectricBxDF>(&boundary.models())) {
    ax = r->distribution.alpha_x;
    ay = r->distribution.alpha_y;
    dist = int(r->distribution.type);
    ms = r->multiscatter ? 1 : 0;
  }
  std::snprintf(buf, sizeof buf, "%a %a %a %d %d %a", double(eta), double(ax), double(ay), dist, ms, double(g));
  return buf;
}

// Every form of the medium; `invert` false skips the albedo table (material_from_json
// needs only the boundary, and the values are checked without it).
// Every length the slab and the renderer derive from a medium is a multiple of its
// transport mean free path 1/σt′, σt′ = σa + (1 − g) σs (the similarity relation): the
// profile's radii reach 20 of them, the diffusion table 10⁴, and squares of such radii are
// taken in float. Where σt′ is tiny but not 0, 1/σt′ overflowed a float (σs = σa = 1e-38:
// infinite radii, NaN in the output). (10⁴/σt′)² < FLT_MAX needs σt′ > 5.4e-16; the
// bound is 1e-15 per unit. A channel with σt′ = 0 scatters nothing and is clear (Rd 0).
void check_transport_coefficients(Params& p, const Medium& medium) {
  constexpr double kMinTransport = 1e-15;
  static constexpr const char* kChannel[] = {"red", "green", "blue"};
  for (int c = 0; c < Color::size(); ++c) {
    const double t = double(medium.sigma_a[c]) + (1 - double(medium.g)) * double(medium.sigma_s[c]);
    if (t > 0 && t < kMinTransport)
      p.fail("the transport coefficient sigma_a + (1 - g) sigma_s of the " + std::string(kChannel[c]) +
             " channel is " + format_number(t) + " 1/unit: it must be 0 or at least " + format_number(kMinTransport) +
             " (a transport mean free path beyond 1e15 units overflows the slab's radii)");
  }
}

Subsurface parse_subsurface(Params& p, bool invert) {
  Subsurface s;
  const bool has_sigma_s = p.has("sigma_s"), has_sigma_a = p.has("sigma_a");
  const bool has_albedo = p.has("albedo"), has_mfp = p.has("mfp");
  const bool has_medium = p.has("medium");
  const int forms = int(has_sigma_s || has_sigma_a) + int(has_albedo || has_mfp) + int(has_medium);
  if (forms == 0) p.fail("missing the medium: give sigma_s and sigma_a, albedo and mfp, or medium");
  if (forms > 1) {
    std::string given;
    for (const char* k : {"sigma_s", "sigma_a", "albedo", "mfp", "medium"})
      if (p.has(k)) given += (given.empty() ? "" : ", ") + std::string(k);
    p.fail("give exactly one form of the medium (sigma_s + sigma_a, albedo + mfp, or medium), got " + given);
  }
  if (has_sigma_s != has_sigma_a) p.fail(has_sigma_s ? "sigma_s needs sigma_a" : "sigma_a needs sigma_s");
  if (has_albedo != has_mfp) p.fail(has_albedo ? "albedo needs mfp" : "mfp needs albedo");
  if (p.has("scale") && !has_medium) p.fail("scale needs medium (it converts the medium's 1/mm to scene units)");

  // The boundary: 1.33 (water-like) by default, the paper's 1.3 for its media.
  s.eta = Float(p.has("eta") ? p.index("eta") : has_medium ? kJensen2001Eta : 1.33);
  if (p.has("alpha")) {
    RoughDielectricBxDF m;
    m.distribution = make_distribution(p);
    m.eta = s.eta;
    // Without it a rough boundary loses what scatters more than once among its
    // microfacets at every crossing: a non-absorbing sphere (η 1.5, α 0.3) in a white
    // furnace rendered to 0.72 (docs/subsurface.md#rendering).
    if (p.boolean("multiscatter")) {
      if (!m.distribution.is_isotropic())
        p.fail("multiscatter needs an isotropic alpha (a number), got [alpha_x, alpha_y]");
      if (m.eta < 0.25f || m.eta > 4)
        p.fail("multiscatter needs eta in [0.25, 4] (the range of its albedo tables), got " + format_number(m.eta));
      if (!m.specular()) m.multiscatter = DielectricMultiscatterLobe::make(m.distribution, m.eta);
    }
    s.boundary = m;
  } else {
    if (p.has("distribution")) p.fail("distribution needs alpha (a rough boundary)");
    if (p.boolean("multiscatter")) p.fail("multiscatter needs alpha (a rough boundary)");
    DielectricBxDF m;
    m.eta = s.eta;
    s.boundary = m;
  }

  const double g = p.number("g");
  // g within (−1, 1) as a double may round to ±1 as a float, where 1 − g = 0 divides
  // σs′ and the phase function is a delta.
  if (!(std::abs(Float(g)) < 1)) p.fail("g must be > -1 and < 1, got " + format_number(g) + " (it rounds to +-1 as a float)");
  s.medium.g = Float(g);
  s.method = p.choice("method") == "diffusion" ? SubsurfaceMethod::Diffusion : SubsurfaceMethod::RandomWalk;
  s.guide = Float(p.number("guide"));
  s.nee = p.boolean("nee");

  if (has_sigma_s) {
    s.medium.sigma_s = p.color("sigma_s");
    s.medium.sigma_a = p.color("sigma_a");
  } else if (has_albedo) {
    const Color albedo = p.color("albedo"), mfp = p.color("mfp");
    const Color sigma_t = map(mfp, [](Float l) { return 1 / l; });
    Color ssa = albedo;  // replaced by the inversion below
    if (invert) {
      const auto table = SlabAlbedoTable::get(s.boundary, s.eta, s.medium.g, albedo_table_key(s.boundary, s.eta, s.medium.g));
      for (int c = 0; c < Color::size(); ++c) ssa[c] = Float(table->single_scattering_albedo(albedo[c]));
    }
    s.medium.sigma_s = ssa * sigma_t;
    s.medium.sigma_a = (1 - ssa) * sigma_t;
  } else {
    const std::string name = p.choice("medium");
    const NamedMedium* m = find_named_medium(name);
    if (!m) throw std::logic_error("material registry: medium " + name + " has no table entry");
    const double scale = p.number("scale");  // scene units per mm: σ per unit = σ per mm / scale
    for (int c = 0; c < Color::size(); ++c) {
      const double ss = m->sigma_s_prime[size_t(c)] / (1 - double(s.medium.g)) / scale;
      const double sa = m->sigma_a[size_t(c)] / scale;
      if (!(ss <= 1e30 && sa <= 1e30))
        p.fail("scale " + format_number(scale) + " makes the medium's coefficients overflow (" + format_number(ss) +
               " 1/unit)");
      s.medium.sigma_s[c] = Float(ss);
      s.medium.sigma_a[c] = Float(sa);
    }
  }
  check_transport_coefficients(p, s.medium);
  return s;
}

BxDF make_subsurface(Params& p) { return parse_subsurface(p, false).boundary; }

BxDF make_mx_oren_nayar(Params& p);
BxDF make_mx_conductor(Params& p);
BxDF make_mx_dielectric(Params& p);
BxDF make_mx_sheen(Params& p);
BxDF make_mx_operator(Params& p, const std::string& type, const std::string& where, int depth);
void check_pbr_depth(Params& p, int depth);
// The maker of a pbrlib leaf node (not an operator), or nullptr.
using LeafMaker = BxDF (*)(Params&);
LeafMaker pbr_leaf_maker(std::string_view type) {
  if (type == "oren_nayar_diffuse_bsdf") return make_mx_oren_nayar;
  if (type == "conductor_bsdf") return make_mx_conductor;
  if (type == "dielectric_bsdf") return make_mx_dielectric;
  if (type == "sheen_bsdf") return make_mx_sheen;
  return nullptr;
}

BxDF make_blend(Params& p, const std::string& where, int depth);
BxDF make_layered(Params& p, const std::string& where, int depth);
BxDF parse_description(const json& description, const std::string& where, int blend_depth, MaterialSpectra& spectra,
                       const std::string& base_dir);


// openpbr's film on the specular layer's reflecting index (µm → nm), none without weight
// or thickness. `table`: with RGB mode's table of its reflectance (thin_film.h), made at
// parse time; without, the model reads the Airy sum at the channels' wavelengths, which
// allocates nothing (with_params, for a textured film or index under it).
ThinFilmT<Color> openpbr_film(const OpenPbrParams<Color>& o, bool table) {
  ThinFilmT<Color> film;
  if (!(o.thin_film_weight > 0 && o.thin_film_thickness > 0)) return film;
  film.lambda = thin_film_rgb_lambda();
  film.thickness = o.thin_film_thickness * 1000;
  film.eta = o.thin_film_ior;
  if (table) {
    const double substrate = openpbr::specular_layer_eta(o.specular_ior, o.coat_ior, o.coat_weight, o.specular_weight);
    film.table = make_thin_film_rgb_table(film.thickness, film.eta,
                                          [substrate](double) { return std::pair<double, double>(substrate, 0); });
  }
  return film;
}

// The same film over openpbr's metal, with RGB mode's table of its reflectance there: the
// substrate at λ is the effective complex index (f82_effective_index.h) of the F82 curve of
// base_color and specular_color upsampled to λ (base_weight times the first), as spectral
// mode upsamples them (spectral_material.cpp); none without a metal.
ThinFilmT<Color> openpbr_metal_film(const OpenPbrParams<Color>& o) {
  ThinFilmT<Color> film = openpbr_film(o, false);
  if (!film.active() || !(o.base_metalness > 0)) return {};
  const SigmoidPolynomial colour = rgb_to_sigmoid_polynomial(o.base_color[0], o.base_color[1], o.base_color[2]);
  const SigmoidPolynomial tint = rgb_to_sigmoid_polynomial(o.specular_color[0], o.specular_color[1], o.specular_color[2]);
  const double weight = std::clamp(double(o.base_weight), 0.0, 1.0);
  film.table = make_thin_film_rgb_table(film.thickness, film.eta, [=](double l) {
    const ComplexIndex c = f82_effective_index(weight * colour.eval(Float(l)), double(tint.eval(Float(l))));
    return std::pair<double, double>(c.n, c.k);
  });
  return film;
}

// The same film over openpbr's glass (transmission, not thin-walled), with RGB mode's table
// over the glass's index; none without a glass.
ThinFilmT<Color> openpbr_glass_film(const OpenPbrParams<Color>& o) {
  ThinFilmT<Color> film = openpbr_film(o, false);
  const double eta = openpbr::modulated_ior(o.specular_ior, o.specular_weight);
  if (!film.active() || !(o.transmission_weight > 0) || o.geometry_thin_walled || eta < openpbr::kMinFilmGlassEta)
    return {};
  film.table = make_thin_film_rgb_table(film.thickness, film.eta, [eta](double) { return std::pair<double, double>(eta, 0); });
  return film;
}

// openpbr (issue 35; SPEC §2): every OpenPBR Surface 1.1 parameter, read from the registry
// (defaults, ranges). OpenPBR's units: thin_film_thickness in µm, the film table in nm.
BxDF make_openpbr(Params& p) {
  OpenPbrParams<Color> o;
  // The table's keys are string literals, so key.data() is a C string.
  for (const auto& f : kOpenPbrFields<Color>) {
    if (f.number) o.*f.number = Float(p.number(f.key.data()));
    else o.*f.colour = p.color(f.key.data());
  }
  o.geometry_thin_walled = p.boolean("geometry_thin_walled");
  o.reciprocal_layering = p.boolean("reciprocal_layering");
  return OpenPbrBxDF::make(o, openpbr_film(o, true), nullptr, {openpbr_metal_film(o), openpbr_glass_film(o)});
}

// gltf_pbr (issues 57, 58): every parameter from the registry (bxdf/gltf_pbr_params.h).
BxDF make_gltf_pbr(Params& p) {
  GltfPbrParams<Color> g;
  for (const auto& f : kGltfPbrFields<Color>) {
    if (f.number) g.*f.number = Float(p.number(f.key.data()));
    else g.*f.colour = p.color(f.key.data());
  }
  if (g.alpha_mode != std::floor(g.alpha_mode)) p.fail("alpha_mode must be 0, 1 or 2, got " + std::to_string(g.alpha_mode));
  if (g.iridescence > 0)
    p.fail("iridescence is not implemented yet (docs/gltf_pbr.md); it must be 0, got " + std::to_string(g.iridescence));
  return GltfPbrBxDF::make(g);
}

// The constructor of each type of the registry but blend (which needs its place and depth).
struct TypeEntry {
  std::string_view name;
  BxDF (*make)(Params&);
};
constexpr TypeEntry kMakers[] = {
    {"diffuse", make_diffuse},
    {"mirror", make_mirror},
    {"conductor", make_conductor},
    {"dielectric", make_dielectric},
    {"roughconductor", make_roughconductor},
    {"roughdielectric", make_roughdielectric},
    {"orennayar", make_orennayar},
    {"eon", make_eon},
    {"phong", make_phong_like<PhongBxDF>},
    {"blinnphong", make_phong_like<BlinnPhongBxDF>},
    {"ward", make_ward},
    {"ashikhminshirley", make_ashikhminshirley},
    {"plastic", make_plastic},
    {"measured", make_measured},
    {"rgl", make_rgl},
    {"subsurface", make_subsurface},
    {"sheen", make_sheen},
    {"thindielectric", make_thindielectric},
    {"openpbr", make_openpbr},
    {"gltf_pbr", make_gltf_pbr},
    {"hair", make_hair},
    {"chiang_hair_bsdf", make_chiang_hair},
};

}  // namespace

const std::vector<std::string_view>& material_type_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const auto& t : material_types()) v.push_back(t.name);
    return v;
  }();
  return names;
}

namespace {
// `depth`: how many blends enclose this one (0 at the top).
BxDF make_blend(Params& p, const std::string& where, int depth) {
  if (depth >= kMaxBlendDepth)
    p.fail("blends nested deeper than " + std::to_string(kMaxBlendDepth) + " levels (each level doubles the cost of an evaluation)");
  const double w = p.number("weight");
  const json& arr = p.raw("bsdfs");
  if (!arr.is_array() || arr.size() != 2) p.fail("bsdfs must be an array of 2 materials, got " + show(arr));
  auto parts = std::make_shared<std::array<BxDF, 2>>();
  p.spectra().parts.resize(2);
  for (size_t i = 0; i < 2; ++i)
    (*parts)[i] = parse_description(arr[i], where + ".bsdfs[" + std::to_string(i) + "]", depth + 1, p.spectra().parts[i],
                                  p.base_dir());
  const Float e0 = (*parts)[0].relative_eta(), e1 = (*parts)[1].relative_eta();
  if (is_transmissive((*parts)[0].flags()) && is_transmissive((*parts)[1].flags()) && e0 != e1)
    p.fail("both parts refract, with different eta (" + format_number(e0) + " and " + format_number(e1) + ")");
  return BlendBxDF::make(Float(w), std::move(parts));
}

// --- MaterialX pbrlib nodes (SPEC §2, wave 4; issue 57; bxdf/pbr_node.h) -------------

// E(μ) of a layerable node's untinted reflection lobe: the mean of its sample weights over
// the upper hemisphere, stratified (24 × 24 in u1, u2; an anisotropic lobe 16 × 16 at each
// of 4 azimuths of wo), channels averaged; exact for a lobe whose sample weight is its
// albedo (a delta lobe, Zeltner's sheen).
std::shared_ptr<const PbrAlbedoTable> pbr_albedo_table(const BxDF& lobe) {
  auto t = std::make_shared<PbrAlbedoTable>();
  const bool iso = lobe.is_isotropic();
  const int grid = iso ? 24 : 16, azimuths = iso ? 1 : 4;
  for (int i = 0; i < PbrAlbedoTable::kSize; ++i) {
    const double x = double(i) / (PbrAlbedoTable::kSize - 1);
    const double mu = std::max(x * x, 1e-6);
    const double sin_o = std::sqrt(1 - mu * mu);
    double sum = 0;
    for (int a = 0; a < azimuths; ++a) {
      const double phi = (a + 0.5) * kPiD / (2 * azimuths);
      const Vec3 wo(Float(sin_o * std::cos(phi)), Float(sin_o * std::sin(phi)), Float(mu));
      for (int j = 0; j < grid; ++j)
        for (int k = 0; k < grid; ++k) {
          const double u_lobe = std::fmod((j * grid + k) * 0.6180339887498949 + 0.5, 1.0);
          const auto s = lobe.sample(wo, Float(u_lobe), Float((j + 0.5) / grid), Float((k + 0.5) / grid),
                                     TransportMode::Radiance);
          if (s && s->wi.z > 0) sum += double(s->weight.average());
        }
    }
    t->e[size_t(i)] = Float(sum / (azimuths * grid * grid));
  }
  return t;
}

void check_pbr_depth(Params& p, int depth) {
  if (depth >= kMaxBlendDepth)
    p.fail("MaterialX nodes, blends and layered materials nested deeper than " + std::to_string(kMaxBlendDepth) +
           " levels (a pbrlib BSDF node counts as one)");
}

// A leaf node: `inner` times `scale`, its spectra moved to the node's first part (as a
// blend's parts hold theirs).
BxDF pbr_leaf(Params& p, BxDF inner, const Color& scale, PbrThroughput through, Float weight,
              std::shared_ptr<const PbrAlbedoTable> table) {
  MaterialSpectra& s = p.spectra();
  MaterialSpectra own = std::move(s);
  s = MaterialSpectra{};
  s.parts.resize(2);
  s.parts[0] = std::move(own);
  auto parts = std::make_shared<std::array<BxDF, 2>>();
  (*parts)[0] = std::move(inner);
  PbrNodeBxDF n = PbrNodeBxDF::make(PbrOp::Scale, std::move(parts));
  n.scale = scale;
  n.through = through;
  n.weight = weight;
  n.albedo_table = table.get();
  n.table_owner = std::move(table);
  return n;
}

void refuse_retroreflective(Params& p) {
  if (p.boolean("retroreflective")) p.fail("retroreflective true is not supported (no retroreflection mode yet)");
  p.choice("distribution");  // ggx, the only one
}

MicrofacetDistribution pbr_distribution(Params& p) {
  MicrofacetDistribution d;
  const auto [ax, ay] = p.roughness("roughness");
  d.alpha_x = Float(ax);
  d.alpha_y = Float(ay);
  return d;
}

// MaterialX's thin film (thickness in nm, its index) on a substrate.
ThinFilmT<Color> pbr_film(Params& p, const std::function<std::pair<double, double>(double)>& substrate) {
  ThinFilmT<Color> film;
  film.lambda = thin_film_rgb_lambda();
  film.thickness = Float(p.number("thinfilm_thickness"));
  film.eta = Float(p.number("thinfilm_ior"));
  if (film.active()) film.table = make_thin_film_rgb_table(film.thickness, film.eta, substrate);
  return film;
}

BxDF make_mx_oren_nayar(Params& p) {
  const Float weight = Float(p.number("weight"));
  const Color color = p.color("color");
  const Float r = Float(p.number("roughness"));
  BxDF inner;
  if (p.boolean("energy_compensation")) {
    inner = EonBxDF::make(color, r);
  } else {
    OrenNayarBxDF m;  // MaterialX's qualitative form: sigma = roughness, in radians
    m.reflectance = color;
    m.sigma = r;
    inner = m;
  }
  return pbr_leaf(p, std::move(inner), Color(weight), PbrThroughput::Opaque, weight, nullptr);
}

BxDF make_mx_conductor(Params& p) {
  const Float weight = Float(p.number("weight"));
  refuse_retroreflective(p);
  RoughConductorBxDF m;
  m.distribution = pbr_distribution(p);
  m.fresnel.model = FresnelModel::Exact;
  m.fresnel.eta = p.color("ior");
  m.fresnel.k = p.color("extinction");
  set_f0_from_index(m.fresnel);
  const Color eta = m.fresnel.eta, k = m.fresnel.k;
  m.fresnel.film = pbr_film(p, [eta, k](double) { return std::pair<double, double>(eta[1], k[1]); });
  if (!m.fresnel.film.active() && !m.distribution.effectively_smooth())
    m.multiscatter = MultiscatterLobe::make(m.distribution, conductor_average_fresnel(m.fresnel));
  return pbr_leaf(p, m, Color(weight), PbrThroughput::Opaque, weight, nullptr);
}

BxDF make_mx_dielectric(Params& p) {
  const Float weight = Float(p.number("weight"));
  const Color tint = p.color("tint");
  refuse_retroreflective(p);
  const double ior = p.number("ior");
  const std::string mode = p.choice("scatter_mode");
  const MicrofacetDistribution dist = pbr_distribution(p);
  if (mode == "T")
    p.fail("scatter_mode \"T\" is not supported yet (transmission without reflection); use \"RT\"");
  if (mode == "RT" && ior < 1e-4)
    p.fail("scatter_mode \"RT\" needs ior >= 0.0001 (0, no Fresnel curve, is for \"R\"), got " + format_number(ior));
  if (mode == "R" && ior > 0 && ior < 1)
    p.fail("scatter_mode \"R\" needs ior >= 1 (or 0: no Fresnel curve), got " + format_number(ior));
  // The reflection lobe alone (R): a microfacet reflector with the dielectric's Fresnel,
  // which is the exact conductor formula with k = 0 (for ior >= 1: no total reflection
  // from outside); ior 0: F = 1 (Schlick with F0 = 1).
  RoughConductorBxDF r;
  r.distribution = dist;
  if (ior == 0) {
    r.fresnel.model = FresnelModel::Schlick;
    r.fresnel.f0 = Color(1);
  } else {
    r.fresnel.model = FresnelModel::Exact;
    r.fresnel.eta = Color(Float(ior));
    r.fresnel.k = Color(0);
    set_f0_from_index(r.fresnel);
  }
  const auto substrate = [ior](double) { return std::pair<double, double>(ior, 0); };
  if (ior > 0) r.fresnel.film = pbr_film(p, substrate);
  else if (p.number("thinfilm_thickness") > 0) p.fail("a thin film needs ior > 0 (its substrate), got 0");
  if (!r.fresnel.film.active() && !dist.effectively_smooth())
    r.multiscatter = MultiscatterLobe::make(dist, conductor_average_fresnel(r.fresnel));
  if (mode == "R") {
    auto table = pbr_albedo_table(r);
    return pbr_leaf(p, r, tint * weight, PbrThroughput::Albedo, weight, std::move(table));
  }
  RoughDielectricBxDF m;
  m.distribution = dist;
  m.eta = Float(ior);
  m.film = pbr_film(p, substrate);
  if (!m.film.active() && m.distribution.is_isotropic() && m.eta >= 0.25f && m.eta <= 4 && !m.specular())
    m.multiscatter = DielectricMultiscatterLobe::make(m.distribution, m.eta);
  p.spectra().index = ConstantSpectrum{Float(ior)};
  auto table = pbr_albedo_table(m);
  return pbr_leaf(p, m, tint * weight, PbrThroughput::Albedo, weight, std::move(table));
}

BxDF make_mx_sheen(Params& p) {
  const Float weight = Float(p.number("weight"));
  SheenBxDF m;
  m.color = p.color("color");
  // MaterialX clamps zeltner's roughness to [0.01, 1] (mx_sheen_bsdf.glsl).
  m.roughness = std::max(Float(p.number("roughness")), Float(0.01));
  if (p.choice("mode") == "conty_kulla") {
    CharlieSheenBxDF c;
    c.color = m.color;
    c.roughness = Float(p.number("roughness"));  // floored at 0.005 by the model, as MaterialX does
    CharlieSheenBxDF cw = c;
    cw.color = Color(1);
    return pbr_leaf(p, c, Color(weight), PbrThroughput::Albedo, weight, pbr_albedo_table(cw));
  }
  SheenBxDF white = m;
  white.color = Color(1);  // the throughput is of the untinted lobe
  return pbr_leaf(p, m, Color(weight), PbrThroughput::Albedo, weight, pbr_albedo_table(white));
}

// One material input of an operator, parsed in the node's spectra part `i`.
BxDF pbr_input(Params& p, const char* key, size_t i, const std::string& where, int depth) {
  const json& v = p.raw(key);
  if (!v.is_object()) p.fail(std::string(key) + " must be a material (a JSON object), got " + show(v));
  return parse_description(v, where + "." + key, depth + 1, p.spectra().parts[i], p.base_dir());
}

BxDF make_mx_operator(Params& p, const std::string& type, const std::string& where, int depth) {
  check_pbr_depth(p, depth);
  p.spectra().parts.resize(2);
  auto parts = std::make_shared<std::array<BxDF, 2>>();
  PbrOp op = PbrOp::Add;
  Float weight = 1;
  Color scale(1);
  if (type == "mix") {
    op = PbrOp::Mix;
    (*parts)[0] = pbr_input(p, "fg", 0, where, depth);
    (*parts)[1] = pbr_input(p, "bg", 1, where, depth);
    weight = Float(p.number("mix"));
  } else if (type == "add") {
    (*parts)[0] = pbr_input(p, "in1", 0, where, depth);
    (*parts)[1] = pbr_input(p, "in2", 1, where, depth);
  } else if (type == "layer") {
    op = PbrOp::Layer;
    (*parts)[0] = pbr_input(p, "top", 0, where, depth);
    (*parts)[1] = pbr_input(p, "base", 1, where, depth);
  } else {  // multiply
    op = PbrOp::Scale;
    (*parts)[0] = pbr_input(p, "in1", 0, where, depth);
    scale = p.color("in2");
  }
  if (op != PbrOp::Scale) {
    const Float e0 = (*parts)[0].relative_eta(), e1 = (*parts)[1].relative_eta();
    if (is_transmissive((*parts)[0].flags()) && is_transmissive((*parts)[1].flags()) && e0 != e1)
      p.fail("both inputs refract, with different ior (" + format_number(e0) + " and " + format_number(e1) + ")");
  }
  PbrNodeBxDF n = PbrNodeBxDF::make(op, std::move(parts));
  n.weight = weight;
  n.scale = scale;
  n.through = op == PbrOp::Scale ? PbrThroughput::Input : PbrThroughput::Opaque;
  return n;
}

// A whole number of the registry's range (max_depth, samples).
int whole_number(Params& p, const char* key) {
  const double v = p.number(key);
  if (v != std::floor(v)) p.fail(std::string(key) + " must be a whole number, got " + format_number(v));
  return int(v);
}

// `depth`: how many blends or layered materials enclose this one (0 at the top); they
// share the nesting limit (and spectral mode's scratch space, one slot per level).
BxDF make_layered(Params& p, const std::string& where, int depth) {
  if (depth >= kMaxBlendDepth)
    p.fail("blends and layered materials nested deeper than " + std::to_string(kMaxBlendDepth) + " levels");
  const json& top_json = p.raw("top");
  const json& bottom_json = p.raw("bottom");
  // The top must be a dielectric interface; named before it is parsed, so that the message
  // says what is wrong with it rather than with its parameters.
  const auto type_of = [](const json& j) -> std::string {
    if (!j.is_object()) return "";
    const auto it = j.find("type");
    return it != j.end() && it->is_string() ? it->get<std::string>() : "";
  };
  const std::string top_type = type_of(top_json);
  if (!top_json.is_object())
    p.fail("top must be a material (a dielectric, roughdielectric or thindielectric), got " + show(top_json));
  if (!bottom_json.is_object()) p.fail("bottom must be a material, got " + show(bottom_json));
  if (top_type != "dielectric" && top_type != "roughdielectric" && top_type != "thindielectric")
    p.fail("top must be a dielectric, roughdielectric or thindielectric material, got type " +
           show(top_json.value("type", json())));
  p.spectra().parts.resize(2);
  const BxDF top = parse_description(top_json, where + ".top", depth + 1, p.spectra().parts[0], p.base_dir());
  auto bottom = std::make_shared<const BxDF>(
      parse_description(bottom_json, where + ".bottom", depth + 1, p.spectra().parts[1], p.base_dir()));
  // The top as the stack holds it (layered.h): smooth ones with alpha 0 (specular()), a
  // sheet with its eta and film.
  RoughDielectricBxDF interface;
  const auto* sheet = std::get_if<ThinDielectricBxDF>(&top.models());
  if (const auto* d = std::get_if<DielectricBxDF>(&top.models())) {
    interface.eta = d->eta;
    interface.film = d->film;
    interface.distribution.alpha_x = interface.distribution.alpha_y = 0;
  } else if (sheet) {
    interface.eta = sheet->eta;
    interface.film = sheet->film;
    interface.distribution.alpha_x = interface.distribution.alpha_y = 0;
  } else {
    interface = std::get<RoughDielectricBxDF>(top.models());
  }
  const double g = p.number("g");
  // Below HG's isotropic threshold its sampler draws the isotropic phase; the walk then
  // uses g = 0 throughout, so that the sampled density is the one it evaluates.
  const Float g_used = std::abs(Float(g)) < kHgIsotropicBelow ? Float(0) : Float(g);
  return LayeredBxDF::make(interface, sheet != nullptr, std::move(bottom), Float(p.number("thickness")), p.color("albedo"), g_used,
                           whole_number(p, "max_depth"), whole_number(p, "samples"));
}
}  // namespace

BxDF material_from_json(const json& description, const std::string& where, const std::string& base_dir) {
  MaterialSpectra spectra;
  return parse_description(description, where, 0, spectra, base_dir);
}

MaterialWithSpectra material_with_spectra_from_json(const json& description, const std::string& where,
                                                    const std::string& base_dir) {
  MaterialWithSpectra m;
  m.bxdf = parse_description(description, where, 0, m.spectra, base_dir);
  return m;
}

MaterialWithSpectra parse_material_with_spectra(std::string_view json_text, std::string_view source) {
  const json j = parse_json_text(json_text, source);
  return material_with_spectra_from_json(j, std::string(source));
}

Subsurface subsurface_from_json(const json& description, const std::string& where, const std::string& base_dir) {
  const std::string at = where.empty() ? "" : where + ": ";
  if (!description.is_object()) throw InputError(at + "material must be a JSON object, got " + show(description));
  const auto it = description.find("type");
  if (it == description.end()) throw InputError(at + "material: missing field 'type'");
  if (!it->is_string() || *it != "subsurface")
    throw InputError(at + "material: type must be \"subsurface\" (a medium under a boundary), got " + show(*it));
  MaterialSpectra spectra;
  Params p(description, at + "subsurface: ", *find_material_type("subsurface"), spectra, base_dir);
  p.reject_undeclared();
  Subsurface s = parse_subsurface(p, true);
  p.reject_unknown();
  return s;
}

namespace {
BxDF parse_description(const json& description, const std::string& where, int blend_depth, MaterialSpectra& spectra,
                       const std::string& base_dir) {
  const std::string at = where.empty() ? "" : where + ": ";
  if (!description.is_object())
    throw InputError(at + "material must be a JSON object, got " + show(description));
  if (description.contains("mtlx")) {
    // SPEC §2: {"mtlx": "file.mtlx", "material": "NAME"}, the document's material as its
    // `openpbr` JSON, then parsed as any other; a relative path as `measured`'s file.
    for (const auto& [key, value] : description.items())
      if (key != "mtlx" && key != "material" && key != "uv" && key != "position")
        throw InputError(at + "mtlx: unknown field '" + key + "' (a MaterialX material takes mtlx, material, uv and position)");
    const json& file = description["mtlx"];
    if (!file.is_string()) throw InputError(at + "mtlx: must be a file name, got " + show(file));
    std::optional<std::string> name;
    if (const auto m = description.find("material"); m != description.end()) {
      if (!m->is_string()) throw InputError(at + "mtlx: material must be a material's name, got " + show(*m));
      name = m->get<std::string>();
    }
    // SPEC §2: the point where the document's node graphs are evaluated (the CLI's --uv
    // and --position), finite numbers.
    MaterialxPoint point;
    const auto numbers = [&](const char* key, size_t n, double* out) {
      const auto it = description.find(key);
      if (it == description.end()) return;
      if (!it->is_array() || it->size() != n)
        throw InputError(at + "mtlx: " + key + " must be an array of " + std::to_string(n) + " numbers, got " + show(*it));
      for (size_t i = 0; i < n; ++i) {
        if (!(*it)[i].is_number() || !std::isfinite((*it)[i].get<double>()))
          throw InputError(at + "mtlx: " + key + " must be an array of " + std::to_string(n) + " finite numbers, got " + show(*it));
        out[i] = (*it)[i].get<double>();
      }
    };
    double uv[2] = {point.u, point.v}, pos[3] = {point.px, point.py, point.pz};
    numbers("uv", 2, uv);
    numbers("position", 3, pos);
    point.u = uv[0];
    point.v = uv[1];
    point.px = pos[0];
    point.py = pos[1];
    point.pz = pos[2];
    std::filesystem::path path = file.get<std::string>();
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    const json produced = materialx_file_to_json(path.string(), name, nullptr, point);
    return parse_description(produced, at + path.string(), blend_depth, spectra, base_dir);
  }
  const auto it = description.find("type");
  if (it == description.end()) throw InputError(at + "material: missing field 'type'");
  if (!it->is_string()) throw InputError(at + "material: type must be a string, got " + show(*it));
  const std::string type = it->get<std::string>();
  const MaterialTypeSpec* spec = find_material_type(type);
  if (!spec) {
    std::string known;
    for (auto n : material_type_names()) known += (known.empty() ? "" : ", ") + std::string(n);
    throw InputError(at + "material: unknown type \"" + type + "\" (known: " + known + ")");
  }
  if (type == "blend") {
    Params p(description, at + "blend: ", *spec, spectra, base_dir);
    p.reject_undeclared();
    BxDF m = make_blend(p, where.empty() ? "blend" : where + ": blend", blend_depth);
    p.reject_unknown();
    return m;
  }
  if (type == "layered") {
    Params p(description, at + "layered: ", *spec, spectra, base_dir);
    p.reject_undeclared();
    BxDF m = make_layered(p, where.empty() ? "layered" : where + ": layered", blend_depth);
    p.reject_unknown();
    return m;
  }
  if (type == "mix" || type == "add" || type == "multiply" || type == "layer") {
    Params p(description, at + type + ": ", *spec, spectra, base_dir);
    p.reject_undeclared();
    BxDF m = make_mx_operator(p, type, where.empty() ? type : where + ": " + type, blend_depth);
    p.reject_unknown();
    return m;
  }
  if (const auto leaf = pbr_leaf_maker(type)) {
    Params p(description, at + type + ": ", *spec, spectra, base_dir);
    check_pbr_depth(p, blend_depth);
    p.reject_undeclared();
    BxDF m = leaf(p);
    p.reject_unknown();
    return m;
  }
  for (const auto& t : kMakers) {
    if (t.name == type) {
      Params p(description, at + type + ": ", *spec, spectra, base_dir);
      p.reject_undeclared();
      BxDF m = t.make(p);
      p.reject_unknown();
      return m;
    }
  }
  throw std::logic_error("material registry: no constructor for type " + type);
}
}  // namespace
// --- Spatially varying parameters (material.h) -----------------------------------

namespace {

using MP = MaterialParam;

// Indexed by MaterialParam. Probes: each passes the parser's checks on its own and keeps
// the combined ones (kd + ks <= 1) whatever the other value.
constexpr MaterialParamInfo kParamInfo[] = {
    {"reflectance", false, 0.5}, {"kd", false, 0}, {"ks", false, 0}, {"rd", false, 0},
    {"rs", false, 0},            {"f0", false, 0.5}, {"eta", false, 1}, {"k", false, 0},
    {"color", false, 1},
    {"alpha", true, 0.5},        {"alpha", true, 0.5}, {"alpha", true, 0.5}, {"sigma", true, 0},
    {"exponent", true, 1},       {"nu", true, 1},    {"nv", true, 1},
};
static_assert(std::size(kParamInfo) == size_t(MP::Nv) + 1);

// Which parameters of which type may vary. Not: the index of a dielectric or plastic (a
// medium whose index changed along its surface would not be one medium, and plastic
// precomputes its internal reflectance from it), Fresnel and distribution choices, flags.
struct VaryingKey {
  std::string_view type;
  MaterialParam param;
};
constexpr VaryingKey kVarying[] = {
    {"diffuse", MP::Reflectance},
    {"mirror", MP::Reflectance},
    {"conductor", MP::Eta}, {"conductor", MP::K}, {"conductor", MP::F0},
    {"roughconductor", MP::Alpha}, {"roughconductor", MP::Eta}, {"roughconductor", MP::K}, {"roughconductor", MP::F0},
    {"roughdielectric", MP::Alpha},
    {"orennayar", MP::Reflectance}, {"orennayar", MP::Sigma},
    {"eon", MP::Reflectance},
    {"phong", MP::Kd}, {"phong", MP::Ks}, {"phong", MP::Exponent},
    {"blinnphong", MP::Kd}, {"blinnphong", MP::Ks}, {"blinnphong", MP::Exponent},
    {"ward", MP::Kd}, {"ward", MP::Ks}, {"ward", MP::Alpha},
    {"ashikhminshirley", MP::Rd}, {"ashikhminshirley", MP::Rs}, {"ashikhminshirley", MP::Nu}, {"ashikhminshirley", MP::Nv},
    {"plastic", MP::Reflectance}, {"plastic", MP::Alpha},
    {"sheen", MP::SheenColor},
};

// What a set of new values touched, for recomputing what depends on it.
struct Changed {
  bool alpha = false, index = false, fresnel = false;
};

void set_alpha(Float& ax, Float& ay, const ParamValue& v, Changed& c) {
  const Float a = v.value[0];
  switch (v.param) {
    case MP::Alpha: ax = ay = a; break;
    case MP::AlphaX: ax = a; break;
    case MP::AlphaY: ay = a; break;
    default: return;
  }
  c.alpha = true;
}
void set_alpha(MicrofacetDistribution& d, const ParamValue& v, Changed& c) { set_alpha(d.alpha_x, d.alpha_y, v, c); }

void set_fresnel(ConductorFresnel& fr, const ParamValue& v, Changed& c) {
  switch (v.param) {
    case MP::F0: fr.f0 = v.value; break;
    case MP::Eta: fr.eta = v.value; c.index = true; break;
    case MP::K: fr.k = v.value; c.index = true; break;
    default: return;
  }
  fr.prepare();  // F82-tint's a depends on f0
  c.fresnel = true;
}

void set_color(Color& field, MaterialParam which, const ParamValue& v) {
  if (v.param == which) field = v.value;
}
void set_scalar(Float& field, MaterialParam which, const ParamValue& v) {
  if (v.param == which) field = v.value[0];
}

void apply(DiffuseBxDF& m, const ParamValue& v, Changed&) { set_color(m.reflectance, MP::Reflectance, v); }
void apply(MirrorBxDF& m, const ParamValue& v, Changed&) { set_color(m.reflectance, MP::Reflectance, v); }
void apply(ConductorBxDF& m, const ParamValue& v, Changed& c) { set_fresnel(m.fresnel, v, c); }
void apply(RoughConductorBxDF& m, const ParamValue& v, Changed& c) {
  set_alpha(m.distribution, v, c);
  set_fresnel(m.fresnel, v, c);
}
void apply(RoughDielectricBxDF& m, const ParamValue& v, Changed& c) { set_alpha(m.distribution, v, c); }
void apply(OrenNayarBxDF& m, const ParamValue& v, Changed&) {
  set_color(m.reflectance, MP::Reflectance, v);
  if (v.param == MP::Sigma) m.sigma = sigma_radians(v.value[0]);
}
void apply(EonBxDF& m, const ParamValue& v, Changed&) {
  set_color(m.reflectance, MP::Reflectance, v);
  m.prepare();  // ρ_ms depends on the reflectance (eon::Constants)
}
template <typename M>
  requires std::is_same_v<M, PhongBxDF> || std::is_same_v<M, BlinnPhongBxDF>
void apply(M& m, const ParamValue& v, Changed&) {
  set_color(m.kd, MP::Kd, v);
  set_color(m.ks, MP::Ks, v);
  set_scalar(m.exponent, MP::Exponent, v);
}
void apply(WardBxDF& m, const ParamValue& v, Changed& c) {
  set_color(m.kd, MP::Kd, v);
  set_color(m.ks, MP::Ks, v);
  set_alpha(m.alpha_x, m.alpha_y, v, c);
}
void apply(AshikhminShirleyBxDF& m, const ParamValue& v, Changed&) {
  set_color(m.rd, MP::Rd, v);
  set_color(m.rs, MP::Rs, v);
  set_scalar(m.nu, MP::Nu, v);
  set_scalar(m.nv, MP::Nv, v);
}
void apply(PlasticBxDF& m, const ParamValue& v, Changed& c) {
  set_color(m.reflectance, MP::Reflectance, v);
  if (m.coat) set_alpha(*m.coat, v, c);
}
void apply(DielectricBxDF&, const ParamValue&, Changed&) {}
void apply(SheenBxDF& m, const ParamValue& v, Changed&) { set_color(m.color, MP::SheenColor, v); }
void apply(ThinDielectricBxDF&, const ParamValue&, Changed&) {}

template <typename M>
void finish(M&, const Changed&) {}
void finish(RoughDielectricBxDF& m, const Changed& c) {
  if (!m.multiscatter || !c.alpha) return;
  if (m.specular() || !m.distribution.is_isotropic()) {
    // As material_from_json does for a specular model; an anisotropic one (textured
    // alpha_x, alpha_y) has no compensation (see dielectric_multiscatter.h).
    m.multiscatter.reset();
    return;
  }
  m.multiscatter = DielectricMultiscatterLobe::remake(m.distribution, m.eta, m.multiscatter->fbar_out);
}
void finish(ConductorBxDF& m, const Changed& c) {
  if (c.index) set_f0_from_index(m.fresnel);
}
void finish(PlasticBxDF& m, const Changed& c) {
  if (c.alpha) m.update_coat();  // the rough coat's internal reflectance depends on α
}
void finish(RoughConductorBxDF& m, const Changed& c) {
  if (c.index) set_f0_from_index(m.fresnel);
  if (!m.multiscatter || !(c.alpha || c.fresnel)) return;
  if (m.distribution.effectively_smooth()) {
    m.multiscatter.reset();  // as material_from_json does for a smooth distribution
    return;
  }
  m.multiscatter = MultiscatterLobe::make(m.distribution, c.fresnel ? conductor_average_fresnel(m.fresnel) : m.multiscatter->f_avg);
}

// openpbr: the model made again from its parameters with the new values (make() derives
// everything else from them). Its quadratures (the diffuse's normalisation, the film's
// change of E_s: tens of thousands of operations) are `model`'s while none of their inputs
// changed; RGB mode's film table is kept while the film and the index under it are the
// same, else the film is read at the channels' wavelengths (openpbr_film: no allocation).
OpenPbrBxDF with_openpbr_params(const OpenPbrBxDF& model, std::span<const ParamValue> values) noexcept {
  OpenPbrParams<Color> p = model.params;
  for (const ParamValue& v : values) {
    const size_t i = size_t(v.param) - size_t(MP::OpenPbrFirst);
    if (v.param < MP::OpenPbrFirst || i >= kOpenPbrFieldCount) continue;
    const auto& f = kOpenPbrFields<Color>[i];
    if (f.number) p.*f.number = v.value[0];
    else p.*f.colour = v.value;
  }
  bool same_solved = true, same_film = true;
  for (const auto& f : kOpenPbrFields<Color>) {
    // Every input of the quadratures and of the film table is a number.
    if (!f.number || p.*f.number == model.params.*f.number) continue;
    same_solved = same_solved && !f.solved;
    same_film = same_film && !f.film;
  }
  ThinFilmT<Color> film = openpbr_film(p, false);
  if (same_film && film.active() && model.film.active()) film.table = model.film.table;
  // The metal's and the glass's film tables are kept while the film and their substrates
  // (the metal's colours; the glass's index, a film input) are the same.
  openpbr::SubstrateFilms<Color> films;
  const auto keep = [&](const ThinFilmT<Color>& old, bool same_substrate) {
    ThinFilmT<Color> f;
    if (same_film && same_substrate && film.active() && old.active() && old.table) {
      f = film;
      f.table = old.table;
    }
    return f;
  };
  films.metal = keep(model.metal.fresnel.film, p.base_color == model.params.base_color &&
                                                   p.base_weight == model.params.base_weight &&
                                                   p.specular_color == model.params.specular_color);
  films.glass = keep(model.glass.film, true);
  const openpbr::Solved solved = model.solved();
  return OpenPbrBxDF::make(p, std::move(film), same_solved ? &solved : nullptr, std::move(films));
}

// gltf_pbr: the new values set in its parameters (make() derives nothing else).
GltfPbrBxDF with_gltf_pbr_params(const GltfPbrBxDF& model, std::span<const ParamValue> values) noexcept {
  GltfPbrParams<Color> p = model.params;
  for (const ParamValue& v : values) {
    const size_t i = size_t(v.param) - kGltfPbrFirst;
    if (size_t(v.param) < kGltfPbrFirst || i >= kGltfPbrFieldCount) continue;
    const auto& f = kGltfPbrFields<Color>[i];
    if (f.number) p.*f.number = v.value[0];
    else p.*f.colour = v.value;
  }
  return GltfPbrBxDF::make(p);
}

}  // namespace

const MaterialParamInfo& material_param_info(MaterialParam p) {
  const size_t i = static_cast<size_t>(p);
  if (i < std::size(kParamInfo)) return kParamInfo[i];
  if (i >= kGltfPbrFirst) {
    // gltf_pbr's, from its field table; each probe is the parameter's default.
    static const auto gltf = [] {
      const GltfPbrParams<Color> d;
      std::array<MaterialParamInfo, kGltfPbrFieldCount> info{};
      for (size_t k = 0; k < kGltfPbrFieldCount; ++k) {
        const auto& f = kGltfPbrFields<Color>[k];
        info[k] = {f.key, f.number != nullptr, double(f.number ? d.*f.number : (d.*f.colour)[0])};
      }
      return info;
    }();
    return gltf[std::min(i - kGltfPbrFirst, kGltfPbrFieldCount - 1)];
  }
  // openpbr's, from its field table; each probe is the parameter's default, which its
  // range accepts whatever the others (make_openpbr checks no combination).
  static const auto openpbr = [] {
    const OpenPbrParams<Color> d;
    std::array<MaterialParamInfo, kOpenPbrFieldCount> info{};
    for (size_t k = 0; k < kOpenPbrFieldCount; ++k) {
      const auto& f = kOpenPbrFields<Color>[k];
      info[k] = {f.key, f.number != nullptr, double(f.number ? d.*f.number : (d.*f.colour)[0])};
    }
    return info;
  }();
  return openpbr[std::min(i - std::size(kParamInfo), kOpenPbrFieldCount - 1)];
}

std::optional<MaterialParam> varying_param(std::string_view type, std::string_view key) {
  if (type == GltfPbrBxDF::kName) {
    for (size_t i = 0; i < kGltfPbrFieldCount; ++i)
      if (kGltfPbrFields<Color>[i].varying && kGltfPbrFields<Color>[i].key == key) return MaterialParam(kGltfPbrFirst + i);
    return std::nullopt;
  }
  if (type == OpenPbrBxDF::kName) {
    for (size_t i = 0; i < kOpenPbrFieldCount; ++i)
      if (kOpenPbrFields<Color>[i].key == key) return MaterialParam(size_t(MP::OpenPbrFirst) + i);
    return std::nullopt;
  }
  for (const auto& v : kVarying)
    if (v.type == type && material_param_info(v.param).key == key) return v.param;
  return std::nullopt;
}

std::string varying_param_keys(std::string_view type) {
  std::string keys;
  const auto add = [&keys](std::string_view key) { keys += (keys.empty() ? "" : ", ") + std::string(key); };
  if (type == OpenPbrBxDF::kName)
    for (const auto& f : kOpenPbrFields<Color>) add(f.key);
  if (type == GltfPbrBxDF::kName)
    for (const auto& f : kGltfPbrFields<Color>)
      if (f.varying) add(f.key);
  for (const auto& v : kVarying)
    if (v.type == type) add(material_param_info(v.param).key);
  return keys;
}

std::optional<std::string> varying_param_refused(const json& description, std::string_view key) {
  const auto type = description.find("type");
  if (type == description.end() || !type->is_string() || type->get<std::string>() != OpenPbrBxDF::kName)
    return std::nullopt;
  const auto param = varying_param(OpenPbrBxDF::kName, key);
  if (!param) return std::nullopt;
  // The interior `gonio render` fills a translucent shape with (docs/openpbr.md,
  // "Rendering"): one medium per shape, from the transmission's colour at its depth.
  const auto depth = description.find("transmission_depth");
  const bool has_depth = depth != description.end() && !(depth->is_number() && depth->get<double>() == 0);
  const bool interior = key == "transmission_depth" || key == "transmission_scatter" ||
                        key == "transmission_scatter_anisotropy" || (key == "transmission_color" && has_depth);
  if (!interior && !kOpenPbrFields<Color>[size_t(*param) - size_t(MP::OpenPbrFirst)].medium) return std::nullopt;
  const auto thin = description.find("geometry_thin_walled");
  if (thin != description.end() && thin->is_boolean() && thin->get<bool>()) return std::nullopt;
  const auto trans = description.find("transmission_weight");
  if (trans == description.end() || (trans->is_number() && trans->get<double>() == 0)) return std::nullopt;
  if (interior)
    return std::string(key) + " sets the medium that fills the translucent shape, which is one medium: it may be a "
           "texture only where transmission_weight is 0 or geometry_thin_walled is true" +
           (key == "transmission_color" ? " (or transmission_depth is 0: a tint at the surface)" : "");
  return std::string(key) + " sets the index of the medium behind the translucent base, which must be one index: "
         "it may be a texture only where transmission_weight is 0 or geometry_thin_walled is true";
}

BxDF with_params(const BxDF& model, std::span<const ParamValue> values) noexcept {
  return std::visit(
      [&](const auto& base) -> BxDF {
        using M = std::decay_t<decltype(base)>;
        if constexpr (std::is_same_v<M, OpenPbrBxDF>) {
          return with_openpbr_params(base, values);
        } else if constexpr (std::is_same_v<M, GltfPbrBxDF>) {
          return with_gltf_pbr_params(base, values);
        } else if constexpr (std::is_same_v<M, BlendBxDF> || std::is_same_v<M, UserBxDF> || std::is_same_v<M, PbrNodeBxDF> ||
                             std::is_same_v<M, CharlieSheenBxDF> ||
                             std::is_same_v<M, MeasuredBxDF> || std::is_same_v<M, LayeredBxDF> ||
                             std::is_same_v<M, HairBxDF> || std::is_same_v<M, RglBxDF>) {
          return base;  // nothing of theirs varies
        } else {
          M m = base;
          Changed changed;
          for (const ParamValue& v : values) apply(m, v, changed);
          finish(m, changed);
          return m;
        }
      },
      model.models());
}

BxDF parse_material(std::string_view json_text, std::string_view source) {
  const json j = parse_json_text(json_text, source);
  return material_from_json(j, std::string(source));
}

}  // namespace gonio
