#pragma once
// Helpers for renderer tests: render a scene given as JSON text, and compare images
// within their Monte Carlo noise.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "gonio/render/renderer.h"
#include "gonio/render/scene_loader.h"

namespace gonio::render::test {

inline Image render_text(const std::string& json, int threads = 0) {
  const Scene scene = parse_scene(json, "test scene", "");
  RenderOptions options;
  options.threads = threads;
  return render(scene, options);
}

// The form factor from a point to a rectangle 2a × 2b parallel to its plane at height h,
// centred above it (Howell, "A Catalog of Radiation Heat Transfer Configuration Factors",
// C-11, summed over the four corner rectangles a × b).
inline double centred_rectangle_form_factor(double a, double b, double h) {
  const double X = a / h, Y = b / h;
  return 4 / (2 * kPiD) *
         (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
          Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)));
}

// Mean of one channel over a block of pixels, in double.
inline double block_mean(const Image& img, int x0, int y0, int size, int channel) {
  double s = 0;
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) s += img.at(x, y)[channel];
  return s / (size * size);
}

}  // namespace gonio::render::test
