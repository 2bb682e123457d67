// libFuzzer target: MERL tables (SPEC §2 `measured`) → read_merl / parse_merl, then the
// measured model built from an accepted table (interpolation, the sampler's tables) and
// its f, pdf, eval and sample. Only InputError may escape the reader; every value of an
// accepted table's model must be finite and >= 0 (issue 39: entries that overflow a float
// were accepted and gave NaN at their bins).
//
// A whole table is 35 MB, far beyond a fuzzer's inputs, so the input describes one:
// byte 0 even: the rest is a file's bytes, read from a scratch file by read_merl (headers,
// sizes, the file checks). Byte 0 odd: bytes 1–8 are the raw bits of a double stored in
// every entry of every channel; then up to 64 records of 14 bytes (u32 first entry,
// channel-major as in the file, modulo 3 × 1,458,000; u16 run length − 1; the raw bits of a
// double) each store a value in a run of entries. The table's bytes are built in memory
// and parsed by parse_merl; an accepted table is exercised at fixed direction pairs and at
// 16 pairs and random numbers derived from the input's bytes.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "fuzz_bxdf.h"
#include "fuzz_util.h"
#include "gonio/bxdf/measured.h"
#include "gonio/error.h"
#include "gonio/measured_data.h"
#include "gonio/merl.h"

using namespace gonio;

namespace {

constexpr std::size_t kHeader = 12, kValues = 3 * MerlTable::kEntries, kRecord = 14, kMaxRecords = 64;

std::vector<unsigned char> table_bytes(const uint8_t* data, size_t size) {
  std::vector<unsigned char> bytes(kHeader + kValues * sizeof(double));
  const std::int32_t dims[3] = {MerlTable::kThetaH, MerlTable::kThetaD, MerlTable::kPhiD};
  std::memcpy(bytes.data(), dims, sizeof dims);  // little-endian hosts (x86, arm64)
  // The base value in every entry: the first 8 bytes, then the filled part copied onto
  // the rest in doubling steps (22 copies, not 4.4 million: inputs per second matter).
  std::memcpy(&bytes[kHeader], data + 1, std::min<size_t>(8, size - 1));
  for (std::size_t done = 8, total = kValues * sizeof(double); done < total; done *= 2)
    std::memcpy(&bytes[kHeader + done], &bytes[kHeader], std::min(done, total - done));
  const uint8_t* p = data + 9;
  for (size_t n = 0; p + kRecord <= data + size && n < kMaxRecords; p += kRecord, ++n) {
    const std::size_t first = gonio_fuzz::read_u32(p) % kValues;
    const std::size_t run = std::size_t(p[4]) | (std::size_t(p[5]) << 8);
    for (std::size_t e = first; e < std::min(kValues, first + run + 1); ++e) std::memcpy(&bytes[kHeader + 8 * e], p + 6, 8);
  }
  return bytes;
}

// A direction from two numbers in [0, 1): anywhere on the sphere, the poles and the
// horizon included at the ends.
Vec3 sphere_direction(Float a, Float b) {
  const Float z = 1 - 2 * a, r = std::sqrt(std::max(Float(0), 1 - z * z)), phi = 2 * Float(3.14159265358979) * b;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  MerlTable table;
  try {
    if (!(data[0] & 1)) {
      (void)read_merl(gonio_fuzz::write_scratch(data + 1, size - 1, ".binary"));
      return 0;
    }
    table = parse_merl(table_bytes(data, size), "fuzz");
  } catch (const InputError&) {
    return 0;  // the documented error for a bad table
  }
  const MeasuredBxDF m = MeasuredBxDF::make(std::make_shared<const MeasuredData>(std::move(table), "fuzz"));
  const Vec3 fixed[] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {1, 0, 0}, {0, 0.6f, -0.8f}, {0.99999f, 0, 0.0044721f}};
  for (const Vec3& wo : fixed)
    for (const Vec3& wi : fixed) gonio_fuzz::exercise(m, wo, wi, 0.3f, 0.7f, 0.1f, TransportMode::Radiance);
  // Directions and random numbers from the input's bytes, cycled.
  const auto byte = [&](size_t k) { return data[k % size]; };
  for (size_t n = 0; n < 16; ++n) {
    uint8_t b[20];
    for (size_t k = 0; k < sizeof b; ++k) b[k] = byte(20 * n + k);
    const Vec3 wo = sphere_direction(gonio_fuzz::decode_u(b), gonio_fuzz::decode_u(b + 4));
    const Vec3 wi = sphere_direction(gonio_fuzz::decode_u(b + 8), gonio_fuzz::decode_u(b + 12));
    gonio_fuzz::exercise(m, wo, wi, gonio_fuzz::decode_u(b + 16), gonio_fuzz::decode_u(b + 4),
                         gonio_fuzz::decode_u(b + 12), TransportMode::Radiance);
  }
  return 0;
}
