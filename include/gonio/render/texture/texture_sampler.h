#pragma once
// Texture lookups: gonio's own, over a TextureImage (texture_image.h). A sampler holds
// glTF's sampler state (magFilter/minFilter, wrapS/wrapT, glTF 2.0 §5.26); lookup() is
// allocation-free, branch-light and never returns NaN for finite coordinates
// (non-finite coordinates read texel (0, 0)).
//
// Mip choice: lookup() takes the footprint of the lookup in level-0 texels (the larger
// side of the pixel's projection, from ray differentials); level log2(footprint) is read,
// blended linearly between the two nearest levels (trilinear) when the min filter is
// linear, the nearest level otherwise. Footprint ≤ 1 (magnification), or 0 when the caller
// has no differentials (today's path tracer: every lookup reads level 0), uses level 0.

#include <algorithm>
#include <cmath>

#include "gonio/math/warp.h"
#include "gonio/render/texture/texture_image.h"

namespace gonio::render {

// glTF's wrap modes (REPEAT 10497, CLAMP_TO_EDGE 33071, MIRRORED_REPEAT 33648).
enum class TextureWrap { Repeat, Clamp, Mirror };
enum class TextureFilter { Nearest, Linear };

struct TextureSampler {
  TextureFilter mag = TextureFilter::Linear;
  TextureFilter min = TextureFilter::Linear;  // within a level; also across levels (trilinear)
  bool mipmaps = true;                        // false: level 0 only (glTF minFilter NEAREST or LINEAR)
  TextureWrap wrap_s = TextureWrap::Repeat, wrap_t = TextureWrap::Repeat;
};

namespace texture_detail {

// Integer texel index i (any int) mapped into [0, n) by the wrap mode.
inline int wrap_index(int i, int n, TextureWrap mode) {
  switch (mode) {
    case TextureWrap::Clamp: return std::clamp(i, 0, n - 1);
    case TextureWrap::Mirror: {
      // Period 2n: 0..n-1 then n-1..0 (mirrored repeat, OpenGL 4.6 §8.14.2).
      int m = i % (2 * n);
      if (m < 0) m += 2 * n;
      return m < n ? m : 2 * n - 1 - m;
    }
    case TextureWrap::Repeat:
    default: {
      const int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

// A finite coordinate reduced to a range where float → int conversion cannot overflow:
// repeat and mirror are periodic (period 1 and 2 in texture space), clamp saturates.
inline Float reduce(Float s, TextureWrap mode) {
  if (!std::isfinite(s)) return 0;
  if (mode == TextureWrap::Clamp) return std::clamp(s, Float(-1), Float(2));
  const Float period = mode == TextureWrap::Mirror ? 2 : 1;
  return s - period * std::floor(s / period);
}

inline Rgba lerp(const Rgba& a, const Rgba& b, Float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t, a.a + (b.a - a.a) * t};
}

inline Rgba level_lookup(const TextureLevel& l, Float s, Float t, TextureFilter f,
                         const TextureSampler& smp) {
  s = reduce(s, smp.wrap_s) * Float(l.width);
  t = reduce(t, smp.wrap_t) * Float(l.height);
  if (f == TextureFilter::Nearest) {
    const int x = wrap_index(int(std::floor(s)), l.width, smp.wrap_s);
    const int y = wrap_index(int(std::floor(t)), l.height, smp.wrap_t);
    return l.at(x, y);
  }
  // Bilinear between the four texel centres around (s, t); centres at (i + 0.5).
  const Float fs = s - Float(0.5), ft = t - Float(0.5);
  const Float x0f = std::floor(fs), y0f = std::floor(ft);
  const Float ws = fs - x0f, wt = ft - y0f;
  const int x0 = int(x0f), y0 = int(y0f);
  const int xa = wrap_index(x0, l.width, smp.wrap_s), xb = wrap_index(x0 + 1, l.width, smp.wrap_s);
  const int ya = wrap_index(y0, l.height, smp.wrap_t), yb = wrap_index(y0 + 1, l.height, smp.wrap_t);
  return lerp(lerp(l.at(xa, ya), l.at(xb, ya), ws), lerp(l.at(xa, yb), l.at(xb, yb), ws), wt);
}

}  // namespace texture_detail

// The texel value at texture coordinates (s, t): s to the right, t down from the top row
// (glTF's uv); texel (x, y) covers [x, x+1)/width × [y, y+1)/height. An empty image
// gives (0, 0, 0, 1). `footprint`: see the header comment.
inline Rgba lookup(const TextureImage& img, const TextureSampler& smp, Vec2 st, Float footprint = 0) {
  if (img.empty()) return {};
  using namespace texture_detail;
  if (!(footprint > 1) || !smp.mipmaps || img.level_count() == 1)
    return level_lookup(img.level(0), st.x, st.y, footprint > 1 ? smp.min : smp.mag, smp);
  const Float lod = std::min(std::log2(footprint), Float(img.level_count() - 1));
  if (smp.min == TextureFilter::Nearest) {
    const int l = std::min(int(lod + Float(0.5)), img.level_count() - 1);
    return level_lookup(img.level(l), st.x, st.y, TextureFilter::Nearest, smp);
  }
  const int l0 = std::min(int(lod), img.level_count() - 1);
  const int l1 = std::min(l0 + 1, img.level_count() - 1);
  const Rgba a = level_lookup(img.level(l0), st.x, st.y, TextureFilter::Linear, smp);
  const Rgba b = level_lookup(img.level(l1), st.x, st.y, TextureFilter::Linear, smp);
  return lerp(a, b, lod - Float(l0));
}

}  // namespace gonio::render
