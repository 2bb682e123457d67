// The rgl model (RGL .bsdf, issue 59): eval and sample per call on an isotropic file gonio
// writes at default resolution (GGX conductor α 0.3), RGB and spectral (4 wavelengths).
// docs/measured.md records the figures.

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/io/tensor_file.h"
#include "gonio/material.h"
#include "gonio/rgl/data.h"
#include "gonio/rgl/write.h"
#include "gonio/spectral_material.h"

namespace {

using namespace gonio;

std::shared_ptr<const RglData> bench_table() {
  static const std::shared_ptr<const RglData> t = [] {
    const std::vector<std::uint8_t> bytes =
        tabulate_rgl(parse_material(R"({"type":"roughconductor","alpha":0.3,"material":"Cu"})"), RglWriteOptions{});
    return std::make_shared<const RglData>(parse_rgl(TensorFile::parse(bytes, "bench.bsdf")));
  }();
  return t;
}

std::vector<Vec3> bench_dirs(int n, unsigned seed) {
  std::vector<Vec3> v;
  unsigned s = seed;
  auto next = [&] {
    s = s * 1664525u + 1013904223u;
    return float(s >> 8) / float(1 << 24);
  };
  for (int k = 0; k < n; ++k) {
    const float z = 0.05f + 0.95f * next(), r = std::sqrt(1 - z * z), p = 6.2831853f * next();
    v.push_back({r * std::cos(p), r * std::sin(p), z});
  }
  return v;
}

template <typename M>
void bench_eval(benchmark::State& state, const M& m) {
  const auto wo = bench_dirs(1024, 1), wi = bench_dirs(1024, 2);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.eval(wo[k & 1023], wi[k & 1023], TransportMode::Radiance));
    ++k;
  }
}
template <typename M>
void bench_sample(benchmark::State& state, const M& m) {
  const auto wo = bench_dirs(1024, 3), u = bench_dirs(1024, 4);
  std::size_t k = 0;
  for (auto _ : state) {
    const Vec3& r = u[k & 1023];
    benchmark::DoNotOptimize(m.sample(wo[k & 1023], 0.5f, 0.5f * (r.x + 1), 0.5f * (r.y + 1), TransportMode::Radiance));
    ++k;
  }
}

void BM_RglEvalRgb(benchmark::State& s) { bench_eval(s, RglBxDF::make(bench_table())); }
void BM_RglSampleRgb(benchmark::State& s) { bench_sample(s, RglBxDF::make(bench_table())); }
RglBxDFT<SampledSpectrum> bench_spectral() {
  RglBxDFT<SampledSpectrum> m;
  m.owner = bench_table();
  m.data = m.owner.get();
  m.wavelengths = SampledWavelengths::sample_visible(0.37f);
  return m;
}
void BM_RglEvalSpectral4(benchmark::State& s) { bench_eval(s, bench_spectral()); }
void BM_RglSampleSpectral4(benchmark::State& s) { bench_sample(s, bench_spectral()); }

BENCHMARK(BM_RglEvalRgb);
BENCHMARK(BM_RglSampleRgb);
BENCHMARK(BM_RglEvalSpectral4);
BENCHMARK(BM_RglSampleSpectral4);

}  // namespace

BENCHMARK_MAIN();
