#pragma once
// A 3-vector of Float for directions and points; plain value type, all inline.

#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

struct Vec3 {
  Float x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(Float x_, Float y_, Float z_) : x(x_), y(y_), z(z_) {}

  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(const Vec3& b) { x += b.x; y += b.y; z += b.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  constexpr Vec3& operator*=(Float s) { x *= s; y *= s; z *= s; return *this; }
  constexpr Float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator*(Vec3 a, Float s) { return a *= s; }
constexpr Vec3 operator*(Float s, Vec3 a) { return a *= s; }
constexpr Vec3 operator/(Vec3 a, Float s) { return a *= (1 / s); }

constexpr Float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Float abs_dot(const Vec3& a, const Vec3& b) {
  const Float d = dot(a, b);
  return d < 0 ? -d : d;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr Float length_squared(const Vec3& v) { return dot(v, v); }
inline Float length(const Vec3& v) { return std::sqrt(length_squared(v)); }

// Unit vector along v; the zero vector stays zero rather than becoming NaN.
// Always inlined: GCC outlined it from the large walk and path functions (a call per use,
// 3.4 % of a marble render's time in `perf`).
[[gnu::always_inline]] inline Vec3 normalize(const Vec3& v) {
  const Float l2 = length_squared(v);
  return l2 > 0 ? v * (1 / std::sqrt(l2)) : Vec3{};
}

inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace gonio
