#pragma once
// atan2 by a polynomial instead of libm's call: the measured model computes four angles per
// evaluation (measured_data.h), and libm's atanf was half of its time. Abramowitz & Stegun
// 1964, eq. 4.4.49 (Hastings): atan x = x (1 + a2 x² + ... + a16 x¹⁶) on [0, 1] with
// |error| ≤ 2e-8 rad — below float resolution; octants by atan x = π/2 − atan(1/x) and
// symmetry. Same conventions as std::atan2: result in [−π, π], atan2(0, 0) = 0; NaN in,
// NaN out.

#include <cmath>
#include <cstdint>

#include "gonio/math/constants.h"

namespace gonio {
namespace detail {
// atan t on [0, 1] by A&S 4.4.49: t + t·z·p(z), z = t², p of degree 7 in z. p is taken by
// Estrin's scheme (pairs c_k + c_{k+1} z, then z², then z⁴) rather than Horner's: a chain
// of 3 multiply-adds instead of 7, for the same operations per call; the rounding differs
// from Horner's by at most 1 ulp (1.2e-7 relative) in 1.7% of arguments. V is Float or Float4.
// c in every lane of V (c itself for a scalar). A braced vector constant, which g++ keeps
// in the constant pool: `Float * vector` made it broadcast each scalar at run time
// (movss + shufps per coefficient). The same values, so the same results.
template <typename V>
constexpr V splat(Float c) {
  if constexpr (sizeof(V) == sizeof(Float)) {
    return c;
  } else {
    return V{c, c, c, c};
  }
}
template <typename V>
inline V atan_poly(V t) {
  const V z = t * t, z2 = z * z, z4 = z2 * z2;
  const V p01 = splat<V>(Float(-0.3333314528)) + splat<V>(Float(0.1999355085)) * z;
  const V p23 = splat<V>(Float(-0.1420889944)) + splat<V>(Float(0.1065626393)) * z;
  const V p45 = splat<V>(Float(-0.0752896400)) + splat<V>(Float(0.0429096138)) * z;
  const V p67 = splat<V>(Float(-0.0161657367)) + splat<V>(Float(0.0028662257)) * z;
  const V p = (p01 + z2 * p23) + z4 * (p45 + z2 * p67);
  return t + t * z * p;
}
}  // namespace detail

inline Float fast_atan2(Float y, Float x) {
  const Float ax = std::abs(x), ay = std::abs(y);
  const Float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  const Float t = hi == 0 ? lo : lo / hi;  // in [0, 1]; a NaN argument gives NaN
  Float r = detail::atan_poly(t);
  if (ay > ax) r = kPi / 2 - r;
  if (x < 0) r = kPi - r;
  return std::signbit(y) ? -r : r;
}

// Four lanes of fast_atan2 at once, in GCC/Clang vector types (SSE on x86-64, NEON on
// ARM): the same operations in the same order per lane, so each lane is bit for bit the
// scalar fast_atan2 of its arguments, for about the cost of one.
typedef float Float4 __attribute__((vector_size(16)));
typedef std::int32_t Int4 __attribute__((vector_size(16)));

inline Float4 fast_atan2(Float4 y, Float4 x) {
  const Int4 abs_bits = Int4{} + 0x7fffffff;
  const Float4 ax = Float4(Int4(x) & abs_bits), ay = Float4(Int4(y) & abs_bits);
  const Int4 x_larger = ax > ay;
  const Float4 hi = x_larger ? ax : ay, lo = x_larger ? ay : ax;
  const Float4 t = hi == 0 ? lo : lo / hi;
  Float4 r = detail::atan_poly(t);
  r = ay > ax ? kPi / 2 - r : r;
  r = x < 0 ? kPi - r : r;
  return Int4(y) < 0 ? -r : r;  // the sign bit, as std::signbit
}

}  // namespace gonio
