#pragma once
// Branch-free selection for hot paths whose conditions are data-dependent (which side
// of the surface a direction lies on): a mispredicted branch costs more than the model.

#include <bit>
#include <cmath>
#include <cstdint>

#include "gonio/math/constants.h"

namespace gonio {

// x if cond, else +0 — through an integer mask, which the compiler keeps branch-free
// (it turns `cond ? x : 0` back into a jump).
inline Float keep_if(bool cond, Float x) {
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(cond);
  return std::bit_cast<Float>(std::bit_cast<std::uint32_t>(x) & mask);
}

// cond ? a : b without a branch (the same integer-mask device).
inline Float select(bool cond, Float a, Float b) {
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(cond);
  return std::bit_cast<Float>((std::bit_cast<std::uint32_t>(a) & mask) |
                              (std::bit_cast<std::uint32_t>(b) & ~mask));
}

// Sine and cosine of x in [−π/4, π/4] by their Taylor polynomials (through x⁹ and x⁸;
// truncation error below 3e-8, under float rounding): no call, no branch.
struct SinCos {
  Float sin, cos;
};
inline SinCos sincos_quarter(Float x) {
  const Float x2 = x * x;
  const Float s = x * (1 + x2 * (Float(-1.0 / 6) + x2 * (Float(1.0 / 120) + x2 * (Float(-1.0 / 5040) + x2 * Float(1.0 / 362880)))));
  const Float c = 1 + x2 * (Float(-0.5) + x2 * (Float(1.0 / 24) + x2 * (Float(-1.0 / 720) + x2 * Float(1.0 / 40320))));
  return {s, c};
}

// cos(2πu) and sin(2πu) for u in [0, 1]: the nearest quarter turn k = round(4u) is
// split off exactly, the remainder (π/2)(4u − k) lies in [−π/4, π/4], and the result is
// turned by k quarter turns. Replaces a libm sincos call (~15 ns) in the samplers.
inline SinCos sincos_2pi(Float u) {
  const Float q = 4 * u;
  const Float k = std::nearbyint(q);
  const SinCos r = sincos_quarter(kPiOver2 * (q - k));
  const int quarter = static_cast<int>(k) & 3;
  // (cos, sin) of r + k π/2
  const Float c = quarter == 0 ? r.cos : quarter == 1 ? -r.sin : quarter == 2 ? -r.cos : r.sin;
  const Float s = quarter == 0 ? r.sin : quarter == 1 ? r.cos : quarter == 2 ? -r.sin : -r.cos;
  return {s, c};
}

}  // namespace gonio
