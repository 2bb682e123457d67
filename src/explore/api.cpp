// The explorer's JSON API (api.h): request parsing, the material's file names confined to
// --data, and each view computed by the library — eval_batch for the lobe and /api/eval,
// the renderer's slice_values for the slice, directional_albedo, the Fresnel equations of
// fresnel.h, and the validator.

#include "explore/api.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "explore/material_request.h"
#include "gonio/batch.h"
#include "gonio/bxdf/evaluation_cost.h"
#include "gonio/error.h"
#include "gonio/fresnel.h"
#include "gonio/json_text.h"
#include "gonio/material.h"
#include "gonio/material_types.h"
#include "gonio/merl.h"
#include "gonio/metals.h"
#include "gonio/named_index.h"
#include "gonio/reflectance.h"
#include "gonio/render/colormap.h"
#include "gonio/render/slice.h"
#include "gonio/spectrum/glasses.h"
#include "gonio/spectrum/wavelengths.h"
#include "gonio/validate.h"
#include "gonio/version.h"

namespace gonio::explore {

using nlohmann::json;

namespace {

constexpr double kDegree = kPiD / 180;

// Numbers as the CLI prints them (SPEC §1): %.9g for a float, %.17g for a double.
void put_number(std::string& out, double v, int digits) {
  if (!std::isfinite(v)) {  // never expected; JSON has no NaN
    out += "null";
    return;
  }
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  out += buf;
}
void put_float(std::string& out, Float v) { put_number(out, double(v), 9); }

template <typename C>
void put_colour(std::string& out, const C& c) {
  out += '[';
  if constexpr (std::is_same_v<C, Color>) {
    for (int i = 0; i < 3; ++i) {
      if (i) out += ',';
      put_float(out, c[i]);
    }
  } else {
    put_float(out, c[0]);  // one wavelength: the hero's value (SPEC §1: a one-element array)
  }
  out += ']';
}

// The luminance gonio slice shows, of either colour type (one wavelength: its value).
template <typename C>
double shown_value(const C& c) {
  if constexpr (std::is_same_v<C, Color>) return render::luminance(c);
  else return double(c[0]);
}

double number_field(const json& body, const char* name, double fallback, double lo, double hi,
                    const char* unit = "") {
  const auto it = body.find(name);
  if (it == body.end() || it->is_null()) return fallback;
  if (!it->is_number())
    throw InputError(std::string(name) + " must be a number, got " + json_excerpt(*it));
  const double v = it->get<double>();
  if (!(v >= lo && v <= hi))
    throw InputError(std::string(name) + " must be in [" + format_number(lo) + ", " + format_number(hi) + "]" + unit +
                     ", got " + format_number(v));
  return v;
}

bool bool_field(const json& body, const char* name, bool fallback) {
  const auto it = body.find(name);
  if (it == body.end() || it->is_null()) return fallback;
  if (!it->is_boolean()) throw InputError(std::string(name) + " must be true or false, got " + json_excerpt(*it));
  return it->get<bool>();
}

TransportMode mode_field(const json& body) {
  const auto it = body.find("mode");
  if (it == body.end() || it->is_null()) return TransportMode::Radiance;
  if (it->is_string() && *it == "radiance") return TransportMode::Radiance;
  if (it->is_string() && *it == "importance") return TransportMode::Importance;
  throw InputError("mode must be \"radiance\" or \"importance\", got " + json_excerpt(*it));
}

// Runs `f` with the material of the request in RGB mode, or at its "wavelength".
template <typename F>
auto with_material(const json& body, const ApiContext& ctx, F&& f) {
  const std::optional<Float> nm = request_wavelength(body);
  if (nm) {
    const auto m = load_material_at_wavelength(body, ctx, *nm);
    return f(m->bxdf);
  }
  const BxDF bxdf = load_material(body, ctx);
  return f(bxdf);
}

std::string kind_name(ParamKind k) {
  switch (k) {
    case ParamKind::Number: return "number";
    case ParamKind::Colour: return "colour";
    case ParamKind::Roughness: return "roughness";
    case ParamKind::Choice: return "choice";
    case ParamKind::Boolean: return "boolean";
    case ParamKind::Metal: return "metal";
    case ParamKind::Materials: return "materials";
    case ParamKind::Material: return "material";
    case ParamKind::File: return "file";
    case ParamKind::Film: return "film";
    case ParamKind::Lobes: return "lobes";
    case ParamKind::Pair: return "pair";
  }
  return "";
}

std::vector<std::string> split_choices(std::string_view choices) {
  std::vector<std::string> items;
  if (choices.empty()) return items;
  size_t start = 0;
  while (start <= choices.size()) {
    const size_t bar = std::min(choices.find('|', start), choices.size());
    items.emplace_back(choices.substr(start, bar - start));
    start = bar + 1;
  }
  return items;
}

// ---- Fresnel: the index of a material's interface ----------------------------------

struct InterfaceIndex {
  std::vector<std::pair<double, double>> channels;  // (eta, k) per channel
  std::string source;                               // what it was read from, for the page
};

// A colour-valued index parameter as per-channel numbers; nothing for a spectrum or a
// named glass written as an object (the page then asks for an index).
std::optional<std::vector<double>> index_numbers(const json& v) {
  if (v.is_number()) return std::vector<double>{v.get<double>()};
  if (v.is_array() && v.size() == 3 && std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
    return std::vector<double>{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  return std::nullopt;
}

std::optional<InterfaceIndex> interface_index(const json& m, std::optional<Float> nm, int depth = 0) {
  if (!m.is_object() || depth > kMaxBlendDepth) return std::nullopt;
  const std::string type = m.value("type", "");
  if (type == "layered" && m.contains("top")) return interface_index(m["top"], nm, depth + 1);
  if (type == "blend" && m.contains("bsdfs") && m["bsdfs"].is_array()) {
    for (const auto& part : m["bsdfs"])
      if (auto i = interface_index(part, nm, depth + 1)) return i;
    return std::nullopt;
  }
  const MaterialTypeSpec* spec = find_material_type(type);
  if (!spec) return std::nullopt;
  const bool conductor = type == "conductor" || type == "roughconductor";
  if (conductor && m.contains("material") && m["material"].is_string()) {
    const std::string name = m["material"];
    return InterfaceIndex{named_index(name, nm), "material " + name};
  }
  // OpenPBR (docs/openpbr.md): the first interface light meets is the coat's where there
  // is a coat (coat_ior), else the base dielectric's (specular_ior); both are numbers.
  if (type == "openpbr") {
    const auto number = [&](const char* key, double fallback) {
      const auto it = m.find(key);
      return it != m.end() && it->is_number() ? it->get<double>() : fallback;
    };
    const bool coated = number("coat_weight", 0) > 0;
    const char* key = coated ? "coat_ior" : "specular_ior";
    const ParamSpec* p = find_param(*spec, key);
    const double fallback = p && !p->default_json.empty() ? json::parse(p->default_json).get<double>() : 1.5;
    return InterfaceIndex{{{number(key, fallback), 0.0}}, key};
  }
  const ParamSpec* eta_spec = find_param(*spec, "eta");
  if (!eta_spec) return std::nullopt;
  json eta = m.contains("eta") ? m["eta"] : json();
  if (eta.is_null()) {
    if (eta_spec->default_json.empty()) return std::nullopt;  // e.g. a Schlick conductor given by f0
    eta = json::parse(eta_spec->default_json);
  }
  if (eta.is_string() && !conductor) {
    const std::string name = eta;
    return InterfaceIndex{named_index(name, nm), "eta " + name};
  }
  const auto n = index_numbers(eta);
  if (!n) return std::nullopt;
  std::vector<double> k(n->size(), 0.0);
  if (conductor && m.contains("k")) {
    const auto kk = index_numbers(m["k"]);
    if (!kk) return std::nullopt;
    k = *kk;
  }
  const size_t channels = std::max(n->size(), k.size());
  // At one wavelength an RGB index has no single value: the page asks for a number.
  if (nm && channels > 1) return std::nullopt;
  InterfaceIndex out;
  for (size_t c = 0; c < channels; ++c)
    out.channels.emplace_back((*n)[std::min(c, n->size() - 1)], k[std::min(c, k.size() - 1)]);
  out.source = "eta";
  return out;
}

// The angle of least Rp of a conductor (its pseudo-Brewster angle), in degrees: a scan,
// then a golden-section search in the bracket (Rp has one minimum in [0°, 90°)).
double pseudo_brewster_degrees(double eta, double k) {
  const auto rp = [&](double deg) { return fresnel_terms(std::cos(deg * kDegree), eta, k).rp; };
  double best = 0;
  for (int d = 0; d <= 90; ++d)
    if (rp(d) < rp(best)) best = d;
  double a = std::max(0.0, best - 1), b = std::min(90.0, best + 1);
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 60; ++i) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    (rp(c) < rp(d) ? b : a) = (rp(c) < rp(d) ? d : c);
  }
  return (a + b) / 2;
}

// Rs, Rp, R over the angles, for light arriving from the side of relative index `eta`.
json fresnel_side(double eta, double k, const std::vector<double>& thetas) {
  json rs = json::array(), rp = json::array(), r = json::array();
  for (const double t : thetas) {
    const FresnelTerms<double> f = fresnel_terms(std::cos(t * kDegree), eta, k);
    rs.push_back(f.rs);
    rp.push_back(f.rp);
    r.push_back(f.r());
  }
  json side = {{"eta", eta}, {"k", k}, {"Rs", rs}, {"Rp", rp}, {"R", r}};
  // Total internal reflection from sin θt = sin θ / eta ≥ 1 (SPEC §1): θc = asin(eta).
  side["critical"] = (k == 0 && eta < 1) ? json(std::asin(eta) / kDegree) : json();
  // Brewster: Rp = 0 where tan θB = eta (Hecht, Optics, §8.6.1); a conductor's Rp only
  // has a minimum, its pseudo-Brewster angle.
  if (k == 0) {
    side["brewster"] = std::atan(eta) / kDegree;
  } else {
    side["brewster"] = pseudo_brewster_degrees(eta, k);
    side["pseudo_brewster"] = true;
  }
  return side;
}

// One validation at a time (seconds of a core each: the views must stay live), and at
// most 4 waiting: 70 pages asking at once get 429s, not 70 threads held for minutes.
OneAtATime& check_gate() {
  static OneAtATime gate(4);
  return gate;
}


}  // namespace

// ---- stopping and queueing -----------------------------------------------------------

Stopped::Stopped(StopReason r)
    : std::runtime_error(r == StopReason::Superseded     ? "superseded by a newer request of the same view"
                         : r == StopReason::TimeLimit    ? "stopped at the explorer's time limit per request"
                         : r == StopReason::ClientGone   ? "the client closed the connection"
                         : r == StopReason::ShuttingDown ? "the server is stopping"
                                                         : "stopped"),
      reason(r) {}

Busy::Busy(const std::string& what) : std::runtime_error(what) {}

void OneAtATime::acquire(const ApiContext& ctx, const char* what) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (busy_ && waiting_ >= max_waiting_)
    throw Busy("busy: a " + std::string(what) + " is running and " + std::to_string(waiting_) +
               " more wait; try again when they are done");
  ++waiting_;
  while (busy_) {
    freed_.wait_for(lock, std::chrono::milliseconds(20));
    if (ctx.stop && ctx.stop->stop.load()) {
      --waiting_;
      throw Stopped(ctx.stop->why());
    }
  }
  --waiting_;
  busy_ = true;
}

void OneAtATime::release() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    busy_ = false;
  }
  freed_.notify_one();
}


// ---- endpoints -----------------------------------------------------------------------

std::string api_materials() {
  json types = json::array();
  for (const MaterialTypeSpec& t : material_types()) {
    json params = json::array();
    for (const ParamSpec& p : t.params) {
      json q = {{"name", p.name},
                {"kind", kind_name(p.kind)},
                {"required", p.required},
                {"meaning", p.meaning},
                {"unit", p.unit}};
      q["default"] = p.default_json.empty() ? json() : json::parse(p.default_json);
      if (p.range.present) {
        q["range"] = {{"lo", p.range.lo},
                      {"hi", p.range.hi},
                      {"lo_open", p.range.lo_open},
                      {"hi_open", p.range.hi_open},
                      {"text", range_text(p.range, p.unit)}};
      } else {
        q["range"] = nullptr;
      }
      if (p.kind == ParamKind::Choice) q["choices"] = split_choices(p.choices);
      if (p.kind == ParamKind::Metal) {
        json names = json::array();
        for (auto n : named_metal_names()) names.push_back(n);
        q["choices"] = names;
      }
      params.push_back(std::move(q));
    }
    types.push_back({{"name", t.name},
                     {"summary", t.summary},
                     {"source", t.source},
                     {"notes", t.notes},
                     {"params", params},
                     {"example", example_material(t.name)}});
  }
  json metals = json::array(), glasses = json::array();
  for (auto n : named_metal_names()) metals.push_back(n);
  for (auto n : named_glass_names()) glasses.push_back(n);
  const json out = {{"version", GONIO_VERSION_STRING},
                    {"types", types},
                    {"metals", metals},
                    {"glasses", glasses},
                    {"wavelength", {{"min", double(kLambdaMin)}, {"max", double(kLambdaMax)}}},
                    {"fit_models", json::parse(api_fit_models())}};
  return out.dump();
}

std::string api_data(const ApiContext& ctx) {
  json files = json::array();
  if (!ctx.data_dir.empty()) {
    std::error_code ec;
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(ctx.data_dir, ec)) {
      if (e.is_regular_file(ec) && !e.is_symlink(ec)) names.push_back(e.path().filename().string());
      if (names.size() >= 1000) break;
    }
    std::sort(names.begin(), names.end());
    for (auto& n : names) files.push_back(n);
  }
  return json({{"data", !ctx.data_dir.empty()}, {"files", files}}).dump();
}

std::string api_validate(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const BxDF bxdf = load_material(b, ctx);
  const BxDFFlags flags = bxdf.flags();
  return json({{"valid", true},
               {"name", bxdf.name()},
               {"reflection", is_reflective(flags)},
               {"transmission", is_transmissive(flags)},
               {"delta_only", is_delta_only(flags)}})
      .dump();
}

std::string api_eval(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const TransportMode mode = mode_field(b);
  const auto it = b.find("pairs");
  if (it == b.end() || !it->is_array()) throw InputError("pairs: expected an array of [wo_x, wo_y, wo_z, wi_x, wi_y, wi_z]");
  if (it->size() > size_t(kMaxEvalPairs))
    throw InputError("pairs: at most " + std::to_string(kMaxEvalPairs) + " per request, got " + std::to_string(it->size()));
  std::vector<Vec3> wo, wi;
  wo.reserve(it->size());
  wi.reserve(it->size());
  for (size_t i = 0; i < it->size(); ++i) {
    const json& row = (*it)[i];
    const std::string where = "pairs[" + std::to_string(i) + "]: ";
    if (!row.is_array() || row.size() != 6)
      throw InputError(where + "expected 6 numbers, got " + json_excerpt(row));
    double v[6];
    for (int j = 0; j < 6; ++j) {
      if (!row[size_t(j)].is_number()) throw InputError(where + json_excerpt(row[size_t(j)]) + " is not a number");
      v[j] = row[size_t(j)].get<double>();
    }
    const auto a = unit_direction(v[0], v[1], v[2]), c = unit_direction(v[3], v[4], v[5]);
    if (!a) throw InputError(where + "wo is a zero vector");
    if (!c) throw InputError(where + "wi is a zero vector");
    wo.push_back(*a);
    wi.push_back(*c);
  }
  return with_material(b, ctx, [&](const auto& bxdf) {
    check_work(bxdf, double(wo.size()), "eval");
    using C = std::decay_t<decltype(bxdf.f(Vec3{}, Vec3{}))>;
    std::vector<C> f(wo.size());
    std::vector<Float> pdf(wo.size());
    eval_batch<C>(bxdf, wo, wi, mode, f, pdf);
    std::string out = "{\"f\":[";
    for (size_t i = 0; i < f.size(); ++i) {
      if (i) out += ',';
      put_colour(out, f[i]);
    }
    out += "],\"pdf\":[";
    for (size_t i = 0; i < pdf.size(); ++i) {
      if (i) out += ',';
      put_float(out, pdf[i]);
    }
    return out + "]}";
  });
}

std::string api_lobe(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const double theta_i = number_field(b, "theta_i", 30, 0, 90, " degrees");
  const int count = int(integer_field(b, "count", 181, 3, kMaxLobeCount));
  const TransportMode mode = mode_field(b);
  // The plane of incidence is x–z: the light at +θi, wo at θo from −90° to 90° (negative
  // θo on the −x side, where the mirror direction −θi lies).
  const double ti = theta_i * kDegree;
  const Vec3 wi{Float(std::sin(ti)), 0, Float(std::cos(ti))};
  const size_t n = static_cast<size_t>(count);
  std::vector<Vec3> wo(n), wis(n, wi);
  std::vector<double> theta_o(n);
  for (int i = 0; i < count; ++i) {
    theta_o[size_t(i)] = -90 + 180.0 * i / (count - 1);
    const double t = theta_o[size_t(i)] * kDegree;
    wo[size_t(i)] = Vec3{Float(std::sin(t)), 0, Float(std::cos(t))};
  }
  return with_material(b, ctx, [&](const auto& bxdf) {
    // A material that transmits is also evaluated below the surface, wo at θo from the
    // inward normal −z (θo < 0 on the −x side, where the refracted ray goes).
    const bool transmits = is_transmissive(bxdf.flags());
    check_work(bxdf, double(wo.size()) * (transmits ? 2 : 1), "lobe");
    using C = std::decay_t<decltype(bxdf.f(Vec3{}, Vec3{}))>;
    std::vector<C> f(wo.size());
    std::vector<Float> pdf(wo.size());
    eval_batch<C>(bxdf, wo, wis, mode, f, pdf);
    std::vector<C> f_t;
    if (transmits) {
      std::vector<Vec3> below(wo);
      for (Vec3& w : below) w.z = -w.z;
      f_t.resize(n);
      std::vector<Float> pdf_t(n);
      eval_batch<C>(bxdf, below, wis, mode, f_t, pdf_t);
    }
    std::string out = "{\"theta_i\":";
    put_number(out, theta_i, 17);
    out += ",\"mirror\":";
    put_number(out, -theta_i, 17);
    out += ",\"delta_only\":";
    out += is_delta_only(bxdf.flags()) ? "true" : "false";
    out += ",\"channels\":";
    out += std::is_same_v<C, Color> ? "3" : "1";
    out += ",\"theta_o\":[";
    for (size_t i = 0; i < theta_o.size(); ++i) {
      if (i) out += ',';
      put_number(out, theta_o[i], 17);
    }
    out += "],\"f\":[";
    for (size_t i = 0; i < f.size(); ++i) {
      if (i) out += ',';
      put_colour(out, f[i]);
    }
    // f·cos θo: the radiant intensity reflected towards wo per unit irradiance from wi.
    out += "],\"f_cos\":[";
    for (size_t i = 0; i < f.size(); ++i) {
      if (i) out += ',';
      put_colour(out, f[i] * Float(std::max(0.0, std::cos(theta_o[i] * kDegree))));
    }
    out += "],\"pdf\":[";
    for (size_t i = 0; i < pdf.size(); ++i) {
      if (i) out += ',';
      put_float(out, pdf[i]);
    }
    out += "],\"transmission\":";
    out += transmits ? "true" : "false";
    if (transmits) {
      // f and f·|cos θo| below the surface, at the same θo.
      for (const bool cosine : {false, true}) {
        out += cosine ? "],\"f_cos_t\":[" : ",\"f_t\":[";
        for (size_t i = 0; i < n; ++i) {
          if (i) out += ',';
          put_colour(out, cosine ? f_t[i] * Float(std::max(0.0, std::cos(theta_o[i] * kDegree))) : f_t[i]);
        }
      }
      out += ']';
    }
    return out + "}";
  });
}

std::string api_lobe3d(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const double theta_i = number_field(b, "theta_i", 30, 0, 90, " degrees");
  const int rings = int(integer_field(b, "count_theta", 24, 2, kMaxLobe3dTheta));
  const int spokes = int(integer_field(b, "count_phi", 48, 4, kMaxLobe3dPhi));
  const TransportMode mode = mode_field(b);
  // wo over the whole upper hemisphere: θo = 0°..90° in `rings` steps (both ends), φo
  // from 0° in `spokes` steps; the light at +θi in the x–z plane, as /api/lobe.
  const double ti = theta_i * kDegree;
  const Vec3 wi{Float(std::sin(ti)), 0, Float(std::cos(ti))};
  const size_t n = size_t(rings + 1) * size_t(spokes);
  std::vector<Vec3> wo(n), wis(n, wi);
  for (int r = 0; r <= rings; ++r)
    for (int p = 0; p < spokes; ++p) {
      const double t = 90.0 * r / rings * kDegree, ph = 360.0 * p / spokes * kDegree;
      wo[size_t(r) * size_t(spokes) + size_t(p)] =
          Vec3{Float(std::sin(t) * std::cos(ph)), Float(std::sin(t) * std::sin(ph)), Float(std::cos(t))};
    }
  return with_material(b, ctx, [&](const auto& bxdf) {
    using C = std::decay_t<decltype(bxdf.f(Vec3{}, Vec3{}))>;
    check_work(bxdf, double(n), "lobe3d");
    std::vector<C> f(n);
    std::vector<Float> pdf(n);
    eval_batch<C>(bxdf, wo, wis, mode, f, pdf);
    // One number per direction: the luminance of f (of f·cos θo in "f_cos"), as the slice.
    std::string out = "{\"theta_i\":";
    put_number(out, theta_i, 17);
    out += ",\"count_theta\":" + std::to_string(rings) + ",\"count_phi\":" + std::to_string(spokes);
    for (const bool cosine : {false, true}) {
      out += cosine ? "],\"f_cos\":[" : ",\"f\":[";
      for (size_t i = 0; i < n; ++i) {
        if (i) out += ',';
        put_number(out, shown_value(f[i]) * (cosine ? std::max(0.0, double(wo[i].z)) : 1.0), 7);
      }
    }
    return out + "]}";
  });
}

std::string api_slice(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  render::SliceOptions o;
  o.size = int(integer_field(b, "size", 90, render::kMinSliceSize, kMaxSliceSize));
  o.phi_d = number_field(b, "phi_d", 90, 0, 180, " degrees") * kDegree;
  o.theta_h_axis = bool_field(b, "sqrt_theta_h", false) ? render::ThetaHAxis::Sqrt : render::ThetaHAxis::Linear;
  const BxDF bxdf = load_material(b, ctx);
  // With "compare", a second material on the same scale (as `gonio slice --compare`).
  std::optional<BxDF> other;
  if (b.contains("compare") && !b["compare"].is_null()) other = load_material(b, ctx, "compare");
  const double pixels = double(o.size) * double(o.size);
  check_work(bxdf, pixels, "slice");
  if (other) check_work(*other, pixels, "slice: --compare");
  // The values and the automatic scale of `gonio slice` (render/slice.h).
  const std::vector<double> values = render::slice_values(bxdf, o);
  std::vector<std::vector<double>> panels = {values};
  if (other) panels.push_back(render::slice_values(*other, o));
  std::string out = "{\"size\":" + std::to_string(o.size) + ",\"phi_d\":";
  put_number(out, o.phi_d / kDegree, 17);
  out += ",\"sqrt_theta_h\":";
  out += o.theta_h_axis == render::ThetaHAxis::Sqrt ? "true" : "false";
  bool any = false;
  for (const auto& p : panels)
    for (const double v : p) any |= v > 0;
  if (any) {
    const auto [lo, hi] = render::slice_auto_scale(panels);
    out += ",\"lo\":";
    put_number(out, lo, 17);
    out += ",\"hi\":";
    put_number(out, hi, 17);
  } else {
    out += ",\"lo\":null,\"hi\":null";  // a delta-only material: nothing finite to show
  }
  // Luminance of f (1/sr) per pixel, row 0 at the top (θd = 90°); -1 below the horizon.
  const auto put_values = [&](const char* name, const std::vector<double>& v) {
    out += ",\"";
    out += name;
    out += "\":[";
    for (size_t i = 0; i < v.size(); ++i) {
      if (i) out += ',';
      put_number(out, v[i], 7);
    }
    out += ']';
  };
  put_values("values", values);
  if (other) put_values("values_compare", panels[1]);
  return out + "}";
}

std::string api_slice_point(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const double theta_h = number_field(b, "theta_h", 0, 0, 90, " degrees") * kDegree;
  const double theta_d = number_field(b, "theta_d", 0, 0, 90, " degrees") * kDegree;
  const double phi_d = number_field(b, "phi_d", 90, 0, 180, " degrees") * kDegree;
  // The directions of gonio slice's pixels (merl.h).
  const auto [wo, wi] = merl_directions(theta_h, theta_d, phi_d);
  const BxDF bxdf = load_material(b, ctx);
  check_work(bxdf, 1, "slice_point");
  const bool above = wo.z > 0 && wi.z > 0;
  const Color f = above ? bxdf.f(wo, wi) : Color(0);
  std::string out = "{\"wo\":[";
  for (int i = 0; i < 3; ++i) {
    if (i) out += ',';
    put_float(out, wo[i]);
  }
  out += "],\"wi\":[";
  for (int i = 0; i < 3; ++i) {
    if (i) out += ',';
    put_float(out, wi[i]);
  }
  out += "],\"above\":";
  out += above ? "true" : "false";
  out += ",\"f\":";
  put_colour(out, f);
  out += ",\"luminance\":";
  put_number(out, shown_value(f), 9);
  return out + "}";
}

std::string api_albedo(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const int count = int(integer_field(b, "count", 19, 2, kMaxAlbedoCount));
  const auto samples = std::uint64_t(integer_field(b, "samples", 4096, 1, kMaxAlbedoSamples));
  const auto seed = std::uint64_t(integer_field(b, "seed", 1, 0, 2'147'483'647));
  const bool inside = bool_field(b, "inside", false);
  return with_material(b, ctx, [&](const auto& bxdf) {
    // One sample (its weight, an evaluation) per sample and angle.
    check_work(bxdf, double(count) * double(samples), "albedo");
    json theta = json::array(), refl = json::array(), trans = json::array(), alb = json::array(),
         se = json::array(), exact = json::array(), refl_light = json::array(), trans_light = json::array();
    const auto colour = [](const auto& c) {
      json a = json::array();
      if constexpr (std::is_same_v<std::decay_t<decltype(c)>, Color>) {
        for (int i = 0; i < 3; ++i) a.push_back(double(c[i]));
      } else {
        a.push_back(double(c[0]));
      }
      return a;
    };
    for (int i = 0; i < count; ++i) {
      // As gonio albedo --theta: wo at θ in the x–z plane, the same seed at every angle.
      const double t = 90.0 * i / (count - 1);
      const double z = std::cos(t * kDegree);
      const Vec3 wo{Float(std::sin(t * kDegree)), 0, Float(inside ? -z : z)};
      ctx.check_stop();
      const auto e = directional_albedo(bxdf, wo, ReflectanceOptions{samples, seed});
      theta.push_back(t);
      refl.push_back(colour(e.reflectance));
      trans.push_back(colour(e.transmittance));
      alb.push_back(colour(e.albedo));
      se.push_back(colour(e.se_albedo));
      exact.push_back(e.exact);
      if (e.light) {
        refl_light.push_back(colour(e.light->reflectance));
        trans_light.push_back(colour(e.light->transmittance));
      }
    }
    json out({{"theta", theta},
              {"reflectance", refl},
              {"transmittance", trans},
              {"albedo", alb},
              {"stderr", se},
              {"exact", exact},
              {"samples", samples}});
    // The view's figures above (SPEC §3); a model that is not reciprocal adds the light's.
    if (!refl_light.empty()) {
      out["reflectance_light"] = refl_light;
      out["transmittance_light"] = trans_light;
    }
    return out.dump();
  });
}

std::string api_fresnel(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const int count = int(integer_field(b, "count", 91, 2, kMaxFresnelCount));
  const std::optional<Float> nm = request_wavelength(b);
  InterfaceIndex index;
  if (b.contains("eta") || b.contains("k") || b.contains("material")) {
    if (b.contains("material")) {
      if (!b["material"].is_string()) throw InputError("material must be a name, got " + json_excerpt(b["material"]));
      index.channels = named_index(b["material"].get<std::string>(), nm);
      index.source = "material " + b["material"].get<std::string>();
    } else {
      const double eta = number_field(b, "eta", 1.5, -1e300, 1e300), k = number_field(b, "k", 0, -1e300, 1e300);
      check_fresnel_index(eta, k);
      index.channels = {{eta, k}};
      index.source = "eta";
    }
  } else {
    // The material's own interface; parsing it first reports a bad material as such.
    (void)load_material(b, ctx);
    const auto found = interface_index(sanitized_material(b, ctx), nm);
    if (!found)
      return json({{"interface", nullptr},
                   {"reason", "this material has no single interface index here; give \"eta\" (and \"k\") or "
                              "\"material\""}})
          .dump();
    index = *found;
  }
  std::vector<double> thetas(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) thetas[size_t(i)] = 90.0 * i / (count - 1);
  json channels = json::array();
  for (const auto& [eta, k] : index.channels) {
    check_fresnel_index(eta, k);
    json c = {{"outside", fresnel_side(eta, k, thetas)}};
    // Light arriving from inside a dielectric sees 1/eta (SPEC §1).
    c["inside"] = k == 0 ? fresnel_side(1 / eta, 0, thetas) : json();
    channels.push_back(std::move(c));
  }
  return json({{"interface", index.source}, {"theta", thetas}, {"channels", channels}}).dump();
}

std::string api_check(const std::string& body, const ApiContext& ctx) {
  const json b = parse_request(body);
  const auto seed = std::uint64_t(integer_field(b, "seed", 1, 0, 2'147'483'647));
  const BxDF bxdf = load_material(b, ctx);
  check_work(bxdf, kValidationEvaluations, "check");
  check_gate().acquire(ctx, "validation");
  struct Release {
    ~Release() { check_gate().release(); }
  } release;
  // A newer validation of the same page (or the time limit, or the client leaving) stops
  // this one between properties (the signal, looked at before each) instead of after
  // seconds.
  const ValidationReport report = validate(bxdf, {seed, 1.0}, [&] { ctx.check_stop(); });
  // The object of `gonio check --json` (SPEC §3).
  json props = json::array();
  for (const auto& p : report.properties) {
    json q = {{"name", p.name}, {"figure", p.figure ? json(*p.figure) : json()}, {"threshold", p.threshold},
              {"pass", p.pass}};
    if (!p.applicable) {
      q["applicable"] = false;
      q["reason"] = p.detail;
    } else {
      q["detail"] = p.detail;
    }
    props.push_back(std::move(q));
  }
  return json({{"pass", report.pass()}, {"properties", props}, {"name", bxdf.name()}}).dump();
}

}  // namespace gonio::explore
