#pragma once
// Sampling warps from the unit square [0,1)² to directions, each with its density per
// unit solid angle (Pharr, Jakob & Humphreys, PBR 4th ed., §A.5 for the derivations).

#include <algorithm>
#include <cmath>

#include "gonio/math/vec3.h"

namespace gonio {

struct Vec2 {
  Float x = 0, y = 0;
};

// Concentric map of the square onto the unit disk; preserves stratification and has low
// distortion (Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square").
inline Vec2 square_to_concentric_disk(Float u1, Float u2) {
  const Float a = 2 * u1 - 1, b = 2 * u2 - 1;
  if (a == 0 && b == 0) return {0, 0};
  Float r, theta;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    theta = kPiOver4 * (b / a);
  } else {
    r = b;
    theta = kPiOver2 - kPiOver4 * (a / b);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

// Cosine-weighted hemisphere (z ≥ 0) by projecting the concentric disk up (Malley's
// method); density cos θ / π.
inline Vec3 square_to_cosine_hemisphere(Float u1, Float u2) {
  const Vec2 d = square_to_concentric_disk(u1, u2);
  const Float z = std::sqrt(std::max(Float(0), 1 - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}
inline Float cosine_hemisphere_pdf(Float cos_theta) {
  return cos_theta > 0 ? cos_theta * kInvPi : Float(0);
}

// Uniform over the hemisphere z ≥ 0; density 1 / 2π.
inline Vec3 square_to_uniform_hemisphere(Float u1, Float u2) {
  const Float z = u1;
  const Float r = std::sqrt(std::max(Float(0), 1 - z * z));
  const Float ph = 2 * kPi * u2;
  return {r * std::cos(ph), r * std::sin(ph), z};
}
inline constexpr Float uniform_hemisphere_pdf() { return kInv2Pi; }

// Uniform over the whole sphere; density 1 / 4π.
inline Vec3 square_to_uniform_sphere(Float u1, Float u2) {
  const Float z = 1 - 2 * u1;
  const Float r = std::sqrt(std::max(Float(0), 1 - z * z));
  const Float ph = 2 * kPi * u2;
  return {r * std::cos(ph), r * std::sin(ph), z};
}
inline constexpr Float uniform_sphere_pdf() { return kInv4Pi; }

// Uniform over the cone of directions within θmax of +z; density 1 / (2π (1 − cos θmax)).
inline Vec3 square_to_uniform_cone(Float u1, Float u2, Float cos_theta_max) {
  const Float z = 1 - u1 * (1 - cos_theta_max);
  const Float r = std::sqrt(std::max(Float(0), 1 - z * z));
  const Float ph = 2 * kPi * u2;
  return {r * std::cos(ph), r * std::sin(ph), z};
}
inline Float uniform_cone_pdf(Float cos_theta_max) {
  return 1 / (2 * kPi * (1 - cos_theta_max));
}

// Cosine-weighted over the cone within θmax of +z (a cone about the normal):
// cos θ is drawn so that sin²θ is uniform on [0, sin²θmax]; density cos θ / (π sin²θmax).
inline Vec3 square_to_cosine_cone(Float u1, Float u2, Float sin2_theta_max) {
  const Float s2 = u1 * sin2_theta_max;
  const Float r = std::sqrt(s2);
  const Float z = std::sqrt(std::max(Float(0), 1 - s2));
  const Float ph = 2 * kPi * u2;
  return {r * std::cos(ph), r * std::sin(ph), z};
}

}  // namespace gonio
