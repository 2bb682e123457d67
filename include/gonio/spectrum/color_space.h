#pragma once
// CIE 1931 XYZ and linear sRGB (D65 white). The XYZ → linear-sRGB matrix is the one of
// IEC 61966-2-1:1999 (sRGB), §5.2 (eq. 5.2, four decimals); RGB → XYZ is its exact
// inverse (computed here), so that RGB → XYZ → RGB is the identity up to rounding.
// No gamma: gonio's colours are linear (SPEC §1).

#include <array>

#include "gonio/color.h"

namespace gonio {

struct XYZ {
  Float x = 0, y = 0, z = 0;
};

using Matrix3d = std::array<std::array<double, 3>, 3>;

inline constexpr Matrix3d kXyzToLinearSrgb{{
    {3.2406, -1.5372, -0.4986},
    {-0.9689, 1.8758, 0.0415},
    {0.0557, -0.2040, 1.0570},
}};

constexpr Matrix3d inverse(const Matrix3d& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  const double s = 1 / det;
  return Matrix3d{{
      {c00 * s, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * s, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * s},
      {c01 * s, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * s, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * s},
      {c02 * s, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * s, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * s},
  }};
}

inline constexpr Matrix3d kLinearSrgbToXyz = inverse(kXyzToLinearSrgb);

constexpr std::array<double, 3> mat_mul(const Matrix3d& m, const std::array<double, 3>& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

// Linear sRGB of an XYZ (may be negative outside the sRGB gamut; not clamped).
inline Color xyz_to_linear_srgb(const XYZ& c) {
  const auto v = mat_mul(kXyzToLinearSrgb, {c.x, c.y, c.z});
  return Color(Float(v[0]), Float(v[1]), Float(v[2]));
}
inline XYZ linear_srgb_to_xyz(const Color& c) {
  const auto v = mat_mul(kLinearSrgbToXyz, {c[0], c[1], c[2]});
  return {Float(v[0]), Float(v[1]), Float(v[2])};
}

}  // namespace gonio
