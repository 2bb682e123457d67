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

#include "fuzz_bxdf.h"
#include "fuzz_util.h"
#include "gonio/material.h"
#include "gonio/spectral_material.h"

using namespace gonio;
using gonio_fuzz::check_value;
using gonio_fuzz::decode_direction;
using gonio_fuzz::decode_u;
using gonio_fuzz::exercise;

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
