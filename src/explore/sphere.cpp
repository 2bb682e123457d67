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

}  // namespace

std::string api_sphere(const std::string& body, const ApiContext& ctx) {
  using nlohmann::json;
  const json b = parse_request(body);
  const int size = int(number_in(b, "size", 128, 16, kMaxSphereSize));
  const int spp = int(number_in(b, "spp", 1, 1, kMaxSphereSpp));
  const auto seed = std::int64_t(number_in(b, "seed", 0, 0, 2'147'483'647));
  // The light's direction from the sphere's centre, in the camera's frame: x right, y up,
  // z towards the camera; 5 radii away. Its intensity makes the irradiance at the sphere's
  // nearest point about π, so that a white Lambertian sphere faces it at radiance ~1.
  const double lx = number_in(b, "light_x", 0.5, -1, 1), ly = number_in(b, "light_y", 0.5, -1, 1);
  const double lz = std::sqrt(std::max(0.0, 1 - lx * lx - ly * ly));
  const double env = number_in(b, "environment", 0.1, 0, 10);
  const json material = sanitized_material(b, ctx);
  const json scene = {
      {"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 30}, {"width", size}, {"height", size}}},
      {"render", {{"spp", spp}, {"seed", seed}, {"max_depth", 8}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", material}}}},
      {"lights", {{{"type", "point"}, {"position", {5 * lx, 5 * ly, 5 * lz}}, {"intensity", 16 * 3.14159265358979}}}},
      {"environment", {{"radiance", env}}},
  };
  const render::Scene s = render::parse_scene(scene.dump(), "--bsdf", "");
  render::RenderOptions o;
  o.threads = 1;  // one core per request: the other views stay live
  o.stop = ctx.stale.get();  // a newer pass of the same page stops this one between tiles
  render::RenderStats stats;
  const render::Image img = render::render(s, o, &stats);
  if (stats.stopped) throw Superseded();
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
