// Light sampling: quads by area, spheres by the cone they subtend, environment maps by a
// piecewise-constant distribution over their pixels (Pharr et al., PBR 4th ed., §12.5).

#include "gonio/render/lights.h"

#include "gonio/math/cdf_guide.h"
#include "gonio/spectrum/rgb_to_spectrum.h"

#include <algorithm>
#include <cmath>

namespace gonio::render {
namespace {

Float pixel_weight(const Color& c) {
  if constexpr (kColorChannels == 3) return Float(0.2126) * c[0] + Float(0.7152) * c[1] + Float(0.0722) * c[2];
  else return c.average();
}

// 1 − cos θmax of the cone subtended by a sphere of radius r at distance d > r, without
// the cancellation of 1 − sqrt(1 − s²) for small s² = r²/d².
Float one_minus_cos_cone(Float sin2) {
  return sin2 / (1 + std::sqrt(std::max(Float(0), 1 - sin2)));
}

}  // namespace

Environment::Environment(Image map, Float scale, Float rotation_deg)
    : map_(std::move(map)), scale_(scale), rotation_(rotation_deg * kPi / 180) {
  const int w = map_.width(), h = map_.height();
  row_cdf_.assign(static_cast<size_t>(h + 1), 0);
  col_cdf_.assign(static_cast<size_t>(h) * static_cast<size_t>(w + 1), 0);
  double total = 0, mean = 0, solid = 0;
  for (int y = 0; y < h; ++y) {
    // Pixels near the poles cover less solid angle: weight by sin θ of the row.
    const double sin_theta = std::sin(kPiD * (y + 0.5) / h);
    Float* col = &col_cdf_[static_cast<size_t>(y) * static_cast<size_t>(w + 1)];
    double row = 0;
    for (int x = 0; x < w; ++x) {
      row += std::max(0.0, static_cast<double>(pixel_weight(map_.at(x, y)))) * sin_theta;
      mean += static_cast<double>(map_.at(x, y).average()) * sin_theta;
      solid += sin_theta;
      col[x + 1] = static_cast<Float>(row);
    }
    for (int x = 1; x <= w; ++x) col[x] = row > 0 ? static_cast<Float>(col[x] / row) : Float(x) / Float(w);
    total += row;
    row_cdf_[static_cast<size_t>(y + 1)] = static_cast<Float>(total);
  }
  for (int y = 1; y <= h; ++y)
    row_cdf_[static_cast<size_t>(y)] = total > 0 ? static_cast<Float>(row_cdf_[static_cast<size_t>(y)] / total) : Float(y) / Float(h);
  // Mean of the sin-weighted luminance per pixel; pdf over (u, v) is weight / mean.
  total_ = static_cast<Float>(total / (static_cast<double>(w) * h));
  mean_ = solid > 0 ? static_cast<Float>(std::max(0.0, mean / solid) * static_cast<double>(scale_)) : Float(0);
}

// The centre column (u = 0.5) looks along −z, the default camera's view, and u grows
// towards +x, so that the map seen from inside is not mirrored; row 0 looks along +y.
Vec2 Environment::direction_to_uv(const Vec3& d) const {
  const Float theta = std::acos(std::clamp(d.y, Float(-1), Float(1)));
  Float u = Float(0.5) + (std::atan2(d.x, -d.z) + rotation_) * kInv2Pi;
  u -= std::floor(u);
  return {u, theta * kInvPi};
}

Vec3 Environment::uv_to_direction(Float u, Float v) const {
  const Float theta = v * kPi, phi = 2 * kPi * (u - Float(0.5)) - rotation_;
  const Float st = std::sin(theta);
  return {st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
}

Color Environment::radiance(const Vec3& dir) const {
  if (map_.width() == 0) return constant_;
  const Vec2 uv = direction_to_uv(dir);
  const int x = std::min(static_cast<int>(uv.x * Float(map_.width())), map_.width() - 1);
  const int y = std::min(static_cast<int>(uv.y * Float(map_.height())), map_.height() - 1);
  return map_.at(x, y) * scale_;
}

SampledSpectrum Environment::radiance(const Vec3& dir, const SampledWavelengths& w) const {
  if (map_.width() == 0) return emission_spectrum(constant_spectrum_, constant_, w);
  return rgb_illuminant(radiance(dir), w);
}

LightSample Environment::sample(Float u1, Float u2) const {
  LightSample s;
  s.distance = std::numeric_limits<Float>::infinity();
  if (map_.width() == 0) {
    s.wi = square_to_uniform_sphere(u1, u2);
    s.radiance = constant_;
    s.pdf = uniform_sphere_pdf();
    return s;
  }
  const int w = map_.width(), h = map_.height();
  const int y = cdf_interval(row_cdf_.data(), h, u1);
  const Float* col = &col_cdf_[static_cast<size_t>(y) * static_cast<size_t>(w + 1)];
  const int x = cdf_interval(col, w, u2);
  // Reuse the remainder of each uniform number for the position inside the pixel.
  const Float dy = row_cdf_[y + 1] - row_cdf_[y], dx = col[x + 1] - col[x];
  const Float fy = dy > 0 ? std::clamp((u1 - row_cdf_[y]) / dy, Float(0), kOneMinusEpsilon) : Float(0.5);
  const Float fx = dx > 0 ? std::clamp((u2 - col[x]) / dx, Float(0), kOneMinusEpsilon) : Float(0.5);
  s.wi = uv_to_direction((Float(x) + fx) / Float(w), (Float(y) + fy) / Float(h));
  s.radiance = map_.at(x, y) * scale_;
  s.pdf = pdf(s.wi);
  return s;
}

Float Environment::pdf(const Vec3& dir) const {
  if (map_.width() == 0) return uniform_sphere_pdf();
  if (!(total_ > 0)) return 0;
  const Vec2 uv = direction_to_uv(dir);
  const int w = map_.width(), h = map_.height();
  const int x = std::min(static_cast<int>(uv.x * Float(w)), w - 1);
  const int y = std::min(static_cast<int>(uv.y * Float(h)), h - 1);
  const Float sin_theta = std::sin(kPi * (Float(y) + Float(0.5)) / Float(h));
  const Float weight = std::max(Float(0), pixel_weight(map_.at(x, y))) * sin_theta;
  const Float sin_dir = std::sqrt(std::max(Float(0), 1 - dir.y * dir.y));
  if (!(sin_dir > 0)) return 0;
  // Density over (u, v) is weight / mean; dω = 2π² sin θ du dv.
  return weight / total_ / (2 * kPi * kPi * sin_dir);
}

LightSample sample_area_light(const AreaLight& light, const Vec3& p, Float u1, Float u2) {
  LightSample s;
  if (const auto* q = std::get_if<QuadLight>(&light)) {
    const Vec3 x = q->corner + q->edge1 * u1 + q->edge2 * u2;
    const Vec3 d = x - p;
    const Float dist2 = length_squared(d);
    if (!(dist2 > 0)) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d / s.distance;
    const Vec3 n = q->normal();
    const Float cos_l = std::abs(dot(n, s.wi));
    if (!(cos_l > 0)) return s;
    s.pdf = dist2 / (cos_l * q->area());
    s.radiance = area_light_radiance(light, n, -s.wi);
    return s;
  }
  const auto& sp = std::get<SphereLight>(light);
  const Vec3 to_center = sp.center - p;
  const Float d2 = length_squared(to_center);
  const Float r2 = sp.radius * sp.radius;
  if (d2 <= r2) return s;  // inside the emitter: it is not sampled from there
  const Float d = std::sqrt(d2);
  const Float sin2 = r2 / d2;
  const Float omc = one_minus_cos_cone(sin2);
  if (!(omc > 0)) return s;  // r²/d² underflowed: the sphere subtends no solid angle in float
  const Vec3 local = square_to_uniform_cone(u1, u2, 1 - omc);
  const Frame frame = Frame::from_normal(to_center / d);
  s.wi = normalize(frame.to_world(local));
  // Nearest intersection with the sphere along wi (it exists: wi lies in the cone).
  const Float b = dot(s.wi, to_center);
  const Float disc = std::max(Float(0), r2 - (d2 - b * b));
  s.distance = std::max(Float(0), b - std::sqrt(disc));
  s.pdf = 1 / (2 * kPi * omc);
  s.radiance = sp.radiance;
  return s;
}

Float area_light_pdf(const AreaLight& light, const Vec3& p, const Vec3& on_light,
                     const Vec3& n_light) {
  if (const auto* q = std::get_if<QuadLight>(&light)) {
    const Vec3 d = on_light - p;
    const Float dist2 = length_squared(d);
    const Float cos_l = std::abs(dot(n_light, d)) / std::sqrt(dist2);
    if (!(cos_l > 0) || !(dist2 > 0)) return 0;
    return dist2 / (cos_l * q->area());
  }
  const auto& sp = std::get<SphereLight>(light);
  const Float d2 = length_squared(sp.center - p);
  const Float r2 = sp.radius * sp.radius;
  if (d2 <= r2) return 0;
  const Float omc = one_minus_cos_cone(r2 / d2);
  return omc > 0 ? 1 / (2 * kPi * omc) : Float(0);
}

Color area_light_radiance(const AreaLight& light, const Vec3& n, const Vec3& w) {
  if (const auto* q = std::get_if<QuadLight>(&light))
    return (q->two_sided || dot(n, w) > 0) ? q->radiance : Color(0);
  return dot(n, w) > 0 ? std::get<SphereLight>(light).radiance : Color(0);
}

SampledSpectrum emission_spectrum(const std::optional<Spectrum>& spectrum, const Color& rgb, const SampledWavelengths& w) {
  return spectrum ? spectrum->eval(w) : rgb_illuminant(rgb, w);
}

SampledSpectrum area_light_spectrum(const AreaLight& light, const SampledWavelengths& w) {
  return std::visit([&](const auto& l) { return emission_spectrum(l.spectrum, l.radiance, w); }, light);
}

}  // namespace gonio::render
