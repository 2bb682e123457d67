#pragma once
// acos by a polynomial and one square root, without a division: Abramowitz & Stegun 1964,
// eq. 4.4.46: acos x = √(1 − x) (a0 + a1 x + ... + a7 x⁷) on [0, 1], |error| ≤ 2e-8 rad
// (2.2e-8 measured in double over 2·10⁶ points) — below float resolution, as fast_atan2's
// bound. Where acos is needed of a cosine x ∈ [0, 1] that also needs √(1 − x²) (sin θ), both
// roots fit in one vector square root, and the polynomial runs alongside it instead of
// after a division (atan2's argument): a shorter dependency chain. V is Float or Float4.

#include "gonio/math/fast_atan.h"

namespace gonio {
namespace detail {
// a0 + a1 x + ... + a7 x⁷ of A&S 4.4.46, by Estrin's scheme as atan_poly.
template <typename V>
inline V acos_poly(V x) {
  const V x2 = x * x, x4 = x2 * x2;
  const V p01 = splat<V>(Float(1.5707963050)) + splat<V>(Float(-0.2145988016)) * x;
  const V p23 = splat<V>(Float(0.0889789874)) + splat<V>(Float(-0.0501743046)) * x;
  const V p45 = splat<V>(Float(0.0308918810)) + splat<V>(Float(-0.0170881256)) * x;
  const V p67 = splat<V>(Float(0.0066700901)) + splat<V>(Float(-0.0012624911)) * x;
  return (p01 + x2 * p23) + x4 * (p45 + x2 * p67);
}
}  // namespace detail
}  // namespace gonio
