#pragma once
// Branch-free selection for hot paths whose conditions are data-dependent (which side
// of the surface a direction lies on): a mispredicted branch costs more than the model.

#include <bit>
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

}  // namespace gonio
