// libFuzzer target: material JSON → parse_material_with_spectra, then f, pdf and sample on
// directions decoded from the bytes after the JSON, for the RGB model and for the spectral
// model (to_spectral) at a decoded wavelength. Input: JSON text, a NUL byte, then up to 16
// records of 10 × 4 bytes (wo, wi as raw float bit patterns, scaled to unit length; u0, u1,
// u2 as 24-bit fractions in [0, 1); a mode byte; 16 bits of wavelength in [360, 830] nm;
// a byte choosing one wavelength or 4 hero-sampled ones). Only InputError may escape the
// parser (material.h documents it); f, pdf and sample weights must be finite and >= 0,
// sampled directions unit length.

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <string_view>

#include "fuzz_util.h"
#include "gonio/material.h"
#include "gonio/spectral_material.h"

using namespace gonio;
using gonio_fuzz::check_color;
using gonio_fuzz::check_value;

namespace {

uint32_t read_u32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

// Raw bits as a float; a non-finite or zero vector gives nullopt-like {0,0,0}. Scaling by
// the largest component first keeps denormal and huge components meaningful.
Vec3 decode_direction(const uint8_t* p) {
  float c[3];
  std::memcpy(c, p, 12);
  double x = c[0], y = c[1], z = c[2];
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return {0, 0, 0};
  const double m = std::fmax(std::fabs(x), std::fmax(std::fabs(y), std::fabs(z)));
  if (!(m > 0)) return {0, 0, 0};
  x /= m, y /= m, z /= m;
  const double inv = 1 / std::sqrt(x * x + y * y + z * z);
  return {Float(x * inv), Float(y * inv), Float(z * inv)};
}

// 24 random bits → [0, 1 − 2^-24], which includes 0 and 1 − ulp.
Float decode_u(const uint8_t* p) { return Float(read_u32(p) >> 8) * 0x1p-24f; }

template <typename Model>
void exercise(const Model& m, Vec3 wo, Vec3 wi, Float u0, Float u1, Float u2, TransportMode mode) {
  check_color("f", m.f(wo, wi, mode));
  check_value("pdf", m.pdf(wo, wi, mode));
  const auto e = m.eval(wo, wi, mode);
  check_color("eval.f", e.f);
  check_value("eval.pdf", e.pdf);
  const auto s = m.sample(wo, u0, u1, u2, mode);
  if (!s) return;
  check_color("sample.weight", s->weight);
  check_value("sample.pdf", s->pdf);
  const double len = std::sqrt(double(s->wi.x) * s->wi.x + double(s->wi.y) * s->wi.y + double(s->wi.z) * s->wi.z);
  if (!(std::fabs(len - 1) < 1e-4)) gonio_fuzz::fail("sample.wi not unit length", len);
  check_value("sample.eta", s->eta);
  if (!s->delta) {
    check_color("f(sampled wi)", m.f(wo, s->wi, mode));
    check_value("pdf(sampled wi)", m.pdf(wo, s->wi, mode));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto* end = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t json_size = end ? size_t(end - data) : size;
  MaterialWithSpectra parsed;
  try {
    parsed = parse_material_with_spectra(std::string_view(reinterpret_cast<const char*>(data), json_size), "fuzz");
  } catch (const InputError&) {
    return 0;  // the documented error for bad input
  }
  const BxDF& m = parsed.bxdf;
  SpectralScratch scratch;
  const auto spectral = [&](SampledWavelengths w) {
    scratch.reset();
    const SpectralBxDF s = to_spectral(m, parsed.spectra, w, scratch);
    for (int j = 0; j < SampledWavelengths::size(); ++j) check_value("wavelength pdf", w.pdf(j));
    return s;
  };
  // A few fixed pairs (normal, oblique, grazing, below; radiance and importance on
  // alternate pairs), then the decoded records.
  const Vec3 fixed[] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {1, 0, 0}, {0, 0.6f, -0.8f}};
  const SpectralBxDF ends[] = {spectral(SampledWavelengths::single(kLambdaMin)),
                               spectral(SampledWavelengths::single(kLambdaMax)),
                               spectral(SampledWavelengths::sample_visible(0.37f))};
  for (int i = 0; i < 16; ++i) {
    const TransportMode mode = (i & 1) ? TransportMode::Importance : TransportMode::Radiance;
    exercise(m, fixed[i / 4], fixed[i % 4], 0.3f, 0.7f, 0.1f, mode);
    exercise(ends[i % 3], fixed[i / 4], fixed[i % 4], 0.3f, 0.7f, 0.1f, mode);
  }
  const uint8_t* p = end ? end + 1 : data + size;
  const uint8_t* stop = data + size;
  constexpr size_t kRecord = 40;
  for (int n = 0; p + kRecord <= stop && n < 16; p += kRecord, ++n) {
    const TransportMode mode = (p[36] & 1) ? TransportMode::Importance : TransportMode::Radiance;
    const Vec3 wo = decode_direction(p), wi = decode_direction(p + 12);
    const Float u0 = decode_u(p + 24), u1 = decode_u(p + 28), u2 = decode_u(p + 32);
    exercise(m, wo, wi, u0, u1, u2, mode);
    const Float t = Float(p[37] | (p[38] << 8)) / 65535;
    const SampledWavelengths w = (p[39] & 1) ? SampledWavelengths::sample_visible(std::min(t, kOneMinusEpsilon))
                                             : SampledWavelengths::single(kLambdaMin + t * (kLambdaMax - kLambdaMin));
    exercise(spectral(w), wo, wi, u0, u1, u2, mode);
  }
  return 0;
}
