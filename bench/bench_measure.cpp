// Speed of the virtual gonioreflectometer (docs/benchmarks.md): traced segments per
// second (every Embree query counts: the first hit, each bounce, each wrap and the exit)
// on Gaussian microsurfaces with white conductor facets, and the MERL table mode.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>

#include "gonio/material.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/gaussian_surface.h"
#include "gonio/measure/instrument.h"
#include "gonio/measure/microsurface.h"
#include "gonio/measure/table.h"

namespace {

using namespace gonio;
using namespace gonio::measure;

// One surface per resolution, built once (α = 0.3, the generator's default correlation).
const Microsurface& surface(int n) {
  static std::map<int, std::unique_ptr<Microsurface>> cache;
  auto& s = cache[n];
  if (!s) {
    GaussianSurfaceParams p;
    p.resolution = n;
    p.alpha_x = p.alpha_y = 0.3;
    s = std::make_unique<Microsurface>(gaussian_height_field(p), parse_material(R"({"type":"mirror"})"));
  }
  return *s;
}

// Gantry: 4 incidences (0°, 30°, 60°, 80°), 18 detectors; args: resolution, threads.
void BM_GantrySegments(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)));
  GantrySpec g;
  g.theta_i = {0, 30, 60, 80};
  g.theta_o = {5, 15, 25, 35, 45, 55, 65, 75, 85};
  g.phi_o = {0, 180};
  RunOptions o;
  o.samples = 400000;
  o.threads = int(state.range(1));
  double segments = 0, rays = 0;
  for (auto _ : state) {
    const GantryReading r = run_gantry(s, g, o);
    for (const auto& inc : r.incidences) segments += double(inc.counts.segments), rays += double(inc.counts.launched);
    benchmark::DoNotOptimize(r.incidences.data());
  }
  state.counters["segments/s"] = benchmark::Counter(segments, benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  state.counters["segments/ray"] = segments / rays;
}
BENCHMARK(BM_GantrySegments)->Args({512, 1})->Args({512, 2})->Args({2048, 1})->Args({2048, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The gantry's ray loop on one thread, without the detectors: blocks of kBlockRays rays
// entering in the blocks' Morton-ordered strata (entry_point), traced one by one with
// trace() (packet = 0) or 16 at a time with trace_packet() (packet = 1); 4 incidences
// (0°, 30°, 60°, 80°) × 100,000 rays. Args: resolution, packet.
void BM_TraceLoop(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)));
  const bool packet = state.range(1) != 0;
  constexpr std::uint64_t kPerIncidence = 100000;
  double segments = 0, rays = 0;
  for (auto _ : state) {
    for (const double theta : {0.0, 30.0, 60.0, 80.0}) {
      const Vec3 dir = -spherical_direction(theta * kPiD / 180, 0);
      for (std::uint64_t first = 0; first < kPerIncidence; first += kBlockRays) {
        const std::uint64_t last = std::min(kPerIncidence, first + kBlockRays);
        const bool full = last - first == kBlockRays;
        Pcg32 rng(1, first);
        for (std::uint64_t k = first; k < last; k += Microsurface::kPacketSize) {
          const int count = int(std::min<std::uint64_t>(Microsurface::kPacketSize, last - k));
          double u[Microsurface::kPacketSize], v[Microsurface::kPacketSize];
          TraceResult t[Microsurface::kPacketSize];
          for (int i = 0; i < count; ++i) entry_point(k + std::uint64_t(i) - first, full, rng, u[i], v[i]);
          if (packet) {
            s.trace_packet(u, v, count, dir, rng, t);
          } else {
            for (int i = 0; i < count; ++i) t[i] = s.trace(u[i], v[i], dir, rng);
          }
          for (int i = 0; i < count; ++i) segments += t[i].segments;
          rays += count;
          benchmark::DoNotOptimize(t);
        }
      }
    }
  }
  state.counters["segments/s"] = benchmark::Counter(segments, benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TraceLoop)->Args({512, 0})->Args({512, 1})->Args({2048, 0})->Args({2048, 1})
    ->Unit(benchmark::kMillisecond)->Iterations(1);

// trace() alone at one incidence (100,000 rays in the blocks' strata, one thread): where
// the time per ray goes. Args: resolution, θi in degrees.
void BM_TraceIncidence(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)));
  const Vec3 dir = -spherical_direction(double(state.range(1)) * kPiD / 180, 0);
  constexpr std::uint64_t kRays = 100000;
  double segments = 0, rays = 0;
  for (auto _ : state) {
    for (std::uint64_t first = 0; first < kRays; first += kBlockRays) {
      const std::uint64_t last = std::min(kRays, first + kBlockRays);
      Pcg32 rng(2, first);
      for (std::uint64_t k = first; k < last; ++k) {
        double u, v;
        entry_point(k - first, last - first == kBlockRays, rng, u, v);
        const TraceResult t = s.trace(u, v, dir, rng);
        segments += t.segments;
        benchmark::DoNotOptimize(t);
      }
      rays += double(last - first);
    }
  }
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  state.counters["segments/ray"] = segments / rays;
}
BENCHMARK(BM_TraceIncidence)->ArgsProduct({{512, 2048}, {0, 30, 60, 80}})->Unit(benchmark::kMillisecond)->Iterations(1);

// The MERL table mode (uniform incidences, every exit binned), 2 M rays; args: threads.
void BM_TableRays(benchmark::State& state) {
  const Microsurface& s = surface(512);
  RunOptions o;
  o.samples = 2000000;
  o.threads = int(state.range(0));
  double segments = 0, rays = 0;
  for (auto _ : state) {
    const TableReading r = measure_table(s, o);
    segments += double(r.counts.segments), rays += double(r.counts.launched);
    benchmark::DoNotOptimize(r.table.rgb.data());
  }
  state.counters["segments/s"] = benchmark::Counter(segments, benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TableRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
