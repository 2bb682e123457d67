// Micro-benchmarks of the measured (MERL) model: f, pdf, eval and sample per call at random
// directions, and the time to load a table (read + sampling distribution). Targets of
// issue 12: eval ≤ 100 ns, sample ≤ 300 ns, load ≤ 0.5 s. Results: docs/benchmarks.md.
//
// Method as bench_bxdf.cpp: 4096 queries drawn before timing (wo, wi uniform on the upper
// hemisphere; the model's cost does not depend on the side), visited in a shuffled order
// of 2^16 indices, every result stored. The table is a GGX rough conductor (α = 0.2)
// tabulated by gonio and written to a temporary file.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/measured_data.h"
#include "gonio/rng.h"
#include "gonio/tabulate.h"

namespace {

using namespace gonio;

constexpr std::size_t kQueries = 4096, kCalls = 1u << 16;

struct Fixture {
  std::string path;
  BxDF model;
  std::vector<Vec3> wo, wi;
  std::vector<float> u;
  std::vector<std::uint32_t> order;
  Fixture() {
    path = (std::filesystem::temp_directory_path() / "gonio_bench_measured.binary").string();
    write_merl(path, tabulate(parse_material(R"({"type":"roughconductor","alpha":0.2,"material":"Au"})")));
    model = parse_material(R"({"type":"measured","file":")" + path + R"("})");
    Pcg32 rng(7);
    for (std::size_t i = 0; i < kQueries; ++i) {
      wo.push_back(square_to_uniform_hemisphere(rng.next_float(), rng.next_float()));
      wi.push_back(square_to_uniform_hemisphere(rng.next_float(), rng.next_float()));
      for (int k = 0; k < 3; ++k) u.push_back(rng.next_float());
    }
    order.resize(kCalls);
    for (std::size_t i = 0; i < kCalls; ++i) order[i] = std::uint32_t(rng.next_u32() % kQueries);
  }
  ~Fixture() { std::remove(path.c_str()); }
};
Fixture& fixture() {
  static Fixture f;
  return f;
}

template <typename T>
inline void escape(T* p) { asm volatile("" : : "g"(p) : "memory"); }

void BM_measured_f(benchmark::State& state) {
  Fixture& fx = fixture();
  std::vector<Color> out(kQueries);
  for (auto _ : state) {
    for (std::uint32_t q : fx.order) out[q] = fx.model.f(fx.wo[q], fx.wi[q]);
    escape(out.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kCalls));
}
// The same pair every call: the table entries stay in L1, so this is the arithmetic alone
// (the difference to BM_measured_f is the cost of fetching entries from memory).
void BM_measured_f_cached(benchmark::State& state) {
  Fixture& fx = fixture();
  std::vector<Color> out(kQueries);
  for (auto _ : state) {
    for (std::uint32_t q : fx.order) out[q] = fx.model.f(fx.wo[0], fx.wi[0]);
    escape(out.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kCalls));
}
void BM_measured_eval(benchmark::State& state) {
  Fixture& fx = fixture();
  std::vector<BSDFEval> out(kQueries);
  for (auto _ : state) {
    for (std::uint32_t q : fx.order) out[q] = fx.model.eval(fx.wo[q], fx.wi[q]);
    escape(out.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kCalls));
}
// eval at one pair every call: its arithmetic alone, as BM_measured_f_cached for f.
void BM_measured_eval_cached(benchmark::State& state) {
  Fixture& fx = fixture();
  std::vector<BSDFEval> out(kQueries);
  for (auto _ : state) {
    for (std::uint32_t q : fx.order) out[q] = fx.model.eval(fx.wo[0], fx.wi[0]);
    escape(out.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kCalls));
}
void BM_measured_sample(benchmark::State& state) {
  Fixture& fx = fixture();
  std::vector<Vec3> out(kQueries);
  std::vector<Color> weight(kQueries);
  for (auto _ : state) {
    for (std::uint32_t q : fx.order) {
      const auto s = fx.model.sample(fx.wo[q], fx.u[3 * q], fx.u[3 * q + 1], fx.u[3 * q + 2]);
      if (s) out[q] = s->wi, weight[q] = s->weight;
    }
    escape(out.data());
    escape(weight.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kCalls));
}
// Reading the file and building the sampling distribution (load_measured without its cache).
void BM_measured_load(benchmark::State& state) {
  Fixture& fx = fixture();
  for (auto _ : state) {
    auto data = std::make_shared<const MeasuredData>(read_merl(fx.path), fx.path);
    escape(data.get());
  }
}

BENCHMARK(BM_measured_f);
BENCHMARK(BM_measured_f_cached);
BENCHMARK(BM_measured_eval);
BENCHMARK(BM_measured_eval_cached);
BENCHMARK(BM_measured_sample);
BENCHMARK(BM_measured_load)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
