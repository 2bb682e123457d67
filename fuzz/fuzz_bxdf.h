#pragma once
// What the fuzz targets that exercise a model share (fuzz_material, fuzz_merl): directions
// and random numbers decoded from raw bytes, and one pass over a model's f, pdf, eval and
// sample that aborts on a value the contract forbids (NaN, infinite or negative; a sampled
// direction not of unit length).

#include <cmath>
#include <cstdint>
#include <cstring>

#include "fuzz_util.h"
#include "gonio/bxdf/contract.h"
#include "gonio/math/vec3.h"

namespace gonio_fuzz {

using gonio::Float;
using gonio::TransportMode;
using gonio::Vec3;

inline uint32_t read_u32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

// Raw bits as a float; a non-finite or zero vector gives nullopt-like {0,0,0}. Scaling by
// the largest component first keeps denormal and huge components meaningful.
inline Vec3 decode_direction(const uint8_t* p) {
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
inline Float decode_u(const uint8_t* p) { return Float(read_u32(p) >> 8) * 0x1p-24f; }

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

}  // namespace gonio_fuzz
