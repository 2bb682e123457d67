#pragma once
// Small helpers several test files need. One definition each, so that the test files can
// be compiled together (CMAKE_UNITY_BUILD, as scripts/test.sh builds them) without two
// copies colliding. They are the tests' own formulas, not gonio's.

#include "gonio/math/constants.h"

namespace gonio {

inline constexpr double kDeg = kPiD / 180;

// Reflectance at normal incidence of an interface from air to a medium of complex index
// n + ik: |(n + ik − 1)/(n + ik + 1)|² (Born & Wolf, Principles of Optics, §14.2).
inline double normal_incidence_reflectance(double n, double k) {
  return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
}

}  // namespace gonio
