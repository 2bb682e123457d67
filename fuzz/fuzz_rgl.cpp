// libFuzzer target: RGL .bsdf files (SPEC §2 `rgl`, issue 59) → TensorFile::parse and
// parse_rgl, then the rgl model of an accepted file and its f, pdf, eval and sample at
// fixed direction pairs and at 16 pairs derived from the input's bytes. Only InputError
// may escape the reader; every value of an accepted file's model must be finite and >= 0.
//
// Byte 0 even: the rest is a whole file's bytes (the container's header, field table and
// offsets fuzzed directly). Byte 0 odd: a small valid file (gonio's writer, 3 θi, 8×8 NDF,
// 4×4 samples) whose float data bytes from byte 64 on are overwritten by the input's
// bytes 1.. (values fuzzed inside a well-formed container: NaN, negative, zero slices).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "fuzz_bxdf.h"
#include "gonio/bxdf/rgl.h"
#include "gonio/error.h"
#include "gonio/io/tensor_file.h"
#include "gonio/material.h"
#include "gonio/rgl/data.h"
#include "gonio/rgl/write.h"

using namespace gonio;

namespace {

const std::vector<std::uint8_t>& rgl_base_file() {
  static const std::vector<std::uint8_t> bytes = [] {
    RglWriteOptions o;
    o.n_theta_i = 3;
    o.n_ndf = 8;
    o.n_sample = 4;
    o.wavelengths = {450, 550, 650};
    return tabulate_rgl(parse_material(R"({"type":"roughconductor","alpha":0.3,"material":"Al"})"), o);
  }();
  return bytes;
}

Vec3 rgl_sphere_direction(Float a, Float b) {
  const Float z = 1 - 2 * a, r = std::sqrt(std::max(Float(0), 1 - z * z)), phi = 2 * Float(3.14159265358979) * b;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  std::shared_ptr<const RglData> table;
  try {
    if (!(data[0] & 1)) {
      table = std::make_shared<const RglData>(
          parse_rgl(TensorFile::parse(std::span<const std::uint8_t>(data + 1, size - 1), "fuzz")));
    } else {
      std::vector<std::uint8_t> bytes = rgl_base_file();
      for (size_t k = 1; k < size && 64 + k < bytes.size(); ++k) bytes[63 + k] = data[k];
      table = std::make_shared<const RglData>(parse_rgl(TensorFile::parse(bytes, "fuzz")));
    }
  } catch (const InputError&) {
    return 0;  // the documented error for a bad file
  }
  const RglBxDF m = RglBxDF::make(table);
  const Vec3 fixed[] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {1, 0, 0}, {0, 0.6f, -0.8f}, {0.99999f, 0, 0.0044721f}};
  for (const Vec3& wo : fixed)
    for (const Vec3& wi : fixed) {
      gonio_fuzz::exercise(m, wo, wi, 0.3f, 0.7f, 0.1f, TransportMode::Radiance);
      gonio_fuzz::exercise(m, wo, wi, 0.3f, 0.2f, 0.9f, TransportMode::Importance);
    }
  const auto byte = [&](size_t k) { return data[k % size]; };
  for (size_t n = 0; n < 16; ++n) {
    uint8_t b[20];
    for (size_t k = 0; k < sizeof b; ++k) b[k] = byte(20 * n + k);
    const Vec3 wo = rgl_sphere_direction(gonio_fuzz::decode_u(b), gonio_fuzz::decode_u(b + 4));
    const Vec3 wi = rgl_sphere_direction(gonio_fuzz::decode_u(b + 8), gonio_fuzz::decode_u(b + 12));
    gonio_fuzz::exercise(m, wo, wi, gonio_fuzz::decode_u(b + 16), gonio_fuzz::decode_u(b + 4),
                         gonio_fuzz::decode_u(b + 12), TransportMode::Radiance);
  }
  return 0;
}
