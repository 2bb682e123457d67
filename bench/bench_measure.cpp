// Speed of the virtual gonioreflectometer (docs/benchmarks.md): traced segments per
// second (every facet query counts: the first hit, each bounce, each wrap and the exit)
// on Gaussian microsurfaces with white conductor facets, and the MERL table mode; with the
// height-field tracer (tracer argument 0, the default) or Embree (1).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "gonio/material.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/gaussian_surface.h"
#include "gonio/measure/heightfield_tracer.h"
#include "gonio/measure/instrument.h"
#include "gonio/measure/microsurface.h"
#include "gonio/measure/table.h"

namespace {

using namespace gonio;
using namespace gonio::measure;

HeightField gaussian_field(int n) {  // α = 0.3, the generator's default correlation
  GaussianSurfaceParams p;
  p.resolution = n;
  p.alpha_x = p.alpha_y = 0.3;
  return gaussian_height_field(p);
}

// One surface per resolution and tracer (0: height field, 1: Embree), built once.
const Microsurface& surface(int n, int tracer = 0) {
  static std::map<std::pair<int, int>, std::unique_ptr<Microsurface>> cache;
  auto& s = cache[{n, tracer}];
  if (!s)
    s = std::make_unique<Microsurface>(gaussian_field(n), parse_material(R"({"type":"mirror"})"),
                                       Microsurface::kDefaultMaxBounces, Microsurface::Mesh::Auto,
                                       tracer ? Microsurface::Tracer::Embree : Microsurface::Tracer::HeightField);
  return *s;
}

// Gantry: 4 incidences (0°, 30°, 60°, 80°), 18 detectors; args: resolution, threads, tracer.
void BM_GantrySegments(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)), int(state.range(2)));
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
BENCHMARK(BM_GantrySegments)->ArgsProduct({{512, 2048}, {1, 2}, {0, 1}})
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
// the time per ray goes. Args: resolution, θi in degrees, tracer.
void BM_TraceIncidence(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)), int(state.range(2)));
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
BENCHMARK(BM_TraceIncidence)->ArgsProduct({{512, 2048}, {0, 30, 60, 80}, {0, 1}})
    ->Unit(benchmark::kMillisecond)->Iterations(1);

// The height-field tracer's work per query (HeightFieldTracer::Stats): 100,000 rays at one
// incidence entering at uniform points from just above the highest point, and for each
// that meets a facet, the mirror-reflected query that leaves it upwards. Counters: node
// visits (all levels) and cells tested per query, for the entry and the exit queries.
void BM_HeightFieldWork(benchmark::State& state) {
  static std::map<int, std::unique_ptr<HeightFieldTracer>> cache;
  const int n = int(state.range(0));
  auto& tr = cache[n];
  static std::map<int, std::pair<double, double>> range;
  if (!tr) {
    const HeightField f = gaussian_field(n);
    tr = std::make_unique<HeightFieldTracer>(f);
    range[n] = {*std::min_element(f.z.begin(), f.z.end()), *std::max_element(f.z.begin(), f.z.end())};
  }
  const auto [lo, hi] = range[n];
  const double th = double(state.range(1)) * kPiD / 180;
  HeightFieldTracer::Stats entry, exit;
  double q_entry = 0, q_exit = 0;
  for (auto _ : state) {
    Pcg32 rng(3);
    for (int k = 0; k < 100000; ++k) {
      const double o[3] = {rng.next_double(), rng.next_double(), hi + 1e-6}, d[3] = {std::sin(th), 0, -std::cos(th)};
      const HeightFieldTracer::Hit h = tr->intersect(o, d, (hi - lo + 1e-5) / std::cos(th), 100000, &entry);
      ++q_entry;
      if (!std::isfinite(h.t)) continue;
      const Vec3 m = normalize(h.ng);
      const double dm = d[0] * m.x + d[1] * m.y + d[2] * m.z;
      const double r[3] = {d[0] - 2 * dm * m.x, d[1] - 2 * dm * m.y, d[2] - 2 * dm * m.z};
      if (!(r[2] > 0)) continue;
      const double o2[3] = {o[0] + d[0] * h.t + 1e-7 * m.x, o[1] + d[1] * h.t + 1e-7 * m.y,
                            o[2] + d[2] * h.t + 1e-7 * m.z};
      benchmark::DoNotOptimize(tr->intersect(o2, r, (hi - o2[2]) / r[2], 100000, &exit, 0));
      ++q_exit;
    }
  }
  state.counters["entry nodes/q"] = double(entry.nodes) / q_entry;
  state.counters["entry cells/q"] = double(entry.cells) / q_entry;
  state.counters["exit nodes/q"] = double(exit.nodes) / q_exit;
  state.counters["exit cells/q"] = double(exit.cells) / q_exit;
}
BENCHMARK(BM_HeightFieldWork)->ArgsProduct({{512, 2048}, {0, 30, 60, 80}})
    ->Unit(benchmark::kMillisecond)->Iterations(1);

// The tracer alone: first-hit queries (Microsurface::probe, one query as trace() makes it,
// no material, no detectors) from the instrument's entry points (entry_point's strata, in
// blocks) just above the highest facet at 0°, 30°, 60° and 80°, 100,000 per incidence per thread, on 1 or 2 threads. The ceiling of any
// measurement on this surface: every scattered ray needs at least one such query (the
// exit queries are shorter, docs/benchmarks.md). Args: resolution, threads, tracer.
void BM_EntryQueries(benchmark::State& state) {
  const Microsurface& s = surface(int(state.range(0)), int(state.range(2)));
  const int threads = int(state.range(1));
  static constexpr std::uint64_t kPerIncidence = 100000;
  double queries = 0;
  for (auto _ : state) {
    std::vector<std::thread> pool;
    std::vector<int> facets(std::size_t(threads), 0);
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&s, &facets, t] {
        for (const double theta : {0.0, 30.0, 60.0, 80.0}) {
          const Vec3 dir = -spherical_direction(theta * kPiD / 180, 0);
          for (std::uint64_t first = 0; first < kPerIncidence; first += kBlockRays) {
            const std::uint64_t last = std::min<std::uint64_t>(kPerIncidence, first + kBlockRays);
            Pcg32 rng(4 + std::uint64_t(t), first);
            for (std::uint64_t k = first; k < last; ++k) {
              double u, v;
              entry_point(k - first, last - first == kBlockRays, rng, u, v);
              const double p[3] = {u * s.size(), v * s.size(), s.z_max() + 1e-6};
              facets[std::size_t(t)] += s.probe(p, dir).facet ? 1 : 0;
            }
          }
        }
      });
    for (auto& th : pool) th.join();
    queries += 4.0 * double(kPerIncidence) * threads;
    benchmark::DoNotOptimize(facets.data());
  }
  state.counters["queries/s"] = benchmark::Counter(queries, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EntryQueries)->ArgsProduct({{512, 2048}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The MERL table mode (uniform incidences, every exit binned), 2 M rays of the estimate and the
// pilot's 0.5 M (table.h); rays/s counts the estimate's. Args: threads, tracer.
void BM_TableRays(benchmark::State& state) {
  const Microsurface& s = surface(512, int(state.range(1)));
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
BENCHMARK(BM_TableRays)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
