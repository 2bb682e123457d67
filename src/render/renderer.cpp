// Tile-parallel rendering with oneTBB, in passes that can be stopped between tiles.

#include "gonio/render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "gonio/render/accel.h"
#include "gonio/render/path_tracer.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/color_space.h"

namespace gonio::render {
namespace {

constexpr int kTile = 16;
// A pass takes at least this many camera samples (several per pixel for small images),
// so that the cost of starting a parallel loop stays small against the work in it.
constexpr std::int64_t kSamplesPerPass = 1 << 16;

}  // namespace

Image render(const Scene& scene_in, const RenderOptions& options, RenderStats* stats, StokesImages* stokes) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  Scene scene = scene_in;  // the camera basis is prepared on a copy
  scene.camera.prepare();
  const int w = scene.camera.width, h = scene.camera.height;
  // The sample indices [begin, end) of every pixel; `spp` of them.
  const int begin = std::max(options.sample_begin, 0);
  const int end = options.sample_end < 0 ? scene.settings.spp : std::max(options.sample_end, begin);
  const int spp = end - begin;
  const size_t pixels = size_t(w) * size_t(h);
  const bool spectral = scene.settings.spectral, polarized = scene.settings.polarized;
  // Colours summed per pixel: the radiance, or the four Stokes components.
  const size_t K = polarized ? 4 : 1;
  // Acquire: what the stopper wrote before setting the flag (a signal number, say) is
  // visible to the caller once render() returns.
  const auto stop_requested = [&] { return options.stop && options.stop->load(std::memory_order_acquire); };

  // Per pixel: its sum of samples after the last completed pass (`sums`) and during the
  // current one (`next`). The samples are added one by one in the same order as in a
  // single pass, so the image does not depend on how the samples are split into passes.
  std::vector<Color> sums(pixels * K, Color(0)), next(pixels * K);
  const int per_pass = static_cast<int>(std::clamp<std::int64_t>(
      (kSamplesPerPass + std::int64_t(pixels) - 1) / std::int64_t(std::max<size_t>(pixels, 1)), 1, std::max(spp, 1)));

  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  std::atomic<std::uint64_t> rays{0}, samples_done{0}, walks{0}, walk_steps{0}, probe_exits{0};
  std::mutex progress_mutex;
  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  const double samples_total = double(pixels) * spp;
  double setup = 0;
  int completed = 0;  // samples per pixel in `sums`
  arena.execute([&] {
    // Embree builds its BVH with TBB too; inside the arena it uses the same threads.
    const Accel accel(scene);
    setup = std::chrono::duration<double>(clock::now() - t0).count();
    const PathTracer tracer(scene, accel);
    // The Z-order layout is fixed by the whole render's count (and any larger index asked
    // for), so that a range of indices is the same samples as in the whole render.
    const PixelSampler sampler_prototype(scene.settings.sampler, std::max(scene.settings.spp, end), scene.settings.seed);
    for (int first = 0; first < spp && !stop_requested(); first += per_pass) {
      const int last = std::min(spp, first + per_pass);  // offsets in the range [begin, end)
      std::atomic<bool> dropped{false};
      tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& range) {
        PathStats local;
        PixelSampler sampler = sampler_prototype;
        thread_local SpectralScratch scratch;  // blends' parts, per thread (spectral_material.h)
        for (int tile = range.begin(); tile != range.end(); ++tile) {
          if (stop_requested()) {
            dropped.store(true, std::memory_order_relaxed);
            break;
          }
          const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
          const int x1 = std::min(x0 + kTile, w), y1 = std::min(y0 + kTile, h);
          for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
              const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
              std::array<Color, 4> sum;
              for (size_t k = 0; k < K; ++k) sum[k] = sums[pixel * K + k];
              for (int i = first; i < last; ++i) {
                // Sample index begin + i is a function of (seed, pixel, index) alone, so
                // that it is the same sample whichever range it is rendered in.
                sampler.start(x, y, static_cast<std::uint64_t>(begin + i));
                const auto [jx, jy] = sampler.get2d(dims::kPixel);
                const Ray ray = scene.camera.generate(Float(x) + jx, Float(y) + jy);
                if (polarized && spectral) {
                  SampledWavelengths wl = SampledWavelengths::sample_response(sampler.get1d(dims::kWavelength));
                  const auto S = tracer.stokes(ray, wl, sampler, local, scratch);
                  for (size_t k = 0; k < 4; ++k) sum[k] += xyz_to_linear_srgb(to_xyz(S[k], wl));
                } else if (polarized) {
                  const auto S = tracer.stokes(ray, sampler, local);
                  for (size_t k = 0; k < 4; ++k) sum[k] += S[k];
                } else if (spectral) {
                  // Hero-wavelength sampling (Wilkie et al. 2014): 4 wavelengths per path,
                  // to CIE XYZ at the film (each divided by its own density), then to
                  // linear sRGB, so that the image is what RGB mode writes.
                  SampledWavelengths wl = SampledWavelengths::sample_response(sampler.get1d(dims::kWavelength));
                  const SampledSpectrum L = tracer.radiance(ray, wl, sampler, local, scratch);
                  sum[0] += xyz_to_linear_srgb(to_xyz(L, wl));
                } else {
                  sum[0] += tracer.radiance(ray, sampler, local);
                }
              }
              for (size_t k = 0; k < K; ++k) next[pixel * K + k] = sum[k];
            }
          }
          const std::uint64_t done = samples_done.fetch_add(std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0) * std::uint64_t(last - first)) +
                                     std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0) * std::uint64_t(last - first);
          if (options.progress) {
            std::lock_guard lock(progress_mutex);
            options.progress(double(done) / samples_total);
          }
        }
        rays += local.rays;
        walks += local.walks;
        walk_steps += local.walk_steps;
        probe_exits += local.probe_exits;
      });
      // A pass cut short leaves some pixels with more samples than others: drop it.
      if (dropped.load()) break;
      sums.swap(next);
      completed = last;
    }
  });
  StokesImages images{Image(w, h), Image(polarized ? w : 0, polarized ? h : 0), Image(polarized ? w : 0, polarized ? h : 0),
                      Image(polarized ? w : 0, polarized ? h : 0)};
  if (completed > 0)
    for (size_t k = 0; k < K; ++k)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          images[k].at(x, y) = options.sums ? sums[(size_t(y) * size_t(w) + size_t(x)) * K + k]
                                            : sums[(size_t(y) * size_t(w) + size_t(x)) * K + k] / Float(completed);
  if (stats) {
    stats->setup_seconds = setup;
    stats->seconds = std::chrono::duration<double>(clock::now() - t0).count() - setup;
    stats->samples = std::uint64_t(pixels) * static_cast<std::uint64_t>(completed);
    stats->rays = rays.load();
    stats->walks = walks.load();
    stats->walk_steps = walk_steps.load();
    stats->probe_exits = probe_exits.load();
    stats->spp = completed;
    stats->stopped = completed < spp;
  }
  if (stokes) *stokes = images;
  return std::move(images[0]);
}

}  // namespace gonio::render
