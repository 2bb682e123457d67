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

// Mean of one channel over a block of pixels, in double.
inline double block_mean(const Image& img, int x0, int y0, int size, int channel) {
  double s = 0;
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) s += img.at(x, y)[channel];
  return s / (size * size);
}

}  // namespace gonio::render::test
