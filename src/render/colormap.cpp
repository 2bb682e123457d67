// The colour maps of colormap.h: piecewise linear in sRGB code values between control
// points chosen for gonio (a luminance that rises with t for the sequential map; blue –
// white – red for the diverging one), then decoded to linear RGB.

#include "gonio/render/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "gonio/render/image.h"

namespace gonio::render {
namespace {

using Rgb = std::array<double, 3>;

template <size_t N>
Color piecewise(const std::array<Rgb, N>& points, double t) {
  if (!(t >= 0)) t = 0;  // NaN too
  t = std::min(t, 1.0);
  const double x = t * (N - 1);
  const size_t i = std::min(size_t(x), N - 2);
  const double w = x - double(i);
  const Rgb& a = points[i];
  const Rgb& b = points[i + 1];
  return from_srgb(a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), a[2] + w * (b[2] - a[2]));
}

constexpr std::array<Rgb, 5> kSequential = {{
    {0.05, 0.02, 0.15},  // near-black violet
    {0.35, 0.05, 0.45},  // purple
    {0.75, 0.15, 0.35},  // crimson
    {0.98, 0.50, 0.10},  // orange
    {0.99, 0.95, 0.60},  // pale yellow
}};
constexpr std::array<Rgb, 3> kDiverging = {{
    {0.23, 0.30, 0.75},  // blue: the other is smaller
    {0.95, 0.95, 0.95},  // no difference
    {0.70, 0.02, 0.15},  // red: the other is larger
}};

}  // namespace

Color from_srgb(double r, double g, double b) {
  return Color(srgb_decode(Float(r)), srgb_decode(Float(g)), srgb_decode(Float(b)));
}

Color sequential_colormap(double t) { return piecewise(kSequential, t); }

Color diverging_colormap(double t) { return piecewise(kDiverging, std::isnan(t) ? 0.5 : 0.5 * (t + 1)); }

}  // namespace gonio::render
