#pragma once
// A ray o + t·d for t in (0, tmax). The renderer keeps d unit length.

#include <algorithm>
#include <cmath>
#include <limits>

#include "gonio/math/vec3.h"

namespace gonio::render {

struct Ray {
  Vec3 o, d;
  Float tmax = std::numeric_limits<Float>::infinity();
};

// Moves a surface point off its surface along the geometric normal, to the side of the
// direction that leaves it, so that the next ray does not hit the surface it starts on.
// The offset grows with the coordinates' magnitude: float spacing near p is what has to
// be cleared (an error-bound offset in the spirit of Pharr et al., PBR 4th ed., §6.8.6).
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& ng, const Vec3& dir) {
  const Float mag = std::max({Float(1), std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const Float eps = Float(2e-4) * mag;
  return p + ng * (dot(ng, dir) >= 0 ? eps : -eps);
}

}  // namespace gonio::render
