// Micro-benchmarks of the spectral layer (docs/spectral.md, figures in docs/benchmarks.md):
// hero-wavelength sampling, RGB → spectrum (coefficient lookup, and evaluation at a path's
// 4 wavelengths), spectrum → XYZ. Inputs are drawn before timing; each iteration visits
// kCalls of them and stores every result, like bench_bxdf.cpp's harness.

#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "gonio/rng.h"
#include "gonio/spectral_material.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/spectrum.h"

namespace {

using namespace gonio;

constexpr int kInputs = 4096;

template <typename T>
inline void escape(T* p) {
  asm volatile("" : : "g"(p) : "memory");
}

struct Inputs {
  std::vector<Float> u;
  std::vector<std::array<Float, 3>> rgb;
  std::vector<SampledWavelengths> w;
  std::vector<SigmoidPolynomial> poly;
  Inputs() {
    Pcg32 rng(42);
    for (int i = 0; i < kInputs; ++i) {
      u.push_back(rng.next_float());
      rgb.push_back({rng.next_float(), rng.next_float(), rng.next_float()});
      w.push_back(SampledWavelengths::sample_visible(rng.next_float()));
      poly.push_back(rgb_to_sigmoid_polynomial(rgb.back()[0], rgb.back()[1], rgb.back()[2]));
    }
  }
};
const Inputs& inputs() {
  static const Inputs in;
  return in;
}

void wavelengths_sample_visible(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<SampledWavelengths> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) out[size_t(i)] = SampledWavelengths::sample_visible(in.u[size_t(i)]);
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(wavelengths_sample_visible);

// The renderer's draw (issue 38): four binary searches in the tabulated CDF.
void wavelengths_sample_response(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<SampledWavelengths> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) out[size_t(i)] = SampledWavelengths::sample_response(in.u[size_t(i)]);
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(wavelengths_sample_response);

void rgb_to_coefficients(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<SigmoidPolynomial> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) {
      const auto& c = in.rgb[size_t(i)];
      out[size_t(i)] = rgb_to_sigmoid_polynomial(c[0], c[1], c[2]);
    }
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(rgb_to_coefficients);

// The per-path cost of an RGB reflectance in spectral mode: S at the 4 wavelengths, from
// coefficients looked up once per material (as a renderer stores them).
void rgb_albedo_eval_4(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<SampledSpectrum> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) out[size_t(i)] = in.poly[size_t(i)].eval(in.w[size_t(kInputs - 1 - i)]);
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(rgb_albedo_eval_4);

// Lookup and evaluation together (a textured RGB: coefficients per hit).
void rgb_lookup_and_eval_4(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<SampledSpectrum> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) {
      const auto& c = in.rgb[size_t(i)];
      out[size_t(i)] = rgb_to_sigmoid_polynomial(c[0], c[1], c[2]).eval(in.w[size_t(i)]);
    }
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(rgb_lookup_and_eval_4);

// An RGB emission through the Spectrum variant (sigmoid × D65 lookup × scale).
void spectrum_variant_illuminant_eval_4(benchmark::State& state) {
  const auto& in = inputs();
  const Spectrum s = RgbIlluminantSpectrum(4, 2, 1);
  std::vector<SampledSpectrum> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) out[size_t(i)] = s.eval(in.w[size_t(i)]);
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(spectrum_variant_illuminant_eval_4);

void spectrum_to_xyz(benchmark::State& state) {
  const auto& in = inputs();
  std::vector<XYZ> out(kInputs);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) {
      const auto& c = in.rgb[size_t(i)];
      out[size_t(i)] = to_xyz(SampledSpectrum(c[0], c[1], c[2], c[0]), in.w[size_t(i)]);
    }
    escape(out.data());
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(spectrum_to_xyz);

}  // namespace

// Making a material's spectral model at a path's wavelengths (to_spectral), once per
// shading point in spectral mode, and evaluating it.
void to_spectral_model(benchmark::State& state, const char* json) {
  const auto& in = inputs();
  const MaterialWithSpectra m = parse_material_with_spectra(json);
  SpectralScratch scratch;
  std::vector<SampledWavelengths> w(kInputs);
  for (int i = 0; i < kInputs; ++i) w[size_t(i)] = SampledWavelengths::sample_visible(in.u[size_t(i)]);
  const Vec3 wo = normalize(Vec3{0.3f, 0.2f, 0.9f}), wi = normalize(Vec3{-0.4f, 0.1f, 0.8f});
  SampledSpectrum sum(0);
  for (auto _ : state) {
    for (int i = 0; i < kInputs; ++i) {
      scratch.reset();
      SampledWavelengths wl = w[size_t(i)];
      sum += to_spectral(m.bxdf, m.spectra, wl, scratch).f(wo, wi);
    }
    escape(&sum);
  }
  state.counters["ns_per_call"] = benchmark::Counter(double(state.iterations()) * kInputs,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(to_spectral_model, diffuse_rgb, R"({"type":"diffuse","reflectance":[0.7,0.3,0.2]})");
BENCHMARK_CAPTURE(to_spectral_model, roughconductor_au, R"({"type":"roughconductor","material":"Au","alpha":0.2})");
BENCHMARK_CAPTURE(to_spectral_model, roughconductor_au_ms,
                  R"({"type":"roughconductor","material":"Au","alpha":0.2,"multiscatter":true})");
BENCHMARK_CAPTURE(to_spectral_model, plastic_rough, R"({"type":"plastic","reflectance":[0.1,0.25,0.7],"alpha":0.12})");
BENCHMARK_CAPTURE(to_spectral_model, dielectric_sf11, R"({"type":"roughdielectric","eta":"SF11","alpha":0.2})");
// openpbr's metal, bare and under a film (the effective index solved per wavelength, and
// the film's F̄ for the Kulla–Conty lobe), and its glass under a film.
BENCHMARK_CAPTURE(to_spectral_model, openpbr_metal,
                  R"({"type":"openpbr","base_metalness":1,"base_color":[0.95,0.64,0.3],"specular_roughness":0.4})");
BENCHMARK_CAPTURE(to_spectral_model, openpbr_metal_film,
                  R"({"type":"openpbr","base_metalness":1,"base_color":[0.95,0.64,0.3],"specular_roughness":0.4,)"
                  R"("thin_film_weight":1,"thin_film_thickness":0.4})");
BENCHMARK_CAPTURE(to_spectral_model, openpbr_base_film,
                  R"({"type":"openpbr","base_diffuse_roughness":0.5,"thin_film_weight":1,"thin_film_thickness":0.4})");
BENCHMARK_CAPTURE(to_spectral_model, openpbr_glass_film,
                  R"({"type":"openpbr","transmission_weight":1,"specular_roughness":0.4,"thin_film_weight":1,"thin_film_thickness":0.4})");

BENCHMARK_MAIN();
