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

// The same on [−π/4, π/4] with the minimax polynomials of the Cephes library's single-
// precision sinf/cosf kernels (Moshier, Cephes Mathematical Library, sinf.c): two terms
// fewer, max error 4.6e-8 (sin) and 7.4e-8 (cos), within float rounding.
inline SinCos sincos_quarter_minimax(Float x) {
  const Float z = x * x;
  const Float s = x + x * z * (Float(-1.6666654611e-1) + z * (Float(8.3321608736e-3) + z * Float(-1.9515295891e-4)));
  const Float c = 1 - Float(0.5) * z +
                  z * z * (Float(4.166664568298827e-2) + z * (Float(-1.388731625493765e-3) + z * Float(2.443315711809948e-5)));
  return {s, c};
}

// cos(2πu) and sin(2πu) for u in [0, 1]: the nearest quarter turn k = round(4u) is
// split off exactly, the remainder (π/2)(4u − k) lies in [−π/4, π/4], and the result is
// turned by k quarter turns. Replaces a libm sincos call (~15 ns) in the samplers.
// Rounding is by a truncating conversion (4u + 1/2 ≥ 0), not std::nearbyint, which is a
// library call on baseline x86-64; the turn is applied with a 4-entry table of (cos, sin)
// of kπ/2 (entries 0 and ±1, so the products are exact) instead of a chain of branches.
inline SinCos sincos_2pi(Float u) {
  const Float q = 4 * u;
  const int k = static_cast<int>(q + Float(0.5));
  const SinCos r = sincos_quarter_minimax(kPiOver2 * (q - static_cast<Float>(k)));
  static constexpr Float kCos[4] = {1, 0, -1, 0}, kSin[4] = {0, 1, 0, -1};
  const int quarter = k & 3;
  // (cos, sin) of r + k π/2
  const Float c = kCos[quarter] * r.cos - kSin[quarter] * r.sin;
  const Float s = kSin[quarter] * r.cos + kCos[quarter] * r.sin;
  return {s, c};
}

}  // namespace gonio
