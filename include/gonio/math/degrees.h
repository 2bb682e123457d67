#pragma once
// Angles given in degrees, as the command line and the Python module take them.

#include <cmath>

#include "gonio/math/constants.h"

namespace gonio {

// cos of an angle in degrees, exact where an exact value exists: the angle is reduced to
// [−45°, 45°] in degrees (std::remquo: exact for any double) before it becomes radians,
// and ±30° takes its sine ½ exactly (Niven: 0, ±½ and ±1 are the only rational sines of
// rational degrees). So 90° gives 0, 60° gives ½ and 30° the correctly rounded √3/2,
// where cos(30 · π/180) rounds up past √3/2 and put the critical angle of η = ½ (30°,
// where SPEC §1 makes the reflection total) on the refracting side.
inline double cos_degrees(double degrees) {
  int quadrant = 0;
  const double r = std::remquo(degrees, 90.0, &quadrant);  // degrees = 90 q + r, |r| <= 45
  const double rad = r * (kPiD / 180);
  const double s = std::abs(r) == 30 ? std::copysign(0.5, r) : std::sin(rad);
  const double c = std::abs(r) == 30 ? std::sqrt(3.0) / 2 : std::cos(rad);
  const int q = quadrant & 3;  // the low bits of q: cos(90 q + r)
  const double v = q == 0 ? c : q == 1 ? -s : q == 2 ? -c : s;
  return v + 0.0;  // 90° gives −sin 0 = −0: +0, as the cosine of a grazing angle
}

}  // namespace gonio
