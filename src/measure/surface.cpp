// parse_surface (surface.h): the surface descriptions of SPEC §3 `gonio measure`.
#include "gonio/measure/surface.h"

#include <cmath>
#include <filesystem>
#include <utility>
#include <string>

#include <nlohmann/json.hpp>

#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/material.h"
#include "gonio/measure/gaussian_surface.h"
#include "gonio/measure/profiles.h"

namespace gonio::measure {
namespace {

using nlohmann::json;

// Error messages show values as json_excerpt does (json_text.h).
std::string show(const json& v) { return json_excerpt(v); }

// The fields of one surface type: read by name, each read marked, the rest refused.
class Fields {
 public:
  Fields(const json& obj, std::string type, std::vector<std::string> keys)
      : obj_(obj), type_(std::move(type)), keys_(std::move(keys)) {
    for (const auto& [key, value] : obj_.items()) {
      if (key == "type") continue;
      bool known = false;
      for (const auto& k : keys_) known = known || k == key;
      if (!known) fail("unknown field '" + key + "'; " + type_ + " takes " + key_list());
    }
  }

  [[noreturn]] void fail(const std::string& what) const { throw InputError(type_ + ": " + what); }

  bool has(const char* key) const { return obj_.contains(key); }

  const json& get(const char* key) const {
    const auto it = obj_.find(key);
    if (it == obj_.end()) fail(std::string("missing field '") + key + "'");
    return *it;
  }

  // A finite number in [lo, hi] (an open end when lo_open / hi_open); `range` shows it.
  double number(const char* key, const json& v, double lo, bool lo_open, double hi, bool hi_open) const {
    if (!v.is_number()) fail(std::string(key) + " must be a number, got " + show(v));
    const double d = v.get<double>();
    const bool ok = std::isfinite(d) && (lo_open ? d > lo : d >= lo) && (hi_open ? d < hi : d <= hi);
    if (!ok)
      fail(std::string(key) + " must be in " + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
           (hi_open ? ")" : "]") + ", got " + format_number(d));
    return d;
  }
  double number(const char* key, double fallback, double lo, bool lo_open, double hi, bool hi_open) const {
    return has(key) ? number(key, get(key), lo, lo_open, hi, hi_open) : fallback;
  }

  // An integer in [lo, hi] (a number with an integral value, 512.0 included).
  long long integer(const char* key, long long fallback, long long lo, long long hi) const {
    if (!has(key)) return fallback;
    const json& v = get(key);
    if (!v.is_number()) fail(std::string(key) + " must be an integer, got " + show(v));
    const double d = v.get<double>();
    if (!(std::isfinite(d) && d == std::floor(d)))
      fail(std::string(key) + " must be an integer, got " + show(v));
    if (!(d >= double(lo) && d <= double(hi)))
      fail(std::string(key) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + show(v));
    return static_cast<long long>(d);
  }

  std::string text(const char* key) const {
    const json& v = get(key);
    if (!v.is_string()) fail(std::string(key) + " must be a string, got " + show(v));
    return v.get<std::string>();
  }

  std::string key_list() const {
    std::string s;
    for (std::size_t i = 0; i < keys_.size(); ++i) s += (i ? ", " : "") + keys_[i];
    return s;
  }

 private:
  const json& obj_;
  std::string type_;
  std::vector<std::string> keys_;
};

// Any side length: the instrument works in float, so keep heights far from its limits.
constexpr double kMaxSize = 1e6;

double read_size(const Fields& f) { return f.number("size", 1.0, 0, true, kMaxSize, false); }

HeightField parse_gaussian(const Fields& f) {
  GaussianSurfaceParams p;
  const json& a = f.get("alpha");
  if (a.is_array() && a.size() == 2) {
    p.alpha_x = f.number("alpha", a[0], 0, true, 2, false);
    p.alpha_y = f.number("alpha", a[1], 0, true, 2, false);
  } else if (a.is_number()) {
    p.alpha_x = p.alpha_y = f.number("alpha", a, 0, true, 2, false);
  } else {
    f.fail("alpha must be a number or [alpha_x, alpha_y], got " + show(a));
  }
  p.resolution = static_cast<int>(f.integer("resolution", 512, GaussianSurfaceParams::kMinResolution,
                                             GaussianSurfaceParams::kMaxResolution));
  const double lo = GaussianSurfaceParams::kMinCorrelationCells / p.resolution;
  if (f.has("correlation")) {
    const json& c = f.get("correlation");
    if (!c.is_number()) f.fail("correlation must be a number, got " + show(c));
    const double d = c.get<double>();
    if (!(std::isfinite(d) && d >= lo && d <= GaussianSurfaceParams::kMaxCorrelation))
      f.fail("correlation must be in [" + format_number(lo) + ", " +
             format_number(GaussianSurfaceParams::kMaxCorrelation) + "] (at least " +
             format_number(GaussianSurfaceParams::kMinCorrelationCells) + " grid cells at resolution " +
             std::to_string(p.resolution) + "), got " + format_number(d));
    p.correlation = d;
  } else {
    p.correlation = default_gaussian_correlation(p.resolution, p.alpha_x, p.alpha_y);
  }
  // An anisotropic surface stretches ℓ along the smoother axis and shrinks it along the
  // other: both must stay resolved and within the patch.
  const CorrelationLengths cl = nominal_correlation_lengths(p);
  for (const auto& [axis, l] : {std::pair{"x", cl.x}, std::pair{"y", cl.y}})
    if (!(l * p.resolution >= GaussianSurfaceParams::kMinCorrelationCells &&
          l <= GaussianSurfaceParams::kMaxCorrelation))
      f.fail("alpha [" + format_number(p.alpha_x) + ", " + format_number(p.alpha_y) +
             "] makes the correlation length along " + axis + " " + format_number(l) + " (" +
             format_number(l * p.resolution) + " grid cells); it must be in [" +
             format_number(GaussianSurfaceParams::kMinCorrelationCells / p.resolution) + ", " +
             format_number(GaussianSurfaceParams::kMaxCorrelation) +
             "]: change correlation or resolution, or lower the anisotropy");
  p.size = read_size(f);
  p.seed = static_cast<std::uint64_t>(f.integer("seed", 1, 0, (1LL << 53)));
  return gaussian_height_field(p);
}

HeightField parse_vgroove(const Fields& f) {
  const double angle = f.number("angle", f.get("angle"), 0, true, 90, true);
  const int grooves = static_cast<int>(f.integer("grooves", 16, 1, kMaxGrooves));
  return vgroove_height_field(angle, grooves, read_size(f));
}

HeightField parse_image(const Fields& f, const std::string& base_dir) {
  const std::string file = f.text("file");
  if (file.empty()) f.fail("file must not be empty");
  const double height = f.number("height", f.get("height"), 0, false, 1e3, false);
  const double size = read_size(f);
  std::filesystem::path path(file);
  if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
  try {
    return image_height_field(path.string(), height, size);
  } catch (const InputError& e) {
    f.fail(e.what());  // "<path>: <problem>", under the type's prefix
  }
}

}  // namespace

Surface parse_surface(std::string_view json_text, std::string_view source, const std::string& base_dir) {
  const json j = parse_json_text(json_text, source);
  if (!j.is_object()) throw InputError("surface must be a JSON object, got " + show(j));
  const auto t = j.find("type");
  if (t == j.end()) throw InputError("surface: missing field 'type'");
  if (!t->is_string()) throw InputError("surface: type must be a string, got " + show(*t));
  const std::string type = t->get<std::string>();

  std::vector<std::string> keys;
  if (type == "flat") keys = {};
  else if (type == "gaussian") keys = {"alpha", "correlation", "resolution", "seed"};
  else if (type == "vgroove") keys = {"angle", "grooves"};
  else if (type == "image") keys = {"file", "height"};
  else throw InputError("surface: unknown type \"" + type + "\" (known: flat, gaussian, vgroove, image)");
  keys.push_back("size");
  keys.push_back("material");
  const Fields f(j, type, std::move(keys));  // refuses unknown fields

  Surface s;
  s.type = type;
  // The material first: it is quick, and its errors should not wait for a synthesis.
  s.material = material_from_json(f.get("material"), type + ": material", base_dir);
  if (type == "flat") s.field = flat_height_field(read_size(f));
  else if (type == "gaussian") s.field = parse_gaussian(f);
  else if (type == "vgroove") s.field = parse_vgroove(f);
  else s.field = parse_image(f, base_dir);
  return s;
}

}  // namespace gonio::measure
