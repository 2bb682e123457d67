#pragma once
// Shared pieces of the validator's property checks (internal).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/rng.h"
#include "gonio/validate.h"

namespace gonio::validation {

inline std::uint64_t scaled(const ValidationOptions& o, std::uint64_t n, std::uint64_t floor = 1000) {
  const double s = o.scale > 0 ? o.scale : 1;
  return std::max<std::uint64_t>(floor, static_cast<std::uint64_t>(double(n) * s));
}

// An independent stream per property, so adding a property does not shift the others.
inline Pcg32 rng_for(const ValidationOptions& o, std::uint64_t property_id) {
  return Pcg32(o.seed, 0x6a09e667f3bcc909ULL + 2 * property_id);
}

inline std::string describe(const Vec3& w) {
  std::ostringstream os;
  os.precision(6);
  os << "(" << w.x << ", " << w.y << ", " << w.z << ")";
  return os.str();
}

inline std::string fmt(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

// Directions that break careless code: exactly normal, grazing (cos θ = 0 and just off
// it), below the horizon, the critical angle of the model's interface from both sides,
// and directions whose components are denormal or just inside the unit sphere.
inline std::vector<Vec3> adversarial_directions(Float eta) {
  std::vector<Vec3> v = {{0, 0, 1},  {0, 0, -1}, {1, 0, 0},  {0, 1, 0},  {-1, 0, 0},
                         {0, -1, 0}, normalize(Vec3{1, 1, 0}),
                         normalize(Vec3{1, 0, 1e-7f}), normalize(Vec3{1, 0, -1e-7f}),
                         normalize(Vec3{0.6f, 0.8f, 1e-30f}), normalize(Vec3{0.6f, -0.8f, -1e-30f}),
                         normalize(Vec3{1e-30f, 0, 1}), normalize(Vec3{0, 1e-30f, -1}),
                         {0.6f, 0.f, 0.8f}, {0.f, -0.8f, 0.6f}};
  for (Float e : {eta, 1 / eta, Float(1.5), Float(1 / 1.5)}) {
    if (!(e < 1)) continue;  // a critical angle exists only leaving the denser side
    const Float crit = std::asin(std::min(Float(1), e));
    for (Float d : {Float(-1e-6), Float(0), Float(1e-6)}) {
      v.push_back(direction_from_angles(crit + d, 0.4f));
      v.push_back(-direction_from_angles(crit + d, 1.3f));
    }
  }
  return v;
}

// Refractive index of the medium on w's side (outside = 1, inside = eta; SPEC §1).
inline Float index_on_side(const Vec3& w, Float eta) { return w.z > 0 ? Float(1) : eta; }

inline double relative_error(double a, double b) {
  const double m = std::max(std::abs(a), std::abs(b));
  return m > 0 ? std::abs(a - b) / m : 0.0;
}

// Largest channel-wise relative error between two colours, ignoring values below `floor`
// in both (where float round-off dominates).
inline double color_relative_error(const Color& a, const Color& b, double floor = 1e-6) {
  double e = 0;
  for (int i = 0; i < Color::size(); ++i) {
    if (std::abs(a[i]) < floor && std::abs(b[i]) < floor) continue;
    e = std::max(e, relative_error(a[i], b[i]));
  }
  return e;
}

// Outgoing directions the sampling checks use: a spread of polar angles including
// near-normal and grazing ones, on both sides when the model transmits, and on both
// sides for two-sided reflection models as well.
inline std::vector<Vec3> test_outgoing_directions(const BxDF& bxdf) {
  std::vector<Vec3> v;
  const Float deg = Float(kPiD / 180);
  for (Float th : {Float(0.5), Float(30), Float(60), Float(80), Float(89)})
    v.push_back(direction_from_angles(th * deg, Float(0.7) + th * deg));
  if (!is_transmissive(bxdf.flags())) {
    v.push_back(-direction_from_angles(45 * deg, 2.1f));  // the mirrored side of a BRDF
  } else {
    for (Float th : {Float(10), Float(40), Float(70), Float(88)})
      v.push_back(-direction_from_angles(th * deg, 4.0f - th * deg));
  }
  if (bxdf.is_fibre()) {
    // A fibre (bxdf/hair.h): normal to its axis x, and nearly along it.
    v.push_back(normalize(Vec3{0, 0.6f, 0.8f}));
    v.push_back(normalize(Vec3{0.98f, 0.1f, -0.17f}));
  }
  return v;
}

}  // namespace gonio::validation
