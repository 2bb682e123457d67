// /api/sphere: a sphere of the material rendered by gonio's renderer (render/renderer.h)
// under a point light and a uniform environment, as a pass of a few samples per pixel; the
// page averages successive passes (different seeds) into a progressively refined image.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "explore/material_request.h"
#include "gonio/error.h"
#include "gonio/json_text.h"
#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"

namespace gonio::explore {

namespace {

std::string base64(const unsigned char* data, size_t n) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (size_t i = 0; i < n; i += 3) {
    const std::uint32_t v = std::uint32_t(data[i]) << 16 | (i + 1 < n ? std::uint32_t(data[i + 1]) << 8 : 0) |
                            (i + 2 < n ? std::uint32_t(data[i + 2]) : 0);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < n ? k[(v >> 6) & 63] : '=';
    out += i + 2 < n ? k[v & 63] : '=';
  }
  return out;
}

double number_in(const nlohmann::json& b, const char* name, double fallback, double lo, double hi) {
  const auto it = b.find(name);
  if (it == b.end() || it->is_null()) return fallback;
  const double v = it->is_number() ? it->get<double>() : NAN;
  if (!(v >= lo && v <= hi))
    throw InputError(std::string(name) + " must be a number in [" + format_number(lo) + ", " + format_number(hi) +
                     "], got " + json_excerpt(*it));
  return v;
}

// The "studio" environment: a lat-long map (lights.h: row 0 straight up, +y) made here, no
// file: a sky from a bluish zenith to a pale horizon, a dark warm ground, and two bright
// rectangular soft boxes above the horizon, so that a glossy sphere shows sharp-edged
// highlights and a rough one their blur. `scale` multiplies it (the page's environment
// slider). Its mean radiance over the sphere of directions is about 1 at scale 1.
render::Image studio_map() {
  constexpr int kW = 128, kH = 64;
  render::Image map(kW, kH);
  for (int y = 0; y < kH; ++y) {
    const double v = (y + 0.5) / kH;  // 0 up, 0.5 horizon, 1 down
    const double up = std::cos(v * 3.14159265358979);
    for (int x = 0; x < kW; ++x) {
      const double u = (x + 0.5) / kW;
      Color c;
      if (up > 0) {
        const double t = std::sqrt(up);  // 0 at the horizon, 1 at the zenith
        c = Color(Float(1.0 - 0.5 * t), Float(1.0 - 0.3 * t), Float(1.0));
      } else {
        c = Color(0.25f, 0.2f, 0.15f);
      }
      const bool box1 = u > 0.20 && u < 0.30 && v > 0.18 && v < 0.36;
      const bool box2 = u > 0.62 && u < 0.67 && v > 0.25 && v < 0.45;
      if (box1 || box2) c = Color(6.0f);
      map.at(x, y) = c;
    }
  }
  return map;
}

}  // namespace

std::string api_sphere(const std::string& body, const ApiContext& ctx) {
  using nlohmann::json;
  const json b = parse_request(body);
  // Integers, as every endpoint's counts (a size of 16.5 is refused, not taken as 16).
  const int size = int(integer_field(b, "size", 128, 16, kMaxSphereSize));
  const int spp = int(integer_field(b, "spp", 1, 1, kMaxSphereSpp));
  const auto seed = std::int64_t(integer_field(b, "seed", 0, 0, 2'147'483'647));
  // The light's direction from the sphere's centre, in the camera's frame: x right, y up,
  // z towards the camera; 5 radii away. Its intensity makes the irradiance at the sphere's
  // nearest point about π, so that a white Lambertian sphere faces it at radiance ~1.
  const double lx = number_in(b, "light_x", 0.5, -1, 1), ly = number_in(b, "light_y", 0.5, -1, 1);
  const double lz = std::sqrt(std::max(0.0, 1 - lx * lx - ly * ly));
  const double env = number_in(b, "environment", 0.1, 0, 10);
  // "uniform" (radiance `environment` from everywhere) or "studio" (studio_map × environment).
  std::string env_map = "uniform";
  if (const auto it = b.find("environment_map"); it != b.end() && !it->is_null()) {
    if (!it->is_string() || (*it != "uniform" && *it != "studio"))
      throw InputError("environment_map must be \"uniform\" or \"studio\", got " + json_excerpt(*it));
    env_map = it->get<std::string>();
  }
  // Spectral mode: gonio render's spectral path tracer (wavelengths sampled per path, the
  // image still RGB), as `gonio render` with "spectral": true.
  bool spectral = false;
  if (const auto it = b.find("spectral"); it != b.end() && !it->is_null()) {
    if (!it->is_boolean()) throw InputError("spectral must be true or false, got " + json_excerpt(*it));
    spectral = it->get<bool>();
  }
  const json material = sanitized_material(b, ctx);
  const json scene = {
      {"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 30}, {"width", size}, {"height", size}}},
      {"render", {{"spp", spp}, {"seed", seed}, {"max_depth", 8}, {"spectral", spectral}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", material}}}},
      {"lights", {{{"type", "point"}, {"position", {5 * lx, 5 * ly, 5 * lz}}, {"intensity", 16 * 3.14159265358979}}}},
      {"environment", {{"radiance", env}}},
  };
  render::Scene s = render::parse_scene(scene.dump(), "--bsdf", "");
  // A path of up to max_depth 8 vertices evaluates and samples the material at each.
  check_work(load_material(b, ctx), double(size) * double(size) * double(spp) * 16, "sphere");
  if (env_map == "studio") s.environment = render::Environment(studio_map(), Float(env), 0);
  render::RenderOptions o;
  o.threads = 1;  // one core per request: the other views stay live
  // A newer pass of the same page (the time limit, the client leaving) stops this one
  // between tiles.
  o.stop = ctx.stop ? &ctx.stop->stop : nullptr;
  render::RenderStats stats;
  const render::Image img = render::render(s, o, &stats);
  if (stats.stopped) {
    ctx.check_stop();
    throw Stopped(StopReason::Superseded);
  }
  std::string bytes(size_t(img.width()) * size_t(img.height()) * 3 * sizeof(float), '\0');
  size_t at = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = float(img.at(x, y)[c]);
        std::memcpy(&bytes[at], &v, sizeof v);
        at += sizeof v;
      }
  return json({{"width", img.width()},
               {"height", img.height()},
               {"spp", spp},
               {"seed", seed},
               {"encoding", "float32 little-endian RGB, row 0 at the top, base64"},
               {"pixels", base64(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size())}})
      .dump();
}

}  // namespace gonio::explore
