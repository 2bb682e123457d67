#pragma once
// Spherical coordinates of unit vectors in the local shading frame (SPEC §1:
// cos θ = w.z, φ = atan2(w.y, w.x)).

#include <algorithm>
#include <cmath>

#include "gonio/math/vec3.h"

namespace gonio {

inline Float cos_theta(const Vec3& w) { return w.z; }
inline Float cos2_theta(const Vec3& w) { return w.z * w.z; }
inline Float abs_cos_theta(const Vec3& w) { return std::abs(w.z); }
inline Float sin2_theta(const Vec3& w) { return std::max(Float(0), 1 - w.z * w.z); }
inline Float sin_theta(const Vec3& w) { return std::sqrt(sin2_theta(w)); }
// tan θ; +inf at grazing is the mathematically right answer, so callers must guard.
inline Float tan2_theta(const Vec3& w) { return sin2_theta(w) / cos2_theta(w); }

inline Float cos_phi(const Vec3& w) {
  const Float st = sin_theta(w);
  return st == 0 ? Float(1) : std::clamp(w.x / st, Float(-1), Float(1));
}
inline Float sin_phi(const Vec3& w) {
  const Float st = sin_theta(w);
  return st == 0 ? Float(0) : std::clamp(w.y / st, Float(-1), Float(1));
}
inline Float phi(const Vec3& w) {
  const Float p = std::atan2(w.y, w.x);
  return p < 0 ? p + 2 * kPi : p;
}

// Unit vector from (θ, φ); also the form used with a precomputed sin/cos θ.
inline Vec3 spherical_direction(Float sin_t, Float cos_t, Float ph) {
  return {std::clamp(sin_t, Float(-1), Float(1)) * std::cos(ph),
          std::clamp(sin_t, Float(-1), Float(1)) * std::sin(ph),
          std::clamp(cos_t, Float(-1), Float(1))};
}
inline Vec3 direction_from_angles(Float theta, Float ph) {
  return spherical_direction(std::sin(theta), std::cos(theta), ph);
}

inline bool same_hemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }

}  // namespace gonio
