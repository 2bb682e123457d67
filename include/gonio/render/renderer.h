#pragma once
// Renders a whole image: tiles in parallel on oneTBB, one independent random stream per
// pixel and sample index (seeded from the seed, the pixel and the index alone), so that
// the image depends on the seed only, not on the thread count or on which thread rendered
// which tile, and so that any range of sample indices can be rendered on its own (a pass
// of a distributed render, docs/distributed.md) with exactly the samples a whole render
// takes for those indices.
//
// The samples are taken in passes over the whole image, each adding the same number of
// samples to every pixel. A render asked to stop (options.stop) drops the pass in progress
// and returns the passes completed: every pixel then holds the same number n of samples,
// the very image a render with spp = n gives, bit for bit.

#include <array>
#include <atomic>
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
  // When it becomes true (a signal handler may set it), the render stops at the next tile.
  const std::atomic<bool>* stop = nullptr;
  // The per-pixel sample indices [sample_begin, sample_end) to take; sample_end < 0: the
  // scene's spp. A range [0, n) is the whole render at spp n.
  int sample_begin = 0;
  int sample_end = -1;
  // Return the per-pixel sums of the samples (in float, added in index order) instead of
  // their mean: passes' sums add up exactly in double (docs/distributed.md).
  bool sums = false;
};

struct RenderStats {
  double seconds = 0;        // rendering, after the scene was built
  double setup_seconds = 0;  // building the acceleration structure
  std::uint64_t samples = 0; // camera samples in the image returned
  std::uint64_t rays = 0;    // closest-hit and shadow rays, the dropped pass's included
  // Subsurface scattering (PathStats): random walks and their steps, diffusion exits.
  std::uint64_t walks = 0, walk_steps = 0, probe_exits = 0;
  int spp = 0;               // samples per pixel of the image returned (0: stopped before any)
                             // (with a sample range: how many of the range's indices)
  bool stopped = false;      // true when `stop` cut the render short of the scene's spp
};

// A polarized render's Stokes images S0..S3 (linear RGB each; S1..S3 may be negative), in
// the image's frame: Q = S1 = I_x − I_y, x to the right, y up (SPEC §1).
using StokesImages = std::array<Image, 4>;

// The image at the scene's spp, or, when stopped, at stats->spp samples per pixel (all
// black when no pass completed). With scene.settings.polarized it is S0, the intensity
// through the camera's polarizer, and `stokes` (when given) receives all four components;
// without, `stokes` receives the image and three empty ones.
Image render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr,
             StokesImages* stokes = nullptr);

}  // namespace gonio::render
