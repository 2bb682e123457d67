#pragma once
// Renders a whole image: tiles in parallel on oneTBB, one independent random stream per
// pixel, so that the image depends on the seed only, not on the thread count or on which
// thread rendered which tile.

#include <cstdint>
#include <functional>

#include "gonio/render/image.h"
#include "gonio/render/scene.h"

namespace gonio::render {

struct RenderOptions {
  int threads = 0;  // 0: all hardware threads
  // Called now and then with the fraction done, from whichever thread finished a tile
  // (never concurrently).
  std::function<void(double)> progress;
};

struct RenderStats {
  double seconds = 0;        // rendering, after the scene was built
  double setup_seconds = 0;  // building the acceleration structure
  std::uint64_t samples = 0; // camera samples
  std::uint64_t rays = 0;    // closest-hit and shadow rays
};

Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

}  // namespace gonio::render
