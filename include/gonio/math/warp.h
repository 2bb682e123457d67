#pragma once
// Sampling warps from the unit square [0,1)² to directions, each with its density per
// unit solid angle (Pharr, Jakob & Humphreys, PBR 4th ed., §A.5 for the derivations).

#include <algorithm>
#include <cmath>

#include "gonio/math/select.h"
#include "gonio/math/vec3.h"

namespace gonio {

struct Vec2 {
  Float x = 0, y = 0;
};

// Concentric map of the square onto the unit disk; preserves stratification and has low
// distortion (Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square"):
// in the wedge |a| > |b| the point is at radius a and angle (π/4)(b/a), else at radius b
// and angle π/2 − (π/4)(a/b). Written without branches: the wedge is a select, and both
// wedges need sin and cos of (π/4)·t with t in [−1, 1], a short polynomial.
inline Vec2 square_to_concentric_disk(Float u1, Float u2) {
  const Float a = 2 * u1 - 1, b = 2 * u2 - 1;
  const bool first = std::abs(a) > std::abs(b);
  const Float r = first ? a : b;
  const Float t = r != 0 ? (first ? b : a) / r : Float(0);
  const SinCos sc = sincos_quarter(kPiOver4 * t);
  // cos(π/2 − x) = sin x, sin(π/2 − x) = cos x
  return {r * (first ? sc.cos : sc.sin), r * (first ? sc.sin : sc.cos)};
}

// Cosine-weighted hemisphere (z ≥ 0) by projecting the concentric disk up (Malley's
// method); density cos θ / π. The disk radius is |a| or |b|, so z = sqrt(1 − r²).
inline Vec3 square_to_cosine_hemisphere(Float u1, Float u2) {
  const Float a = 2 * u1 - 1, b = 2 * u2 - 1;
  const Float r = std::max(std::abs(a), std::abs(b));
  const Vec2 d = square_to_concentric_disk(u1, u2);
  return {d.x, d.y, std::sqrt(std::max(Float(0), 1 - r * r))};
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
