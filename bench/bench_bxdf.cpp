// Micro-benchmarks of the built-in BxDF models: time per f, pdf and sample call, each
// model called directly (value type) and through the gonio::BxDF variant dispatch.
// Results, method and analysis: docs/benchmarks.md.
//
// Method
//   * kQueries = 4096 queries (wo, wi, u_lobe, u1, u2) drawn once with Pcg32 before any
//     timing: wo and wi independent random unit vectors, ~85% in the upper hemisphere and
//     ~15% below it; u_lobe, u1, u2 uniform in [0, 1).
//   * They are visited in a pre-generated random order of kCalls = 2^20 indices (one
//     benchmark iteration = kCalls calls). Cycling through the 4096 queries in a fixed
//     order is NOT enough on this machine: the branch predictor of an AMD Zen 3 learns the
//     whole 4096-long outcome sequence (perf: at most 0.03 mispredictions per call, where
//     the shuffled order gives 0.28 for a Lambert f), so data-dependent branches look free.
//     With a period of 2^20 it cannot. `--order=sequential` visits the queries in order
//     instead (same loop, same loads), to show what the predictor hides.
//   * Every result is stored into a small output array (as a renderer stores a vertex),
//     not summed into one float: a float accumulator is a serial chain of addss (3 cycles,
//     ~0.9 ns at this machine's clock; no reassociation without -ffast-math), a floor under
//     every call right at the 1 ns target. `method/diffuse_f_accumulate` is that variant.
//   * `method/copy_baseline` is the harness alone (index load, query load, one store).
//   * With --benchmark_repetitions=N each benchmark also reports `_min`, the best of the
//     N runs (read its ns_per_call; for items_per_second the min is the worst run).
//   * Opaque sinks of our own (empty asm statements), not benchmark::DoNotOptimize: with
//     g++ 12 and benchmark 1.7.1 DoNotOptimize(T&) has been seen to miscompile.
//       - opaque(p) on the model pointer at every call: the optimiser cannot hoist the
//         variant's index test out of the loop, unswitch or vectorise across calls, so
//         each call is a separate, complete call as in a renderer (the model's parameters
//         are reloaded from L1 each time, as they would be).
//       - escape(out) after each pass makes the stored results observable.
//   * Samples are consumed field by field (SampleOut). Copying the whole
//     std::optional<BSDFSample> (or its Vec3/Color members as aggregates) into memory
//     makes g++ 12 assemble it in a stack temporary and reload it with loads of a
//     different width: store-forwarding stalls that cost more than the model itself
//     (a mirror sample went from 1.5 ns to 6.5 ns), i.e. a measurement of the harness.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/fresnel.h"
#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/metals.h"
#include "gonio/rng.h"

namespace {

using namespace gonio;

constexpr std::size_t kQueries = 4096;     // distinct inputs (power of two)
constexpr std::size_t kCalls = 1u << 20;   // calls per benchmark iteration
constexpr std::size_t kTexturedCalls = 64;  // with_params calls per iteration (up to a millisecond each)
constexpr const char* kOpenPbrCoatFuzz =
    R"({"type":"openpbr","base_diffuse_roughness":0.5,"coat_weight":1,"coat_roughness":0.2,"fuzz_weight":0.5})";
constexpr const char* kOpenPbrFilm =
    R"({"type":"openpbr","base_diffuse_roughness":0.5,"thin_film_weight":1,"thin_film_thickness":0.4})";
constexpr Float kFractionBelow = 0.15f;    // share of directions below the surface

struct Query {
  Vec3 wo, wi;
  Float u_lobe, u1, u2;
};

struct Inputs {
  std::vector<Query> queries;         // kQueries
  std::vector<std::uint16_t> order;   // kCalls indices into queries
};

bool g_sequential = false;  // --order=sequential

// Makes `p` opaque to the optimiser at this point (it may have "changed"); no code.
template <typename T>
inline __attribute__((always_inline)) const T* opaque(const T* p) {
  __asm__ __volatile__("" : "+r"(p));
  return p;
}
// Pretends to read all memory reachable from `p`: stores before it must happen.
inline __attribute__((always_inline)) void escape(const void* p) {
  __asm__ __volatile__("" : : "r"(p) : "memory");
}

Vec3 random_direction(Pcg32& rng) {
  const Float u1 = rng.next_float(), u2 = rng.next_float();
  Vec3 w = square_to_uniform_sphere(u1, u2);
  w.z = std::abs(w.z);
  if (rng.next_float() < kFractionBelow) w.z = -w.z;
  if (w.z == 0) w.z = 1e-3f;  // keep clear of the tangent plane (a measure-zero case)
  return normalize(w);
}

const Inputs& inputs() {
  static const Inputs in = [] {
    Pcg32 rng(0x9e3779b97f4a7c15ULL, 0x2545f4914f6cdd1dULL);
    Inputs r;
    r.queries.resize(kQueries);
    for (auto& e : r.queries) {
      e.wo = random_direction(rng);
      e.wi = random_direction(rng);
      e.u_lobe = rng.next_float();
      e.u1 = rng.next_float();
      e.u2 = rng.next_float();
    }
    r.order.resize(kCalls);
    for (std::size_t i = 0; i < kCalls; ++i)
      r.order[i] = static_cast<std::uint16_t>(g_sequential ? i % kQueries
                                                           : rng.next_u32() % kQueries);
    return r;
  }();
  return in;
}

void set_counters(benchmark::State& state) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(kCalls));
  state.counters["ns_per_call"] = benchmark::Counter(
      static_cast<double>(kCalls),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// --- the timed loops; M is a model type or gonio::BxDF ---------------------------------
// noinline: one symbol per (operation, model), for reading the generated code.

template <typename M>
__attribute__((noinline)) void bench_f(benchmark::State& state, const M& model) {
  const Query* q = inputs().queries.data();
  const std::uint16_t* order = inputs().order.data();
  std::vector<Color> out(kQueries);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCalls; ++i) {
      const Query& e = q[order[i]];
      out[i % kQueries] = opaque(&model)->f(e.wo, e.wi);
    }
    escape(out.data());
  }
  set_counters(state);
}

template <typename M>
__attribute__((noinline)) void bench_pdf(benchmark::State& state, const M& model) {
  const Query* q = inputs().queries.data();
  const std::uint16_t* order = inputs().order.data();
  std::vector<Float> out(kQueries);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCalls; ++i) {
      const Query& e = q[order[i]];
      out[i % kQueries] = opaque(&model)->pdf(e.wo, e.wi);
    }
    escape(out.data());
  }
  set_counters(state);
}

// What a renderer keeps of a sample, read one scalar at a time (see the header comment).
struct SampleOut {
  Float wi[3];
  Float weight[kColorChannels];
  Float pdf, eta;
  std::uint32_t bits;  // 1: valid, 2: delta, 4: transmission
};

template <typename M>
__attribute__((noinline)) void bench_sample(benchmark::State& state, const M& model) {
  const Query* q = inputs().queries.data();
  const std::uint16_t* order = inputs().order.data();
  std::vector<SampleOut> out(kQueries);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCalls; ++i) {
      const Query& e = q[order[i]];
      const auto s = opaque(&model)->sample(e.wo, e.u_lobe, e.u1, e.u2);
      SampleOut& o = out[i % kQueries];
      if (s) {
        o.wi[0] = s->wi.x;
        o.wi[1] = s->wi.y;
        o.wi[2] = s->wi.z;
        for (int c = 0; c < kColorChannels; ++c) o.weight[c] = s->weight[c];
        o.pdf = s->pdf;
        o.eta = s->eta;
        o.bits = 1u | (s->delta ? 2u : 0u) | (s->lobe == Lobe::Transmission ? 4u : 0u);
      } else {
        o.bits = 0;
      }
    }
    escape(out.data());
  }
  set_counters(state);
}

// Method check: the Lambert f calls summed into one float instead of stored. This times
// the serial addss chain, not the call.
__attribute__((noinline)) void bench_f_accumulate(benchmark::State& state,
                                                  const DiffuseBxDF& model) {
  const Query* q = inputs().queries.data();
  const std::uint16_t* order = inputs().order.data();
  Float acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCalls; ++i) {
      const Query& e = q[order[i]];
      acc += opaque(&model)->f(e.wo, e.wi)[0];
    }
    escape(&acc);
  }
  const Float result = acc;
  benchmark::DoNotOptimize(result);  // a const value: the const& overload, not the T& one
  set_counters(state);
}

// Harness floor: the same loop, index load, query load and store, but no model.
__attribute__((noinline)) void bench_copy(benchmark::State& state) {
  const Query* q = inputs().queries.data();
  const std::uint16_t* order = inputs().order.data();
  std::vector<Float> out(kQueries);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCalls; ++i) out[i % kQueries] = opaque(&q[order[i]])->wo.z;
    escape(out.data());
  }
  set_counters(state);
}

// --- the models under test -------------------------------------------------------------

ConductorFresnel gold(FresnelModel model) {
  const auto au = named_metal("Au");
  if (!au) {
    std::fprintf(stderr, "gonio_bench: named_metal(\"Au\") failed\n");
    std::exit(1);
  }
  ConductorFresnel fr;
  fr.model = model;
  fr.eta = au->eta;
  fr.k = au->k;
  fr.f0 = map(au->eta, au->k, [](Float n, Float k) { return fresnel_f0(n, k); });
  return fr;
}

// With --benchmark_repetitions=N, "_min" is the best of the N runs: the figure least
// disturbed by other processes on the machine.
double min_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}

template <typename Fn>
void add(const std::string& name, Fn&& fn) {
  benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn))->ComputeStatistics("min", min_of);
}

template <typename M>
void register_model(const std::string& name, const M& model) {
  // The models live as long as the program; benchmarks run after registration.
  const auto* direct = new M(model);
  const auto* wrapped = new BxDF(model);
  add(name + "/f/direct", [direct](benchmark::State& s) { bench_f(s, *direct); });
  add(name + "/f/BxDF", [wrapped](benchmark::State& s) { bench_f(s, *wrapped); });
  add(name + "/pdf/direct", [direct](benchmark::State& s) { bench_pdf(s, *direct); });
  add(name + "/pdf/BxDF", [wrapped](benchmark::State& s) { bench_pdf(s, *wrapped); });
  add(name + "/sample/direct", [direct](benchmark::State& s) { bench_sample(s, *direct); });
  add(name + "/sample/BxDF", [wrapped](benchmark::State& s) { bench_sample(s, *wrapped); });
}

// A textured material's cost per shading point (docs/scene-format.md, "Textures"): the
// model made again by with_params with one parameter set, alternately to one of two
// values (each differs from the model's own, so that every call does the work), then
// one f there, as the renderer does at a hit. Per call: with_params + f.
__attribute__((noinline)) void bench_with_params(benchmark::State& state, const BxDF& model, MaterialParam param,
                                                 Color a, Color b) {
  const Query* q = inputs().queries.data();
  Color sum(0);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kTexturedCalls; ++i) {
      const ParamValue v{param, (i & 1) ? b : a};
      const BxDF m = with_params(*opaque(&model), {&v, 1});
      const Query& e = q[i % kQueries];
      sum += m.f(e.wo, e.wi);
    }
  }
  benchmark::DoNotOptimize(sum);
  state.counters["ns_per_call"] = benchmark::Counter(
      static_cast<double>(kTexturedCalls), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void register_textured(const std::string& name, const char* material, const char* key, Color a, Color b) {
  const auto* model = new BxDF(parse_material(material));
  const MaterialParam param = varying_param(model->name(), key).value();
  add("textured/" + name, [=](benchmark::State& s) { bench_with_params(s, *model, param, a, b); });
}

// A smooth or rough (GGX 0.2) η 1.5 top over a ρ 0.5 Lambertian base, medium of optical
// depth tau and albedo a (HG g 0).
LayeredBxDF layered_stack(bool rough, Float tau, Float a) {
  RoughDielectricBxDF top{{MicrofacetType::GGX, rough ? 0.2f : 0.0f, rough ? 0.2f : 0.0f}, 1.5f, {}};
  return LayeredBxDF::make(top, false, std::make_shared<const BxDF>(DiffuseBxDF{Color(0.5f)}), tau, Color(a), 0, 100, 1);
}

// --variance: the directional albedo estimated from sample weights, plastic against
// layered on the same stack (smooth η 1.5 over ρ 0.5, no medium): per-sample variance,
// time per sample, and the variance of the estimate one second of sampling buys
// (variance × time per sample), at 0°, 45° and 80°.
int variance_report() {
  const BxDF plastic = PlasticBxDF::make(Color(0.5f), 1.5f, std::nullopt);
  const BxDF layered = layered_stack(false, 0, 0);
  std::printf("theta model mean variance ns_per_sample variance_x_seconds ratio_to_plastic\n");
  for (double th : {0.0, 45.0, 80.0}) {
    const double t = th * kPiD / 180;
    const Vec3 wo{Float(std::sin(t)), 0, Float(std::cos(t))};
    double ref = 0;
    for (const BxDF* m : {&plastic, &layered}) {
      const int n = 400000;
      Pcg32 rng(5);
      double s = 0, s2 = 0;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < n; ++i) {
        const auto smp = m->sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
        const double w = smp ? double(smp->weight[0]) : 0.0;
        s += w;
        s2 += w * w;
      }
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double mean = s / n, var = s2 / n - mean * mean, per = secs / n;
      if (m == &plastic) ref = var * per;
      std::printf("%5.0f %-8s %.5f %.5f %8.1f %.3g %.1f\n", th, m == &plastic ? "plastic" : "layered", mean, var,
                  per * 1e9, var * per, var * per / ref);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Our one option, removed before Google Benchmark parses the rest.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--order=sequential") {
      g_sequential = true;
    } else if (a == "--variance") {
      return variance_report();
    } else if (a == "--order=shuffled") {
      g_sequential = false;
    } else if (a == "--help" || a == "-h") {
      std::printf(
          "gonio_bench [--order=shuffled|sequential] [Google Benchmark options]\n"
          "  --order=shuffled    visit the 4096 queries in a random order of 2^20 (default)\n"
          "  --order=sequential  visit them in order, 256 times (the branch predictor\n"
          "                      learns the sequence: a best case)\n"
          "  --variance          print the albedo estimate's variance at equal time,\n"
          "                      plastic against layered on the same stack, and exit\n\n");
      argv[kept++] = argv[i];
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  (void)inputs();  // generate the inputs before any timing

  register_model("diffuse", DiffuseBxDF{Color(0.5f)});
  register_model("mirror", MirrorBxDF{Color(0.9f)});
  register_model("conductor_exact_Au", ConductorBxDF{gold(FresnelModel::Exact)});
  register_model("conductor_schlick_Au", ConductorBxDF{gold(FresnelModel::Schlick)});
  register_model("dielectric_1.5", DielectricBxDF{1.5f});
  register_model("thindielectric_1.5", ThinDielectricBxDF{1.5f});
  // The glossy models; the issue's targets are for the first three.
  register_model("roughconductor_ggx_Au_0.2",
                 RoughConductorBxDF{{MicrofacetType::GGX, 0.2f, 0.2f}, gold(FresnelModel::Exact), std::nullopt});
  register_model("roughdielectric_ggx_1.5_0.2", RoughDielectricBxDF{{MicrofacetType::GGX, 0.2f, 0.2f}, 1.5f, {}});
  // issue 34: the same under a 400 nm film of n = 1.38 (RGB mode: the tabulated film).
  register_model("roughdielectric_ggx_1.5_0.2_film400", std::get<RoughDielectricBxDF>(parse_material(
      R"({"type":"roughdielectric","alpha":0.2,"eta":1.5,"thin_film":{"thickness":400,"eta":1.38}})").models()));
  register_model("orennayar_qualitative_20deg", OrenNayarBxDF{Color(0.5f), 20 * kPi / 180, false});
  register_model("sheen_0.5", SheenBxDF{Color(0.8f), 0.5f});  // issue 34: eval <= 40 ns
  register_model("roughconductor_beckmann_Au_0.2",
                 RoughConductorBxDF{{MicrofacetType::Beckmann, 0.2f, 0.2f}, gold(FresnelModel::Exact), std::nullopt});
  {
    RoughConductorBxDF ms{{MicrofacetType::GGX, 0.2f, 0.2f}, gold(FresnelModel::Exact), std::nullopt};
    ms.multiscatter = MultiscatterLobe::make(ms.distribution, Color(0.9f));
    register_model("roughconductor_ggx_Au_0.2_multiscatter", ms);
  }
  // Issue 34: EON against Oren–Nayar (target: f ≤ 2×), F82-tint against Schlick on the
  // same rough conductor (target: ≤ +10 %).
  register_model("eon_0.5", EonBxDF::make(Color(0.5f), 0.5f));
  // Issue 60: the hair fibre at one h (target: f <= 250 ns, sample <= 350 ns) and averaged
  // over h (8-point Gauss–Legendre, published separately).
  register_model("hair_h0.3", std::get<HairBxDF>(parse_material(R"({"type":"hair","h":0.3,"eumelanin":0.8})").models()));
  register_model("hair_h_averaged", std::get<HairBxDF>(parse_material(R"({"type":"hair","eumelanin":0.8})").models()));
  // Issue 35: openpbr with its defaults, and a dielectric base with coat and fuzz (target:
  // eval <= 150 ns, sample <= 250 ns).
  register_model("openpbr_default", std::get<OpenPbrBxDF>(parse_material(R"({"type":"openpbr"})").models()));
  register_model("openpbr_coat_fuzz", std::get<OpenPbrBxDF>(parse_material(kOpenPbrCoatFuzz).models()));
  // Issues 57/58: gltf_pbr, the core (a dielectric, roughness 0.5) and with coat and sheen.
  register_model("gltf_pbr_dielectric", std::get<GltfPbrBxDF>(parse_material(
      R"({"type":"gltf_pbr","base_color":[0.8,0.5,0.2],"metallic":0,"roughness":0.5})").models()));
  register_model("gltf_pbr_coat_sheen", std::get<GltfPbrBxDF>(parse_material(
      R"({"type":"gltf_pbr","base_color":[0.8,0.5,0.2],"metallic":0,"roughness":0.5,"clearcoat":1,"clearcoat_roughness":0.1,"sheen_color":0.5,"sheen_roughness":0.3})").models()));
  {
    ConductorFresnel schlick = gold(FresnelModel::Schlick), f82 = schlick;
    f82.model = FresnelModel::F82;
    f82.f82 = Color(0.9f, 0.6f, 0.3f);
    f82.prepare();
    register_model("roughconductor_ggx_schlick_0.2",
                   RoughConductorBxDF{{MicrofacetType::GGX, 0.2f, 0.2f}, schlick, std::nullopt});
    register_model("roughconductor_ggx_f82_0.2", RoughConductorBxDF{{MicrofacetType::GGX, 0.2f, 0.2f}, f82, std::nullopt});
  }
  register_model("phong_20", PhongBxDF{{}, Color(0.5f), Color(0.3f), 20});
  register_model("ward_0.1_0.3", WardBxDF{{}, Color(0.3f), Color(0.5f), 0.1f, 0.3f});
  register_model("plastic_smooth", PlasticBxDF::make(Color(0.5f), 1.5f, std::nullopt));
  register_model("plastic_rough_ggx_0.2", PlasticBxDF::make(Color(0.5f), 1.5f, MicrofacetDistribution{MicrofacetType::GGX, 0.2f, 0.2f}));
  // Extreme coats, whose sampling the weights work of issue 9 changed.
  register_model("plastic_smooth_eta1e4", PlasticBxDF::make(Color(0.5f), 1e4f, std::nullopt));
  register_model("plastic_rough_ggx_0.2_eta1e4", PlasticBxDF::make(Color(0.5f), 1e4f, MicrofacetDistribution{MicrofacetType::GGX, 0.2f, 0.2f}));

  // layered (issue 34): the plastic_smooth stack (a smooth η 1.5 coat on a ρ 0.5 Lambertian
  // base) by the random walk, without a medium and with the default one (τ 0.01, absorbing),
  // and a rough top with a scattering medium; max_depth 100 (the default) throughout.
  register_model("layered_smooth_diffuse", layered_stack(false, 0, 0));
  register_model("layered_smooth_diffuse_default_medium", layered_stack(false, 0.01f, 0));
  register_model("layered_rough_0.2_diffuse_scattering", layered_stack(true, 0.5f, 0.8f));

  // Textures (issue 35 item 2): a rough conductor's alpha (its Kulla–Conty lobe made
  // again), openpbr's colours (its quadratures kept) and its roughness (the diffuse's
  // normalisation solved again under an EON base; nothing to solve under a Lambertian one).
  register_textured("roughconductor_Au_alpha_multiscatter", R"({"type":"roughconductor","material":"Au","alpha":0.3,"multiscatter":true})",
                    "alpha", Color(0.2f), Color(0.25f));
  register_textured("openpbr_coat_fuzz_base_color", kOpenPbrCoatFuzz, "base_color", Color(0.2f, 0.5f, 0.7f), Color(0.6f));
  register_textured("openpbr_coat_fuzz_specular_roughness", kOpenPbrCoatFuzz, "specular_roughness", Color(0.2f), Color(0.25f));
  // gltf_pbr's roughness per hit (with_params copies the parameters: nothing is solved).
  register_textured("gltf_pbr_roughness", R"({"type":"gltf_pbr","metallic":0,"roughness":0.5})", "roughness", Color(0.2f), Color(0.25f));
  register_textured("openpbr_default_specular_roughness", R"({"type":"openpbr"})", "specular_roughness", Color(0.2f), Color(0.25f));
  // Anisotropic: the compensation reads the process's grid of E tables (anisotropic_albedo.h);
  // it tabulated E (20–30 ms) at every call before 2026-12-08.
  register_textured("openpbr_anisotropic_metal_specular_roughness",
                    R"({"type":"openpbr","base_metalness":1,"specular_roughness_anisotropy":0.5})", "specular_roughness",
                    Color(0.2f), Color(0.25f));
  register_textured("openpbr_film_base_color", kOpenPbrFilm, "base_color", Color(0.2f, 0.5f, 0.7f), Color(0.6f));
  register_textured("openpbr_film_thin_film_thickness", kOpenPbrFilm, "thin_film_thickness", Color(0.3f), Color(0.35f));

  static const DiffuseBxDF lambert{Color(0.5f)};
  add("method/copy_baseline", bench_copy);
  add("method/diffuse_f_accumulate", [](benchmark::State& s) { bench_f_accumulate(s, lambert); });

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("queries", std::to_string(kQueries));
  benchmark::AddCustomContext("calls_per_iteration", std::to_string(kCalls));
  benchmark::AddCustomContext("order", g_sequential ? "sequential" : "shuffled");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
