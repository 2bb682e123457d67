// Renderer throughput (Google Benchmark): camera samples/s and rays/s on the issue's
// small scene (scenes/bench_small.json) and on the default scene, with 1 and 2 threads.
// Wall time per image also appears as the benchmark time. The target is stated
// for the full image (256×256, 64 spp, 1 thread, ≤ 3.2 s including start-up); see
// docs/benchmarks.md for the command that measures it end to end.

#include <benchmark/benchmark.h>

#include <string>

#include "gonio/render/renderer.h"
#include "gonio/render/sampler.h"
#include "gonio/render/scene_loader.h"

#ifndef GONIO_SOURCE_DIR
#define GONIO_SOURCE_DIR "."
#endif

namespace {

using namespace gonio::render;

void run(benchmark::State& state, Scene scene) {
  RenderOptions options;
  options.threads = static_cast<int>(state.range(0));
  double samples = 0, rays = 0;
  for (auto _ : state) {
    RenderStats stats;
    Image img = render(scene, options, &stats);
    benchmark::DoNotOptimize(img);
    samples += double(stats.samples);
    rays += double(stats.rays);
  }
  state.counters["samples/s"] = benchmark::Counter(samples, benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
}

void BM_SmallScene(benchmark::State& state) {
  Scene s = load_scene_file(GONIO_SOURCE_DIR "/scenes/bench_small.json");
  s.settings.spp = 16;  // a quarter of the target's image, to keep repetitions short
  run(state, s);
}
BENCHMARK(BM_SmallScene)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same image in spectral mode (issue 11's target: at most 1.4x BM_SmallScene).
void BM_SmallSceneSpectral(benchmark::State& state) {
  Scene s = load_scene_file(GONIO_SOURCE_DIR "/scenes/bench_small.json");
  s.settings.spp = 16;
  s.settings.spectral = true;
  run(state, s);
}
BENCHMARK(BM_SmallSceneSpectral)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The small scene with each sampler (issue 38's time per sample, ≤ 5 % over independent),
// one thread: arg 0 zsobol, 1 sobol, 2 independent.
void BM_SmallSceneSampler(benchmark::State& state) {
  Scene s = load_scene_file(GONIO_SOURCE_DIR "/scenes/bench_small.json");
  s.settings.spp = 16;
  s.settings.sampler = static_cast<SamplerType>(state.range(1));
  state.SetLabel(sampler_type_name(s.settings.sampler));
  run(state, s);
}
BENCHMARK(BM_SmallSceneSampler)
    ->Args({1, 0})->Args({1, 1})->Args({1, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

// One 2-D point of a camera sample, alone: the sampler's own cost per call.
void BM_SamplerGet2d(benchmark::State& state) {
  PixelSampler sampler(static_cast<SamplerType>(state.range(0)), 64, 1);
  state.SetLabel(sampler_type_name(static_cast<SamplerType>(state.range(0))));
  std::uint64_t i = 0;
  for (auto _ : state) {
    sampler.start(int(i & 255), int((i >> 8) & 255), (i >> 16) & 63);
    for (int d = 0; d < 4; ++d) benchmark::DoNotOptimize(sampler.get2d(5 + 2 * d));
    ++i;
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * 4);
}
BENCHMARK(BM_SamplerGet2d)->Arg(0)->Arg(1)->Arg(2);

void BM_DefaultScene(benchmark::State& state) {
  Scene s = parse_scene(default_scene_json(), "default scene", "");
  s.settings.spp = 8;
  run(state, s);
}
BENCHMARK(BM_DefaultScene)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DefaultSceneSpectral(benchmark::State& state) {
  Scene s = parse_scene(default_scene_json(), "default scene", "");
  s.settings.spp = 8;
  s.settings.spectral = true;
  run(state, s);
}
BENCHMARK(BM_DefaultSceneSpectral)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
