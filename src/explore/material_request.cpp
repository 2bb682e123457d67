#include "explore/material_request.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <list>
#include <mutex>
#include <utility>
#include <string>

#include "gonio/error.h"
#include "gonio/bxdf/evaluation_cost.h"
#include "gonio/json_text.h"
#include "gonio/material.h"

namespace gonio::explore {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Keys whose string value the parser reads as a file name: a MERL table (`measured`), a
// CSV spectrum ({"spectrum": "file.csv"}) and, when it comes (SPEC §2), a MaterialX file.
bool is_file_key(const std::string& key) { return key == "file" || key == "spectrum" || key == "mtlx"; }

bool inside(const fs::path& path, const fs::path& dir) {
  auto p = path.begin();
  for (auto d = dir.begin(); d != dir.end(); ++d, ++p)
    if (p == path.end() || *p != *d) return false;
  return true;
}

std::string confined_path(const std::string& name, const std::string& key, const ApiContext& ctx) {
  const std::string what = key + " \"" + name + "\": ";
  if (ctx.data_dir.empty())
    throw InputError(what + "the explorer reads files only from a --data DIR, and none was given");
  const fs::path rel(name);
  bool dotdot = false;
  for (const auto& part : rel) dotdot |= part == "..";
  if (name.empty() || name.find('\0') != std::string::npos || rel.is_absolute() || dotdot)
    throw InputError(what + "name a file inside --data by a relative path without \"..\"");
  std::error_code ec;
  const fs::path full = fs::canonical(fs::path(ctx.data_dir) / rel, ec);
  if (ec) throw InputError(what + "no such file in --data");
  // A symlink inside --data that leads out of it is refused like a path that does.
  if (!inside(full, fs::path(ctx.data_dir))) throw InputError(what + "leads outside --data");
  if (!fs::is_regular_file(full, ec)) throw InputError(what + "not a regular file");
  return full.string();
}

void confine_files(json& v, const ApiContext& ctx) {
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (it->is_string() && is_file_key(it.key())) *it = confined_path(it->get<std::string>(), it.key(), ctx);
      else confine_files(*it, ctx);
    }
  } else if (v.is_array()) {
    for (auto& e : v) confine_files(e, ctx);
  }
}

}  // namespace

json parse_request(std::string_view body) {
  json b = parse_json_text(body, "request body");
  if (!b.is_object()) throw InputError("request body: expected a JSON object, got " + json_excerpt(b));
  return b;
}

std::optional<Float> request_wavelength(const json& body) {
  const auto it = body.find("wavelength");
  if (it == body.end() || it->is_null()) return std::nullopt;
  const double nm = it->is_number() ? it->get<double>() : NAN;
  if (!(nm >= double(kLambdaMin) && nm <= double(kLambdaMax)))
    throw InputError("wavelength must be a number of nanometres in [" + format_number(double(kLambdaMin)) + ", " +
                     format_number(double(kLambdaMax)) + "], got " + json_excerpt(*it));
  return Float(nm);
}

namespace {
std::string source_of(const char* key) { return std::string(key) == "bsdf" ? "--bsdf" : "--" + std::string(key); }
}  // namespace

json sanitized_material(const json& body, const ApiContext& ctx, const char* key) {
  const auto it = body.find(key);
  if (it == body.end() || it->is_null())
    throw InputError(std::string(key) + ": missing (the material, as in gonio eval --bsdf)");
  // Text is parsed as the CLI parses --bsdf, so that a syntax error reads the same.
  json m = it->is_string() ? parse_json_text(it->get<std::string>(), source_of(key)) : *it;
  confine_files(m, ctx);
  return m;
}

namespace {
// Materials that name files (a MERL table is 35 MB, read in ~0.2 s) are kept once made:
// the four most recently used, keyed by their JSON. A model holds its table by shared
// pointer, so a copy is cheap. A file changed on disk is read again only once its
// material has left the cache.
BxDF cached_material(const std::string& text, const std::string& source) {
  static std::mutex mutex;
  static std::list<std::pair<std::string, BxDF>> recent;
  const std::string key = source + "\n" + text;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = recent.begin(); it != recent.end(); ++it)
      if (it->first == key) {
        recent.splice(recent.begin(), recent, it);
        return it->second;
      }
  }
  BxDF made = parse_material(text, source);
  const std::lock_guard<std::mutex> lock(mutex);
  recent.emplace_front(key, made);
  if (recent.size() > 4) recent.pop_back();
  return made;
}
}  // namespace

BxDF load_material(const json& body, const ApiContext& ctx, const char* key) {
  const std::string text = sanitized_material(body, ctx, key).dump();
  if (text.find("\"file\"") != std::string::npos) return cached_material(text, source_of(key));
  return parse_material(text, source_of(key));
}

std::unique_ptr<MaterialAtWavelength> load_material_at_wavelength(const json& body, const ApiContext& ctx, Float nm) {
  auto m = std::make_unique<MaterialAtWavelength>();
  m->material = parse_material_with_spectra(sanitized_material(body, ctx).dump(), "--bsdf");
  m->wavelengths = SampledWavelengths::single(nm);
  m->bxdf = to_spectral(m->material.bxdf, m->material.spectra, m->wavelengths, m->scratch);
  return m;
}

long long integer_field(const json& body, const char* name, long long fallback, long long lo, long long hi) {
  const auto it = body.find(name);
  if (it == body.end() || it->is_null()) return fallback;
  if (!it->is_number_integer() && !(it->is_number_float() && std::floor(it->get<double>()) == it->get<double>()))
    throw InputError(std::string(name) + " must be an integer, got " + json_excerpt(*it));
  const double v = it->get<double>();
  if (!(v >= double(lo) && v <= double(hi)))
    throw InputError(std::string(name) + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got " + format_number(v));
  return static_cast<long long>(v);
}

namespace {
template <typename C>
void check_work_of(const BxDFT<C>& bxdf, double evaluations, std::string_view what) {
  const double cost = evaluation_cost(bxdf);
  const double work = cost * evaluations;
  if (work <= kMaxRequestWork) return;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                ": about %.2g evaluations of %.3g walk steps each (a layered material: 2 x samples x max_depth), "
                "%.2g steps, above the explorer's limit of %.2g per request",
                evaluations, cost, work, kMaxRequestWork);
  throw InputError(std::string(what) + buf + "; lower max_depth or samples, or ask for less");
}
}  // namespace

void check_work(const BxDF& bxdf, double evaluations, std::string_view what) {
  check_work_of(bxdf, evaluations, what);
}
void check_work(const SpectralBxDF& bxdf, double evaluations, std::string_view what) {
  check_work_of(bxdf, evaluations, what);
}

json example_material(std::string_view type) {
  static const json examples = json::parse(R"({
    "diffuse": {"type": "diffuse", "reflectance": [0.8, 0.5, 0.3]},
    "mirror": {"type": "mirror", "reflectance": 1},
    "conductor": {"type": "conductor", "material": "Au"},
    "dielectric": {"type": "dielectric", "eta": 1.5},
    "roughconductor": {"type": "roughconductor", "alpha": 0.2, "material": "Cu"},
    "roughdielectric": {"type": "roughdielectric", "alpha": 0.2, "eta": 1.5},
    "orennayar": {"type": "orennayar", "reflectance": 0.6, "sigma": 20},
    "phong": {"type": "phong", "kd": 0.3, "ks": 0.4, "exponent": 30},
    "blinnphong": {"type": "blinnphong", "kd": 0.3, "ks": 0.4, "exponent": 30},
    "ward": {"type": "ward", "kd": 0.3, "ks": 0.2, "alpha": [0.1, 0.3]},
    "ashikhminshirley": {"type": "ashikhminshirley", "rd": 0.3, "rs": 0.2, "nu": 100, "nv": 20},
    "plastic": {"type": "plastic", "eta": 1.5, "reflectance": [0.6, 0.1, 0.1]},
    "blend": {"type": "blend", "weight": 0.3, "bsdfs": [{"type": "diffuse", "reflectance": 0.7},
              {"type": "roughconductor", "alpha": 0.15, "material": "Au"}]},
    "measured": {"type": "measured", "file": "material.binary"},
    "subsurface": {"type": "subsurface", "medium": "marble"},
    "eon": {"type": "eon", "reflectance": 0.8, "roughness": 0.5},
    "sheen": {"type": "sheen", "color": [0.9, 0.6, 0.6], "roughness": 0.4},
    "thindielectric": {"type": "thindielectric", "eta": 1.5},
    "layered": {"type": "layered", "top": {"type": "roughdielectric", "alpha": 0.1, "eta": 1.5},
                "bottom": {"type": "diffuse", "reflectance": [0.7, 0.2, 0.1]}},
    "gltf_pbr": {"type": "gltf_pbr", "base_color": [0.8, 0.3, 0.1], "metallic": 0, "roughness": 0.4,
                 "clearcoat": 0.5, "clearcoat_roughness": 0.1},
    "rgl": {"type": "rgl", "file": "material.bsdf"},
    "oren_nayar_diffuse_bsdf": {"type": "oren_nayar_diffuse_bsdf", "color": [0.7, 0.4, 0.2], "roughness": 0.3},
    "conductor_bsdf": {"type": "conductor_bsdf", "roughness": 0.2},
    "dielectric_bsdf": {"type": "dielectric_bsdf", "roughness": 0.1, "scatter_mode": "RT"},
    "sheen_bsdf": {"type": "sheen_bsdf", "color": [0.9, 0.6, 0.6], "roughness": 0.4},
    "mix": {"type": "mix", "mix": 0.3, "fg": {"type": "conductor_bsdf", "roughness": 0.2},
            "bg": {"type": "oren_nayar_diffuse_bsdf", "color": 0.6}},
    "add": {"type": "add", "in1": {"type": "sheen_bsdf", "color": 0.3},
            "in2": {"type": "oren_nayar_diffuse_bsdf", "color": 0.5}},
    "multiply": {"type": "multiply", "in1": {"type": "oren_nayar_diffuse_bsdf", "color": 0.8}, "in2": [1, 0.5, 0.2]},
    "layer": {"type": "layer", "top": {"type": "dielectric_bsdf", "roughness": 0.1},
              "base": {"type": "oren_nayar_diffuse_bsdf", "color": [0.7, 0.2, 0.1]}},
    "hair": {"type": "hair", "eumelanin": 0.4, "pheomelanin": 0.3},
    "chiang_hair_bsdf": {"type": "chiang_hair_bsdf", "absorption_coefficient": [0.2, 0.4, 0.8]}
  })");
  const auto it = examples.find(std::string(type));
  return it != examples.end() ? *it : json{{"type", std::string(type)}};
}

}  // namespace gonio::explore
