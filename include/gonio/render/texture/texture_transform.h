#pragma once
// KHR_texture_transform: an affine map of texture coordinates per textureInfo,
// uv' = T(offset) · R(rotation) · S(scale) · uv, with the rotation matrix the extension's
// specification writes in GLSL (columns (cos r, sin r) and (−sin r, cos r)):
//   u' = cos r · sx·u − sin r · sy·v + ox,   v' = sin r · sx·u + cos r · sy·v + oy.

#include <cmath>

#include "gonio/math/warp.h"

namespace gonio::render {

struct TextureTransform {
  // Row-major 2 × 3 matrix; the identity by default.
  Float m00 = 1, m01 = 0, m02 = 0, m10 = 0, m11 = 1, m12 = 0;

  static TextureTransform make(Vec2 offset, Float rotation, Vec2 scale) {
    const Float c = std::cos(rotation), s = std::sin(rotation);
    return {c * scale.x, -s * scale.y, offset.x, s * scale.x, c * scale.y, offset.y};
  }
  Vec2 apply(const Vec2& uv) const { return {m00 * uv.x + m01 * uv.y + m02, m10 * uv.x + m11 * uv.y + m12}; }
};

}  // namespace gonio::render
