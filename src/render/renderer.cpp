// Tile-parallel rendering with oneTBB.

#include "gonio/render/renderer.h"

#include <atomic>
#include <chrono>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "gonio/render/accel.h"
#include "gonio/render/path_tracer.h"

namespace gonio::render {
namespace {

constexpr int kTile = 16;

// SplitMix64 finaliser (Steele, Lea & Flood 2014): decorrelates the per-pixel seeds.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

Image render(const Scene& scene_in, const RenderOptions& options, RenderStats* stats) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  Scene scene = scene_in;  // the camera basis is prepared on a copy
  scene.camera.prepare();
  const int w = scene.camera.width, h = scene.camera.height, spp = scene.settings.spp;

  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  Image image(w, h);
  std::atomic<std::uint64_t> rays{0};
  std::atomic<int> tiles_done{0};
  std::mutex progress_mutex;
  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  double setup = 0;
  arena.execute([&] {
    // Embree builds its BVH with TBB too; inside the arena it uses the same threads.
    const Accel accel(scene);
    setup = std::chrono::duration<double>(clock::now() - t0).count();
    const PathTracer tracer(scene, accel);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& range) {
      PathStats local;
      for (int tile = range.begin(); tile != range.end(); ++tile) {
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        for (int y = y0; y < std::min(y0 + kTile, h); ++y) {
          for (int x = x0; x < std::min(x0 + kTile, w); ++x) {
            const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
            Pcg32 rng(mix(scene.settings.seed ^ mix(pixel)), pixel);
            Color sum(0);
            for (int i = 0; i < spp; ++i) {
              const Float jx = rng.next_float(), jy = rng.next_float();
              const Ray ray = scene.camera.generate(Float(x) + jx, Float(y) + jy);
              sum += tracer.radiance(ray, rng, local);
            }
            image.at(x, y) = sum / Float(spp);
          }
        }
        const int done = tiles_done.fetch_add(1) + 1;
        if (options.progress) {
          std::lock_guard lock(progress_mutex);
          options.progress(double(done) / tiles);
        }
      }
      rays += local.rays;
    });
  });
  if (stats) {
    stats->setup_seconds = setup;
    stats->seconds = std::chrono::duration<double>(clock::now() - t0).count() - setup;
    stats->samples = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * static_cast<std::uint64_t>(spp);
    stats->rays = rays.load();
  }
  return image;
}

}  // namespace gonio::render
