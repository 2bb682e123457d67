#include "gonio/spectrum/rgb_to_spectrum.h"

#include <algorithm>
#include <array>
#include <limits>
#include <cstdio>
#include <string>

#include "gonio/error.h"
#include "gonio/spectrum/data_tables.h"

namespace gonio {
namespace {

using rgb_table::kRes;

constexpr std::array<Float, kRes> make_z_nodes() {
  std::array<Float, kRes> z{};
  for (int k = 0; k < kRes; ++k) z[size_t(k)] = Float(rgb_table::z_node(k));
  return z;
}
constexpr std::array<Float, kRes> kZNodes = make_z_nodes();

Float sanitize(Float c) { return c >= 0 ? std::min(c, Float(1)) : Float(0); }  // NaN -> 0

void check_component(Float v, Float hi, const char* what) {
  if (!(v >= 0 && v <= hi)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s must have components in [0, %g], got %.9g", what, double(hi), double(v));
    throw InputError(buf);
  }
}

}  // namespace

SigmoidPolynomial rgb_to_sigmoid_polynomial(Float r, Float g, Float b) {
  const Float rgb[3] = {sanitize(r), sanitize(g), sanitize(b)};
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
    // Grey: a constant spectrum, σ(c2) = c.
    const Float c = rgb[0];
    if (c == 0) return {0, 0, -std::numeric_limits<Float>::infinity()};
    if (c == 1) return {0, 0, std::numeric_limits<Float>::infinity()};
    return {0, 0, (c - Float(0.5)) / std::sqrt(c * (1 - c))};
  }
  const int l = rgb[0] >= rgb[1] ? (rgb[0] >= rgb[2] ? 0 : 2) : (rgb[1] >= rgb[2] ? 1 : 2);
  const Float z = rgb[l];  // > 0: not grey
  const Float x = rgb[(l + 1) % 3] / z * (kRes - 1);
  const Float y = rgb[(l + 2) % 3] / z * (kRes - 1);
  const int xi = std::min(int(x), kRes - 2), yi = std::min(int(y), kRes - 2);
  const Float tx = x - Float(xi), ty = y - Float(yi);
  const int zi = std::clamp(int(std::upper_bound(kZNodes.begin(), kZNodes.end(), z) - kZNodes.begin()) - 1, 0, kRes - 2);
  const Float tz = std::clamp((z - kZNodes[size_t(zi)]) / (kZNodes[size_t(zi) + 1] - kZNodes[size_t(zi)]), Float(0), Float(1));
  const auto& t = spectral_data::kRgbCoefficients[l];
  Float c[3];
  for (int i = 0; i < 3; ++i) {
    auto lerp = [](Float a, Float b2, Float s) { return a + s * (b2 - a); };
    const Float c00 = lerp(t[zi][yi][xi][i], t[zi][yi][xi + 1][i], tx);
    const Float c01 = lerp(t[zi][yi + 1][xi][i], t[zi][yi + 1][xi + 1][i], tx);
    const Float c10 = lerp(t[zi + 1][yi][xi][i], t[zi + 1][yi][xi + 1][i], tx);
    const Float c11 = lerp(t[zi + 1][yi + 1][xi][i], t[zi + 1][yi + 1][xi + 1][i], tx);
    c[i] = lerp(lerp(c00, c01, ty), lerp(c10, c11, ty), tz);
  }
  return {c[0], c[1], c[2]};
}

RgbAlbedoSpectrum::RgbAlbedoSpectrum(Float r, Float g, Float b) {
  check_component(r, 1, "an RGB reflectance");
  check_component(g, 1, "an RGB reflectance");
  check_component(b, 1, "an RGB reflectance");
  poly_ = rgb_to_sigmoid_polynomial(r, g, b);
}

RgbIlluminantSpectrum::RgbIlluminantSpectrum(Float r, Float g, Float b) {
  check_component(r, kMaxComponent, "an RGB emission");
  check_component(g, kMaxComponent, "an RGB emission");
  check_component(b, kMaxComponent, "an RGB emission");
  set(r, g, b);
}

RgbIlluminantSpectrum RgbIlluminantSpectrum::clamped(const Color& rgb) {
  const auto clean = [](Float v) { return v > 0 ? std::min(v, kMaxComponent) : Float(0); };  // NaN -> 0
  RgbIlluminantSpectrum e;
  e.set(clean(rgb[0]), clean(rgb[1]), clean(rgb[2]));
  return e;
}

void RgbIlluminantSpectrum::set(Float r, Float g, Float b) {
  const Float m = 2 * std::max(r, std::max(g, b));
  scale_ = m;
  poly_ = m > 0 ? rgb_to_sigmoid_polynomial(r / m, g / m, b / m) : rgb_to_sigmoid_polynomial(0, 0, 0);
}

SampledSpectrum rgb_unbounded(const Color& rgb, const SampledWavelengths& w) {
  // The illuminant's scaled sigmoid without its D65 factor.
  const RgbIlluminantSpectrum e = RgbIlluminantSpectrum::clamped(rgb);
  return e.scale() * e.polynomial().eval(w);
}

SampledSpectrum rgb_illuminant(const Color& rgb, const SampledWavelengths& w) {
  return RgbIlluminantSpectrum::clamped(rgb).eval(w);
}

}  // namespace gonio
