// Degree and angle of linear polarization of a polarized render (stokes_image.h).

#include "gonio/render/stokes_image.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gonio/render/colormap.h"

namespace gonio::render {

LinearPolarization linear_polarization(const StokesImages& s, int x, int y) {
  const double s0 = luminance(s[0].at(x, y)), s1 = luminance(s[1].at(x, y)), s2 = luminance(s[2].at(x, y));
  LinearPolarization p;
  if (!(s0 > 0)) return p;
  const double lin = std::hypot(s1, s2);
  p.dolp = std::clamp(lin / s0, 0.0, 1.0);
  if (lin > 0) {
    double a = 0.5 * std::atan2(s2, s1) * 180 / std::numbers::pi;  // (−90°, 90°]
    if (a < 0) a += 180;
    p.aolp_deg = a >= 180 ? 0 : a;
  }
  return p;
}

Image dop_image(const StokesImages& s) {
  const int w = s[0].width(), h = s[0].height();
  Image out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const LinearPolarization p = linear_polarization(s, x, y);
      // HSV with S = 1, V = DoLP, H = AoLP over the whole hue circle (0–180° → 0–360°).
      const double hue6 = p.aolp_deg / 30;  // [0, 6)
      const int sector = std::min(static_cast<int>(hue6), 5);
      const double f = hue6 - sector, v = p.dolp;
      const double rise = v * f, fall = v * (1 - f);
      double r = 0, g = 0, b = 0;
      switch (sector) {
        case 0: r = v, g = rise; break;
        case 1: r = fall, g = v; break;
        case 2: g = v, b = rise; break;
        case 3: g = fall, b = v; break;
        case 4: r = rise, b = v; break;
        default: r = v, b = fall; break;
      }
      out.at(x, y) = from_srgb(r, g, b);
    }
  return out;
}

}  // namespace gonio::render
