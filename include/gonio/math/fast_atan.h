#pragma once
// atan2 by a polynomial instead of libm's call: the measured model computes four angles per
// evaluation (measured_data.h), and libm's atanf was half of its time. Abramowitz & Stegun
// 1964, eq. 4.4.49 (Hastings): atan x = x (1 + a2 x² + ... + a16 x¹⁶) on [0, 1] with
// |error| ≤ 2e-8 rad — below float resolution; octants by atan x = π/2 − atan(1/x) and
// symmetry. Same conventions as std::atan2: result in [−π, π], atan2(0, 0) = 0; NaN in,
// NaN out.

#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

inline Float fast_atan2(Float y, Float x) {
  const Float ax = std::abs(x), ay = std::abs(y);
  const Float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  const Float t = hi == 0 ? lo : lo / hi;  // in [0, 1]; a NaN argument gives NaN
  const Float t2 = t * t;
  Float p = Float(0.0028662257);
  p = p * t2 - Float(0.0161657367);
  p = p * t2 + Float(0.0429096138);
  p = p * t2 - Float(0.0752896400);
  p = p * t2 + Float(0.1065626393);
  p = p * t2 - Float(0.1420889944);
  p = p * t2 + Float(0.1999355085);
  p = p * t2 - Float(0.3333314528);
  Float r = t + t * t2 * p;
  if (ay > ax) r = kPi / 2 - r;
  if (x < 0) r = kPi - r;
  return std::signbit(y) ? -r : r;
}

}  // namespace gonio
